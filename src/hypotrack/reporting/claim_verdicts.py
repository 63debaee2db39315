"""Claims, not rows: one verdict per distinct claim of the five documents, derived from its ledger rows.

The ledger has one row per *check*; several rows may test one claim of a document (two trackers, two
readings, an oracle and the engine). ``document_claims.yaml`` (package data, :data:`CLAIMS_FILE`) lists
every distinct claim of documents 000--004 the ledger tests, with its words, where the document makes it,
the source of its tolerance and the ledger rows that are its evidence (by their stable key
``<experiment>/<key>``, :func:`row_key`); rows beyond the documents sit in extension groups. Every
non-timing row belongs to exactly one claim or group (:func:`placement_problems`); timing rows are
extensions unless a claim names them.

Each evidence row's role (:func:`evidence_table`)
-------------------------------------------------
* *calibration* (ledger evidence ``calibration``): a reading chosen because it hits the published number;
  it pins the reading, not the method; status ``calibration``;
* *identity* (evidence ``identity of the implementation``) and *own closed form* (set in the claims file:
  the project's Monte Carlo or recursion against the project's own closed form): status ``consistency
  check``;
* *illustration* (ledger status ``illustration``): one realisation of a verdict taken over many runs;
* *vacuous* (set in the claims file: no case decides the check, its control cannot fail): ``uninformative``;
* *independent*: every other row; its status is the ledger's, except that a Monte Carlo row takes the
  status :func:`~hypotrack.reporting.verdict.monte_carlo_verdict` gives it (recomputed from ``n``, ``mean``,
  ``se``, ``published`` and the tolerance, or from the claims file's ``note_monte_carlo`` entry when the
  numbers sit in the row's note), and a *reproduced*/*qualitative* row without a failing control is
  ``uninformative``.

Only independent rows carry a verdict; rows of the other roles never make a claim reproduced.

Joint rows (the claims file's ``joint``)
----------------------------------------
Evidence entries of one claim sharing a ``joint`` name measure one verdict over different sources of
randomness (e.g. an MCMC verdict over scenario seeds and over chain seeds on one scenario): the verdict
holds only if it holds over each. A positive member therefore keeps its status only when every decided
member is positive; it takes *not reproduced* when another member is not reproduced, and otherwise the
first of *inconclusive*, *uninformative* among the others (an undecided source leaves the verdict
undecided). Non-positive members keep their own status.

The rule (:func:`claim_verdict`)
--------------------------------
Rows are grouped by the *reading* of the document they measure under (the claims file's ``reading``,
default "as stated"); a *positive* row is *reproduced* or *qualitative*, a *negative* one *not reproduced*.

1. no evidence row in the ledger: ``not run``;
2. no independent row with a verdict: ``uninformative`` when a vacuous row is among them, else ``consistency only`` (calibrations, identities, own closed forms:
   never a reproduction);
3. a reading with both a positive and a negative row: ``contested`` (the evidence contradicts itself);
4. positive rows under one reading, negative under another: ``reproduced in part`` (the claim holds
   under some reading of the document, fails under another);
5. positive rows and no negative one: ``reproduced`` (``qualitative`` when every positive row is
   qualitative: a stated shape or ordering reproduced as such);
6. negative rows and no positive one: ``not reproduced``;
7. otherwise the best-supported of the remaining statuses: ``inconclusive`` before ``uninformative``.

Inconclusive and uninformative rows never contradict a positive one: they decide nothing.

One reading per table (:func:`table_readings`)
----------------------------------------------
Claims that are entries of one published table (the claims file's ``table``, e.g. document 003's Table 6.1)
were produced by one procedure, so they are read under one reading of it: a table *reproduces under* a reading
when every entry with rows under it is positive there (its other entries decided as stated). Each entry is
then judged on the rows of that reading (and the rows that need none). When no reading reproduces the
entries together, an entry that is positive under one reading but not under the others is ``inconclusive``
("no one reading reproduces the table's entries together"): one entry reproducing under one scoring window
and another under a different, mutually exclusive one is no reproduction of the table.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import pandas as pd
import yaml

from .claims import _TOL_TEXT, _calibrated
from .verdict import monte_carlo_verdict, parse_control

__all__ = ["CLAIMS_FILE", "CLAIM_VERDICTS", "CLAIM_VERDICT_MEANING", "DOCUMENTS", "TOLERANCE_SOURCES",
           "claim_verdict", "claim_verdicts", "evidence_table", "headline", "load_claims_file", "table_readings",
           "monte_carlo_mismatches", "placement_problems", "row_key", "row_tolerance"]

CLAIMS_FILE = Path(__file__).with_name("document_claims.yaml")
DOCUMENTS = ("000", "001", "002", "003", "004")
TOLERANCE_SOURCES = ("printed precision", "Monte Carlo error of the document's stated runs", "physical",
                     "chosen here")
ROLES = ("independent", "calibration", "identity", "own closed form", "illustration", "vacuous")
CLAIM_VERDICTS = ("reproduced", "reproduced in part", "contested", "qualitative", "not reproduced", "inconclusive",
                  "uninformative", "consistency only", "not run")
CLAIM_VERDICT_MEANING = {
    "reproduced": "an independent check reproduces it (its control fails) and none fails it",
    "reproduced in part": "reproduced under one reading of the document, not reproduced under another",
    "contested": "checks under the same reading disagree: one reproduces it, another does not",
    "qualitative": "a stated shape or ordering, reproduced as such (its control fails)",
    "not reproduced": "an independent check fails it and none reproduces it",
    "inconclusive": "the Monte Carlo evidence cannot decide it",
    "uninformative": "the checks pass, but so do controls built to fail them (or no case decides them)",
    "consistency only": "only calibrations, identities of the implementation or comparisons with the project's "
                        "own closed form: never a reproduction",
    "not run": "no row of this ledger tests it",
}
VERDICT_ROW_STATUSES = ("reproduced", "not reproduced", "inconclusive", "uninformative", "qualitative")
DEFAULT_READING = "as stated"
TIMING_GROUP = "extension.timing"


def row_key(row) -> str:
    """A ledger row's stable key: ``<experiment>/<key>``, its item when the key is empty."""
    return f"{row['experiment']}/{row.get('key', '') or row['item']}"


@lru_cache(maxsize=4)
def _read_yaml(path: str) -> dict:
    return yaml.safe_load(Path(path).read_text())


def load_claims_file(path=None) -> dict:
    """The claims file (default :data:`CLAIMS_FILE`), checked: ids unique, documents and tolerance
    sources from the vocabularies, roles known, every evidence entry naming a row."""
    spec = _read_yaml(str(path or CLAIMS_FILE))
    ids = [c["id"] for c in spec["claims"]] + [g["id"] for g in spec.get("extensions", [])]
    if len(set(ids)) != len(ids):
        raise ValueError(f"claim ids must be unique: {sorted(i for i in set(ids) if ids.count(i) > 1)}")
    for c in spec["claims"]:
        if c["document"] not in DOCUMENTS:
            raise ValueError(f"{c['id']}: document must be one of {DOCUMENTS}, got {c['document']!r}")
        if c.get("tolerance", {}).get("source") not in TOLERANCE_SOURCES:
            raise ValueError(f"{c['id']}: tolerance source must be one of {TOLERANCE_SOURCES}")
        joints = [e["joint"] for e in map(_entry, c["evidence"]) if e["joint"]]
        for e in map(_entry, c["evidence"]):
            if e["role"] not in ("", *ROLES):
                raise ValueError(f"{c['id']}: role must be one of {ROLES}, got {e['role']!r}")
            if e["joint"] and joints.count(e["joint"]) < 2:
                raise ValueError(f"{c['id']}: joint {e['joint']!r} must name at least two evidence entries, "
                                 f"names only {e['row']}")
    return spec


def _entry(e) -> dict:
    """An evidence entry as a mapping: row, reading, role ('' = derived from the row), joint ('' = none)."""
    if isinstance(e, str):
        e = {"row": e}
    return {"row": e["row"], "reading": e.get("reading", DEFAULT_READING), "role": e.get("role", ""),
            "joint": e.get("joint", "")}


def _joint_statuses(statuses: list[str], roles: list[str]) -> list[str]:
    """The statuses of one ``joint`` group of a claim's rows (module docstring, "Joint rows")."""
    decided = [s for s, r in zip(statuses, roles) if r == "independent" and s in VERDICT_ROW_STATUSES]
    positive = ("reproduced", "qualitative")
    if all(s in positive for s in decided):
        return statuses
    worst = next(s for s in ("not reproduced", "inconclusive", "uninformative") if s in decided)
    return [worst if (r == "independent" and s in positive) else s for s, r in zip(statuses, roles)]


def placement_problems(ledger: pd.DataFrame, spec: dict | None = None, timing: pd.DataFrame | None = None) -> list[str]:
    """Sentences naming every ledger row placed in no claim or group, in two, or named but absent.

    ``timing`` (the ``ledger_timing.csv`` rows) need no place: they are extensions unless a claim names them.
    """
    spec = spec or load_claims_file()
    places: dict[str, list[str]] = {}
    for c in spec["claims"]:
        for e in map(_entry, c["evidence"]):
            places.setdefault(e["row"], []).append(c["id"])
    for g in spec.get("extensions", []):
        for r in g["rows"]:
            places.setdefault(r, []).append(g["id"])
    keys = [row_key(r) for r in ledger.to_dict("records")]
    timing_keys = set() if timing is None else {row_key(r) for r in timing.to_dict("records")}
    out = [f"row {k} is placed in no claim and no extension group" for k in keys if k not in places]
    out += [f"row {k} is placed in {len(v)} places ({', '.join(v)})" for k, v in places.items() if len(v) > 1]
    out += [f"row {k} is named by {', '.join(v)} but is not in the ledger" for k, v in places.items()
            if k not in set(keys) | timing_keys]
    out += [f"ledger row key {k} is not unique" for k in sorted({k for k in keys if keys.count(k) > 1})]
    return out


def row_tolerance(row) -> tuple[float, int | None] | None:
    """``(tolerance, published_runs)`` of a Monte Carlo row against a numeric published value; None otherwise."""
    if not (row.get("n", "") and row.get("mean", "") and row.get("se", "")):
        return None
    try:
        published = float(row["published"])
    except ValueError:
        return None
    m = _TOL_TEXT.fullmatch(row.get("tolerance", ""))
    if not m:
        return None
    tol = float(m["rel"]) / 100 * abs(published) if m["rel"] else float(m["abs"])
    return tol, int(m["runs"]) if m["runs"] else None


def _control_passes(row) -> bool | None:
    parsed = parse_control(row.get("control", ""))
    return None if parsed is None else parsed[2]


def monte_carlo_status(row, factor: float = 1.0, numbers: dict | None = None) -> str | None:
    """The Monte Carlo rule's status of a row (its tolerance times ``factor``), None for a non-Monte-Carlo
    row; ``numbers`` (n, mean, se, published, tolerance) when they sit in the note (``note_monte_carlo``).
    A positive status whose control also passes is *uninformative*."""
    if numbers is not None:
        v = monte_carlo_verdict(float(numbers["mean"]), float(numbers["se"]), float(numbers["published"]),
                                factor * float(numbers["tolerance"]), int(numbers["n"]))
    else:
        tol = row_tolerance(row)
        if tol is None:
            return None
        v = monte_carlo_verdict(float(row["mean"]), float(row["se"]), float(row["published"]), factor * tol[0],
                                int(row["n"]), tol[1])
    status = _calibrated(v.status, row.get("evidence", ""))  # a calibrated reading that passes: never a reproduction
    if status == "reproduced" and _control_passes(row):
        status = "uninformative"
    return status


def monte_carlo_mismatches(ledger: pd.DataFrame, spec: dict | None = None) -> pd.DataFrame:
    """Rows whose recorded status differs from the Monte Carlo rule's (columns row, recorded, recomputed, why);
    ``why`` is the claims file's explanation for a ``note_monte_carlo`` row, empty for an unexplained one."""
    spec = spec or load_claims_file()
    notes = {e["row"]: e for e in spec.get("note_monte_carlo", [])}
    out = []
    for r in ledger.to_dict("records"):
        k = row_key(r)
        status = monte_carlo_status(r, numbers=notes.get(k))
        if status is not None and status != r["status"]:
            out.append((k, r["status"], status, notes.get(k, {}).get("why", "")))
    return pd.DataFrame(out, columns=["row", "recorded", "recomputed", "why"])


def _role(entry: dict, row) -> str:
    if entry["role"]:
        return entry["role"]
    if row.get("evidence") == "calibration":
        return "calibration"
    if row.get("evidence") == "identity of the implementation":
        return "identity"
    if row["status"] == "illustration":
        return "illustration"
    return "independent"


def _row_status(role: str, row, numbers: dict | None, factor: float = 1.0) -> str:
    if role == "calibration":
        return "calibration"
    if role in ("identity", "own closed form"):
        return "consistency check"
    if role == "illustration":
        return "illustration"
    if role == "vacuous":
        return "uninformative"
    status = monte_carlo_status(row, factor, numbers) or row["status"]
    if status in ("reproduced", "qualitative") and _control_passes(row) is not False:
        return "uninformative"  # a positive row needs a control that fails
    return status


def evidence_table(ledger: pd.DataFrame, spec: dict | None = None, timing: pd.DataFrame | None = None,
                   factors: dict | None = None) -> pd.DataFrame:
    """One row per (claim, evidence row present in the ledger): claim, document, row, reading, role,
    ledger_status and status (the claims table's status of the row, module docstring).

    ``factors`` maps a claim id to a tolerance factor for its Monte Carlo rows (the sensitivity table).
    """
    spec = spec or load_claims_file()
    frames = [ledger] if timing is None else [ledger, timing]
    rows = {row_key(r): r for f in frames for r in f.to_dict("records")}
    notes = {e["row"]: e for e in spec.get("note_monte_carlo", [])}
    out = []
    for c in spec["claims"]:
        joints = {}
        for e in map(_entry, c["evidence"]):
            r = rows.get(e["row"])
            if r is None:
                continue
            role = _role(e, r)
            status = _row_status(role, r, notes.get(e["row"]), (factors or {}).get(c["id"], 1.0))
            if e["joint"]:
                joints.setdefault(e["joint"], []).append(len(out))
            out.append((c["id"], c["document"], e["row"], e["reading"], role, r["status"], status))
        for members in joints.values():
            statuses = _joint_statuses([out[i][6] for i in members], [out[i][4] for i in members])
            for i, status in zip(members, statuses):
                out[i] = (*out[i][:6], status)
    return pd.DataFrame(out, columns=["claim", "document", "row", "reading", "role", "ledger_status", "status"])


def claim_verdict(evidence: pd.DataFrame) -> tuple[str, str]:
    """``(verdict, reason)`` of one claim from its rows of :func:`evidence_table` (the rule: module docstring)."""
    if evidence.empty:
        return "not run", "no row of the ledger tests it"
    decided = evidence[(evidence["role"] == "independent") & evidence["status"].isin(VERDICT_ROW_STATUSES)]
    if decided.empty and (evidence["role"] == "vacuous").any():
        return "uninformative", "no case decides it: " + ", ".join(evidence.loc[evidence["role"] == "vacuous", "row"])
    if decided.empty:
        return "consistency only", "no independent row: " + ", ".join(
            f"{r['row']} {r['status']}" for r in evidence.to_dict("records"))
    positive = decided[decided["status"].isin(("reproduced", "qualitative"))]
    negative = decided[decided["status"] == "not reproduced"]

    def named(rows):
        return ", ".join(rows["row"])

    both = sorted(set(positive["reading"]) & set(negative["reading"]))
    if both:
        return "contested", (f"under the same reading ({'; '.join(both)}) {named(positive)} reproduced, "
                             f"{named(negative)} not")
    if len(positive) and len(negative):
        return "reproduced in part", (f"reproduced under {'; '.join(sorted(set(positive['reading'])))} "
                                      f"({named(positive)}), not under {'; '.join(sorted(set(negative['reading'])))} "
                                      f"({named(negative)})")
    if len(positive):
        verdict = "qualitative" if (positive["status"] == "qualitative").all() else "reproduced"
        return verdict, f"{len(positive)} of {len(decided)} independent rows positive ({named(positive)}), none negative"
    if len(negative):
        return "not reproduced", (f"{len(negative)} of {len(decided)} independent rows not reproduced "
                                  f"({named(negative)}), none positive")
    for status in ("inconclusive", "uninformative"):
        if (decided["status"] == status).any():
            return status, ("no independent row decides it: "
                            + ", ".join(f"{r['row']} {r['status']}" for r in decided.to_dict("records")))
    raise AssertionError("unreachable: decided rows carry a verdict status")


def _positive_under(ev: pd.DataFrame, reading: str) -> bool | None:
    """Whether a claim is positive under ``reading`` (its rows of that reading and those needing none);
    ``None`` when it has no decided row under that reading."""
    rows = ev[ev["reading"].isin((reading, "as stated"))]
    decided = rows[(rows["role"] == "independent") & rows["status"].isin(VERDICT_ROW_STATUSES)
                   & (rows["reading"] == reading)]
    if decided.empty:
        return None
    return claim_verdict(rows)[0] in ("reproduced", "qualitative")


def table_readings(spec: dict, table: pd.DataFrame) -> dict:
    """Per table (claims sharing ``table`` in the claims file): the reading under which every entry with
    rows under it is positive, or ``None`` when no reading reproduces the entries together."""
    out = {}
    groups = {}
    for c in spec["claims"]:
        if c.get("table"):
            groups.setdefault(c["table"], []).append(c["id"])
    for name, ids in groups.items():
        ev = table[table["claim"].isin(ids)]
        readings = [r for r in dict.fromkeys(ev["reading"]) if r != "as stated"]
        out[name] = next((r for r in readings
                          if all(_positive_under(ev[ev["claim"] == i], r) is not False for i in ids)), None)
    return out


def _table_verdict(ev: pd.DataFrame, reading: str | None, table_name: str) -> tuple[str, str]:
    """A table entry's verdict under the table's one reading (module docstring)."""
    if reading is not None:
        verdict, reason = claim_verdict(ev[ev["reading"].isin((reading, "as stated"))])
        return verdict, f"{reason} (the table's reading: {reading})"
    verdict, reason = claim_verdict(ev)
    if verdict in ("reproduced", "qualitative", "reproduced in part") and len(set(ev["reading"]) - {"as stated"}) > 1:
        return "inconclusive", (f"no one reading reproduces the entries of {table_name} together; this entry: "
                                f"{reason}")
    return verdict, reason


def claim_verdicts(ledger: pd.DataFrame, spec: dict | None = None, timing: pd.DataFrame | None = None,
                   factors: dict | None = None) -> pd.DataFrame:
    """One row per claim of the claims file: id, document, where, words, verdict, reason, rows (evidence rows
    in the ledger), independent (of them, independent rows with a verdict), tolerance_source, tolerance_reason,
    note."""
    spec = spec or load_claims_file()
    table = evidence_table(ledger, spec, timing, factors)
    readings = table_readings(spec, table)
    out = []
    for c in spec["claims"]:
        ev = table[table["claim"] == c["id"]]
        if c.get("table") and not ev.empty:
            verdict, reason = _table_verdict(ev, readings[c["table"]], c["table"])
        else:
            verdict, reason = claim_verdict(ev)
        independent = int(((ev["role"] == "independent") & ev["status"].isin(VERDICT_ROW_STATUSES)).sum())
        out.append((c["id"], c["document"], c["where"], c["words"], verdict, reason, len(ev), independent,
                    c["tolerance"]["source"], c["tolerance"].get("reason", ""), c.get("note", "")))
    return pd.DataFrame(out, columns=["id", "document", "where", "words", "verdict", "reason", "rows", "independent",
                                      "tolerance_source", "tolerance_reason", "note"])


def headline(verdicts: pd.DataFrame, ledger: pd.DataFrame, spec: dict | None = None,
             timing: pd.DataFrame | None = None) -> dict:
    """Counts per claim: ``claims`` (of the documents, 'not run' left out), one entry per verdict of
    :data:`CLAIM_VERDICTS` (zeros included), ``extension_rows`` and ``extension_groups`` (the ledger's rows
    in extension groups, and the groups), ``timing_rows`` (timing rows no claim names) and ``ledger_rows``."""
    spec = spec or load_claims_file()
    run = verdicts[verdicts["verdict"] != "not run"]
    counts = {"claims": len(run), **{v: int((verdicts["verdict"] == v).sum()) for v in CLAIM_VERDICTS}}
    keys = {row_key(r) for r in ledger.to_dict("records")}
    groups = [g for g in spec.get("extensions", []) if keys & set(g["rows"])]
    counts["extension_rows"] = sum(len(keys & set(g["rows"])) for g in groups)
    counts["extension_groups"] = len(groups)
    named = {_entry(e)["row"] for c in spec["claims"] for e in c["evidence"]}
    counts["timing_rows"] = 0 if timing is None else sum(row_key(r) not in named for r in timing.to_dict("records"))
    counts["ledger_rows"] = len(ledger) + (0 if timing is None else len(timing))
    return counts


r"""The claims of the reproduction ledger: their schema, their constructors and the ledger's rules.

Every experiment writes ``results/<experiment>/claims.csv`` (one row per published item it
checks, columns :data:`CLAIM_COLUMNS`), each row a :class:`Claim`: built by :func:`numeric_claim`
(a tolerance on a published number) or :func:`monte_carlo_claim` (the Monte Carlo rule below).
:func:`ledger_problems` lists the rows that break the ledger's rules; files are read and written
by :mod:`.ledger_io`, typeset by :mod:`.macros` and :mod:`.renderers` (:mod:`.ledger` gathers them).

Status vocabulary
-----------------
``reproduced``         measured value within the stated tolerance of the published one (Monte Carlo:
                       the row's whole 99.73 % interval inside it, :mod:`.verdict`), and a negative
                       control (``control`` column) *fails* the same check;
``not reproduced``     outside it (Monte Carlo: the whole interval outside); the note gives the likely cause;
``inconclusive``       Monte Carlo only: the interval straddles the tolerance's edge (the note says how
                       many runs would decide);
``uninformative``      the check passed, but so did its negative control: it cannot tell the method
                       from a broken one, so it is no evidence either way;
``qualitative``        the paper states a shape or ordering, checked as such (with a failing control);
``extension``          a result beyond the papers (no published value), or a paper's claim tested
                       beyond the problem it was made on;
``illustration``       one realisation shown for a claim whose verdict is taken over many (the row
                       names the verdict row in its note); it carries no verdict of its own;
``calibration``        the check passes, but the reading it rests on (an unstated convention) was chosen
                       because it gives the published number (evidence ``calibration``): never a reproduction;
``consistency check``  the implementation agrees with the formula it implements: evidence of type
                       *identity of the implementation*, which never counts as a reproduction (the
                       reproduction, if any, is a separate row with independent evidence).

Evidence vocabulary (:data:`EVIDENCE`)
--------------------------------------
Every row names what its verdict rests on. ``identity of the implementation`` (a check that shares
the code path under test, e.g. a weight compared with the formula the engine itself used) never
counts as a reproduction on its own. ``calibration`` marks a row whose reading of the document (an
unstated convention) was chosen because it gives the published number: its agreement shows the reading
is consistent, not that an independent computation lands on the number.

The Monte Carlo rule (one rule for every Monte Carlo row)
---------------------------------------------------------
An equivalence test (:func:`hypotrack.reporting.verdict.monte_carlo_verdict`): with n runs, mean x̄
and standard error s, the interval x̄ ± q·s (q the t quantile of n − 1 d.o.f. at 99.73 %, 3 for
large n; the published number's own Monte Carlo error added when it is an estimate over a known
number of runs) must lie wholly inside published ± tolerance to *reproduce*, wholly outside to be
*not reproduced*; otherwise the row is *inconclusive*. z = (x̄ − p)/s is reported for reference.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import pandas as pd

from .verdict import monte_carlo_verdict

__all__ = [
    "CAUSES",
    "CLAIM_COLUMNS",
    "EVIDENCE",
    "KEY_PATTERN",
    "NEEDS_CONTROL",
    "OPTIONAL_COLUMNS",
    "SOFT_PROBLEMS",
    "STATUSES",
    "STATUS_MEANING",
    "VERDICT_STATUSES",
    "Claim",
    "format_value",
    "hard_problems",
    "ledger_problems",
    "measured_text",
    "monte_carlo_claim",
    "numeric_claim",
    "timing_in_text",
    "tolerance_text",
]

CLAIM_COLUMNS = ["experiment", "item", "source", "published", "reproduced", "tolerance", "status", "evidence",
                 "n", "mean", "se", "z", "note", "key", "control", "claim", "cause"]
#: Columns a claims file may lack (written before the column existed); read as empty.
OPTIONAL_COLUMNS = ("key", "control", "claim", "cause")
#: A claim key or macro name: letters, digits and underscores, starting with a letter.
KEY_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
STATUSES = ("reproduced", "not reproduced", "inconclusive", "uninformative", "qualitative", "extension", "illustration",
            "consistency check", "calibration")
EVIDENCE = ("published number", "independent oracle", "brute force", "peer implementation",
            "identity of the implementation", "measurement", "calibration")
#: One sentence per status (the README and the report define every status with these).
STATUS_MEANING = {
    "reproduced": "the measured value is within the stated tolerance of the published one (Monte Carlo: the whole "
                  "99.73 % interval is inside it) and a negative control fails the same check",
    "not reproduced": "the measured value (Monte Carlo: its whole interval) is outside the tolerance",
    "inconclusive": "the Monte Carlo interval straddles the tolerance's edge; the note says how many runs would decide",
    "uninformative": "the check passed, but so did its negative control, so it cannot tell the method from a broken one",
    "qualitative": "a shape or ordering the document states, checked as such, with a control that fails it",
    "extension": "a result beyond the documents, or a document's claim tested beyond its own problem",
    "illustration": "one realisation of a claim whose verdict is taken over many runs (no verdict of its own)",
    "consistency check": "the code agrees with the formula it implements (shares the code path: never a reproduction)",
    "calibration": "a reading of an unstated convention chosen because it gives the published number: it pins the "
                   "reading, not the method (never a reproduction)",
}
#: Why a row did not reproduce (its ``cause``; the report's Section on the gaps groups rows by it).
CAUSES = {
    "document": "the document's own claim: its formula or statement does not hold as written",
    "unstated parameter": "a parameter the document does not state decides the number (the sensitivity table "
                          "shows the plausible readings)",
    "project choice": "this project's choice or reconstruction, not the document's method",
    "too few runs": "the Monte Carlo interval is too wide to decide",
    "no power": "the check also passes a control built to fail it",
    "untestable": "the document's problems hold too few cases that decide the claim",
}
VERDICT_STATUSES = ("reproduced", "not reproduced", "inconclusive", "uninformative", "qualitative")
NEEDS_CONTROL = ("reproduced", "qualitative")  # statuses that claim power: a control must fail them


@dataclass(frozen=True)
class Claim:
    """One published item and what the pipeline measured for it."""

    experiment: str
    item: str
    source: str
    published: str
    reproduced: str
    tolerance: str
    status: str
    note: str = ""
    evidence: str = ""
    n: str = ""
    mean: str = ""
    se: str = ""
    z: str = ""
    key: str = ""
    control: str = ""  # what ran as a negative control, its value, and whether it fails (verdict.control_text)
    claim: str = ""  # the published claim this row decides, shared by rows measuring one claim in two ways
    cause: str = ""  # why a row did not reproduce: a key of CAUSES (inconclusive: "too few runs" by default)

    def __post_init__(self):
        if self.key and not KEY_PATTERN.fullmatch(self.key):
            raise ValueError(f"key must be letters, digits and underscores (starting with a letter), got {self.key!r}")
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}, got {self.status!r}")
        if self.evidence and self.evidence not in EVIDENCE:
            raise ValueError(f"evidence must be one of {EVIDENCE}, got {self.evidence!r}")
        if self.cause and self.cause not in CAUSES:
            raise ValueError(f"cause must be one of {tuple(CAUSES)}, got {self.cause!r}")
        if self.control:
            from .verdict import parse_control

            parse_control(self.control)


def format_value(value, digits: int) -> str:
    """A value as a ledger cell: text as is, ``--`` for none/NaN, integers without a decimal point,
    other numbers to ``digits`` significant digits."""
    if isinstance(value, str):
        return value
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "--"
    if isinstance(value, int) or float(value).is_integer() and abs(value) < 1e15:
        return f"{int(value):d}"
    return f"{value:.{digits}g}"


def _calibrated(status: str, evidence: str) -> str:
    """A passing check on a calibrated reading is a *calibration*, never a reproduction."""
    return "calibration" if evidence == "calibration" and status == "reproduced" else status


def numeric_claim(experiment, item, source, published, reproduced, *, rel_tol=None, abs_tol=None,
                  digits=4, note="", evidence="published number", key="") -> Claim:
    """A claim decided by a relative or absolute tolerance on a published number.

    ``key`` names the claim's macros stably (module docstring)."""
    if (rel_tol is None) == (abs_tol is None):
        raise ValueError("give exactly one of rel_tol, abs_tol")
    if rel_tol is not None:
        ok = abs(reproduced - published) <= rel_tol * abs(published)
        tol = f"{100 * rel_tol:g} %"
    else:
        ok = abs(reproduced - published) <= abs_tol
        tol = f"+/- {abs_tol:g}"
    if not math.isfinite(reproduced):
        ok = False
    return Claim(experiment, item, source, format_value(published, digits), format_value(reproduced, digits), tol,
                 _calibrated("reproduced" if ok else "not reproduced", evidence), note, evidence, key=key)


def monte_carlo_claim(experiment, item, source, published, samples=None, *, n=None, mean=None, se=None,
                      rel_tol=None, abs_tol=None, digits=4, note="", evidence="published number",
                      key="", published_runs=None, claim="") -> Claim:
    """A Monte Carlo claim decided by :func:`monte_carlo_verdict`.

    Give either ``samples`` (one value per run; s.e. = sample sd / √n) or ``n``, ``mean`` and ``se``,
    and exactly one of ``rel_tol`` (relative to the published value) or ``abs_tol`` as the stated
    reconstruction tolerance; ``published_runs`` when the published number is itself a Monte Carlo
    estimate over that many runs (its standard error enters the interval).

    ``published=None``: a Monte Carlo measurement the documents give no number for (status
    ``extension``, evidence ``measurement``): n, mean and s.e. are reported, z is empty and no
    tolerance is taken.
    """
    import numpy as np

    if samples is not None:
        if n is not None or mean is not None or se is not None:
            raise ValueError("give either samples or (n, mean, se), not both")
        x = np.asarray(samples, dtype=float).ravel()
        if x.size < 2 or not np.isfinite(x).all():
            raise ValueError(f"samples must hold at least 2 finite values, got {x.size}")
        n, mean, se = int(x.size), float(x.mean()), float(x.std(ddof=1) / math.sqrt(x.size))
    elif n is None or mean is None or se is None:
        raise ValueError("give samples, or all of n, mean and se")
    if int(n) < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    if published is None:
        if rel_tol is not None or abs_tol is not None:
            raise ValueError("a claim without a published value takes no tolerance")
        return Claim(experiment, item, source, "--", format_value(float(mean), digits), "--", "extension", note,
                     "measurement" if evidence == "published number" else evidence, str(int(n)),
                     f"{float(mean):.6g}", f"{float(se):.3g}", "", key, claim=claim)
    if (rel_tol is None) == (abs_tol is None):
        raise ValueError("give exactly one of rel_tol, abs_tol")
    tol = rel_tol * abs(published) if rel_tol is not None else abs_tol
    v = monte_carlo_verdict(float(mean), float(se), float(published), tol, int(n), published_runs)
    tol_text = tolerance_text(rel_tol, abs_tol, published_runs)
    if v.status == "inconclusive":
        decide = ("no number of runs decides it (the published number's own error is too large)"
                  if v.runs_to_decide is None or math.isinf(v.runs_to_decide) else
                  f"about {int(v.runs_to_decide):,} runs would decide it")  # at least 2 (verdict.py)
        note = f"{note}; interval {v.low:.4g} to {v.high:.4g}: {decide}" if note else \
            f"interval {v.low:.4g} to {v.high:.4g}: {decide}"
    return Claim(experiment, item, source, format_value(float(published), digits), format_value(float(mean), digits), tol_text,
                 _calibrated(v.status, evidence), note, evidence, str(int(n)), f"{float(mean):.6g}", f"{float(se):.3g}",
                 _z_text(v.z), key, claim=claim)


def _z_text(z: float) -> str:
    """z as the ledger prints it: two decimals, three significant digits from 10⁶ on (a mean whose seeds agree to
    rounding has an s.e. of ~1e-15 and a z of ~1e13, whose 17 digits said nothing and overflowed the report's
    table), ``inf``/``-inf`` for a zero s.e."""
    if not math.isfinite(z):
        return "inf" if z > 0 else "-inf"
    return f"{z:.2f}" if abs(z) < 1e6 else f"{z:.3g}"


def tolerance_text(rel_tol=None, abs_tol=None, published_runs=None) -> str:
    """The tolerance cell of a Monte Carlo row (parsed back by :func:`ledger_problems`)."""
    text = "99.73 % interval within " + (f"{100 * rel_tol:g} %" if rel_tol is not None else f"+/- {abs_tol:g}")
    return text + (f"; published over {int(published_runs)} runs" if published_runs else "")


_TOL_TEXT = re.compile(r"99\.73 % interval within (?:(?P<rel>[\d.eE+-]+) %|\+/- (?P<abs>[\d.eE+-]+))"
                       r"(?:; published over (?P<runs>\d+) runs)?")


#: Problems reported but not refused (the report's gaps section lists such rows as "not yet diagnosed"): a
#: failing row whose cause is still open. A reproduced or qualitative row without a failing negative control
#: is refused: it would claim power it has not shown.
SOFT_PROBLEMS = ("names no cause yet",)


def hard_problems(problems: list[str]) -> list[str]:
    """The problems of :func:`ledger_problems` that fail a run (all but :data:`SOFT_PROBLEMS`)."""
    return [p for p in problems if not p.endswith(SOFT_PROBLEMS)]


def ledger_problems(claims: pd.DataFrame) -> list[str]:
    """Rows that break the ledger's rules, each as a sentence naming the row.

    * every row names its evidence (one of :data:`EVIDENCE`);
    * a row with ``n`` gives ``mean`` and ``se``; with a numeric published value also ``z``, and its
      status is the one :func:`~hypotrack.reporting.verdict.monte_carlo_verdict` gives from n, mean,
      se and the tolerance stated in the row (recomputed here, so a hand-edited verdict is caught);
      a control that also passes demotes it to *uninformative*;
    * every *reproduced* or *qualitative* row names a negative control that *fails* its check; a row
      whose control also passes is *uninformative*;
    * a row whose evidence is an identity of the implementation is never *reproduced* (its status is
      *consistency check*: it shares the code path under test);
    * rows sharing a ``claim`` give it at most one verdict (the others are illustrations or extensions).
    """
    from .verdict import parse_control

    problems = []
    for r in claims.to_dict("records"):
        name = f"{r['experiment']}: {r['item']!r}"
        if r.get("evidence", "") not in EVIDENCE:
            problems.append(f"{name} names no evidence")
        if r.get("evidence") == "calibration" and r["status"] == "reproduced":
            problems.append(f"{name} is 'reproduced' on a calibration (status must be 'calibration')")
        if r.get("evidence") == "identity of the implementation" and r["status"] == "reproduced":
            problems.append(f"{name} is 'reproduced' on an identity of the implementation only "
                            "(status must be 'consistency check')")
        try:
            control = parse_control(r.get("control", ""))
        except ValueError as exc:
            problems.append(f"{name}: {exc}")
            control = None
        if r["status"] in NEEDS_CONTROL and control is not None and control[2]:
            problems.append(f"{name} is {r['status']!r} but its control also passes (status must be 'uninformative')")
        if r["status"] in NEEDS_CONTROL and control is None:
            problems.append(f"{name} is {r['status']!r} but names no negative control (a check a broken method "
                            "must fail)")
        if r.get("cause", "") and r["cause"] not in CAUSES:
            problems.append(f"{name}: cause must be one of {tuple(CAUSES)}, got {r['cause']!r}")
        if r["status"] == "not reproduced" and not r.get("cause", ""):
            problems.append(f"{name} is 'not reproduced' and names no cause yet")
        if r["status"] == "uninformative" and (control is None or not control[2]):
            problems.append(f"{name} is 'uninformative' but names no control that also passes")
        if not r.get("n", ""):
            continue
        if not (r.get("mean", "") and r.get("se", "")):
            problems.append(f"{name} has n but no mean or standard error")
            continue
        try:
            published = float(r["published"])
        except ValueError:
            continue
        m = _TOL_TEXT.fullmatch(r["tolerance"])
        if not r.get("z", "") or not m:
            problems.append(f"{name}: a Monte Carlo row against a published value needs z and a tolerance "
                            f"'99.73 % interval within <tol>', got z={r.get('z', '')!r}, tolerance={r['tolerance']!r}")
            continue
        tol = float(m["rel"]) / 100 * abs(published) if m["rel"] else float(m["abs"])
        status = monte_carlo_verdict(float(r["mean"]), float(r["se"]), published, tol, int(r["n"]),
                                     int(m["runs"]) if m["runs"] else None).status
        status = _calibrated(status, r.get("evidence", ""))
        if status in NEEDS_CONTROL and control is not None and control[2]:
            status = "uninformative"
        if status != r["status"]:
            problems.append(f"{name}: status {r['status']!r} but the Monte Carlo rule gives {status!r}")
    if "claim" in claims.columns:
        decided = claims[(claims["claim"] != "") & claims["status"].isin(VERDICT_STATUSES)]
        for claim_id, rows in decided.groupby("claim"):
            if len(rows) > 1:
                problems.append(f"claim {claim_id!r} has {len(rows)} rows with a verdict "
                                f"({', '.join(rows['status'])}): one decides it, the others are illustrations")
    return problems


_TIME_TEXT = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:e[+-]?\d+)?\s*(?:ms|µs|us|s|sec|seconds|CPU-s|"
                        r"CPU-minutes|minutes)(?![\w.])|\bper second\b|\d\s*/s\b")


def timing_in_text(claims: pd.DataFrame) -> list[str]:
    """Rows of a non-timing ledger whose text quotes a measured run time (``9 ms per scan``, ``0.36 s``).

    A run time changes with the machine's load, so a ledger row quoting one would make two runs of
    one config and seed differ; timings belong in the ``*timing*`` claims files (``ledger_timing.csv``).
    """
    out = []
    for r in claims.to_dict("records"):
        for col in ("item", "published", "reproduced", "tolerance", "note"):
            hit = _TIME_TEXT.search(str(r.get(col, "")))
            if hit:
                out.append(f"{r['experiment']}: '{r['item']}' quotes a run time in its {col} ({hit.group(0)!r}); "
                           "move it to a *timing* claims file")
                break
    return out


def measured_text(r) -> str:
    """The measured value of a claims row (a mapping); a Monte Carlo row gives mean ± s.e., n and z."""
    if r.get("n", ""):
        z = f", z = {r['z']}" if r.get("z", "") else ""
        return f"{r['mean']} ± {r['se']} (n = {r['n']}{z})"
    return r["reproduced"]

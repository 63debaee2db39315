r"""The reproduction ledger: claims of the papers, their measured values, and their LaTeX form.

Every experiment writes ``results/<experiment>/claims.csv`` (one row per published item it
checks, see :data:`CLAIM_COLUMNS`); the paper and the README's status table are built from the
union of those files, so no number in the paper is typed by hand.

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

Stable macro keys (how the paper quotes a number)
-------------------------------------------------
Macro names never embed a configuration value (an item "M = m = 100" or a seed would change name
with the config and leave the paper with an undefined macro). Two mechanisms give stable names:

* a claim's optional ``key`` (letters, digits, underscore; unique within its experiment): its
  macros are ``\ht<Experiment><Key>`` + ``Pub``, ``Rep``, ``Status``, ``Evidence`` and, for Monte
  Carlo rows, ``N``, ``Mean``, ``Se``, ``Z`` (see :func:`claim_macros`). A claim without a key gets
  names derived from its item text (kept for old rows; the paper must quote only keyed claims);
* numbers the paper quotes that are not ledger rows: an experiment writes
  ``results/<experiment>/macros.csv`` with :func:`write_macros` (columns ``experiment,name,value``;
  ``name`` as a key), declares it as a rule output in ``ALL_TARGETS``, and the paper rule collects
  every ``macros.csv`` into ``\ht<Experiment><Name>`` (see :func:`read_macros`).

Digits in a key become letters in the command name (LaTeX names are letters only: 0->A ... 9->J).
Values such as ``3e-14`` are typeset as :math:`3\times10^{-14}` (:func:`latex_value`).

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
from dataclasses import asdict, dataclass
from pathlib import Path

import pandas as pd

from .verdict import monte_carlo_verdict
from .latex_text import latex_escape, latex_text

__all__ = [
    "CAUSES",
    "CLAIM_COLUMNS",
    "EVIDENCE",
    "MACRO_COLUMNS",
    "OPTIONAL_COLUMNS",
    "STATUSES",
    "STATUS_MEANING",
    "NEEDS_CONTROL",
    "VERDICT_STATUSES",
    "Claim",
    "tolerance_text",
    "LiteralText",
    "build_paper_inputs",
    "claim_macros",
    "claims_markdown",
    "claims_table_tex",
    "claims_html",
    "STATUS_COLOURS",
    "config_macros",
    "is_timing_table",
    "latex_escape",
    "ledger_problems",
    "hard_problems",
    "SOFT_PROBLEMS",
    "latex_value",
    "macro_name",
    "macros_tex",
    "monte_carlo_claim",
    "monte_carlo_verdict",
    "numeric_claim",
    "read_claims",
    "read_macros",
    "write_claims",
    "write_macros",
]

CLAIM_COLUMNS = ["experiment", "item", "source", "published", "reproduced", "tolerance", "status", "evidence",
                 "n", "mean", "se", "z", "note", "key", "control", "claim", "cause"]
#: Columns a claims file may lack (written before the column existed); read as empty.
OPTIONAL_COLUMNS = ("key", "control", "claim", "cause")
MACRO_COLUMNS = ["experiment", "name", "value"]
_KEY = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
STATUSES = ("reproduced", "not reproduced", "inconclusive", "uninformative", "qualitative", "extension", "illustration",
            "consistency check")
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
        if self.key and not _KEY.fullmatch(self.key):
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


def _fmt(value, digits: int) -> str:
    if isinstance(value, str):
        return value
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "--"
    if isinstance(value, int) or float(value).is_integer() and abs(value) < 1e15:
        return f"{int(value):d}"
    return f"{value:.{digits}g}"


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
    return Claim(experiment, item, source, _fmt(published, digits), _fmt(reproduced, digits), tol,
                 "reproduced" if ok else "not reproduced", note, evidence, key=key)


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
        return Claim(experiment, item, source, "--", _fmt(float(mean), digits), "--", "extension", note,
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
                  f"about {int(v.runs_to_decide):,} runs would decide it")
        note = f"{note}; interval {v.low:.4g} to {v.high:.4g}: {decide}" if note else \
            f"interval {v.low:.4g} to {v.high:.4g}: {decide}"
    return Claim(experiment, item, source, _fmt(float(published), digits), _fmt(float(mean), digits), tol_text,
                 v.status, note, evidence, str(int(n)), f"{float(mean):.6g}", f"{float(se):.3g}",
                 f"{v.z:.2f}" if math.isfinite(v.z) else ("inf" if v.z > 0 else "-inf"), key, claim=claim)


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


def write_claims(claims, path) -> pd.DataFrame:
    """Write claims as CSV with :data:`CLAIM_COLUMNS`; returns the table."""
    df = pd.DataFrame([asdict(c) for c in claims], columns=CLAIM_COLUMNS)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def is_timing_table(path) -> bool:
    """Timing tables (and timing claims) are named so (``*timing*``): their values are measured run
    times, not byte-reproducible; the paper rule writes their rows to ``ledger_timing.csv``."""
    return "timing" in Path(path).name


def read_claims(paths) -> pd.DataFrame:
    """Concatenate claims files (missing columns are an error naming the file)."""
    frames = []
    for p in sorted(map(Path, paths)):
        df = pd.read_csv(p, dtype=str, keep_default_na=False)
        for col in OPTIONAL_COLUMNS:
            if col not in df.columns:
                df[col] = ""
        missing = set(CLAIM_COLUMNS) - set(df.columns)
        if missing:
            raise ValueError(f"{p}: claims file lacks columns {sorted(missing)}")
        bad = set(df["status"]) - set(STATUSES)
        if bad:
            raise ValueError(f"{p}: status must be one of {STATUSES}, got {sorted(bad)}")
        bad = set(df["evidence"]) - set(EVIDENCE) - {""}
        if bad:
            raise ValueError(f"{p}: evidence must be one of {EVIDENCE}, got {sorted(bad)}")
        frames.append(df[CLAIM_COLUMNS])
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=CLAIM_COLUMNS)


def macro_name(*parts) -> str:
    """A LaTeX command name from words: letters only, camel-cased (``ht`` prefix)."""
    words = re.split(r"[^A-Za-z0-9]+", " ".join(map(str, parts)))
    digits = str.maketrans("0123456789", "ABCDEFGHIJ")  # command names may not contain digits
    return "ht" + "".join(w[:1].upper() + w[1:] for w in words if w).translate(digits)


_SCI = re.compile(r"([+-]?\d+(?:\.\d+)?)e([+-]?)0*(\d+)")


class LiteralText(str):
    """A macro value that is an identifier, not a number (a commit hash such as ``95e7490``):
    :func:`latex_value` escapes it and never typesets it as a power of ten or groups its digits."""


def latex_value(value) -> str:
    """A generated value in LaTeX: ``3e-14`` -> ``\\ensuremath{3\\times10^{-14}}``, else escaped text.

    Only a value that is entirely one number in e-notation is typeset as a power of ten; a
    mantissa of 1 is dropped (``1e8`` -> ``10^{8}``). A :class:`LiteralText` is always text.
    """
    if isinstance(value, LiteralText):
        return latex_escape(value)
    text = str(value).strip()
    if re.fullmatch(r"-?\d{5,}", text):  # 100000 -> 100{,}000
        return re.sub(r"(?<=\d)(?=(\d{3})+$)", "{,}", text)
    m = _SCI.fullmatch(text)
    if not m:
        return latex_text(text)
    mant, sign, exp = m.groups()
    power = f"10^{{{'-' if sign == '-' else ''}{exp}}}"
    return rf"\ensuremath{{{power}}}" if mant in ("1", "+1", "1.0") else rf"\ensuremath{{{mant}\times{power}}}"


def macros_tex(values: dict) -> str:
    """``\\newcommand`` lines for a mapping of macro name -> value (plain text, see :func:`latex_value`)."""
    lines = ["% Generated by the pipeline (hypotrack.reporting.ledger); do not edit."]
    for name in sorted(values):
        if not re.fullmatch(r"[A-Za-z]+", name):
            raise ValueError(f"macro name must be letters only, got {name!r}")
        lines.append(f"\\newcommand{{\\{name}}}{{{latex_value(values[name])}}}")
    return "\n".join(lines) + "\n"


def write_macros(experiment: str, values: dict, path) -> pd.DataFrame:
    """Write an experiment's non-claim numbers as ``macros.csv`` (``experiment,name,value``).

    ``values`` maps a stable name (letters, digits, underscore; never a config value) to a value;
    floats are written with 4 significant digits unless already formatted as text.
    """
    rows = []
    for name, value in values.items():
        if not _KEY.fullmatch(str(name)):
            raise ValueError(f"macro name must be letters, digits and underscores, got {name!r}")
        if isinstance(value, float):
            value = _fmt(value, 4)
        rows.append((experiment, name, str(value)))
    df = pd.DataFrame(rows, columns=MACRO_COLUMNS)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def read_macros(paths) -> dict:
    """Macros ``\\ht<Experiment><Name>`` from ``macros.csv`` files; a name defined twice is an error."""
    values = {}
    for p in sorted(map(Path, paths)):
        df = pd.read_csv(p, dtype=str, keep_default_na=False)
        if list(df.columns) != MACRO_COLUMNS:
            raise ValueError(f"{p}: macros file must have columns {MACRO_COLUMNS}, got {list(df.columns)}")
        for r in df.to_dict("records"):
            if not _KEY.fullmatch(r["name"]):
                raise ValueError(f"{p}: macro name must be letters, digits and underscores, got {r['name']!r}")
            name = macro_name(r["experiment"], r["name"])
            if name in values:
                raise ValueError(f"{p}: macro {name} defined twice")
            values[name] = r["value"]
    return values


def config_macros(config: dict) -> dict:
    """``\\htCfg<Section><Key>...`` for every scalar of the run's config (lists are skipped).

    The paper quotes a setting (runs, steps, sensors) through these, so a changed config changes
    the text with it; the names are the config's keys, never its values.
    """
    values = {}

    def walk(node, path):
        for k, v in node.items():
            if isinstance(v, dict):
                walk(v, (*path, str(k)))
            elif isinstance(v, bool) or v is None or isinstance(v, (list, tuple)):
                continue
            else:
                name = macro_name("cfg", *path, k)
                if name in values:
                    raise ValueError(f"config keys {'.'.join((*path, str(k)))!r} and another both give {name}")
                values[name] = _fmt(v, 6) if isinstance(v, (int, float)) else str(v)

    walk({k: v for k, v in config.items() if k != "results"}, ())  # a path, not a setting
    return values


def _measured_text(r) -> str:
    """The measured value; a Monte Carlo row gives mean ± s.e., n and z."""
    if r.get("n", ""):
        z = f", z = {r['z']}" if r.get("z", "") else ""
        return f"{r['mean']} ± {r['se']} (n = {r['n']}{z})"
    return r["reproduced"]


def _cell_tex(text) -> str:
    """A table cell: escaped with its mathematics typeset (:func:`.latex_text.latex_text`), and long tokens
    given break points after ``_``, ``)``, ``:`` and at camel-case joins (so no cell overflows its column;
    the table forbids hyphenation)."""
    out = []
    for token in latex_text(text).split(" "):
        if len(token) > 12:
            token = re.sub(r"(?<=[a-z])(?=[A-Z0-9])|(?<=\\_)|(?<=[):;/])|(?=[(])", r"\\allowbreak{}", token)
        out.append(token)
    return " ".join(out)


# one colour per status, shared by the LaTeX ledger and the HTML ledger of the Snakemake report
STATUS_COLOURS = {"reproduced": ("ForestGreen", "#e6f4ea"), "not reproduced": ("BrickRed", "#fce8e6"),
                  "inconclusive": ("Gray", "#eeeeee"), "uninformative": ("BurntOrange", "#fdebd0"),
                  "qualitative": ("NavyBlue", "#e8eefa"), "extension": ("Gray", "#ffffff"),
                  "illustration": ("Gray", "#ffffff"), "consistency check": ("Gray", "#f4f4f4")}


def claims_html(claims: pd.DataFrame) -> str:
    """The ledger as one HTML page (for ``snakemake --report``): a table per experiment, rows coloured by
    status, the status counts on top."""
    import html

    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>hypotrack ledger</title><style>"
             "body{font-family:sans-serif;font-size:13px} table{border-collapse:collapse;margin-bottom:1.5em}"
             "td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top;text-align:left}</style></head><body>",
             f"<h2>Reproduction ledger: {len(claims)} claims</h2>"]
    counts = claims["status"].value_counts()
    parts.append("<p>" + ", ".join(f"{html.escape(s)}: {int(counts[s])}" for s in STATUSES if s in counts) + "</p>")
    for experiment, rows in claims.groupby("experiment", sort=False):
        styled = rows.drop(columns="experiment").style.hide(axis="index").apply(
            lambda r: [f"background-color:{STATUS_COLOURS[r['status']][1]}"] * len(r), axis=1)
        parts += [f"<h3>{html.escape(experiment)}</h3>", styled.to_html(escape="html")]
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


LEDGER_CAPTION = (r"The reproduction ledger: one row per claim, grouped by the experiment whose \texttt{claims.csv} "
                  r"wrote it. \emph{published} is the document's value, \emph{reproduced} this run's (Monte Carlo "
                  r"rows: mean $\pm$ standard error, $n$ runs and $z$); each row's note and negative control follow "
                  r"it. The statuses are defined in Section~\ref{sec:ledger}.")


def claims_table_tex(claims: pd.DataFrame) -> str:
    """A longtable of the claims grouped by experiment; each note on its own line below its item.

    Columns are set ragged right (no hyphenated verdicts); Monte Carlo rows show mean ± s.e., n and z.
    """
    colour = {status: latex for status, (latex, _html) in STATUS_COLOURS.items()}
    widths = {"item": 0.22, "source": 0.09, "published": 0.09, "reproduced": 0.15, "tolerance": 0.10,
              "evidence": 0.12, "status": 0.12}
    spec = "".join(rf">{{\raggedright\arraybackslash}}p{{{w}\linewidth}}" for w in widths.values())
    ncol = len(widths)
    header = r"\toprule " + " & ".join(widths) + r"\tabularnewline\midrule"
    out = [r"\begingroup\setlength{\tabcolsep}{3pt}\footnotesize\hyphenpenalty=10000\exhyphenpenalty=10000",
           rf"\begin{{longtable}}{{@{{}}{spec}@{{}}}}",
           rf"\caption{{{LEDGER_CAPTION}}}\label{{tab:ledger}}\tabularnewline",
           header + r"\endfirsthead",
           rf"\multicolumn{{{ncol}}}{{@{{}}l}}{{\emph{{Table~\thetable, continued}}}}\tabularnewline" + header + r"\endhead",
           r"\bottomrule\endfoot"]
    for experiment, group in claims.groupby("experiment", sort=False):
        out.append(rf"\multicolumn{{{ncol}}}{{@{{}}l}}{{\textbf{{\texttt{{{latex_escape(experiment)}}}}}}}\tabularnewline")
        for r in group.to_dict("records"):
            status = rf"\textcolor{{{colour[r['status']]}}}{{\textbf{{{r['status']}}}}}"
            cells = [_cell_tex(r["item"]), _cell_tex(r["source"]), _cell_tex(r["published"]),
                     _cell_tex(_measured_text(r)), _cell_tex(r["tolerance"]), _cell_tex(r.get("evidence", "") or "--"),
                     status]
            out.append(" & ".join(cells) + r"\tabularnewline")
            if r["note"]:
                out.append(rf"\multicolumn{{{ncol}}}{{@{{}}p{{0.97\linewidth}}@{{}}}}{{\hspace{{1em}}\emph{{{latex_text(r['note'])}}}}}"
                           r"\tabularnewline[2pt]")
            if r.get("control", ""):
                out.append(rf"\multicolumn{{{ncol}}}{{@{{}}p{{0.97\linewidth}}@{{}}}}{{\hspace{{1em}}control: "
                           rf"{latex_text(r['control'])}}}\tabularnewline[2pt]")
    out.append(r"\end{longtable}\endgroup")
    return "\n".join(out) + "\n"


def claim_macros(claims: pd.DataFrame) -> dict:
    """Macros for the paper: the values of every claim, and the status counts.

    A claim gives ``\\ht<Experiment><Key>`` + ``Pub``, ``Rep``, ``Status``, ``Evidence`` and, when it
    has ``n``, ``N``, ``Mean``, ``Se``, ``Z``; without a key, ``<Item>`` stands for ``<Key>``. Two
    claims with the same name are an error naming both. Counts: ``\\htClaimsTotal``,
    ``\\htClaims<Status>`` for every status.
    """
    values, owner = {}, {}
    for r in claims.to_dict("records"):
        base = macro_name(r["experiment"], r.get("key") or r["item"])
        if base in owner:
            raise ValueError(f"claims {owner[base]!r} and {r['item']!r} of {r['experiment']} both give macro "
                             f"{base}; give them distinct keys")
        owner[base] = r["item"]
        values[base + "Pub"] = r["published"]
        values[base + "Rep"] = r["reproduced"]
        values[base + "Status"] = r["status"]
        values[base + "Evidence"] = r.get("evidence", "")
        if r.get("n", ""):
            for col in ("n", "mean", "se", "z"):
                values[base + col.capitalize()] = r[col]
    counts = claims["status"].value_counts()
    values["htClaimsTotal"] = str(len(claims))
    for status in STATUSES:
        values[macro_name("claims", status)] = str(int(counts.get(status, 0)))
    return values


def build_paper_inputs(claims_paths, figure_paths, out_dir, results_dir, extra_macros=None,
                       macros_paths=()) -> pd.DataFrame:
    """Write ``macros.tex``, ``claims_table.tex`` and copies of the figures under ``out_dir``
    (the generated sections come from :mod:`.sections`).

    Macros come from the claims (:func:`claim_macros`), the experiments' ``macros.csv`` files
    (``macros_paths``, :func:`read_macros`) and ``extra_macros``; a name from two sources is an error.

    Figures keep their path relative to ``results_dir`` (``figures/<experiment>/<name>.pdf``) so
    the paper refers to them by experiment. Returns the union of the claims.
    """
    import shutil

    out_dir = Path(out_dir)
    (out_dir / "figures").mkdir(parents=True, exist_ok=True)
    claims = read_claims(claims_paths)
    values = claim_macros(claims)
    for more in (read_macros(macros_paths), extra_macros or {}):
        clash = sorted(set(values) & set(more))
        if clash:
            raise ValueError(f"macros defined twice: {clash}")
        values.update(more)
    (out_dir / "macros.tex").write_text(macros_tex(values))
    (out_dir / "claims_table.tex").write_text(claims_table_tex(claims))
    for fig in map(Path, figure_paths):
        dest = out_dir / "figures" / fig.resolve().relative_to(Path(results_dir).resolve())
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(fig, dest)
    return claims


def claims_markdown(claims: pd.DataFrame) -> str:
    """The ledger as a Markdown table (for the README), one row per claim."""
    rows = ["| experiment | item | source | published | reproduced | tolerance | evidence | control | status |",
            "|---|---|---|---|---|---|---|---|---|"]
    for r in claims.to_dict("records"):
        cells = [r["experiment"], r["item"], r["source"], r["published"], _measured_text(r), r["tolerance"],
                 r.get("evidence", "") or "—", r.get("control", "") or "—", f"**{r['status']}**"]
        rows.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in cells) + " |")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":  # python -m hypotrack.reporting.ledger <claims.csv ...>  -> the ledger as Markdown
    import sys

    if sys.argv[1:2] == ["check"]:  # python -m hypotrack.reporting.ledger check <ledger.csv>: the ledger's rules
        found = ledger_problems(read_claims(sys.argv[2:]))
        print("\n".join(found) or "ledger: every row follows the rules")
        raise SystemExit(1 if found else 0)
    print(claims_markdown(read_claims(sys.argv[1:])), end="")

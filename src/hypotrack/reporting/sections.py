r"""Report text generated from the ledger: the status counts with every status defined, and the
section on what did not reproduce, one paragraph per row (so no failing row goes undiscussed).

:func:`status_summary_tex` writes ``generated/status_summary.tex`` (the counts add up to the
ledger's rows; every status is defined by :data:`~.claims.STATUS_MEANING`); :func:`gaps_tex` writes
``generated/gaps_rows.tex``: for every row that is *not reproduced*, *inconclusive* or
*uninformative*, its measured value against the published one, the tolerance, the evidence, the
control and the experiment's note on the cause, in the ledger's appendix. The report's hand-written
discussion (``paper/sections/discussion.tex``) takes the causes one by one and quotes their row counts
(:func:`.findings.cause_count_macros`).
"""

from __future__ import annotations

import re

import pandas as pd

from .latex_text import latex_escape, latex_text
from .claims import CAUSES, STATUS_MEANING, STATUSES, measured_text

__all__ = ["FAILING", "gap_cause", "gap_label", "gaps_tex", "monte_carlo_rule_tex", "status_summary_tex"]

FAILING = ("not reproduced", "inconclusive", "uninformative")


def status_summary_tex(claims: pd.DataFrame) -> str:
    """One sentence of counts (every status, zeros included, summing to the row count) and a
    description list defining each status."""
    counts = claims["status"].value_counts()
    parts = [rf"\textbf{{{int(counts.get(s, 0))} {latex_escape(s)}}}" for s in STATUSES]
    lines = [rf"Of the ledger's {len(claims)} rows, " + ", ".join(parts[:-1]) + f" and {parts[-1]}" + ". These "
             r"count rows (checks), not claims: several rows often test one claim, and Table~\ref{tab:claims} "
             r"counts the documents' claims, one verdict each.",
             r"\begin{description}\setlength{\itemsep}{0pt}"]
    lines += [rf"\item[{latex_escape(s)}] {latex_text(STATUS_MEANING[s])}." for s in STATUSES]
    lines.append(r"\end{description}")
    lines.append(monte_carlo_rule_tex())
    return "\n".join(lines) + "\n"


def monte_carlo_rule_tex() -> str:
    """The Monte Carlo rule as a paragraph, its numbers from :mod:`.verdict` (none typed in the report)."""
    from .verdict import COVERAGE, interval_quantile

    return (r"\paragraph{The Monte Carlo rule.} One rule decides every Monte Carlo row, an equivalence test. With $n$ "
            r"runs, sample mean $\bar x$ and standard error $s=\mathrm{sd}/\sqrt n$, the row's interval is "
            rf"$\bar x\pm q\,s$, with $q$ the Student-$t$ quantile of $n-1$ degrees of freedom at "
            rf"{100 * COVERAGE:.2f}\,\% ($q={interval_quantile(None):g}$ for many runs, {interval_quantile(10):.2f} "
            r"for ten); when the published value $p$ is itself a Monte Carlo estimate over a known number of runs, "
            r"its standard error (this project's spread over that number) is added in quadrature. The row is "
            r"\emph{reproduced} when the whole interval lies inside $p\pm\tau$, $\tau$ the tolerance stated in its "
            r"row; \emph{not reproduced} when it lies wholly outside; \emph{inconclusive} otherwise, and its note "
            r"gives the number of runs that would decide it. A wide interval therefore never reproduces; "
            r"$z=(\bar x-p)/s$ is given for reference.")


def gap_cause(row) -> str:
    """The row's cause key (:data:`~.claims.CAUSES`); inconclusive rows default to too few runs,
    uninformative ones to no power, an undiagnosed failure to ``""``."""
    cause = row.get("cause", "") or ""
    if cause:
        return cause
    return {"inconclusive": "too few runs", "uninformative": "no power"}.get(row["status"], "")


def gap_label(row) -> str:
    """The LaTeX label of a failing row's paragraph: ``gap:<experiment>:<key or item>``."""
    return "gap:" + re.sub(r"[^A-Za-z0-9_:-]+", "-", f"{row['experiment']}:{row.get('key', '') or row['item']}")


def _gap_row_tex(r) -> str:
    control = f" Control: {latex_text(r['control'])}." if r.get("control", "") else ""
    note = r.get("note", "")
    note = f" {latex_text(note[:1].upper() + note[1:])}." if note else ""
    return (rf"\textbf{{{latex_text(r['item'])}}}\label{{{gap_label(r)}}} ({latex_escape(r['experiment'])}; "
            rf"{latex_text(r['source'])}): \emph{{{latex_escape(r['status'])}}}, published {latex_text(r['published'])}, "
            rf"measured {latex_text(measured_text(r))}, tolerance {latex_text(r['tolerance'])}; evidence: "
            rf"{latex_text(r.get('evidence', '') or '--')}." + note + control)


def gaps_tex(claims: pd.DataFrame) -> str:
    """Every failing row (:data:`FAILING`), grouped by its cause (:data:`~.claims.CAUSES`), one paragraph
    per claim: rows sharing a ``claim`` id are discussed together. Each paragraph carries a
    ``\\label`` per row (:func:`gap_label`), so a test can check that none is missing."""
    bad = claims[claims["status"].isin(FAILING)]
    if bad.empty:
        return "Every row with a published value reproduced, with a control that fails its check.\n"
    rows = bad.to_dict("records")
    order = list(CAUSES) + [""]
    out = []
    for cause in order:
        group = [r for r in rows if gap_cause(r) == cause]
        if not group:
            continue
        title = CAUSES[cause] if cause else "not yet diagnosed: the cause is still open"
        out.append(rf"\subsubsection*{{{latex_text(title[:1].upper() + title[1:])} ({len(group)} "
                   rf"row{'s' if len(group) > 1 else ''})}}")
        seen = {}
        for r in group:
            seen.setdefault(r.get("claim", "") or id(r), []).append(r)
        for members in seen.values():
            out.append(r"\paragraph{}" + " ".join(_gap_row_tex(r) for r in members))
    return "\n\n".join(out) + "\n"

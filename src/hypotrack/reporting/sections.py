r"""Report text generated from the ledger: the status counts with every status defined, and the
section on what did not reproduce, one paragraph per row (so no failing row goes undiscussed).

:func:`status_summary_tex` writes ``generated/status_summary.tex`` (the counts add up to the
ledger's rows; every status is defined by :data:`~.ledger.STATUS_MEANING`); :func:`gaps_tex` writes
``generated/gaps_rows.tex``: for every row that is *not reproduced*, *inconclusive* or
*uninformative*, its measured value against the published one, the tolerance, the evidence, the
control and the experiment's note on the cause. The report's hand-written discussion of the larger
gaps (``paper/sections/gaps.tex``) precedes it and cites rows by their macros.
"""

from __future__ import annotations

import pandas as pd

from .ledger import STATUS_MEANING, STATUSES, _measured_text, latex_escape

__all__ = ["FAILING", "gaps_tex", "monte_carlo_rule_tex", "status_summary_tex"]

FAILING = ("not reproduced", "inconclusive", "uninformative")


def status_summary_tex(claims: pd.DataFrame) -> str:
    """One sentence of counts (every status, zeros included, summing to the row count) and a
    description list defining each status."""
    counts = claims["status"].value_counts()
    parts = [rf"\textbf{{{int(counts.get(s, 0))} {latex_escape(s)}}}" for s in STATUSES]
    lines = [rf"Of the ledger's {len(claims)} rows, " + ", ".join(parts[:-1]) + f" and {parts[-1]}" + ".",
             r"\begin{description}\setlength{\itemsep}{0pt}"]
    lines += [rf"\item[{latex_escape(s)}] {latex_escape(STATUS_MEANING[s])}." for s in STATUSES]
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


def gaps_tex(claims: pd.DataFrame) -> str:
    """One paragraph per failing row (:data:`FAILING`), grouped by experiment, in ledger order."""
    bad = claims[claims["status"].isin(FAILING)]
    if bad.empty:
        return "Every row with a published value reproduced, with a control that fails its check.\n"
    out = []
    for r in bad.to_dict("records"):
        control = f" Control: {latex_escape(r['control'])}." if r.get("control", "") else ""
        note = r.get("note", "")
        note = f" {latex_escape(note[:1].upper() + note[1:])}." if note else ""
        out.append(rf"\paragraph{{{latex_escape(r['experiment'])}: {latex_escape(r['item'])}}}"
                   rf" Source: {latex_escape(r['source'])}; \emph{{{latex_escape(r['status'])}}}. Published "
                   rf"{latex_escape(r['published'])}, measured {latex_escape(_measured_text(r))} "
                   rf"(tolerance {latex_escape(r['tolerance'])}; evidence: {latex_escape(r.get('evidence', '') or '--')})."
                   + note + control)
    return "\n\n".join(out) + "\n"

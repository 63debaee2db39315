"""The ledger's three renderings: a Markdown table (README), a LaTeX longtable (paper), an HTML page
(``snakemake --report``). Each is one row per claim, in the claims' order; the LaTeX and HTML ones colour
the statuses alike (:data:`STATUS_COLOURS`).
"""

from __future__ import annotations

import re

import pandas as pd

from .claims import STATUSES, measured_text
from .latex_text import latex_escape, latex_text

__all__ = ["LEDGER_CAPTION", "STATUS_COLOURS", "claims_html", "claims_markdown", "claims_table_tex"]


def _cell_tex(text) -> str:
    """A table cell: escaped with its mathematics typeset (:func:`.latex_text.latex_text`), and long tokens
    given break points after ``_``, ``)``, ``:`` and at camel-case joins, and a leading zero-width glue so
    that TeX may hyphenate its first word too (so no cell overflows its column)."""
    out = []
    for token in latex_text(text).split(" "):
        if len(token) > 12:
            token = re.sub(r"(?<=[a-z])(?=[A-Z0-9])|(?<=\\_)|(?<=[):;/])|(?=[(])", r"\\allowbreak{}", token)
        out.append(token)
    return r"\hspace{0pt}" + " ".join(out)


# one colour per status, shared by the LaTeX ledger and the HTML ledger of the Snakemake report
STATUS_COLOURS = {"reproduced": ("ForestGreen", "#e6f4ea"), "not reproduced": ("BrickRed", "#fce8e6"),
                  "inconclusive": ("Gray", "#eeeeee"), "uninformative": ("BurntOrange", "#fdebd0"),
                  "qualitative": ("NavyBlue", "#e8eefa"), "extension": ("Gray", "#ffffff"),
                  "illustration": ("Gray", "#ffffff"), "consistency check": ("Gray", "#f4f4f4"),
                  "calibration": ("Gray", "#f4f4f4")}


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
              "evidence": 0.11, "status": 0.13}
    spec = "".join(rf">{{\raggedright\arraybackslash}}p{{{w}\linewidth}}" for w in widths.values())
    ncol = len(widths)
    header = r"\toprule " + " & ".join(widths) + r"\tabularnewline\midrule"
    # Words in the narrow cells may hyphenate (a long word otherwise sticks out of its column); a status
    # never does: each is one box, and its column is as wide as the longest ("uninformative", bold).
    out = [r"\begingroup\setlength{\tabcolsep}{3pt}\footnotesize",
           rf"\begin{{longtable}}{{@{{}}{spec}@{{}}}}",
           rf"\caption{{{LEDGER_CAPTION}}}\label{{tab:ledger}}\tabularnewline",
           header + r"\endfirsthead",
           rf"\multicolumn{{{ncol}}}{{@{{}}l}}{{\emph{{Table~\thetable, continued}}}}\tabularnewline" + header + r"\endhead",
           r"\bottomrule\endfoot"]
    for experiment, group in claims.groupby("experiment", sort=False):
        out.append(rf"\multicolumn{{{ncol}}}{{@{{}}l}}{{\textbf{{\texttt{{{latex_escape(experiment)}}}}}}}\tabularnewline")
        for r in group.to_dict("records"):
            status = rf"\hyphenpenalty=10000\textcolor{{{colour[r['status']]}}}{{\textbf{{{r['status']}}}}}"
            cells = [_cell_tex(r["item"]), _cell_tex(r["source"]), _cell_tex(r["published"]),
                     _cell_tex(measured_text(r)), _cell_tex(r["tolerance"]), _cell_tex(r.get("evidence", "") or "--"),
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


def claims_markdown(claims: pd.DataFrame) -> str:
    """The ledger as a Markdown table (for the README), one row per claim."""
    rows = ["| experiment | item | source | published | reproduced | tolerance | evidence | control | status |",
            "|---|---|---|---|---|---|---|---|---|"]
    for r in claims.to_dict("records"):
        cells = [r["experiment"], r["item"], r["source"], r["published"], measured_text(r), r["tolerance"],
                 r.get("evidence", "") or "—", r.get("control", "") or "—", f"**{r['status']}**"]
        rows.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in cells) + " |")
    return "\n".join(rows) + "\n"

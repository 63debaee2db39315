r"""The claims' verdicts as text: the headline counts, the per-document table and the tolerance sensitivity,
in Markdown (README) and LaTeX (the report's first page), and the counts as the paper's macros.

Inputs are the tables of :mod:`.claim_verdicts` (:func:`~.claim_verdicts.claim_verdicts`,
:func:`~.claim_verdicts.headline`) and :mod:`.claim_sensitivity`; nothing here decides a verdict.
"""

from __future__ import annotations

import pandas as pd

from .claim_verdicts import CLAIM_VERDICT_MEANING, CLAIM_VERDICTS
from .latex_text import latex_escape, latex_text
from .macros import macro_name

__all__ = ["claim_count_macros", "claims_markdown_table", "claims_summary_tex", "headline_text",
           "sensitivity_markdown", "sensitivity_tex"]


def _shown(counts: dict) -> list[str]:
    """Verdicts to name in the headline: every verdict, 'not run' only when some claim was not run."""
    return [v for v in CLAIM_VERDICTS if v != "not run" or counts.get(v, 0)]


def headline_text(counts: dict, bold: str = "**") -> str:
    """``"41 claims of the five documents: **23 reproduced**, ...; beyond them, ..."`` (counts per claim,
    :func:`~.claim_verdicts.headline`); ``bold`` is the Markdown emphasis ('' for plain text)."""
    parts = [f"{bold}{counts[v]} {v}{bold}" for v in _shown(counts)]
    extra = (f"{counts['extension_rows']} extension rows in {counts['extension_groups']} groups"
             + (f" and {counts['timing_rows']} timing row{'s' if counts['timing_rows'] > 1 else ''}"
                if counts.get("timing_rows") else ""))
    return (f"{counts['claims']} claims of the five documents: " + ", ".join(parts)
            + f"; beyond them, {extra} (never counted among the documents' verdicts); "
            f"{counts['ledger_rows']} ledger rows in all.")


def _cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def claims_markdown_table(verdicts: pd.DataFrame) -> str:
    """One row per claim, grouped by document: claim, where, verdict, evidence rows (independent of them),
    the tolerance's source."""
    rows = ["| document | claim | where | verdict | rows (independent) | tolerance |", "|---|---|---|---|---|---|"]
    for r in verdicts.to_dict("records"):
        cells = [r["document"], f"{r['words']} (`{r['id']}`)", r["where"], f"**{r['verdict']}**",
                 f"{r['rows']} ({r['independent']})", r["tolerance_source"]]
        rows.append("| " + " | ".join(_cell(c) for c in cells) + " |")
    return "\n".join(rows) + "\n"


def sensitivity_markdown(table: pd.DataFrame) -> str:
    """The sensitivity table: one row per claim, one column per tolerance factor (the verdict, * when it changes)."""
    factors = sorted(set(table["factor"]))
    head = "| claim | " + " | ".join(f"{f:g}× tolerance" for f in factors) + " |"
    rows = [head, "|---|" + "---|" * len(factors)]
    for claim, g in table.groupby("claim", sort=False):
        by = g.set_index("factor")
        rows.append(f"| `{claim}` | " + " | ".join(
            by.loc[f, "verdict"] + (" *" if by.loc[f, "changed"] else "") for f in factors) + " |")
    changed = table.groupby("factor")["changed"].sum()
    rows.append("| claims whose verdict changes | " + " | ".join(str(int(changed[f])) for f in factors) + " |")
    return "\n".join(rows) + "\n"


def sensitivity_tex(table: pd.DataFrame, verdicts: pd.DataFrame | None = None) -> str:
    """:func:`sensitivity_markdown` as a LaTeX tabular (a changed verdict in italics). With ``verdicts``
    (:func:`~.claim_verdicts.claim_verdicts`) a claim is named by its document, place and words, as a
    reader knows it, instead of its identifier."""
    factors = sorted(set(table["factor"]))
    named = {} if verdicts is None else {r["id"]: f"document {r['document']}, {r['where']}: {r['words']}"
                                         for r in verdicts.to_dict("records")}
    cols = "".join(r">{\raggedright\arraybackslash}p{0.11\linewidth}" for _ in factors)
    out = [r"\begin{tabular}{@{}>{\raggedright\arraybackslash}p{0.3\linewidth}" + cols + r"@{}}\toprule",
           "claim & " + " & ".join(rf"$\times${f:g}" for f in factors) + r"\\\midrule"]
    for claim, g in table.groupby("claim", sort=False):
        by = g.set_index("factor")
        cells = [(rf"\emph{{{latex_escape(by.loc[f, 'verdict'])}}}" if by.loc[f, "changed"]
                  else latex_escape(by.loc[f, "verdict"])) for f in factors]
        name = latex_text(named[claim]) if claim in named else rf"\texttt{{{latex_escape(claim)}}}"
        out.append(name + " & " + " & ".join(cells) + r"\\")
    changed = table.groupby("factor")["changed"].sum()
    out.append(r"\midrule claims whose verdict changes & " + " & ".join(str(int(changed[f])) for f in factors)
               + r"\\\bottomrule")
    out.append(r"\end{tabular}")
    return "\n".join(out) + "\n"


def claims_summary_tex(verdicts: pd.DataFrame, counts: dict) -> str:
    """The report's first-page table: the headline (counts as ``\\htval`` macros of :func:`claim_count_macros`,
    so the report types no number) and one row per claim, grouped by document, with its verdict."""
    parts = [rf"\textbf{{\htval{{{macro_name('document claims', v)}}} {latex_escape(v)}}}" for v in _shown(counts)]
    lines = [r"\paragraph{Claims, not rows.} The ledger's rows test "
             rf"\htval{{{macro_name('document claims', 'total')}}} distinct claims of the five documents: "
             + ", ".join(parts) + r". Beyond them, \htval{" + macro_name("document claims", "extension rows")
             + r"} extension rows (never counted among the documents' verdicts). A claim is \emph{reproduced} only "
             r"when an independent check reproduces it, with a negative control that fails, and none fails it; "
             r"calibrations, identities of the implementation and comparisons with the project's own closed form "
             r"never reproduce a claim (Section~\ref{sec:ledger}).",
             r"\begingroup\footnotesize\setlength{\tabcolsep}{3pt}",
             r"\begin{longtable}{@{}>{\raggedright\arraybackslash}p{0.52\linewidth}>{\raggedright\arraybackslash}"
             r"p{0.17\linewidth}>{\raggedright\arraybackslash}p{0.15\linewidth}r@{}}",
             r"\caption{The documents' claims, one verdict each (rows: the ledger rows that are its evidence; in "
             r"brackets, the independent ones).}\label{tab:claims}\tabularnewline",
             r"\toprule claim & where & verdict & rows\tabularnewline\midrule\endfirsthead",
             r"\toprule claim & where & verdict & rows\tabularnewline\midrule\endhead",
             r"\bottomrule\endfoot"]
    for document, group in verdicts.groupby("document", sort=True):
        lines.append(rf"\multicolumn{{4}}{{@{{}}l}}{{\textbf{{document {latex_escape(document)}}}}}\tabularnewline")
        for r in group.to_dict("records"):
            lines.append(rf"{latex_text(r['words'])} & {latex_text(r['where'])} & {latex_escape(r['verdict'])} & "
                         rf"\htval{{{macro_name('document claim rows', r['id'])}}}\tabularnewline")
    lines += [r"\end{longtable}\endgroup", r"\begin{description}\setlength{\itemsep}{0pt}"]
    lines += [rf"\item[{latex_escape(v)}] {latex_text(CLAIM_VERDICT_MEANING[v])}." for v in _shown(counts)]
    lines.append(r"\end{description}")
    return "\n".join(lines) + "\n"


def claim_count_macros(verdicts: pd.DataFrame, counts: dict) -> dict:
    """Macros for :func:`claims_summary_tex`: ``\\htDocumentClaimsTotal``, one per verdict
    (``\\htDocumentClaimsReproduced``, ...), ``\\htDocumentClaimsExtensionRows`` and, per claim, its evidence-row
    count ``\\htDocumentClaimRows<id>`` (the ledger's row counts are ``\\htClaims<Status>``: rows, not claims)."""
    out = {macro_name("document claims", "total"): counts["claims"],
           macro_name("document claims", "extension rows"): counts["extension_rows"]}
    out.update({macro_name("document claims", v): counts[v] for v in CLAIM_VERDICTS})
    out.update({macro_name("document claim rows", r["id"]): f"{r['rows']} ({r['independent']})"
                for r in verdicts.to_dict("records")})
    return out

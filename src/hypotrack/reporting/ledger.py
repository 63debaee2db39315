r"""The reproduction ledger: claims of the papers, their measured values, and their LaTeX form.

Every experiment writes ``results/<experiment>/claims.csv`` (one row per published item it
checks, see :data:`CLAIM_COLUMNS`); the paper and the README's status table are built from the
union of those files, so no number in the paper is typed by hand.

The ledger is four modules, gathered here (every name keeps its ``hypotrack.reporting.ledger`` import):

:mod:`.claims`
    the claim schema (columns, statuses, evidence, causes), :class:`Claim` and its constructors
    (:func:`numeric_claim`, :func:`monte_carlo_claim`: the Monte Carlo rule), and the ledger's rules
    (:func:`ledger_problems`, :func:`timing_in_text`);
:mod:`.ledger_io`
    claims files and the experiments' ``macros.csv`` (read and write);
:mod:`.macros`
    the paper's LaTeX macros: stable names, values typeset, claims and config as macros;
:mod:`.renderers`
    the ledger as a Markdown table, a LaTeX longtable and an HTML page.

This module adds :func:`build_paper_inputs` (the paper's generated inputs) and the command line::

    python -m hypotrack.reporting.ledger <claims.csv ...>        # the ledger as Markdown
    python -m hypotrack.reporting.ledger check <ledger.csv ...>  # the rows that break its rules
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .claims import (
    CAUSES,
    CLAIM_COLUMNS,
    EVIDENCE,
    NEEDS_CONTROL,
    OPTIONAL_COLUMNS,
    SOFT_PROBLEMS,
    STATUS_MEANING,
    STATUSES,
    VERDICT_STATUSES,
    Claim,
    hard_problems,
    ledger_problems,
    monte_carlo_claim,
    numeric_claim,
    timing_in_text,
    tolerance_text,
)
from .latex_text import latex_escape
from .ledger_io import MACRO_COLUMNS, is_timing_table, read_claims, read_macros, write_claims, write_macros
from .macros import LiteralText, claim_macros, config_macros, latex_value, macro_name, macros_tex
from .renderers import LEDGER_CAPTION, STATUS_COLOURS, claims_html, claims_markdown, claims_table_tex
from .verdict import monte_carlo_verdict

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
    "LEDGER_CAPTION",
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
    "timing_in_text",
]


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


if __name__ == "__main__":  # python -m hypotrack.reporting.ledger <claims.csv ...>  -> the ledger as Markdown
    import sys

    if sys.argv[1:2] == ["check"]:  # python -m hypotrack.reporting.ledger check <ledger.csv>: the ledger's rules
        found = ledger_problems(read_claims(sys.argv[2:]))
        print("\n".join(found) or "ledger: every row follows the rules")
        raise SystemExit(1 if found else 0)
    print(claims_markdown(read_claims(sys.argv[1:])), end="")

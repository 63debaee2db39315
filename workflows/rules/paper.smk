# The reproduction report: reads every experiment's claims.csv, macros.csv and figures from results/,
# writes {results}/paper/generated/ (macros, ledger table, figure copies) and the ledger, and, when
# LaTeX is installed, compiles paper/ms.tex (sources stay in the tree; latexmk's build directory is
# {results}/paper/build) into {results}/paper/hypotrack_report.pdf. No rule writes outside results.
# The PDF rule fails (naming each cause) on a missing macro or figure, an undefined reference, a line
# overfull by more than 1 pt, more than 30 pages before the appendix, or garbled text in the PDF
# (hypotrack.reporting.paper.build_pdf).
import shutil


def _paper_claims(wildcards):
    return sorted(t for t in ALL_TARGETS if str(t).endswith("claims.csv"))


def _paper_macros(wildcards):
    return sorted(t for t in ALL_TARGETS if str(t).endswith("macros.csv"))


def _paper_figures(wildcards):
    return sorted(t for t in ALL_TARGETS if str(t).endswith(".pdf") and "/paper/" not in str(t))


rule paper_generated:
    input:
        claims=_paper_claims,
        figures=_paper_figures,
        macros=_paper_macros,
    output:
        macros=f"{RESULTS}/paper/generated/macros.tex",
        table=f"{RESULTS}/paper/generated/claims_table.tex",
        status_summary=f"{RESULTS}/paper/generated/status_summary.tex",
        gaps=f"{RESULTS}/paper/generated/gaps_rows.tex",
        claims_summary=f"{RESULTS}/paper/generated/claims_summary.tex",
        claims_sensitivity=f"{RESULTS}/paper/generated/claims_sensitivity.tex",
        sensitivity_csv=f"{RESULTS}/paper/claims_sensitivity.csv",
        ledger=f"{RESULTS}/paper/ledger.csv",
        ledger_timing=f"{RESULTS}/paper/ledger_timing.csv",
        run_config=f"{RESULTS}/paper/run_config.json",
    params:
        results=RESULTS,
        config=config,
    log:
        f"{RESULTS}/logs/paper_generated.log",
    script:
        "../scripts/paper_generated.py"


rule paper_pdf:
    input:
        rules.paper_generated.output,
        tex=["paper/ms.tex", "paper/refs.bib", *sorted(glob.glob("paper/sections/**/*.tex", recursive=True))],
    output:
        f"{RESULTS}/paper/hypotrack_report.pdf",
    params:
        inputs=f"{RESULTS}/paper",
        build=f"{RESULTS}/paper/build",
    log:
        f"{RESULTS}/logs/paper_pdf.log",
    script:
        "../scripts/paper_pdf.py"


_PAPER = [*rules.paper_generated.output]
if shutil.which("latexmk"):
    _PAPER.append(rules.paper_pdf.output[0])
else:
    print("hypotrack: latexmk not found; the paper's generated inputs are built, its PDF is not "
          "(apt-get install latexmk texlive-latex-extra to build it).")


rule paper:
    input:
        _PAPER,


ALL_TARGETS.extend(_PAPER)

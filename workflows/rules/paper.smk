# The reproduction report: reads every experiment's claims.csv and figures from results/,
# writes paper/generated/ (macros, ledger table, figure copies) and, when LaTeX is installed,
# compiles paper/ms.tex into results/paper/hypotrack_report.pdf.
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
        macros="paper/generated/macros.tex",
        table="paper/generated/claims_table.tex",
        ledger=f"{RESULTS}/paper/ledger.csv",
    params:
        results=RESULTS,
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
    log:
        f"{RESULTS}/logs/paper_pdf.log",
    shell:
        "cd paper && latexmk -pdf -interaction=nonstopmode -halt-on-error ms.tex > ../{log} 2>&1"
        " && cd .. && cp paper/ms.pdf {output}"


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

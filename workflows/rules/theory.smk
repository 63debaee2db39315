# Theory notebooks (theory/*.py, jupytext percent format): each is converted to .ipynb, executed
# with the native python3 kernel of ipykernel (the kernel runs in the interpreter that runs
# nbconvert), and rendered to HTML. Each notebook asserts its checks, so a broken identity fails
# its job; it writes <name>.json (findings, checks, ledger rows) and its figures next to it.
import os

TH_DIR = f"{RESULTS}/theory"
# Figures each notebook saves as <name>_<stem>.pdf/.png (see the notebook's findings.figure calls).
TH_FIGURES = {
    "hypothesis_count": ["growth"],
    "likelihood_normalisation": ["eq9"],
    "birth_poisson_limit": ["tv_distance", "eq43"],
    "set_integrals": [],
    "ideal_filter_mospa": [],
}
TH_NOTEBOOKS = config["theory"]["notebooks"]


def _theory_outputs(name, for_report=False):
    def mark(path, caption):  # report flags only on the rules' own outputs, not on ALL_TARGETS
        return report_figure(path, "theory", caption) if for_report else path

    figures = [f"{TH_DIR}/{name}_{stem}.pdf" for stem in TH_FIGURES[name]]
    figures += [mark(f"{TH_DIR}/{name}_{stem}.png", "figure") for stem in TH_FIGURES[name]]
    return [f"{TH_DIR}/{name}.json", f"{TH_DIR}/{name}.ipynb", mark(f"{TH_DIR}/{name}.html", "notebook"), *figures]


for _name in TH_NOTEBOOKS:

    rule:
        name:
            f"theory_{_name}"
        input:
            notebook=f"theory/{_name}.py",
            common="theory/_common.py",
        output:
            _theory_outputs(_name, for_report=True),
        params:
            ipynb=f"{TH_DIR}/{_name}.ipynb",
            out=os.path.abspath(TH_DIR),
            theory=os.path.abspath("theory"),
            timeout=config["theory"]["timeout_s"],
        log:
            f"{RESULTS}/logs/theory_{_name}.log",
        shell:
            "export HYPOTRACK_THEORY_OUT={params.out} PYTHONPATH={params.theory}${{PYTHONPATH:+:$PYTHONPATH}}; "
            "(python -m jupytext --to ipynb --output {params.ipynb} {input.notebook}"
            " && python -m nbconvert --to notebook --execute --inplace"
            " --ExecutePreprocessor.kernel_name=python3 --ExecutePreprocessor.timeout={params.timeout}"
            " {params.ipynb}"
            " && python -m nbconvert --to html {params.ipynb}) > {log} 2>&1"


rule theory_claims:
    input:
        findings=[f"{TH_DIR}/{name}.json" for name in TH_NOTEBOOKS],
    output:
        claims=f"{TH_DIR}/claims.csv",
    script:
        "../scripts/theory_claims.py"


TH_TARGETS = [out for name in TH_NOTEBOOKS for out in _theory_outputs(name)] + [f"{TH_DIR}/claims.csv"]


rule theory:
    input:
        TH_TARGETS,


ALL_TARGETS.extend(TH_TARGETS)

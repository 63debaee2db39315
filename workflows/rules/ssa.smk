# SSA scenarios of document 000 (Figs 6, 8-14): truth, scans and initial hypothesis of the
# 50-object birth case and the 15-object comparison case, and a figure of each scenario.
# Config section: ssa (workflows/config/schema/ssa.schema.yaml).

SSA_CASES = ["ssa50", "ssa15"]


rule ssa_scenario:
    wildcard_constraints:
        case="|".join(SSA_CASES),
    output:
        truth=f"{RESULTS}/ssa/{{case}}_truth.csv",
        scans=f"{RESULTS}/ssa/{{case}}_scans.csv",
        prior=f"{RESULTS}/ssa/{{case}}_prior.csv",
    params:
        # The script reads the config itself; these make a change of the section (or the master
        # seed) re-run the rule, as Snakemake re-runs a job whose params changed.
        ssa=config["ssa"],
        seed=config["seed"],
    log:
        f"{RESULTS}/logs/ssa/{{case}}_scenario.log",
    script:
        "../scripts/ssa_scenario.py"


rule ssa_figure:
    wildcard_constraints:
        case="|".join(SSA_CASES),
    input:
        truth=f"{RESULTS}/ssa/{{case}}_truth.csv",
        scans=f"{RESULTS}/ssa/{{case}}_scans.csv",
        prior=f"{RESULTS}/ssa/{{case}}_prior.csv",
    output:
        pdf=f"{RESULTS}/ssa/{{case}}_scenario.pdf",
        png=report_figure(f"{RESULTS}/ssa/{{case}}_scenario.png", "ssa", "scenario"),
    params:
        ssa=config["ssa"],
    script:
        "../scripts/ssa_figure.py"


SSA_OUTPUTS = expand(
    f"{RESULTS}/ssa/{{case}}_{{kind}}",
    case=SSA_CASES,
    kind=["truth.csv", "scans.csv", "prior.csv", "scenario.pdf", "scenario.png"],
)


rule ssa:
    input:
        SSA_OUTPUTS,


ALL_TARGETS.extend(SSA_OUTPUTS)

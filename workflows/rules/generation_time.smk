# Seed 000 Fig. 15: per-parent hypothesis-generation time against the number of possible
# hypotheses A(M, m), for exhaustive HOMHT (until its event budget breaks it), R-FISST's MCMC
# search and Murty k-best HOMHT, on synthetic parents drawn from a known true association.
# One job per method (the `method` wildcard), then the table and the figure.
GT_DIR = f"{RESULTS}/generation_time"
GT_METHODS = ["homht", "rfisst", "homht_kbest"]


rule generation_time_method:
    output:
        f"{GT_DIR}/shards/{{method}}.csv",
    wildcard_constraints:
        method="|".join(GT_METHODS),
    params:
        cfg=config["generation_time"],
        seed=config["seed"],
    script:
        "../scripts/generation_time_sweep.py"


rule generation_time_figure:
    input:
        expand(f"{GT_DIR}/shards/{{method}}.csv", method=GT_METHODS),
    output:
        table=report_table(f"{GT_DIR}/generation_time.csv", "generation_time", "generation_time_table"),
        outcomes=f"{GT_DIR}/generation_time_outcomes.csv",
        pdf=f"{GT_DIR}/generation_time.pdf",
        png=report_figure(f"{GT_DIR}/generation_time.png", "generation_time", "generation_time"),
        claims=f"{GT_DIR}/claims.csv",
    params:
        cfg=config["generation_time"],
    script:
        "../scripts/generation_time_figure.py"


GT_TARGETS = [*rules.generation_time_figure.output]


rule generation_time:
    input:
        GT_TARGETS,


ALL_TARGETS.extend(GT_TARGETS)

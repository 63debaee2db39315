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
        timing_claims=f"{GT_DIR}/timing_claims.csv",
    params:
        cfg=config["generation_time"],
    script:
        "../scripts/generation_time_figure.py"


# The same figure on problems with real ambiguity: one job per difficulty (object spacing), the
# exact top-k benchmark, then tables, figure, claims and macros.
GT_DIFFICULTIES = config["generation_time"]["difficulty"]["difficulties"]


rule generation_time_difficulty:
    output:
        outcomes=f"{GT_DIR}/shards/difficulty_{{difficulty}}.csv",
        timing=f"{GT_DIR}/shards/difficulty_{{difficulty}}_timing.csv",
    wildcard_constraints:
        difficulty="paper|[1248]sigma",
    params:
        cfg=config["generation_time"],
        seed=config["seed"],
    script:
        "../scripts/generation_time_difficulty.py"


rule generation_time_benchmark:
    output:
        table=f"{GT_DIR}/exact_top_k_timing.csv",
        claims=f"{GT_DIR}/exact_top_k_timing_claims.csv",
        macros=f"{GT_DIR}/exact_top_k_timing_macros.csv",
    params:
        cfg=config["generation_time"],
        seed=config["seed"],
    script:
        "../scripts/generation_time_benchmark.py"


rule generation_time_difficulty_figure:
    input:
        outcomes=expand(f"{GT_DIR}/shards/difficulty_{{d}}.csv", d=GT_DIFFICULTIES),
        timing=expand(f"{GT_DIR}/shards/difficulty_{{d}}_timing.csv", d=GT_DIFFICULTIES),
    output:
        table=report_table(f"{GT_DIR}/difficulty.csv", "generation_time", "difficulty_table"),
        timing=f"{GT_DIR}/difficulty_timing.csv",
        summary=f"{GT_DIR}/difficulty_summary.csv",
        pdf=f"{GT_DIR}/difficulty.pdf",
        png=report_figure(f"{GT_DIR}/difficulty.png", "generation_time", "difficulty"),
        map_pdf=f"{GT_DIR}/difficulty_map.pdf",
        map_png=report_figure(f"{GT_DIR}/difficulty_map.png", "generation_time", "difficulty_map"),
        truth_pdf=f"{GT_DIR}/difficulty_truth.pdf",
        truth_png=report_figure(f"{GT_DIR}/difficulty_truth.png", "generation_time", "difficulty_truth"),
        claims=f"{GT_DIR}/difficulty_claims.csv",
        macros=f"{GT_DIR}/difficulty_macros.csv",
    params:
        cfg=config["generation_time"],
    script:
        "../scripts/generation_time_difficulty_figure.py"


GT_TARGETS = [*rules.generation_time_figure.output, *rules.generation_time_difficulty_figure.output,
              *rules.generation_time_benchmark.output]


rule generation_time:
    input:
        GT_TARGETS,


ALL_TARGETS.extend(GT_TARGETS)

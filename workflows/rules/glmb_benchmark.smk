# The GLMB papers' linear-Gaussian benchmark (Vo, Vo & Hoang 2017): the δ-GLMB filter (Gibbs),
# R-FISST (chain alone and with completion) and HOMHT k-best on the same scans; OSPA and
# cardinality over time, one side-by-side table. Monte Carlo runs are sharded.
GB_DIR = f"{RESULTS}/glmb_benchmark"
GB_SHARDS = range(config["glmb_benchmark"]["n_shards"])


rule glmb_benchmark_shard:
    output:
        per_scan=f"{GB_DIR}/shards/per_scan_{{shard}}_timing.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["glmb_benchmark"],
        seed=config["seed"],
    script:
        "../scripts/glmb_benchmark_shard.py"


rule glmb_benchmark_table:
    input:
        per_scan=expand(f"{GB_DIR}/shards/per_scan_{{shard}}_timing.csv", shard=GB_SHARDS),
    output:
        summary=report_table(f"{GB_DIR}/summary.csv", "glmb_benchmark", "summary"),
        timing=f"{GB_DIR}/summary_timing.csv",
        curves=f"{GB_DIR}/curves.csv",
        fig_pdf=f"{GB_DIR}/ospa_cardinality.pdf",
        fig_png=report_figure(f"{GB_DIR}/ospa_cardinality.png", "glmb_benchmark", "ospa_cardinality"),
        claims=f"{GB_DIR}/claims.csv",
        macros=f"{GB_DIR}/macros.csv",
        timing_macros=f"{GB_DIR}/timing_macros.csv",
    params:
        cfg=config["glmb_benchmark"],
    script:
        "../scripts/glmb_benchmark_table.py"


# One seeded realisation run by the glmb tracker; the association problems the engine builds on the
# scans with the most children are saved for the sampler head-to-head (samplers.smk reads them).
rule glmb_benchmark_record:
    output:
        problems=f"{GB_DIR}/recorded_problems.npz",
        table=f"{GB_DIR}/recorded_problems.csv",
    params:
        cfg=config["glmb_benchmark"],
        recorded=config["samplers"]["recorded"],
        seed=config["seed"],
    script:
        "../scripts/glmb_benchmark_record.py"


GB_TARGETS = [*rules.glmb_benchmark_table.output, *rules.glmb_benchmark_record.output]


rule glmb_benchmark:
    input:
        GB_TARGETS,


ALL_TARGETS.extend(GB_TARGETS)

# The Williams-2015 scenario of the PMBM paper (García-Fernández et al. 2018 Sec. VI): every configured tracker
# on the same scans, GOSPA (c = 10, p = 2, alpha = 2) and its decomposition over time, trajectory GOSPA per run;
# the paper's own PMBM code under GNU Octave on the first runs (or its committed record); Murty's k best against
# nrl-tracker's. Monte Carlo runs are sharded.
WB_DIR = f"{RESULTS}/williams2015"
WB_SHARDS = range(config["williams2015"]["n_shards"])


rule williams2015_shard:
    output:
        per_scan=f"{WB_DIR}/shards/per_scan_{{shard}}_timing.csv",
        per_run=f"{WB_DIR}/shards/per_run_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["williams2015"],
        seed=config["seed"],
    script:
        "../scripts/williams2015_shard.py"


# Reruns the reference where Octave and both checkouts (reference.mtt_dir, reference.tcl_dir) are present;
# otherwise copies the committed record (which must match the scenario and seed).
rule williams2015_reference:
    input:
        driver="workflows/scripts/williams2015_reference.m",
        record=config["williams2015"]["reference"]["record"],
    output:
        estimates=f"{WB_DIR}/reference_estimates.csv",
        timing=f"{WB_DIR}/reference_estimates_timing.csv",
    params:
        cfg=config["williams2015"],
        seed=config["seed"],
    script:
        "../scripts/williams2015_reference.py"


rule williams2015_table:
    input:
        per_scan=expand(f"{WB_DIR}/shards/per_scan_{{shard}}_timing.csv", shard=WB_SHARDS),
        per_run=expand(f"{WB_DIR}/shards/per_run_{{shard}}.csv", shard=WB_SHARDS),
        ref_estimates=f"{WB_DIR}/reference_estimates.csv",
        ref_timing=f"{WB_DIR}/reference_estimates_timing.csv",
    output:
        summary=report_table(f"{WB_DIR}/summary.csv", "williams2015", "summary"),
        timing=f"{WB_DIR}/summary_timing.csv",
        curves=f"{WB_DIR}/per_scan.csv",
        trajectory=f"{WB_DIR}/trajectory_gospa.csv",
        fig_pdf=f"{WB_DIR}/gospa_over_time.pdf",
        fig_png=report_figure(f"{WB_DIR}/gospa_over_time.png", "williams2015", "gospa_over_time"),
        comparison=report_table(f"{WB_DIR}/reference_comparison.csv", "williams2015", "reference_comparison"),
        comparison_timing=f"{WB_DIR}/reference_comparison_timing.csv",
        claims=f"{WB_DIR}/claims.csv",
        macros=f"{WB_DIR}/macros.csv",
        timing_macros=f"{WB_DIR}/timing_macros.csv",
    params:
        cfg=config["williams2015"],
        seed=config["seed"],
    script:
        "../scripts/williams2015_table.py"


rule williams2015_kbest:
    output:
        timing=report_table(f"{WB_DIR}/kbest_timing.csv", "williams2015", "kbest_timing"),
    params:
        cfg=config["williams2015"],
        seed=config["seed"],
    script:
        "../scripts/williams2015_kbest.py"


WB_TARGETS = [*rules.williams2015_table.output, *rules.williams2015_kbest.output]


rule williams2015:
    input:
        WB_TARGETS,


ALL_TARGETS.extend(WB_TARGETS)

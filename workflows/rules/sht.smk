# Seed 004 (lecture notes on single-hypothesis tracking): the worked example's association
# hypotheses and clusters; GNN vs JPDA on crossing targets (track coalescence) with OSPA over
# Monte Carlo; a clutter-rate sweep of OSPA and track loss. Monte Carlo runs are sharded.
SHT_DIR = f"{RESULTS}/sht"
SHT_CROSS_SHARDS = range(config["sht"]["n_shards"])
SHT_SWEEP_SHARDS = range(config["sht"]["sweep"]["n_shards"])


rule sht_lecture:
    output:
        validation=report_table(f"{SHT_DIR}/lecture_validation.csv", "sht", "lecture_validation"),
        hypotheses=f"{SHT_DIR}/lecture_hypotheses.csv",
        summary=f"{SHT_DIR}/lecture_summary.csv",
        clusters=f"{SHT_DIR}/lecture_clusters.csv",
    params:
        cfg=config["sht"],
    script:
        "../scripts/sht_lecture.py"


rule sht_crossing_shard:
    output:
        per_scan=f"{SHT_DIR}/shards/crossing_per_scan_{{shard}}.csv",
        per_run=f"{SHT_DIR}/shards/crossing_per_run_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["sht"],
        seed=config["seed"],
    script:
        "../scripts/sht_crossing_shard.py"


rule sht_crossing:
    input:
        per_scan=expand(f"{SHT_DIR}/shards/crossing_per_scan_{{shard}}.csv", shard=SHT_CROSS_SHARDS),
        per_run=expand(f"{SHT_DIR}/shards/crossing_per_run_{{shard}}.csv", shard=SHT_CROSS_SHARDS),
    output:
        curves=f"{SHT_DIR}/crossing_mospa.csv",
        summary=report_table(f"{SHT_DIR}/crossing_summary.csv", "sht", "crossing_summary"),
        example=f"{SHT_DIR}/crossing_example.csv",
        fig_pdf=f"{SHT_DIR}/crossing_coalescence.pdf",
        fig_png=report_figure(f"{SHT_DIR}/crossing_coalescence.png", "sht", "crossing_coalescence"),
    params:
        cfg=config["sht"],
        seed=config["seed"],
    script:
        "../scripts/sht_crossing_figure.py"


rule sht_sweep_shard:
    output:
        per_run=f"{SHT_DIR}/shards/sweep_per_run_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["sht"],
        seed=config["seed"],
    script:
        "../scripts/sht_sweep_shard.py"


rule sht_sweep:
    input:
        per_run=expand(f"{SHT_DIR}/shards/sweep_per_run_{{shard}}.csv", shard=SHT_SWEEP_SHARDS),
    output:
        table=f"{SHT_DIR}/clutter_sweep.csv",
        fig_pdf=f"{SHT_DIR}/clutter_sweep.pdf",
        fig_png=report_figure(f"{SHT_DIR}/clutter_sweep.png", "sht", "clutter_sweep"),
    params:
        cfg=config["sht"],
    script:
        "../scripts/sht_sweep_figure.py"


rule sht_claims:
    input:
        clusters=rules.sht_lecture.output.clusters,
        curves=rules.sht_crossing.output.curves,
        summary=rules.sht_crossing.output.summary,
        lecture=rules.sht_lecture.output.summary,
    output:
        claims=f"{SHT_DIR}/claims.csv",
        macros=f"{SHT_DIR}/macros.csv",
    params:
        cfg=config["sht"],
    script:
        "../scripts/sht_claims.py"


SHT_TARGETS = [
    *rules.sht_claims.output,
    *rules.sht_lecture.output,
    *rules.sht_crossing.output,
    *rules.sht_sweep.output,
]


rule sht:
    input:
        SHT_TARGETS,


ALL_TARGETS.extend(SHT_TARGETS)

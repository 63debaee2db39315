# Seed 003 Table 6.1 and Figs 6.1-6.2: two closely spaced OU targets, 10 sensors; MOSPA of the
# ideal filter, PDAF, MHT (GNNF) and ECMHT. Monte Carlo runs are sharded (vectorised within a shard);
# the ideal filter's closed form (hypotrack.experiments.closely_spaced.oracle) checks it and finds the
# convention behind the published ideal value.
CS_DIR = f"{RESULTS}/closely_spaced"
CS_SHARDS = range(config["closely_spaced"]["n_shards"])


rule closely_spaced_shard:
    output:
        per_run=f"{CS_DIR}/shards/per_run_{{shard}}.csv",
        per_scan=f"{CS_DIR}/shards/per_scan_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["closely_spaced"],
        seed=config["seed"],
    script:
        "../scripts/closely_spaced_shard.py"


rule closely_spaced_table:
    input:
        per_run=expand(f"{CS_DIR}/shards/per_run_{{shard}}.csv", shard=CS_SHARDS),
        per_scan=expand(f"{CS_DIR}/shards/per_scan_{{shard}}.csv", shard=CS_SHARDS),
    output:
        table=report_table(f"{CS_DIR}/table_6_1.csv", "closely_spaced", "table_6_1"),
        steady=f"{CS_DIR}/table_6_1_after_transient.csv",
        conventions=f"{CS_DIR}/ideal_closed_form_conventions.csv",
        curves=f"{CS_DIR}/mospa_vs_scan.csv",
        fig_pdf=f"{CS_DIR}/mospa_vs_scan.pdf",
        fig_png=report_figure(f"{CS_DIR}/mospa_vs_scan.png", "closely_spaced", "mospa_vs_scan"),
        claims=f"{CS_DIR}/claims.csv",
    params:
        cfg=config["closely_spaced"],
    script:
        "../scripts/closely_spaced_table.py"


rule closely_spaced_realisation:
    output:
        tracks=f"{CS_DIR}/realisation.csv",
        fig61_pdf=f"{CS_DIR}/fig_6_1.pdf",
        fig61_png=report_figure(f"{CS_DIR}/fig_6_1.png", "closely_spaced", "fig_6_1"),
        fig62_pdf=f"{CS_DIR}/fig_6_2.pdf",
        fig62_png=report_figure(f"{CS_DIR}/fig_6_2.png", "closely_spaced", "fig_6_2"),
    params:
        cfg=config["closely_spaced"],
        seed=config["seed"],
    script:
        "../scripts/closely_spaced_realisation.py"


CS_TARGETS = [
    *rules.closely_spaced_table.output,
    *rules.closely_spaced_realisation.output,
]


rule closely_spaced:
    input:
        CS_TARGETS,


ALL_TARGETS.extend(CS_TARGETS)

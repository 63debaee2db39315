# Seed 003 Fig 4.2 (+ a Monte Carlo table): counts-only tracking, classical MHT vs the
# cardinality tracker (Tetris extraction) vs the exact equivalence-class MAP.
CA_DIR = f"{RESULTS}/cardinality"
CA_SHARDS = range(config["cardinality"]["n_shards"])


rule cardinality_shard:
    output:
        f"{CA_DIR}/shards/shard_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["cardinality"],
        seed=config["seed"],
    script:
        "../scripts/cardinality_shard.py"


rule cardinality_table:
    input:
        shards=expand(f"{CA_DIR}/shards/shard_{{shard}}.csv", shard=CA_SHARDS),
        realisation=f"{CA_DIR}/fig_4_2.csv",
        control=f"{CA_DIR}/fig_4_2_low_clutter_control.csv",
    output:
        table=report_table(f"{CA_DIR}/monte_carlo.csv", "cardinality", "monte_carlo"),
        optimality=report_table(f"{CA_DIR}/tetris_optimality.csv", "cardinality", "tetris_optimality"),
        claims=f"{CA_DIR}/claims.csv",
    params:
        cfg=config["cardinality"],
    script:
        "../scripts/cardinality_table.py"


rule cardinality_realisation:
    output:
        counts=f"{CA_DIR}/fig_4_2.csv",
        tracks=f"{CA_DIR}/fig_4_2_tracks.csv",
        control=f"{CA_DIR}/fig_4_2_low_clutter_control.csv",
        fig_pdf=f"{CA_DIR}/fig_4_2.pdf",
        fig_png=report_figure(f"{CA_DIR}/fig_4_2.png", "cardinality", "fig_4_2"),
    params:
        cfg=config["cardinality"],
        seed=config["seed"],
    script:
        "../scripts/cardinality_realisation.py"


CA_TARGETS = [
    *rules.cardinality_table.output,
    *rules.cardinality_realisation.output,
]


rule cardinality:
    input:
        CA_TARGETS,


ALL_TARGETS.extend(CA_TARGETS)

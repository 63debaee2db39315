# Seed 003 Figs 5.1-5.3: merging N sensors' returns of two static targets with random swaps.
SW_DIR = f"{RESULTS}/swaps"
SW_SHARDS = range(config["swaps"]["n_shards"])


rule swaps_shard:
    output:
        f"{SW_DIR}/shards/shard_{{shard}}.csv",
    wildcard_constraints:
        shard=r"\d+",
    params:
        cfg=config["swaps"],
        seed=config["seed"],
    script:
        "../scripts/swaps_shard.py"


rule swaps_figures:
    input:
        expand(f"{SW_DIR}/shards/shard_{{shard}}.csv", shard=SW_SHARDS),
    output:
        curves=f"{SW_DIR}/swap_curves.csv",
        rates=report_table(f"{SW_DIR}/optimal_swap_rate.csv", "swaps", "optimal_swap_rate"),
        fig51_pdf=f"{SW_DIR}/fig_5_1.pdf",
        fig51_png=report_figure(f"{SW_DIR}/fig_5_1.png", "swaps", "fig_5_1"),
        fig52_pdf=f"{SW_DIR}/fig_5_2.pdf",
        fig52_png=report_figure(f"{SW_DIR}/fig_5_2.png", "swaps", "fig_5_2"),
        fig53_pdf=f"{SW_DIR}/fig_5_3.pdf",
        fig53_png=report_figure(f"{SW_DIR}/fig_5_3.png", "swaps", "fig_5_3"),
        claims=f"{SW_DIR}/claims.csv",
    params:
        cfg=config["swaps"],
    script:
        "../scripts/swaps_figures.py"


rule swaps:
    input:
        rules.swaps_figures.output,


ALL_TARGETS.extend(rules.swaps_figures.output)

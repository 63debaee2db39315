# The SSA verdicts of document 000 (ssa50, Sec. IV-A; ssa15, Sec. V-A) over scenario seeds: one shard per
# seed runs R-FISST (paper chain; chain + completion) on a fresh ssa50 realisation and R-FISST (also with a
# fixed number of objects) and HOMHT (also with R-FISST's births and deaths) on a fresh ssa15 realisation, and
# the blind tracker (the negative control) on both; chain-seed shards rerun the case's trackers on the report's
# realisation with a new MCMC stream each (the chain's own randomness alone); the table rule gives the per-seed
# and per-chain tables, the distributions over seeds, the ledger rows and a figure.
# Config section: ssa_seeds (workflows/config/schema/ssa_seeds.schema.yaml); trackers from ssa50 / ssa15.
SSA_SEEDS_DIR = f"{RESULTS}/ssa_seeds"
SSA_SEEDS = range(config["ssa_seeds"]["n_seeds"])
for _case, _names in config["ssa_seeds"]["trackers"].items():
    _extra = (config["ssa_seeds"].get("extra_trackers") or {}).get(_case) or {}
    if not set(_names) <= set(config[_case]["trackers"]) | set(_extra):
        raise ValueError(f"ssa_seeds.trackers.{_case}: {_names} names a tracker not in {_case}.trackers "
                         "nor ssa_seeds.extra_trackers")
# Chain seeds: the report's realisation of a case (rule ssa_scenario's tables) with a new MCMC stream per
# chain seed, the same trackers and chain length as the scenario-seed shards (ssa_seeds.n_chain_seeds).
SSA_SEEDS_CHAINS = [(_case, _j) for _case, _n in (config["ssa_seeds"].get("n_chain_seeds") or {}).items()
                    for _j in range(_n)]
for _case, _ in SSA_SEEDS_CHAINS:
    if _case not in config["ssa_seeds"]["trackers"]:
        raise ValueError(f"ssa_seeds.n_chain_seeds.{_case}: not a case of ssa_seeds.trackers "
                         f"{sorted(config['ssa_seeds']['trackers'])}")


rule ssa_seeds_shard:
    wildcard_constraints:
        shard=r"\d+",
    output:
        rows=f"{SSA_SEEDS_DIR}/shards/seed_{{shard}}.csv",
        timing=f"{SSA_SEEDS_DIR}/shards/seed_{{shard}}_timing.csv",
    params:
        # What a shard reads: a change of these reruns the shards.
        settings={"seed": config["seed"], "ssa": config["ssa"], "ssa_seeds": config["ssa_seeds"],
                  **{case: config[case] for case in config["ssa_seeds"]["trackers"]}},
    log:
        f"{RESULTS}/logs/ssa_seeds/seed_{{shard}}.log",
    script:
        "../scripts/ssa_seeds_shard.py"


rule ssa_seeds_chain_shard:
    wildcard_constraints:
        case="ssa50|ssa15",
        chain=r"\d+",
    input:
        truth=f"{RESULTS}/ssa/{{case}}_truth.csv",
        scans=f"{RESULTS}/ssa/{{case}}_scans.csv",
        prior=f"{RESULTS}/ssa/{{case}}_prior.csv",
    output:
        rows=f"{SSA_SEEDS_DIR}/chain_shards/{{case}}_chain_{{chain}}.csv",
        timing=f"{SSA_SEEDS_DIR}/chain_shards/{{case}}_chain_{{chain}}_timing.csv",
    params:
        # What a chain shard reads besides the scenario tables: a change of these reruns it.
        # (not the number of scenario seeds nor of chain seeds: chain seed j is the same whatever their number)
        settings=lambda wildcards: {"seed": config["seed"], "ssa": config["ssa"], wildcards.case: config[wildcards.case],
                                    "ssa_seeds": {k: v for k, v in config["ssa_seeds"].items()
                                                  if k not in ("n_seeds", "n_chain_seeds")}},
    log:
        f"{RESULTS}/logs/ssa_seeds/{{case}}_chain_{{chain}}.log",
    script:
        "../scripts/ssa_seeds_chain_shard.py"


rule ssa_seeds_table:
    input:
        rows=expand(f"{SSA_SEEDS_DIR}/shards/seed_{{shard}}.csv", shard=SSA_SEEDS),
        timing=expand(f"{SSA_SEEDS_DIR}/shards/seed_{{shard}}_timing.csv", shard=SSA_SEEDS),
        chain_rows=[f"{SSA_SEEDS_DIR}/chain_shards/{c}_chain_{j}.csv" for c, j in SSA_SEEDS_CHAINS],
        chain_timing=[f"{SSA_SEEDS_DIR}/chain_shards/{c}_chain_{j}_timing.csv" for c, j in SSA_SEEDS_CHAINS],
    output:
        per_seed=report_table(f"{SSA_SEEDS_DIR}/per_seed.csv", "ssa_seeds", "per_seed"),
        summary=report_table(f"{SSA_SEEDS_DIR}/summary.csv", "ssa_seeds", "summary"),
        timing=f"{SSA_SEEDS_DIR}/seed_timing.csv",
        per_chain=report_table(f"{SSA_SEEDS_DIR}/per_chain.csv", "ssa_seeds", "per_chain"),
        chain_summary=report_table(f"{SSA_SEEDS_DIR}/chain_summary.csv", "ssa_seeds", "chain_summary"),
        chain_timing=f"{SSA_SEEDS_DIR}/chain_timing.csv",
        claims=f"{SSA_SEEDS_DIR}/claims.csv",
        fig_pdf=f"{SSA_SEEDS_DIR}/distributions.pdf",
        fig_png=report_figure(f"{SSA_SEEDS_DIR}/distributions.png", "ssa_seeds", "distributions"),
    script:
        "../scripts/ssa_seeds_table.py"


SSA_SEEDS_TARGETS = [*rules.ssa_seeds_table.output]


rule ssa_seeds:
    input:
        SSA_SEEDS_TARGETS,


ALL_TARGETS.extend(SSA_SEEDS_TARGETS)

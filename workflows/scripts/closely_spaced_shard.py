"""Table 6.1, one Monte Carlo shard: per-run and per-scan MOSPA of every filter."""
from hypotrack.experiments.closely_spaced.run import closely_spaced_monte_carlo, shard_tables
from hypotrack.experiments.seeds import experiment_seeds, shard_runs
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
shard = int(snakemake.wildcards.shard)  # noqa: F821
n_runs = shard_runs(cfg["n_runs"], cfg["n_shards"], shard)
first_run = sum(shard_runs(cfg["n_runs"], cfg["n_shards"], s) for s in range(shard))
seed = experiment_seeds(snakemake.params.seed, "closely_spaced", cfg["n_shards"])[shard]  # noqa: F821
print(f"closely_spaced shard {shard}/{cfg['n_shards']}: {n_runs} runs x {cfg['n_scans']} scans", flush=True)
res = closely_spaced_monte_carlo(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_runs=n_runs, n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"],
    R=cfg["R"], dt=cfg["dt"], initial_variance=cfg["initial_variance"], pdaf_variant=cfg["pdaf_variant"],
    extra_pdaf_variants=[v for v in cfg["extra_pdaf_variants"] if v != cfg["pdaf_variant"]],
    transient_scans=cfg["transient_scans"], controls=True,
    noise_factors=cfg["mht_noise_factors"], seed=seed,
)
per_run, per_scan = shard_tables(res, first_run=first_run, dt=cfg["dt"])
write_table(per_run, snakemake.output.per_run)  # noqa: F821
write_table(per_scan, snakemake.output.per_scan)  # noqa: F821

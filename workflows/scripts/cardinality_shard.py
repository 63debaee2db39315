"""Cardinality Monte Carlo, one shard: per-run cardinality errors and Tetris optimality gaps."""
from hypotrack.experiments.cardinality.run import cardinality_monte_carlo, monte_carlo_table
from hypotrack.experiments.seeds import experiment_seeds, shard_runs
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
shard = int(snakemake.wildcards.shard)  # noqa: F821
n_runs = shard_runs(cfg["n_runs"], cfg["n_shards"], shard)
first_run = sum(shard_runs(cfg["n_runs"], cfg["n_shards"], s) for s in range(shard))
seed = experiment_seeds(snakemake.params.seed, "cardinality", cfg["n_shards"])[shard]  # noqa: F821
print(f"cardinality shard {shard}: {n_runs} runs of {cfg['n_scans']} scans", flush=True)
params = {k: cfg[k] for k in ("n_scans", "p_chi", "lambda_b", "p_d", "lambda_fa", "start", "max_alive_factor")}
res = cardinality_monte_carlo(n_runs=n_runs, seed=seed, progress=True, **params)
write_table(monte_carlo_table(res, first_run), snakemake.output[0])  # noqa: F821

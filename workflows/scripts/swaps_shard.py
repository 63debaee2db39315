"""Figs 5.1-5.3, one Monte Carlo shard: summed errors and log-probabilities per (distance, swaps)."""
import numpy as np

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.seeds import experiment_seeds, shard_runs
from hypotrack.experiments.swaps.run import swap_shard
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
shard = int(snakemake.wildcards.shard)  # noqa: F821
grid = cfg["distances"]
distances = np.union1d(np.arange(grid["start"], grid["stop"] + 0.5 * grid["step"], grid["step"]), [cfg["distance"]])
n_runs = shard_runs(cfg["n_runs"], cfg["n_shards"], shard)
seed = experiment_seeds(snakemake.params.seed, "swaps", cfg["n_shards"])[shard]  # noqa: F821
print(f"swaps shard {shard}: {n_runs} runs at {len(distances)} distances", flush=True)
table = swap_shard(distances, n_sensors=cfg["n_sensors"], sigma=cfg["sigma"], n_runs=n_runs, seed=seed)
write_table(table, snakemake.output[0])  # noqa: F821

"""Clutter-rate sweep, one Monte Carlo shard: GNN and JPDA at every clutter rate."""
import numpy as np

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.sht.run import sweep_runs
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
shard = int(snakemake.wildcards.shard)  # noqa: F821
runs = np.array_split(np.arange(cfg["sweep"]["n_runs"]), cfg["sweep"]["n_shards"])[shard]
print(f"sht sweep shard {shard}: runs {runs.min()}..{runs.max()}", flush=True)
write_table(sweep_runs(cfg, snakemake.params.seed, runs), snakemake.output.per_run)  # noqa: F821

"""Crossing targets, one Monte Carlo shard: GNN and JPDA on the same scenarios."""
import numpy as np

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.sht.run import crossing_runs
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
shard = int(snakemake.wildcards.shard)  # noqa: F821
runs = np.array_split(np.arange(cfg["n_runs"]), cfg["n_shards"])[shard]
print(f"sht crossing shard {shard}: runs {runs.min()}..{runs.max()}", flush=True)
per_scan, per_run = crossing_runs(cfg, snakemake.params.seed, runs)  # noqa: F821
write_table(per_scan, snakemake.output.per_scan)  # noqa: F821
write_table(per_run, snakemake.output.per_run)  # noqa: F821

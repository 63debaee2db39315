"""Run one tracker (wildcard ``tracker``) over the ssa50 scenario tables; save its per-scan tables."""

from hypotrack.experiments.ssa import run_and_save
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
run_and_save(snakemake.config, "ssa50", snakemake.wildcards.tracker, snakemake.input, snakemake.output,
             snakemake.log[0], snapshot_key="weight_snapshots")

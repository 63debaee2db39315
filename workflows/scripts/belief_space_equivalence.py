"""Seed 001 Sec. V-A: FISST vs HOMHT (and H-FISST) posteriors for a fixed number of targets (thin)."""

from hypotrack.experiments.belief_space.run import equivalence_table
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
print(f"belief_space: {cfg['equivalence']['n_runs']} runs of FISST, HOMHT and H-FISST", flush=True)
write_table(equivalence_table(cfg["equivalence"], snakemake.params.seed), snakemake.output.table)  # noqa: F821

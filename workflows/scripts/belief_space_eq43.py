"""Seed 001 Eq. 42-43: one scan after an undetected birth, formulas and engine (thin)."""

from hypotrack.experiments.belief_space.run import eq43_noise_table, eq43_offsets_table
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg["eq43"]  # noqa: F821
print("belief_space: Eq. 43 across the pixel and against the noise", flush=True)
write_table(eq43_offsets_table(cfg), snakemake.output.offsets)  # noqa: F821
write_table(eq43_noise_table(cfg), snakemake.output.noise)  # noqa: F821

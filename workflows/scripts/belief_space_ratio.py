"""Seed 001 Eq. 39: undetected-birth weight ratio, formulas and engine, over (p_D, alpha) (thin)."""

from hypotrack.experiments.belief_space.run import ratio_table
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

print("belief_space: Eq. 39 ratio over the (p_D, alpha) grid", flush=True)
write_table(ratio_table(snakemake.params.cfg["ratio"]), snakemake.output.table)  # noqa: F821

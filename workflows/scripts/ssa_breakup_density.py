"""ssa_breakup: nearest-neighbour distances of the objects in view, per scenario and seed."""
from hypotrack.experiments.ssa_breakup.jobs import density
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

rows, distances = density(snakemake.params.cfg, snakemake.params.catalogue)  # noqa: F821 (injected by Snakemake)
write_table(rows, snakemake.output.density)  # noqa: F821
write_table(distances, snakemake.output.distances)  # noqa: F821

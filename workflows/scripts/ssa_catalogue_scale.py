"""ssa_catalogue: CPU, real-time factor and peak memory per tracker and cloned population size (one process per run)."""
from hypotrack.experiments.ssa_catalogue.scale import scale_runs, scale_summary
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
runs = scale_runs(cfg, seed)
write_table(runs, snakemake.output.runs)  # noqa: F821
write_table(scale_summary(runs), snakemake.output.summary)  # noqa: F821

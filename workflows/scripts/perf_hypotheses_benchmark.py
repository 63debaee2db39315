"""Hypothesis-engine throughput and memory benchmark (targets: 1e6 MCMC proposals/s, 5e6 children/s)."""

from hypotrack.experiments.generation_time.run import throughput_table
from hypotrack.experiments.generation_time.figures import plot_throughput
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
cfg = snakemake.params.cfg
table = throughput_table(cfg, progress=lambda s: print(s, flush=True))
table.to_csv(snakemake.output.table, index=False, float_format="%.6g")
plot_throughput(table, snakemake.output.pdf, snakemake.output.png)

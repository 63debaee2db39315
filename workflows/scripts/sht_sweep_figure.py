"""Clutter-rate sweep: merge shards, table of mean OSPA and track loss, figure."""
import pandas as pd

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.sht.figures import plot_sweep
from hypotrack.experiments.sht.run import summarise_sweep
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
per_run = pd.concat([pd.read_csv(f) for f in snakemake.input.per_run], ignore_index=True)  # noqa: F821
table = summarise_sweep(per_run)
write_table(table, snakemake.output.table)  # noqa: F821
plot_sweep(table, cfg, snakemake.output.fig_pdf, snakemake.output.fig_png)  # noqa: F821
print(table.to_string(index=False), flush=True)

"""Crossing targets: merge shards, mean OSPA / separation curves, example run, coalescence figure."""
import pandas as pd

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.sht.figures import plot_crossing
from hypotrack.experiments.sht.run import crossing_example, summarise_crossing
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
per_scan = pd.concat([pd.read_csv(f) for f in snakemake.input.per_scan], ignore_index=True)  # noqa: F821
per_run = pd.concat([pd.read_csv(f) for f in snakemake.input.per_run], ignore_index=True)  # noqa: F821
curves, summary = summarise_crossing(per_scan, per_run)
example = crossing_example(cfg, snakemake.params.seed)  # noqa: F821
write_table(curves, snakemake.output.curves)  # noqa: F821
write_table(summary, snakemake.output.summary)  # noqa: F821
write_table(example, snakemake.output.example)  # noqa: F821
plot_crossing(example, curves, cfg, snakemake.output.fig_pdf, snakemake.output.fig_png)  # noqa: F821
print(summary.to_string(index=False), flush=True)

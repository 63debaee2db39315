"""GLMB benchmark: side-by-side table, curves over time, figure and ledger rows from the shards."""
import pandas as pd

from hypotrack.experiments.glmb_benchmark.run import implementation_labels, legend_labels
from hypotrack.experiments.glmb_benchmark.summary import (
    benchmark_claims,
    benchmark_macros,
    curves,
    plot_benchmark,
    summary_table,
)
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
out = snakemake.output  # noqa: F821
per_scan = pd.concat([pd.read_csv(p) for p in snakemake.input.per_scan], ignore_index=True)  # noqa: F821
implementations = implementation_labels(cfg["trackers"])
summary, timing = summary_table(per_scan, implementations)
write_table(summary, out.summary)
write_table(timing, out.timing)
curve = curves(per_scan)
write_table(curve, out.curves)
curve.attrs["n_runs"] = per_scan.run.nunique()
plot_benchmark(curve, out.fig_pdf, out.fig_png, legend_labels(cfg["trackers"]))
write_claims(benchmark_claims(summary, cfg["reference_tracker"]), out.claims)
values, times = benchmark_macros(summary, timing)
write_macros("glmb_benchmark", values, out.macros)
write_macros("glmb_benchmark", times, out.timing_macros)

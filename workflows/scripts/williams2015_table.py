"""Williams-2015: summary and per-scan tables, trajectory GOSPA per run, the figure, the reference comparison,
ledger rows and macros from the shards."""
import pandas as pd

from hypotrack.experiments.williams2015.compare import comparison_macros, reference_comparison, reference_claims
from hypotrack.experiments.williams2015.summary import (curves, plot_gospa, summary_table, trajectory_table,
                                                        williams_claims, williams_macros)
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
inp, out = snakemake.input, snakemake.output  # noqa: F821
per_scan = pd.concat([pd.read_csv(p) for p in inp.per_scan], ignore_index=True)
per_run = pd.concat([pd.read_csv(p) for p in inp.per_run], ignore_index=True)
summary, timing = summary_table(per_scan, per_run, int(cfg["settled_after"]))
write_table(summary, out.summary)
write_table(timing, out.timing)
curve = curves(per_scan)
write_table(curve, out.curves)
write_table(trajectory_table(per_run), out.trajectory)
plot_gospa(curve, out.fig_pdf, out.fig_png, float(cfg["gospa_c"]), per_scan.run.nunique())
ref_est, ref_times = pd.read_csv(inp.ref_estimates), pd.read_csv(inp.ref_timing)
comparison, comparison_timing = reference_comparison(cfg, snakemake.params.seed, per_scan, ref_est, ref_times,  # noqa: F821
                                                     per_run)
write_table(comparison, out.comparison)
write_table(comparison_timing, out.comparison_timing)
write_claims(williams_claims(summary) + reference_claims(comparison), out.claims)
values, times = williams_macros(summary, timing)
ref_values, ref_times = comparison_macros(comparison, comparison_timing)
values, times = {**values, **ref_values}, {**times, **ref_times}
write_macros("williams2015", values, out.macros)
write_macros("williams2015", times, out.timing_macros)

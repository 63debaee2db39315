"""Table 6.1 from the pooled shards, the ideal filter's closed form under each convention,
the MOSPA-over-time figure and the ledger rows."""
import pandas as pd

from hypotrack.experiments.closely_spaced.run import pool_per_scan, summarise_closely_spaced
from hypotrack.experiments.closely_spaced.claims import closely_spaced_claims, conventions_table
from hypotrack.experiments.closely_spaced.figures import plot_mospa_vs_scan
from hypotrack.experiments.closely_spaced.controls import CONTROLS
from hypotrack.reporting.ledger import write_claims
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
per_run = pd.concat(pd.read_csv(p) for p in snakemake.input.per_run)  # noqa: F821
kw = dict(rel_tol=cfg["reconstruction_rel_tol"], published_runs=cfg["published_runs"])
table = summarise_closely_spaced(per_run, cfg["pdaf_variant"], **kw)
steady = summarise_closely_spaced(per_run, cfg["pdaf_variant"], column="mospa_steady", **kw)
write_table(table, out.table)
write_table(steady, out.steady)
write_table(conventions_table(cfg), out.conventions)
curves = pool_per_scan(pd.concat(pd.read_csv(p) for p in snakemake.input.per_scan))  # noqa: F821
write_table(curves, out.curves)
print("closely_spaced table:\n" + table.to_string(index=False), flush=True)
plot_mospa_vs_scan(curves[~curves["method"].isin(CONTROLS)], table, cfg, out.fig_pdf, out.fig_png)  # no controls
oracle = pd.read_csv(snakemake.input.oracle)  # noqa: F821
pdaf = pd.read_csv(snakemake.input.pdaf)  # noqa: F821
write_claims(closely_spaced_claims(table, steady, cfg, oracle, pdaf), out.claims)

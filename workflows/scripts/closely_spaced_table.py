"""Table 6.1 from the pooled shards, the ideal filter's closed form under each convention,
the MOSPA-over-time figure and the ledger rows."""
import pandas as pd

from hypotrack.experiments.closely_spaced.run import pool_per_scan, summarise_closely_spaced
from hypotrack.experiments.closely_spaced.claims import closely_spaced_claims, conventions_table
from hypotrack.experiments.closely_spaced.figures import plot_mospa_vs_scan
from hypotrack.experiments.closely_spaced.controls import controlled_method
from hypotrack.experiments.closely_spaced.power import mht_power_macros, mht_power_table
from hypotrack.reporting.ledger import write_claims, write_macros
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
controls = [m for m in curves["method"].unique() if controlled_method(m)]
plot_mospa_vs_scan(curves[~curves["method"].isin(controls)], table, cfg, out.fig_pdf, out.fig_png)  # no controls
power = mht_power_table(per_run, cfg)
write_table(power, out.power)
print("broken MHTs through the MHT row's check:\n" + power.to_string(index=False), flush=True)
write_macros("closely_spaced", mht_power_macros(power), out.power_macros)
oracle = pd.read_csv(snakemake.input.oracle)  # noqa: F821
pdaf = pd.read_csv(snakemake.input.pdaf)  # noqa: F821
write_claims(closely_spaced_claims(table, steady, cfg, oracle, pdaf, power), out.claims)

"""Figs 5.1-5.3 from the pooled shards, and the reproduction claims (thin)."""

import pandas as pd

from hypotrack.experiments.swaps.claims import swap_claims
from hypotrack.experiments.swaps.figures import plot_swap_figures
from hypotrack.experiments.swaps.run import summarise_swaps
from hypotrack.reporting.ledger import write_claims
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
curves, rates = summarise_swaps(pd.concat(pd.read_csv(p) for p in snakemake.input))  # noqa: F821
write_table(curves, out.curves)
write_table(rates, out.rates)
plot_swap_figures(curves, rates, distance=cfg["distance"], n_sensors=cfg["n_sensors"], sigma=cfg["sigma"],
                  paths={"fig51": (out.fig51_pdf, out.fig51_png), "fig52": (out.fig52_pdf, out.fig52_png),
                         "fig53": (out.fig53_pdf, out.fig53_png)})
write_claims(swap_claims(curves, rates, distance=cfg["distance"], n_sensors=cfg["n_sensors"]), out.claims)

"""Table 6.1 sensitivity tables (methods x initial variance x window x estimate; PDAF forms), their
verdicts, figures and the numbers the paper quotes."""
import pandas as pd

from hypotrack.experiments.closely_spaced.sensitivity import (plot_pdaf_variants, plot_table61_sensitivity,
                                                              sensitivity_macros, sensitivity_verdicts)
from hypotrack.reporting.ledger import write_macros
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
kw = dict(rel_tol=cfg["reconstruction_rel_tol"], published_runs=cfg["published_runs"])
table = sensitivity_verdicts(pd.concat(pd.read_csv(p) for p in snakemake.input.cells), **kw)  # noqa: F821
pdaf = sensitivity_verdicts(pd.concat(pd.read_csv(p) for p in snakemake.input.pdaf), **kw)  # noqa: F821
write_table(table, out.table)
write_table(pdaf, out.pdaf)
plot_table61_sensitivity(table, out.fig_pdf, out.fig_png, rel_tol=cfg["reconstruction_rel_tol"])
plot_pdaf_variants(pdaf, out.pdaf_pdf, out.pdaf_png, rel_tol=cfg["reconstruction_rel_tol"])
write_macros("closely_spaced", sensitivity_macros(table, pdaf, cfg), out.macros)

"""Figures, checks table and ledger claims of the belief_space experiment (thin)."""
import matplotlib

matplotlib.use("Agg")
import pandas as pd

from hypotrack.experiments.belief_space.figures import plot_eq43, plot_equivalence, plot_ratio
from hypotrack.experiments.belief_space.claims import checks_table, claims_from_checks
from hypotrack.experiments.belief_space.oracle import oracle_claims
from hypotrack.reporting.ledger import write_claims
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
inp, out = snakemake.input, snakemake.output  # noqa: F821
ratio, offsets, noise, equiv = (pd.read_csv(p) for p in (inp.ratio, inp.offsets, inp.noise, inp.equivalence))
plot_ratio(ratio, [out.ratio_pdf, out.ratio_png], cfg["ratio"])
plot_eq43(offsets, noise, [out.eq43_pdf, out.eq43_png], cfg["eq43"])
plot_equivalence(equiv, [out.equivalence_pdf, out.equivalence_png])
checks = checks_table(ratio, offsets, noise, equiv, cfg)
write_table(checks, out.checks)
oracle = pd.read_csv(inp.oracle)
write_claims(claims_from_checks(checks) + oracle_claims(oracle, cfg["oracle"]["tolerance"]), out.claims)

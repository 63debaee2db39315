"""ssa_catalogue: the operator's scorecard table, figure, ledger rows and macros from the tracker jobs."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.figures import plot_scorecard
from hypotrack.experiments.ssa_catalogue.scorecard import scorecard_claims, scorecard_macros, scorecard_table
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
inp, out = snakemake.input, snakemake.output  # noqa: F821
table = scorecard_table(pd.concat([pd.read_csv(p) for p in inp.cards], ignore_index=True))
write_table(table, out.table)
write_claims(scorecard_claims(table, cfg["reference_tracker"]), out.claims)
write_macros("ssa_catalogue", scorecard_macros(table, cfg["reference_tracker"]), out.macros)
plot_scorecard(table, out.pdf, out.png)

"""ssa_catalogue fusion: the radar-alone and fused scorecards of every tracker as one table, its CPU times, ledger
rows, macros and figure."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.fused import fused_table, fusion_claims, fusion_macros, plot_fusion
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

inp, out = snakemake.input, snakemake.output  # noqa: F821 (injected by Snakemake)
cards = pd.concat([pd.read_csv(p) for p in inp.cards], ignore_index=True)
table = fused_table(cards.to_dict("records"))
write_table(table, out.table)
write_table(cards[["tracker", "sensors", "n_objects", "n_scans", "cpu_s"]], out.timing)
write_claims(fusion_claims(table), out.claims)
write_macros("ssa_catalogue", fusion_macros(table), out.macros)
plot_fusion(table, out.pdf, out.png)

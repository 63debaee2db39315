"""ssa_catalogue: macros of the committed whole-catalogue record (paper/record/ssa_catalogue_full.csv)."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.summary import full_record_macros
from hypotrack.reporting.ledger import write_macros

table = pd.read_csv(snakemake.input[0])  # noqa: F821 (injected by Snakemake)
write_macros("ssa_catalogue", full_record_macros(table, snakemake.params.goal), snakemake.output.macros)  # noqa: F821

"""ssa_catalogue: macros of the committed whole-catalogue record (paper/record/ssa_catalogue_full.csv, and its
timing at scale, paper/record/ssa_catalogue_scale.csv, when recorded)."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.scale_record import scale_record_macros
from hypotrack.experiments.ssa_catalogue.summary import full_record_macros
from hypotrack.reporting.ledger import write_macros

table = pd.read_csv(snakemake.input[0])  # noqa: F821 (injected by Snakemake)
macros = full_record_macros(table, snakemake.params.goal)  # noqa: F821
for path in snakemake.input.scale:  # noqa: F821
    macros.update(scale_record_macros(pd.read_csv(path)))
write_macros("ssa_catalogue", macros, snakemake.output.macros)  # noqa: F821

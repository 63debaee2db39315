"""Cardinality Monte Carlo table, Tetris optimality table and the reproduction claims."""
import pandas as pd

from hypotrack.report import write_claims
from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.cardinality import cardinality_claims, summarise_cardinality

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
errors, optimality = summarise_cardinality(pd.concat(pd.read_csv(p) for p in snakemake.input.shards))  # noqa: F821
write_table(errors, out.table)
write_table(optimality, out.optimality)

fig42 = pd.read_csv(snakemake.input.realisation)  # noqa: F821
write_claims(cardinality_claims(errors, optimality, fig42, p_d=cfg["p_d"]), out.claims)

"""Cardinality Monte Carlo table, Tetris optimality table and the reproduction claims."""
import pandas as pd

from hypotrack.experiments.cardinality.claims import cardinality_claims
from hypotrack.experiments.cardinality.run import summarise_cardinality
from hypotrack.reporting.ledger import write_claims
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
errors, optimality = summarise_cardinality(pd.concat(pd.read_csv(p) for p in snakemake.input.shards))  # noqa: F821
write_table(errors, out.table)
write_table(optimality, out.optimality)
print(errors.to_string(index=False), "\n", optimality.to_string(index=False), flush=True)
write_claims(cardinality_claims(errors, optimality, pd.read_csv(snakemake.input.realisation), cfg,  # noqa: F821
                                control=pd.read_csv(snakemake.input.control)), out.claims)  # noqa: F821

"""Ledger rows and paper numbers of the sht experiment (thin)."""

import pandas as pd

from hypotrack.reporting.joblog import prefix_output
from hypotrack.experiments.sht.claims import lecture_macros, sht_claims
from hypotrack.reporting.ledger import write_claims, write_macros

prefix_output(snakemake)  # noqa: F821  every line this job prints names the job

inp = snakemake.input  # noqa: F821
cfg = snakemake.params.cfg  # noqa: F821
write_claims(sht_claims(pd.read_csv(inp.clusters), pd.read_csv(inp.curves), pd.read_csv(inp.summary),
                        validation=cfg["lecture_validation"], min_lag=cfg["coalescence_min_lag"]),
             snakemake.output.claims)  # noqa: F821
write_macros("sht", lecture_macros(pd.read_csv(inp.lecture)), snakemake.output.macros)  # noqa: F821

"""Ledger rows of the sht experiment (thin)."""

import pandas as pd

from hypotrack.experiments.sht import sht_claims
from hypotrack.report import write_claims
from hypotrack.experiments.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

inp = snakemake.input  # noqa: F821
write_claims(sht_claims(pd.read_csv(inp.clusters), pd.read_csv(inp.curves), pd.read_csv(inp.summary)),
             snakemake.output.claims)  # noqa: F821

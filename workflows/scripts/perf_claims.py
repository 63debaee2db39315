"""Ledger rows of the performance benchmarks (thin)."""

import pandas as pd

from hypotrack.experiments.generation_time.claims import throughput_claims
from hypotrack.experiments.perf_sht.claims import perf_sht_claims
from hypotrack.reporting.ledger import write_claims
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

inp = snakemake.input  # noqa: F821
if "throughput" in inp.keys():
    claims = throughput_claims(pd.read_csv(inp.throughput))
else:
    claims = perf_sht_claims(pd.read_csv(inp.speedups), pd.read_csv(inp.largest), pd.read_csv(inp.timings))
write_claims(claims, snakemake.output.claims)  # noqa: F821

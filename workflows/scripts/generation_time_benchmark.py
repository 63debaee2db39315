"""Time of the exact best-k children (Murty per detection count) at the benchmark size, per difficulty,
with its ledger row and macros (named *timing*: measured, not byte-reproducible)."""

import pandas as pd

from hypotrack.experiments.generation_time.difficulty import difficulty_params, exact_top_k_claims, murty_benchmark
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
rows = murty_benchmark(difficulty_params(snakemake.params.cfg), snakemake.params.seed,
                       progress=lambda s: print(s, flush=True))
pd.DataFrame(rows).to_csv(snakemake.output.table, index=False, float_format="%.6g")
claims, macros = exact_top_k_claims(rows)
write_claims(claims, snakemake.output.claims)
write_macros("generation_time", macros, snakemake.output.macros)

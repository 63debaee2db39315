"""Combine the difficulty shards: outcome, timing and summary tables, the figures (mass captured, MAP found,
truth found), claims and macros."""

import pandas as pd

from hypotrack.experiments.generation_time.difficulty import (
    DIFFICULTY_LABELS,
    difficulty_claims,
    difficulty_params,
    difficulty_summary,
)
from hypotrack.experiments.generation_time.figures import plot_difficulty
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
params = difficulty_params(snakemake.params.cfg)
table = pd.concat([pd.read_csv(p) for p in snakemake.input.outcomes], ignore_index=True)
timing = pd.concat([pd.read_csv(p) for p in snakemake.input.timing], ignore_index=True)
table.to_csv(snakemake.output.table, index=False, float_format="%.10g")
timing.to_csv(snakemake.output.timing, index=False, float_format="%.6g")
summary = difficulty_summary(table)
summary.to_csv(snakemake.output.summary, index=False, float_format="%.10g")
out = snakemake.output
for measure, pdf, png in [("mass", out.pdf, out.png), ("map", out.map_pdf, out.map_png),
                          ("truth", out.truth_pdf, out.truth_png)]:
    plot_difficulty(summary, pdf, png, labels=DIFFICULTY_LABELS, mcmc_steps=int(params["mcmc_steps"]),
                    keep=int(params["keep"]), reference_k=int(params["reference_k"]),
                    exhaustive_max_events=int(params["exhaustive_max_events"]), measure=measure)
claims, macros = difficulty_claims(table, params)
write_claims(claims, snakemake.output.claims)
write_macros("generation_time", macros, snakemake.output.macros)

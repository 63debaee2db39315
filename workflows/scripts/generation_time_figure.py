"""Combine the per-method sweeps into the Fig. 15 table, its machine-independent outcomes, the figure
and the reproduction claims."""

import pandas as pd

from hypotrack.experiments.generation_time.claims import generation_time_claims, generation_time_timing_claims
from hypotrack.experiments.generation_time.figures import OUTCOME_COLUMNS, plot_generation_time
from hypotrack.reporting.ledger import write_claims
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
cfg = snakemake.params.cfg
table = pd.concat([pd.read_csv(p) for p in snakemake.input], ignore_index=True)
table.to_csv(snakemake.output.table, index=False, float_format="%.10g")
table[OUTCOME_COLUMNS].to_csv(snakemake.output.outcomes, index=False, float_format="%.10g")
plot_generation_time(table, snakemake.output.pdf, snakemake.output.png, budget=cfg["exhaustive_max_events"],
                     mcmc_steps=cfg["mcmc_steps"], keep=cfg["keep"])
write_claims(generation_time_claims(table, cfg), snakemake.output.claims)
write_claims(generation_time_timing_claims(table, cfg), snakemake.output.timing_claims)  # machine dependent

"""One difficulty of the Fig. 15 difficulty sweep: outcomes (deterministic) and timings."""

import pandas as pd

from hypotrack.experiments.generation_time.difficulty import (
    OUTCOME_COLUMNS,
    TIMING_COLUMNS,
    difficulty_params,
    difficulty_sweep,
)
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
params = difficulty_params(snakemake.params.cfg)
rows, timing = difficulty_sweep(snakemake.wildcards.difficulty, params, snakemake.params.seed,
                                progress=lambda s: print(s, flush=True))
pd.DataFrame(rows, columns=OUTCOME_COLUMNS).to_csv(snakemake.output.outcomes, index=False, float_format="%.10g")
pd.DataFrame(timing, columns=TIMING_COLUMNS).to_csv(snakemake.output.timing, index=False, float_format="%.6g")

"""One method's sweep of document 000 Fig. 15: generation time vs A(M, m) on synthetic parents."""

import pandas as pd

from hypotrack.experiments.generation_time.run import generation_time_sweep
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
method = snakemake.wildcards.method
rows = generation_time_sweep(method, snakemake.params.cfg, snakemake.params.seed, progress=lambda s: print(s, flush=True))
pd.DataFrame(rows).to_csv(snakemake.output[0], index=False, float_format="%.10g")

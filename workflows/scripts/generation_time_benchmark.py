"""Time of the exact best-k children (Murty per detection count) at the benchmark size, per difficulty."""

import pandas as pd

from hypotrack.experiments.generation_time_difficulty import difficulty_params, murty_benchmark

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
rows = murty_benchmark(difficulty_params(snakemake.params.cfg), snakemake.params.seed,
                       progress=lambda s: print(s, flush=True))
pd.DataFrame(rows).to_csv(snakemake.output[0], index=False, float_format="%.6g")

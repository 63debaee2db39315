"""One seed of the SSA Monte Carlo: every configured tracker on fresh ssa50 and ssa15 realisations."""

from hypotrack.reporting.joblog import prefix_output, progress_log
from hypotrack.experiments.ssa_seeds.run import run_seed
from hypotrack.scenarios.tables import write_table

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
with progress_log(snakemake.log[0]) as progress:
    rows, timing = run_seed(snakemake.config, int(snakemake.wildcards.shard), progress=progress)
    write_table(rows, snakemake.output.rows)
    write_table(timing, snakemake.output.timing)
    progress(timing.to_string(index=False))

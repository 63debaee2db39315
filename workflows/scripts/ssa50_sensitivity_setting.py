"""One setting (λ, p_D) of the ssa50 sensitivity grid: the tracker and the blind tracker on every scenario seed."""

from hypotrack.experiments.ssa.sensitivity import run_setting
from hypotrack.reporting.joblog import prefix_output, progress_log
from hypotrack.scenarios.tables import write_table

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
with progress_log(snakemake.log[0]) as progress:
    rows, timing = run_setting(snakemake.config, int(snakemake.wildcards.setting), progress=progress)
    write_table(rows, snakemake.output.rows)
    write_table(timing, snakemake.output.timing)
    progress(timing.to_string(index=False))

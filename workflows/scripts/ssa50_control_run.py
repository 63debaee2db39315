"""The clutter-ignoring control of ssa50: the primary tracker with its clutter density 10⁶ times too small,
up to the first birth (the negative control of "E[N] before the first birth")."""

from hypotrack.experiments import ssa as st
from hypotrack.reporting.joblog import prefix_output, progress_log
from hypotrack.scenarios.tables import write_table

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
config, inp = snakemake.config, snakemake.input
scenario = st.scenario_from_files(config, "ssa50", inp.truth, inp.scans, inp.prior)
primary = config["ssa50"]["primary"]
settings = st.TrackerSettings.from_config(config["ssa50"], primary)
with progress_log(snakemake.log[0]) as progress:
    run = st.clutter_control_run(scenario, settings, st.tracker_seed(config["seed"], "ssa50", f"{primary}_clutter_control"),
                                 progress=progress)
    write_table(run.summary, snakemake.output.summary)
    progress(f"clutter-ignoring control: {run.timing()}")

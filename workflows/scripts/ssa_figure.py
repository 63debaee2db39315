"""Draw an SSA scenario from its saved tables (PDF + PNG)."""

import pandas as pd

from hypotrack.reporting import figure_style

from hypotrack.experiments.ssa.scenario_figures import plot_scenario
from hypotrack.scenarios.ssa import params_from_config, read_prior
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
params = params_from_config(snakemake.config["ssa"], snakemake.wildcards.case)
known_ids, _, _ = read_prior(pd.read_csv(snakemake.input.prior))
fig = plot_scenario(
    pd.read_csv(snakemake.input.truth), pd.read_csv(snakemake.input.scans), params.fov, known_ids
)
figure_style.save(fig, snakemake.output.pdf, snakemake.output.png, dpi=130)

"""Table 6.1 sensitivity, one initial variance of X0: MOSPA of ideal, MHT, ECMHT per window and estimate."""
from hypotrack.experiments.closely_spaced.sensitivity import table61_sensitivity_cells
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
i = int(snakemake.wildcards.i)  # noqa: F821
variances = cfg["closed_form_initial_variances"]
seed = experiment_seeds(snakemake.params.seed, "closely_spaced_sensitivity", len(variances))[i]  # noqa: F821
table = table61_sensitivity_cells(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"], R=cfg["R"],
    dt=cfg["dt"], initial_variance=variances[i], skips=cfg["sensitivity_skips"], n_runs=cfg["sensitivity_runs"],
    chunk_runs=cfg["mc_chunk_runs"], seed=seed,
)
write_table(table, snakemake.output[0])  # noqa: F821

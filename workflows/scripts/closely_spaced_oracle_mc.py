"""The ideal filter alone over many runs: the Monte Carlo side of the closed-form rows of Table 6.1."""
from hypotrack.experiments.closely_spaced.sensitivity import ideal_oracle_monte_carlo
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "closely_spaced_oracle", 1)[0]  # noqa: F821
table = ideal_oracle_monte_carlo(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"], R=cfg["R"],
    dt=cfg["dt"], initial_variance=cfg["initial_variance"], transient_scans=cfg["transient_scans"],
    n_runs=cfg["oracle_runs"], chunk_runs=cfg["mc_chunk_runs"], seed=seed,
)
print(table.to_string(index=False), flush=True)
write_table(table, snakemake.output[0])  # noqa: F821

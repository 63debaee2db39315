"""PDAF readings of Table 6.1, one start: MOSPA of every multi-sensor PDAF form per window and estimate."""
from hypotrack.experiments.closely_spaced.sensitivity import pdaf_variant_cells
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
start = snakemake.wildcards.start  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, f"closely_spaced_pdaf_{start}", 1)[0]  # noqa: F821
table = pdaf_variant_cells(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"], R=cfg["R"],
    dt=cfg["dt"], initial_variance=cfg["pdaf_variant_starts"][start], start=start, forms=cfg["pdaf_variant_forms"],
    skips=cfg["sensitivity_skips"], n_runs=cfg["pdaf_variant_runs"], chunk_runs=cfg["mc_chunk_runs"], seed=seed,
)
write_table(table, snakemake.output[0])  # noqa: F821

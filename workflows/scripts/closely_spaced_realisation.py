"""Figs 6.1-6.2: one realisation's truth and the MHT, PDAF and ECMHT tracks."""
from hypotrack.experiments.closely_spaced.run import closely_spaced_realisation, realisation_table
from hypotrack.experiments.closely_spaced.figures import plot_realisation
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "closely_spaced_realisation", 1)[0]  # noqa: F821
res = closely_spaced_realisation(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"], R=cfg["R"],
    dt=cfg["dt"], initial_variance=cfg["initial_variance"], pdaf_variant=cfg["pdaf_variant"], seed=seed,
)
table = realisation_table(res)
write_table(table, out.tracks)
plot_realisation(table, cfg, {"fig61": (out.fig61_pdf, out.fig61_png), "fig62": (out.fig62_pdf, out.fig62_png)})

"""Fig 4.2: one realisation of truth, measured counts, classical MHT and the cardinality tracker."""
import matplotlib
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

matplotlib.use("Agg")
from hypotrack.reporting import figure_style  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from hypotrack.experiments.cardinality.figures import plot_realisation  # noqa: E402
from hypotrack.experiments.cardinality.run import cardinality_run, low_clutter_control, realisation_tables  # noqa: E402
from hypotrack.experiments.seeds import experiment_seeds  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "cardinality_realisation", 1)[0]  # noqa: F821
params = {k: cfg[k] for k in ("n_scans", "p_chi", "lambda_b", "p_d", "lambda_fa", "start", "max_alive_factor")}
counts, tracks = realisation_tables(cardinality_run(rng=np.random.default_rng(seed), **params))
write_table(counts, out.counts)
write_table(tracks, out.tracks)
control = low_clutter_control(rng=np.random.default_rng(seed), **{**params, "lambda_fa": cfg["control_lambda_fa"]})
write_table(pd.DataFrame({"scan": np.arange(len(control["r"])), **control}), out.control)
fig = plot_realisation(counts, cfg)
figure_style.save(fig, out.fig_pdf, out.fig_png)

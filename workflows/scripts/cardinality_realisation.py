"""Fig 4.2: one realisation of truth, measured counts, classical MHT and the cardinality tracker."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from hypotrack.scenarios.tables import write_table  # noqa: E402
from hypotrack.experiments.cardinality import CARDINALITY_METHODS, cardinality_run  # noqa: E402
from hypotrack.experiments.seeds import experiment_seeds  # noqa: E402

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "cardinality_realisation", 1)[0]  # noqa: F821
params = {k: cfg[k] for k in ("n_scans", "p_chi", "lambda_b", "p_d", "lambda_fa", "start", "max_alive_factor")}
res = cardinality_run(rng=np.random.default_rng(seed), **params)
table = pd.DataFrame({"scan": np.arange(cfg["n_scans"]), "n_true": res["n_true"], "r": res["r"]})
for m in CARDINALITY_METHODS:
    table[m] = res[m]
write_table(table, out.counts)
write_table(pd.DataFrame([{"row": t.row, "start": t.start, "end": t.end, "n_meas": len(t.scans), "log_score": t.log_score}
                          for t in res["tracks"]]), out.tracks)

fig, ax = plt.subplots(figsize=(8, 4.8))
ax.plot(table["scan"], table["r"], ".", color="0.6", ms=3, label="measured count r_k")
ax.plot(table["scan"], table["n_true"], "k-", lw=2, label="truth n_k")
ax.plot(table["scan"], table["cardinality_tracker"], "-", color="tab:blue", label="cardinality tracker (Tetris)")
ax.plot(table["scan"], table["exact_class_map"], "--", color="tab:cyan", lw=1, label="exact class MAP (count DP)")
ax.plot(table["scan"], table["classical_mht"], "-", color="tab:red", label="classical MHT (MAP hypothesis)")
ax.set_xlabel("scan k")
ax.set_ylabel("number of targets")
ax.set_title(f"Fig 4.2: cardinality tracking, truth vs estimated number of targets\n"
             f"N = {cfg['n_scans']} scans, p_chi = {cfg['p_chi']:g}, "
             f"lambda_b = {cfg['lambda_b']:g}, lambda_fa = {cfg['lambda_fa']:g}, p_d = {cfg['p_d']:g}")
ax.legend(fontsize=8, loc="center right")
fig.tight_layout()
fig.savefig(out.fig_pdf)
fig.savefig(out.fig_png, dpi=150)

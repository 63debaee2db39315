"""Figs 6.1-6.2: one realisation's truth and the MHT, PDAF and ECMHT tracks."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

from hypotrack.scenarios.tables import write_table  # noqa: E402
from hypotrack.experiments.seeds import experiment_seeds  # noqa: E402
from hypotrack.experiments.ecmht import closely_spaced_realisation  # noqa: E402

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "closely_spaced_realisation", 1)[0]  # noqa: F821
res = closely_spaced_realisation(
    sigma2=cfg["sigma2"], gamma=cfg["gamma"], n_scans=cfg["n_scans"], n_sensors=cfg["n_sensors"], R=cfg["R"],
    dt=cfg["dt"], initial_variance=cfg["initial_variance"], pdaf_variant=cfg["pdaf_variant"], seed=seed,
)
table = pd.DataFrame({"time": res["time"]})
for name in ("truth", "ideal", "PDAF", "MHT", "ECMHT"):
    for j in range(2):
        table[f"{name}_{j}"] = res[name][:, j]
write_table(table, out.tracks)


def figure(other, colour, title, pdf, png):
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    for j in range(2):
        ax.plot(table["time"], table[f"truth_{j}"], "k-", lw=2, label="truth" if j == 0 else None)
        ax.plot(table["time"], table[f"{other}_{j}"], "--", color=colour, label=f"{other} tracks" if j == 0 else None)
        ax.plot(table["time"], table[f"ECMHT_{j}"], "-", color="tab:blue", lw=1, label="ECMHT tracks" if j == 0 else None)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("position (m)")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(pdf)
    fig.savefig(png, dpi=150)


figure("MHT", "tab:orange", "Fig 6.1: the ECMHT does not show the MHT's track repulsion\n"
       f"(one realisation, {cfg['n_sensors']} sensors, filtered estimates X(k|k))", out.fig61_pdf, out.fig61_png)
figure("PDAF", "tab:red", "Fig 6.2: the ECMHT does not show the PDAF's track coalescence\n"
       f"(same realisation; PDAF form '{cfg['pdaf_variant']}')", out.fig62_pdf, out.fig62_png)

"""Figs 5.1-5.3 from the pooled shards, and the reproduction claims."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from hypotrack.report import Claim, write_claims  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402
from hypotrack.experiments.ecmht import summarise_swaps  # noqa: E402

cfg = snakemake.params.cfg  # noqa: F821
out = snakemake.output  # noqa: F821
curves, rates = summarise_swaps(pd.concat(pd.read_csv(p) for p in snakemake.input))  # noqa: F821
write_table(curves, out.curves)
write_table(rates, out.rates)
c = curves[np.isclose(curves["distance"], cfg["distance"])]
n, N, d, s = int(c["n_runs"].iloc[0]), cfg["n_sensors"], cfg["distance"], cfg["sigma"]
setting = f"{d:g} m apart, {N} sensors, sigma = {s:g} m, {n} runs"


def save(fig, pdf, png):
    fig.tight_layout()
    fig.savefig(pdf)
    fig.savefig(png, dpi=150)


fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.plot(c["swaps"], c["rms"], "o-", ms=3)
i_min = int(c["swaps"].to_numpy()[np.argmin(c["rms"].to_numpy())])
ax.axvline(i_min, color="gray", ls=":", label=f"minimum at {i_min} swaps")
ax.set_xlabel("number of random measurement swaps i")
ax.set_ylabel("RMS error of the equivalent measurement (m)")
ax.set_title(f"Fig 5.1: equivalent-measurement error vs swaps\n({setting})")
ax.legend()
save(fig, out.fig51_pdf, out.fig51_png)

fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.plot(c["swaps"], c["log_prob_single"], "o-", ms=3, label="unique hypothesis")
ax.plot(c["swaps"], c["log_prob_class"], "s-", ms=3, label="hypothesis class (Eq. 5.22)")
ax.set_xlabel("number of swaps i")
ax.set_ylabel("average log posterior probability")
ax.set_title(f"Fig 5.2: single-hypothesis vs class posterior\n({setting})")
ax.legend()
save(fig, out.fig52_pdf, out.fig52_png)

fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.plot(rates["distance"], rates["rms_optimal_rate"], "o-", ms=3, label="minimum RMS error (Fig 5.1 criterion)")
ax.plot(rates["distance"], rates["class_optimal_rate"], "s--", ms=3, label="maximum class posterior (Eq. 5.22)")
ax.set_xlabel("distance between targets (m)")
ax.set_ylabel("optimal swap rate i*/N")
ax.set_title(f"Fig 5.3: optimal swap rate vs target separation\n({N} sensors, sigma = {s:g} m, {n} runs per distance)")
ax.set_ylim(-0.02, 0.55)
ax.legend()
save(fig, out.fig53_pdf, out.fig53_png)

r = rates.set_index("distance")
i_cls = int(c["swaps"].to_numpy()[np.argmax(c["log_prob_class"].to_numpy())])
far = r.index.max()
claims = [
    Claim("swaps", "Fig 5.1 RMS minimum at about 4 swaps", "003 Sec. 5, Fig 5.1", "about 4", str(i_min),
          "3-5 swaps", "reproduced" if 3 <= i_min <= 5 else "not reproduced",
          f"RMS {c['rms'].iloc[0]:.3g} m with no swaps, {c['rms'].min():.3g} m at the minimum"),
    Claim("swaps", "Fig 5.2 class posterior peak consistent with Fig 5.1", "003 Sec. 5, Fig 5.2",
          "consistent with about 4", str(i_cls), "within 3 of the RMS minimum",
          "reproduced" if abs(i_cls - i_min) <= 3 else "not reproduced",
          "the single-hypothesis curve peaks at 0 swaps (the MAP hypothesis has none)"),
    Claim("swaps", "Fig 5.3 optimal swap rate at zero distance", "003 Sec. 5, Fig 5.3", "0.5",
          f"{r['rms_optimal_rate'].iloc[0]:.3g}", f"+/- 1/{N}",
          "reproduced" if abs(r["rms_optimal_rate"].iloc[0] - 0.5) <= 1 / N + 1e-12 else "not reproduced"),
    Claim("swaps", "Fig 5.3 optimal swap rate for distant targets", "003 Sec. 5, Fig 5.3", "0",
          f"{r.loc[far, 'rms_optimal_rate']:.3g} at {far:g} m", "exact",
          "reproduced" if r.loc[far, "rms_optimal_rate"] == 0 else "not reproduced",
          f"first zero at {r.index[r['rms_optimal_rate'] == 0].min():g} m"),
]
write_claims(claims, out.claims)

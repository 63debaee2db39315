"""The figure of the ``ssa_breakup`` experiment: how crowded the breakup cloud is against the sparse catalogue,
and the cross-tags each tracker makes in both.

Sized for a full text width (6.5 in) with ≥ 8 pt labels; legends sit outside the data.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .summary import SCENARIO_NAMES, TRACKER_NAMES

__all__ = ["plot_breakup"]

_STYLE = {"font.size": 8, "axes.labelsize": 8, "xtick.labelsize": 8, "ytick.labelsize": 8, "legend.fontsize": 8}
_COLOURS = {"breakup": "tab:red", "catalogue": "tab:blue"}


_SHORT = {"glmb": "δ-GLMB\n(Gibbs)", "glmb_murty": "δ-GLMB\n(Murty)", "homht_kbest": "HOMHT\nk-best",
          "glmb_amb": "δ-GLMB G.\n+ambig.", "glmb_murty_amb": "δ-GLMB M.\n+ambig.", "homht_kbest_amb": "HOMHT\n+ambig.",
          "rfisst_amb": "R-FISST\n+ambig."}
_ONE_LINE = {"glmb": "δ-GLMB Gibbs", "glmb_murty": "δ-GLMB Murty", "homht_kbest": "HOMHT",
             "glmb_amb": "δ-GLMB Gibbs +amb.", "glmb_murty_amb": "δ-GLMB Murty +amb.", "homht_kbest_amb": "HOMHT +amb.",
             "rfisst_amb": "R-FISST +amb."}


def plot_breakup(distances: dict, gate_km: float, summary: pd.DataFrame, pdf, png, ratios: pd.DataFrame | None = None):
    """Left: the distribution (CDF) of each object's distance to its nearest neighbour in view, per scenario
    (``distances``: scenario → km), with the smallest gate marked. Middle: cross-tags per 10⁴ returns per tracker
    and scenario (mean ± s.e. over seeds, ``summary`` of :func:`.summary.scorecard_summary`). Right, when
    ``ratios`` (:func:`.summary.cross_tag_ratios` of the metrics) is given: each compared tracker's ratio to the
    reference in the breakup cloud, cross-tags, catalogue cross-tags and identity switches (mean ± s.e. over
    seeds), against the goal."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ...reporting import figure_style

    plt.rcParams.update(_STYLE)
    if ratios is None:
        fig, (a, b) = plt.subplots(1, 2, figsize=(6.5, 3.4))
    else:  # the ratios below, across the full width
        fig = plt.figure(figsize=(6.5, 6.2))
        grid = fig.add_gridspec(2, 2, height_ratios=[1.0, 0.8], width_ratios=[1.0, 1.35])
        a, b, c = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, :])
    for scen, d in distances.items():
        d = np.sort(np.asarray(d, float))
        if len(d):
            a.step(d, np.arange(1, len(d) + 1) / len(d), where="post", color=_COLOURS.get(scen, "k"),
                   label=f"{SCENARIO_NAMES.get(scen, scen)} (median {np.median(d):.3g} km)")
    a.axvline(gate_km, color="k", ls="--", lw=1, label=f"smallest gate across the beam, {gate_km:.2f} km")
    a.set_xscale("log")
    a.set_xlabel("distance to the nearest other object in view (km)")
    a.set_ylabel("share of (scan, object) pairs")
    a.legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), frameon=False)
    names = [t for t in TRACKER_NAMES if t in set(summary["tracker"])]
    scens = [s for s in SCENARIO_NAMES if s in set(summary["scenario"])]
    x = np.arange(len(names))
    w = 0.8 / max(len(scens), 1)
    for i, scen in enumerate(scens):
        g = summary[summary["scenario"] == scen].set_index("tracker").reindex(names)
        b.bar(x + (i - (len(scens) - 1) / 2) * w, g["cross_tags_per_1e4"], w,
              yerr=g["cross_tags_per_1e4_se"].fillna(0.0), color=_COLOURS.get(scen, "k"), capsize=2,
              label=SCENARIO_NAMES.get(scen, scen))
        for xi, v in zip(x + (i - (len(scens) - 1) / 2) * w, g["cross_tags_per_1e4"]):
            if v == 0:  # a bar of height zero is invisible: say so
                b.annotate("0", (xi, 0), xytext=(0, 2), textcoords="offset points", ha="center", va="bottom",
                           color=_COLOURS.get(scen, "k"))
    # short two-line names side by side: long or rotated ones overlapped or pushed the legend off the figure
    if ratios is not None and len(names) > 4:  # six two-line names overlap in half the width: one line, slanted
        b.set_xticks(x, [_ONE_LINE.get(t, TRACKER_NAMES[t]) for t in names], rotation=35, ha="right",
                     rotation_mode="anchor")
    else:
        b.set_xticks(x, [_SHORT.get(t, TRACKER_NAMES[t]) for t in names])
    b.set_ylabel("cross-tags per 10$^4$ object returns")
    b.set_ylim(bottom=0.0)  # counts: an axis below zero (all bars zero) reads as an error
    b.legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), frameon=False, ncol=1)
    if ratios is not None:
        _plot_ratios(c, ratios)
    fig.tight_layout()
    figure_style.save(fig, pdf, png, width=1.0)  # refuses text under 7 pt; closes the figure


_METRIC_STYLE = {"cross_tags_per_1e4": ("cross-tags", "tab:red"),
                 "catalogue_cross_tags_per_1e4": ("catalogue cross-tags", "tab:blue"),
                 "id_switches_per_1e4": ("identity switches", "tab:gray")}


def _plot_ratios(ax, ratios: pd.DataFrame):
    """Each compared tracker's ratio to the reference in the breakup cloud, one bar per metric, the goal dashed."""
    r = ratios[ratios["scenario"] == "breakup"]
    names = [t for t in TRACKER_NAMES if t in set(r["tracker"])]
    x = np.arange(len(names))
    metrics = [m for m in _METRIC_STYLE if m in set(r["metric"])]
    w = 0.8 / max(len(metrics), 1)
    for i, m in enumerate(metrics):
        g = r[r["metric"] == m].set_index("tracker").reindex(names)
        label, colour = _METRIC_STYLE[m]
        xs = x + (i - (len(metrics) - 1) / 2) * w
        ax.bar(xs, g["ratio"], w, yerr=g["ratio_se"].fillna(0.0), color=colour, capsize=2, label=label)
        for xi, v in zip(xs, g["ratio"]):
            # a missing bar (no seed where the reference made one) and a zero (off a log axis) would read alike
            if not np.isfinite(v) or v == 0:
                ax.annotate("0" if v == 0 else "none: GNN\nhas zero", (xi, 0.0), xycoords=("data", "axes fraction"),
                            xytext=(0, 3), textcoords="offset points", ha="center", va="bottom", color=colour,
                            fontsize=7)
    goal = float(r["goal"].iloc[0]) if len(r) else 0.5
    ax.axhline(goal, color="k", ls="--", lw=1, label=f"goal {goal:g}")
    ax.axhline(1.0, color="k", ls=":", lw=0.8, label="parity")
    ax.set_xticks(x, [_SHORT.get(t, TRACKER_NAMES[t]) for t in names])
    ax.set_ylabel("breakup cloud:\nratio to GNN's")
    # ratios from a tenth to tens: on a log scale the goal, parity and both metrics read alike
    ax.set_yscale("log")
    low = r["ratio"][np.isfinite(r["ratio"]) & (r["ratio"] > 0)]
    ax.set_ylim(bottom=min(0.1, 0.5 * float(low.min())) if len(low) else 0.1)
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.02), frameon=False, ncol=3)

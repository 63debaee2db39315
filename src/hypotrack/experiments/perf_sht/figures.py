"""The perf_sht figure: per-scan time of hypotrack's GNN and JPDA against each peer, and the speed-ups."""

from __future__ import annotations

import pandas as pd

from .run import BASELINE

__all__ = ["plot_benchmark"]


_STYLE = {
    "hypotrack": dict(color="tab:red", marker="o"),
    "GNNWith2DAssignment": dict(color="tab:blue", marker="s"),
    "JPDAwithEHM2": dict(color="midnightblue", marker="D", ls="-."),  # not GNNWith2DAssignment's style
    "JPDA": dict(color="tab:green", marker="^"),
    "numpy_scipy_gnn": dict(color="0.3", marker="x", ls="--"),
}


def plot_benchmark(timings: pd.DataFrame, ratios: pd.DataFrame, pdf, png):
    """Per-scan time vs number of targets (GNN; JPDA at each clutter rate) and the speed-ups, with
    the goals as dotted lines named in the legend (below the panels, never over the data)."""
    from ...reporting import figure_style

    rates = sorted(timings.loc[timings["algorithm"] == "jpda", "clutter_rate"].unique())
    n_panels = 2 + len(rates)
    nrows = (n_panels + 1) // 2
    fig, grid = figure_style.subplots(nrows, 2, height=min(2.2 * nrows + 1.4, figure_style.MAX_HEIGHT_IN),
                                      squeeze=False)
    axes = grid.ravel()[:n_panels]
    for extra in grid.ravel()[n_panels:]:
        extra.set_visible(False)
    panels = [("gnn", None, axes[0])] + [("jpda", r, ax) for r, ax in zip(rates, axes[1:])]
    for alg, rate, ax in panels:
        g = timings[timings["algorithm"] == alg]
        if rate is not None:
            g = g[g["clutter_rate"] == rate]
        for impl, h in g.groupby("implementation"):
            h = h.sort_values("n_targets")
            name = {"hypotrack": impl, BASELINE: "minimal numpy + SciPy GNN (baseline)"}.get(impl, f"Stone Soup {impl}")
            ax.plot(h["n_targets"], h["median_ms"], label=name, **_STYLE.get(impl, {}))
        ax.set_yscale("log")
        ax.set_xlabel("number of closely spaced targets")
        ax.set_ylabel("median time per scan (ms)")
        clutter = f"{rate:g} clutter returns/scan" if rate is not None else f"{g['clutter_rate'].iloc[0]:g} clutter/scan"
        ax.set_title(f"{alg.upper()}: predict + associate + update,\n{clutter}")
        ax.grid(True, which="both", alpha=0.3)
    ax = axes[-1]
    # speed-up lines: dashed, in colours and markers no timing line uses (their legend entries stay apart)
    ratio_styles = [dict(color=c, marker=m, ls="--") for c, m in zip(
        ["tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "tab:gray"] * 4, ["D", "v", "P", "X", "*", "h"] * 4)]
    for ((alg, peer, rate), g), style in zip(ratios.groupby(["algorithm", "peer", "clutter_rate"]), ratio_styles):
        g = g.sort_values("n_targets")
        ax.plot(g["n_targets"], g["speedup"], label=f"speed-up: {alg.upper()} vs {peer} ({rate:g} clutter/scan)", **style)
    for goal, ls in zip(sorted(ratios["goal"].dropna().unique()), [":", "--", "-."] * 4):
        sizes = ratios.loc[ratios["goal"] == goal, "n_targets"]
        ax.axhline(goal, color="k", ls=ls, lw=1, label=f"goal {goal:.3g}× ({sizes.min()}–{sizes.max()} targets)")
    ax.set_yscale("log")
    ax.set_xlabel("number of closely spaced targets")
    ax.set_ylabel("speed-up (peer time / hypotrack time)")
    ax.set_title("hypotrack speed-up over each peer\n(< 1: slower than it)")
    ax.grid(True, which="both", alpha=0.3)
    figure_style.legend_below(fig, ncol=2)
    fig.suptitle("Single-hypothesis trackers: hypotrack vs Stone Soup, same scenarios, one run")
    figure_style.save(fig, pdf, png, width=1.0)


"""The sht figures: coalescence on crossing targets (one run and the Monte Carlo curves) and the clutter sweep."""

from __future__ import annotations

import numpy as np

from .run import COLORS, LABELS, METHODS

__all__ = ["plot_crossing", "plot_sweep"]


def _save(fig, pdf, png, width: float = 1.0):
    from ...reporting import figure_style

    figure_style.save(fig, pdf, png, width=width)


_TRUTH_DASHES = ("--", (0, (1, 1.5)), "-.", (0, (5, 1, 1, 1, 1, 1)))


def _band(ax, x, y, se, color, **kw):
    ax.plot(x, y, color=color, **kw)
    ax.fill_between(x, y - 2 * se, y + 2 * se, color=color, alpha=0.15)


def plot_crossing(example, curves, cfg, pdf, png):
    """Coalescence figure: one run's tracks (GNN, JPDA) near the crossing (top, shared legend below
    them), MC track separation and MC OSPA (bottom, each with its legend below it)."""
    from ...reporting import figure_style

    figure_style.use()
    import matplotlib.pyplot as plt

    s = cfg["scenario"]
    n_t = s["n_targets"]
    fig = plt.figure(figsize=(figure_style.TEXT_WIDTH_IN, figure_style.MAX_HEIGHT_IN - 0.05), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 1.05])
    half = s["speed"] * s["dt"] * s["n_scans"] / 4  # zoom on the middle half of the run
    y_half = half * np.tan(np.deg2rad(s["crossing_angle_deg"] / 2)) + 6 * s["sigma"]
    merged = {}
    for ax, method in zip(top.subplots(1, len(METHODS), squeeze=False)[0], METHODS):
        cl = example[example["kind"] == "clutter"]
        tr = example[example["kind"] == "target_return"]
        ax.plot(cl["x"], cl["y"], ".", color="0.75", ms=3, label="clutter returns")
        ax.plot(tr["x"], tr["y"], "x", color="0.35", ms=4, label="target returns")
        for tid, g in example[example["kind"] == "truth"].groupby("id"):
            # each target's path its own dash, named in the legend (no label drawn over the returns)
            ax.plot(g["x"], g["y"], color="k", ls=_TRUTH_DASHES[int(tid) % len(_TRUTH_DASHES)], lw=1,
                    label=f"true path of target {tid}")
        tracks = example[(example["kind"] == "track") & (example["method"] == method)]
        for tid, g in tracks.groupby("id"):
            if tid < n_t:
                ax.plot(g["x"], g["y"], ".-", ms=3, lw=1.8, color=f"C{tid}",
                        label=f"track {tid} (started on target {tid})")
            else:
                ax.plot(g["x"], g["y"], ".-", ms=2, lw=0.8, alpha=0.6, color="tab:gray",
                        label="tracks from initiation" if tid == n_t else None)
        ax.set_xlim(-half, half)
        ax.set_ylim(-y_half, y_half)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"{LABELS[method]}: Monte Carlo run 0,\nmiddle half of the run")
        for h, lab in zip(*ax.get_legend_handles_labels()):
            merged.setdefault(lab, h)
    top.legend(list(merged.values()), list(merged), loc="outside lower center", ncol=3)
    n_runs = int(curves["n_runs"].max())
    left, right = bottom.subfigures(1, 2)
    ax = left.subplots()
    for method in METHODS:
        g = curves[curves["method"] == method]
        _band(ax, g["time"], g["separation"], g["separation_se"], COLORS[method], label=f"{LABELS[method]} tracks 0 and 1")
    g = curves[curves["method"] == METHODS[0]]
    ax.plot(g["time"], g["truth_separation"], "k--", label="true targets")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("distance between the two tracks (m)")
    ax.set_title(f"Track separation, mean ± 2 s.e. over {n_runs} runs:\nJPDA coalescence")
    left.legend(loc="outside lower center", ncol=2)
    ax = right.subplots()
    for method in METHODS:
        g = curves[curves["method"] == method]
        _band(ax, g["time"], g["mospa"], g["mospa_se"], COLORS[method], label=f"{LABELS[method]}, all confirmed tracks")
        _band(ax, g["time"], g["mospa_targets"], g["mospa_targets_se"], COLORS[method], ls=":",
              label=f"{LABELS[method]}, tracks started on the targets")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"OSPA (m), c = {cfg['ospa']['c']:g} m, p = {cfg['ospa']['p']:g}")
    ax.set_title(f"Mean OSPA ± 2 s.e. over {n_runs} runs")
    right.legend(loc="outside lower center", ncol=1)
    fig.suptitle(figure_style.wrap(
        f"Two targets crossing at {s['crossing_angle_deg']:g}° in clutter ({s['clutter_rate']:g} false returns/scan, "
        f"$P_D$ = {s['p_D']:g}, σ = {s['sigma']:g} m): GNN vs JPDA", fig))
    _save(fig, pdf, png)


def plot_sweep(table, cfg, pdf, png):
    """Clutter sweep: mean OSPA, confirmed tracks and track-loss fraction vs clutter rate, GNN vs JPDA,
    stacked, each panel's legend beside it."""
    from ...reporting import figure_style

    fig, axes = figure_style.subplots(3, 1, height=6.4, sharex=True)
    for method in METHODS:
        g = table[table["method"] == method]
        kw = dict(marker="o", capsize=3, color=COLORS[method])
        axes[0].errorbar(g["clutter_rate"], g["mospa"], yerr=2 * g["mospa_se"], label=f"{LABELS[method]}, all tracks", **kw)
        axes[0].errorbar(g["clutter_rate"], g["mospa_targets"], yerr=2 * g["mospa_targets_se"], ls=":",
                         label=f"{LABELS[method]}, tracks\nstarted on the targets", **kw)
        axes[1].plot(g["clutter_rate"], g["mean_tracks"], marker="o", color=COLORS[method], label=LABELS[method])
        axes[2].errorbar(g["clutter_rate"], g["track_loss"], yerr=2 * g["track_loss_se"], label=LABELS[method], **kw)
    axes[1].axhline(cfg["scenario"]["n_targets"], color="k", ls="--", lw=1, label="true number of targets")
    axes[0].set_ylabel(f"time-averaged OSPA (m)\nc = {cfg['ospa']['c']:g} m, p = {cfg['ospa']['p']:g}")
    axes[1].set_ylabel("mean number of\nconfirmed tracks")
    axes[2].set_ylabel(f"track-loss fraction\n(deleted or > {cfg['loss_distance']:g} m\noff at the end)")
    axes[-1].set_xlabel("expected clutter returns per scan")
    for ax in axes:
        figure_style.legend_right(ax)
    n = int(table["n_runs"].max())
    axes[0].set_title(f"Mean OSPA ± 2 s.e. ({n} runs per point)")
    axes[1].set_title("Confirmed tracks (false ones come from initiation)")
    axes[2].set_title(f"Track loss ± 2 s.e. ({n} runs per point)")
    fig.suptitle(figure_style.wrap(
        f"Crossing targets ({cfg['scenario']['crossing_angle_deg']:g}°): GNN vs JPDA against clutter rate", fig))
    _save(fig, pdf, png)


"""SSA experiments, step 4: the figures, drawn from the saved tables only (document 000 Figs 6, 8–14).

Every figure is drawn at the report's line width in the style of :mod:`hypotrack.reporting.figure_style`.
"""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from ...models.orbit import EARTH_RADIUS
from ...reporting import figure_style
from .evaluation import AGREEMENT_TOLERANCE_KM, OSPASettings
from .run import percent_of_run as _percent

__all__ = [
    "plot_comparison",
    "plot_estimate_snapshots",
    "plot_expected_number",
    "plot_ospa",
    "plot_weight_snapshots",
    "save_figure",
]


def save_figure(fig, pdf, png, dpi: int = 150) -> None:
    """Check the figure is legible at full line width, save it as PDF (paper) and PNG (report), close it."""
    figure_style.save(fig, pdf, png, width=1.0, dpi=dpi)


_STATUS_STYLE = {
    "correct": dict(marker="o", mfc="none", mec="#1a9641", ms=7, mew=1.4, ls="none",
                    label="estimate within its error bound"),
    "incorrect": dict(marker="*", color="#d7191c", ms=12, ls="none",
                      label="estimate outside its error bound"),
    "false": dict(marker="X", color="#d7191c", ms=9, ls="none", label="estimate of no catalogued object"),
}


def _cardinality_colour(n: int):
    """One colour per number of objects, the same in every figure (tab10 cycled by n)."""
    import matplotlib.pyplot as plt

    palette = plt.get_cmap("tab10").colors
    return palette[int(n) % len(palette)]


def plot_weight_snapshots(weights: pd.DataFrame, n_scans: int, *, title: str):
    """Document 000 Fig. 6: the weights of all kept hypotheses at a few scans.

    One panel per snapshot scan: bars of the hypotheses' weights by rank (log scale, so the
    light hypotheses stay visible next to the MAP), coloured by their number of objects; the
    panel title gives the scan, the number kept, the MAP weight and the effective number 1/Σw².
    """
    from matplotlib.patches import Patch
    from matplotlib.ticker import MaxNLocator

    scans = sorted(weights["scan"].unique())
    n_obj = np.sort(weights["n_objects"].unique())
    colour = {n: _cardinality_colour(n) for n in n_obj}
    n_cols = min(len(scans), 2)
    n_rows = -(-len(scans) // n_cols)
    fig, axes = figure_style.subplots(n_rows, n_cols, height=min(2.3 * n_rows + 1.0, figure_style.MAX_HEIGHT_IN),
                                      sharey=True, squeeze=False)
    floor = max(weights["weight"].min(), 1e-300) if len(weights) else 1e-12
    for ax, k in zip(axes.flat, scans):
        g = weights[weights["scan"] == k].sort_values("rank")
        w = g["weight"].to_numpy()
        ax.bar(g["rank"], w, width=0.85, color=[colour[n] for n in g["n_objects"]], edgecolor="none")
        ax.set_yscale("log")
        ax.set_ylim(floor / 3, 3.0)
        ax.set_xlim(0.3, max(len(w), 1) + 0.7)
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        t_h = g["time"].iloc[0] / 3600
        ax.set_title(f"{_percent(k, n_scans):.0f} % of the run ({t_h:.1f} h), {len(w)} kept\n"
                     f"MAP weight {w[0]:.3f}, 1/Σw² = {1 / np.sum(w**2):.2f}")
        ax.set_xlabel("hypothesis rank (1 = heaviest)")
        ax.grid(alpha=0.3, axis="y")
    for ax in axes.flat[len(scans):]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel("hypothesis weight")
    figure_style.legend_below(fig, [Patch(color=colour[n]) for n in n_obj], [f"{n}" for n in n_obj],
                              ncol=min(len(n_obj), 10), title="number of objects in the hypothesis")
    fig.suptitle(figure_style.wrap(title, fig))
    return fig


def _draw_fov(ax, fov):
    from matplotlib.patches import Circle, Wedge

    u = 1e-3
    ax.add_patch(Circle((0, 0), EARTH_RADIUS * u, color="#cfe2f3", ec="#3b6ea5", lw=0.6, zorder=0))
    lo, hi = fov.angle_limits_deg
    ax.add_patch(Wedge((0, 0), fov.r_max * u, lo, hi, width=(fov.r_max - fov.r_min) * u, fc="#fff3c4",
                       ec="black", lw=1.0, zorder=0))


def plot_estimate_snapshots(matched: pd.DataFrame, fov, n_scans: int, *, columns: Sequence[str] = ("",),
                            column_titles: Sequence[str] = ("top hypothesis",), birth_ids=(), title: str):
    """Document 000 Figs 8–10 and 12–14: true positions of every catalogued object and the MAP
    hypothesis's estimates.

    Parameters
    ----------
    matched : DataFrame
        Rows of :func:`evaluate_map` at the snapshot scans, with a ``tracker`` column when
        several trackers are drawn (``columns`` names them).
    fov : FieldOfView
    n_scans : int
        Scans in the run (for the percentage of each snapshot).
    columns, column_titles : sequences of str
        Values of ``matched["tracker"]`` to draw, one row of panels each (``""``: no tracker
        column), and their names (written beside each row).
    birth_ids : sequence of int
        True objects not in the initial hypothesis, drawn in orange once seen.

    One column of panels per snapshot scan. Every panel shows all catalogued objects, in the
    sensor's field of view (yellow wedge) or not. True objects are black dots (orange: a birth,
    grey: a birth not yet seen); estimates are green circles when the true object lies within
    their error bound, red stars when not (the paper's Fig. 7 convention); a catalogued object
    without a correct estimate is ringed in red.
    """
    from matplotlib.lines import Line2D

    scans = sorted(matched["scan"].unique())
    u = 1e-3
    xy = matched[["x", "y"]].to_numpy() * u
    lo = np.minimum(xy.min(axis=0, initial=0.0), -EARTH_RADIUS * u) - 2
    hi = np.maximum(xy.max(axis=0, initial=0.0), fov.r_max * u) + 2
    aspect = (hi[1] - lo[1]) / (hi[0] - lo[0])
    n_rows, n_cols = len(columns), len(scans)
    panel = (figure_style.TEXT_WIDTH_IN - 0.7) / n_cols  # inches per panel, less the y labels
    height = min(n_rows * (0.9 * panel * aspect + 0.6) + 1.3, figure_style.MAX_HEIGHT_IN)
    fig, axes = figure_style.subplots(n_rows, n_cols, height=height, squeeze=False, sharex=True, sharey=True)
    for r, (col, col_title) in enumerate(zip(columns, column_titles)):
        for c, k in enumerate(scans):
            ax = axes[r][c]
            at = matched[matched["scan"] == k]
            g = at[at["tracker"] == col] if col else at
            tr = g[g["role"] == "truth"]
            es = g[g["role"] == "estimate"]
            _draw_fov(ax, fov)
            seen = tr[tr["status"] != "unseen"]
            born = seen["id"].isin(birth_ids)
            ax.plot(seen.loc[~born, "x"] * u, seen.loc[~born, "y"] * u, ".", color="black", ms=3, zorder=2)
            ax.plot(seen.loc[born, "x"] * u, seen.loc[born, "y"] * u, ".", color="#e07b00", ms=5, zorder=2)
            unseen = tr[tr["status"] == "unseen"]
            ax.plot(unseen["x"] * u, unseen["y"] * u, ".", color="0.6", ms=3, zorder=2)
            missed = tr[tr["status"] == "missed"]
            ax.plot(missed["x"] * u, missed["y"] * u, "o", mfc="none", mec="#d7191c", ms=8, mew=1.0,
                    zorder=3)
            for status, style in _STATUS_STYLE.items():
                e = es[es["status"] == status]
                marker_style = {key: v for key, v in style.items() if key != "label"}
                marker_style["ms"] = 0.7 * marker_style["ms"]
                ax.plot(e["x"] * u, e["y"] * u, zorder=4, **marker_style)
            n_ok = int((es["status"] == "correct").sum())
            ax.set_title(f"{_percent(k, n_scans):.0f} % of the run\n"
                         f"{n_ok}/{len(es)} correct, {len(missed)} missed")
            ax.set_aspect("equal")
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            if r == n_rows - 1:
                ax.set_xlabel("x (10³ km)")
            if c == 0:
                ax.set_ylabel(f"{col_title}\ny (10³ km)")
            ax.grid(alpha=0.3)
    handles = [
        Line2D([], [], marker=".", color="black", ls="none", ms=6, label="true position (all catalogued objects)"),
        *([Line2D([], [], marker=".", color="#e07b00", ls="none", ms=7, label="true position, birth (seen)")]
          if len(birth_ids) else []),
        *([Line2D([], [], marker=".", color="0.6", ls="none", ms=6,
                  label="true position, birth not yet in view")]
          if (matched["status"] == "unseen").any() else []),
        *[Line2D([], [], **{**style, "ms": 0.7 * style["ms"]}) for style in _STATUS_STYLE.values()],
        Line2D([], [], marker="o", mfc="none", mec="#d7191c", ls="none", ms=7,
               label="catalogued object missed"),
        Line2D([], [], color="black", lw=1.0, label="sensor field of view (yellow)"),
    ]
    figure_style.legend_below(fig, handles, [h.get_label() for h in handles], ncol=2)
    fig.suptitle(figure_style.wrap(title, fig))
    return fig


def plot_expected_number(metrics: pd.DataFrame, cardinality: pd.DataFrame, *, title: str):
    """Document 000 Fig. 11: expected number of objects over the run, with the cardinality
    distribution ``P(N = n)`` that it averages (the "hand-off" of weight between cardinalities).

    ``metrics`` needs ``scan, time, expected_number, n_catalogue``.
    """
    K = int(metrics["scan"].max()) + 1
    pct = _percent(metrics["scan"], K)
    fig, (ax, ax_p) = figure_style.subplots(2, 1, height=4.8, sharex=True, gridspec_kw={"height_ratios": [3, 2]})
    ax.step(pct, metrics["n_catalogue"], where="post", color="black", ls="--", lw=1.2,
            label="true number of\ncatalogued objects")
    ax.plot(pct, metrics["expected_number"], color="#2c7bb6", lw=1.6, label="expected number\nof objects E[N]")
    ax.set_ylabel("number of objects")
    ax.set_title("expected number of objects (Fig. 11) and the true number the filter could know")
    figure_style.legend_right(ax)
    ax.grid(alpha=0.3)
    lo = int(np.floor(min(metrics["expected_number"].min(), metrics["n_catalogue"].min())))
    hi = int(np.ceil(max(metrics["expected_number"].max(), metrics["n_catalogue"].max())))
    ax.set_ylim(lo - 0.5, hi + 0.5)
    card = cardinality.pivot_table(index="scan", columns="n_objects", values="probability", fill_value=0.0)
    card = card.reindex(metrics["scan"], fill_value=0.0)
    shown = [n for n in card.columns if card[n].max() >= 1e-2]
    for n in shown:
        ax_p.plot(pct, card[n], color=_cardinality_colour(n), lw=1.3, label=f"N = {n}")
    ax_p.set_ylabel("P(N = n)")
    ax_p.set_title("cardinality distribution: weight of all hypotheses with n objects")
    ax_p.set_ylim(-0.03, 1.03)
    ax_p.set_xlabel("simulation time (% of the run)")
    figure_style.legend_right(ax_p, title="cardinality", ncol=1 + len(shown) // 8)
    ax_p.grid(alpha=0.3)
    hours = metrics["time"].max() / 3600
    fig.suptitle(figure_style.wrap(f"{title}\n(run of {hours:.1f} h; cardinalities shown once P(N = n) "
                                   "reaches 0.01)", fig))
    return fig


def _ospa_ylim(ax, values, c):
    """From 0 to a little above the largest value, never above the cut-off (OSPA <= c)."""
    top = float(np.nanmax(values)) if np.isfinite(values).any() else c
    ax.set_ylim(0, min(max(1.15 * top, 1e-3 * c), 1.05 * c))


_LINE_STYLES = (dict(color="#2c7bb6", lw=1.6), dict(color="#d7191c", lw=1.0, ls="--"),
                dict(color="#1a9641", lw=1.0, ls=":"), dict(color="#7b3294", lw=1.0, ls="-."))


def _ospa_panels(axes, metrics, ospa_settings, trackers, labels):
    """OSPA in view (first axis) and over the catalogue (second axis), one line per tracker;
    returns the legend's handles and names (with each tracker's two means)."""
    cols = [("ospa_in_view", ospa_settings.c_in_view,
             "objects in the field of view (gaps: none in view; spikes: an object at the FOV edge, "
             "in view on one side only)"),
            ("ospa_catalogue", ospa_settings.c_catalogue,
             "all catalogued objects (out-of-view errors grow along track until the next pass)")]
    for ax, (col, c, what) in zip(axes, cols):
        for tr, style in zip(trackers, _LINE_STYLES):
            g = metrics[metrics["tracker"] == tr] if tr else metrics
            ax.plot(g["time"] / 3600, g[col], **style)
        ax.set_ylabel(f"OSPA (km)\np = {ospa_settings.p:g}, c = {c:g} km")
        ax.set_title(textwrap.fill(f"MAP estimates vs truth: {what}", 55))  # the axes' width beside the legend
        _ospa_ylim(ax, metrics[col], c)
        ax.grid(alpha=0.3)
    # one legend for both panels (same line per tracker), beside the first and running down beside the second
    handles, names = [], []
    for tr, line in zip(trackers, axes[0].lines):
        g = metrics[metrics["tracker"] == tr] if tr else metrics
        handles.append(line)
        names.append(f"{labels[tr]}\nmean {g[cols[0][0]].mean():.3g} km in view, {g[cols[1][0]].mean():.3g} km all")
    return handles, names


def plot_ospa(metrics: pd.DataFrame, ospa_settings: OSPASettings, *, title: str, labels: Mapping):
    """OSPA of the MAP estimates over time: objects in view (top) and the catalogue (bottom).

    ``metrics`` rows of :func:`evaluate_map` with ``time``; ``labels`` maps each value of its
    ``tracker`` column to a legend name (key ``""`` when there is no ``tracker`` column).
    """
    fig, axes = figure_style.subplots(2, 1, height=4.6, sharex=True)
    handles, names = _ospa_panels(axes, metrics, ospa_settings, list(labels), labels)
    figure_style.legend_right(axes[0], handles, names, label_chars=36)
    axes[-1].set_xlabel("time (h)")
    fig.suptitle(figure_style.wrap(title, fig))
    return fig


def _agreement_panel(ax, agreement, times, label_a, label_b):
    ag = agreement["agree"].to_numpy(dtype=bool)
    same = agreement["same_objects"].to_numpy(dtype=bool)
    diff = agreement["max_difference_km"].to_numpy(dtype=float)
    floor = 1e-15
    ax.semilogy(times[same], np.maximum(diff[same], floor), ".", ms=3, color="#1a9641",
                label="largest difference of\nthe two estimates of\nan object (0 drawn at " + figure_style.pow10(np.log10(floor)) + ")")
    ax.axhline(AGREEMENT_TOLERANCE_KM, color="black", ls=":", lw=1.0,
               label=f"agreement tolerance\n({AGREEMENT_TOLERANCE_KM * 1e3:g} m)")
    for t in times[~ag]:
        ax.axvline(t, color="#d7191c", alpha=0.4, lw=1.0)
    if (~same).any():
        ax.plot(times[~same], np.full((~same).sum(), 1e3), "x", color="#d7191c",
                label="different objects (e.g. a\nbirth in one MAP hypothesis)")
    ax.plot([], [], color="#d7191c", alpha=0.4, label="scan where the MAP\nhypotheses differ")
    ax.set_ylim(floor / 30, 1e6)
    ax.set_ylabel("km")
    ax.set_title(textwrap.fill(f"{label_a} vs {label_b}: same MAP hypothesis in {100 * ag.mean():.1f} % of "
                               f"{len(ag)} scans", 55))
    ax.grid(alpha=0.3)
    return ax.get_legend_handles_labels()


def plot_comparison(agreements: Mapping, metrics: pd.DataFrame, ospa_settings: OSPASettings, *,
                    labels: Mapping, title: str):
    """ssa15: per-scan agreement of pairs of MAP hypotheses and the OSPA of every tracker.

    ``agreements`` maps ``(tracker_a, tracker_b)`` to :func:`map_agreement` tables; ``labels``
    maps each tracker (values of ``metrics["tracker"]``) to its legend name. All panels share
    one legend, below them.
    """
    n = len(agreements)
    fig, axes = figure_style.subplots(n + 2, 1, height=min(1.15 * n + 3.6, figure_style.MAX_HEIGHT_IN),
                                      sharex=True, gridspec_kw={"height_ratios": [1.0] * n + [1.6, 1.6]})
    first = next(iter(labels))
    times = metrics.loc[metrics["tracker"] == first, "time"].to_numpy() / 3600
    merged = {}
    for ax, ((a, b), agreement) in zip(axes[:n], agreements.items()):
        for h, lab in zip(*_agreement_panel(ax, agreement, times, labels[a], labels[b])):
            merged.setdefault(lab, h)
    handles, names = _ospa_panels(axes[n:], metrics, ospa_settings, list(labels), labels)
    # one legend for every panel, below them all, so the panels keep the page's width
    figure_style.legend_below(fig, [*merged.values(), *handles],
                              [lab.replace("\n", " ") for lab in [*merged, *names]], ncol=2)
    axes[-1].set_xlabel("time (h)")
    fig.suptitle(figure_style.wrap(title, fig))
    return fig

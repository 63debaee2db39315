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
        *([Line2D([], [], marker=".", color="#e07b00", ls="none", ms=7, label="true position, birth (seen; its estimate drawn on it)")]
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
    for i, (tr, line) in enumerate(zip(trackers, axes[0].lines)):
        g = metrics[metrics["tracker"] == tr] if tr else metrics
        handles.append(line)
        name = f"{labels[tr]}\nmean {g[cols[0][0]].mean():.3g} km in view, {g[cols[1][0]].mean():.3g} km all"
        same = _coincides_with(metrics, tr, trackers[:i], [c for c, _, _ in cols], [ax.get_ylim() for ax in axes])
        if same is not None:
            other, largest = same
            name += (f"\ncoincides with {labels[other]} (" + ("identical" if largest == 0 else
                                                              f"differences ≤ {largest:.2g} km") + ")")
        names.append(name)
    return handles, names


def _coincides_with(metrics, tracker, earlier, columns, limits):
    """The first of ``earlier`` trackers whose curves ``tracker``'s lie on in every panel (the same
    scans without a value, and differences under 1 % of each panel's height: drawn over it),
    with the largest difference (km); ``None`` if there is none."""
    if not tracker:
        return None
    mine = metrics[metrics["tracker"] == tracker].set_index("scan")
    for other in earlier:
        theirs = metrics[metrics["tracker"] == other].set_index("scan").reindex(mine.index)
        largest = 0.0
        for col, (lo, hi) in zip(columns, limits):
            a, b = mine[col].to_numpy(dtype=float), theirs[col].to_numpy(dtype=float)
            if (np.isnan(a) != np.isnan(b)).any():
                break
            d = np.abs(a - b)
            d = float(d[~np.isnan(d)].max(initial=0.0))
            if d > 0.01 * (hi - lo):
                break
            largest = max(largest, d)
        else:
            return other, largest
    return None


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


def _runs(mask):
    """(start, stop) index pairs of the maximal runs of True in ``mask``."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)))


def _agreement_panel(ax, agreements, times, labels):
    """One row per compared pair: the scans where the two MAP hypotheses agree (green) or not (red).

    Agreement is a yes/no per scan (same objects and every object's two estimates within the
    agreement tolerance), so it is drawn as that: a strip per pair, not a difference on a log axis.
    """
    dt = float(np.median(np.diff(times))) if len(times) > 1 else 1.0
    edges = np.concatenate([times, [times[-1] + dt]]) if len(times) else np.zeros(1)
    n = len(agreements)
    for row, ((a, b), agreement) in enumerate(agreements.items()):
        y = n - 1 - row
        ag = agreement["agree"].to_numpy(dtype=bool)
        same = agreement["same_objects"].to_numpy(dtype=bool)
        for value, colour, lw in ((True, "#a6d96a", 0.0), (False, "#d7191c", 2.0)):
            # a differing scan is 1/720 of the axis: its edge line keeps it at least 2 pt wide
            spans = [(edges[i], edges[j] - edges[i]) for i, j in _runs(ag == value)]
            ax.broken_barh(spans, (y - 0.2, 0.4), facecolors=colour, edgecolor=colour, lw=lw)
        if (~same).any():
            ax.plot(times[~same], np.full((~same).sum(), y + 0.2), "v", color="black", ms=4.5)  # on the strip's top
        # the pair's name in the white band above its strip, never over it
        ax.text(0.005, y + 0.3, f"{labels[a]} vs {labels[b]}: same in {100 * ag.mean():.1f} % of {len(ag)} scans",
                transform=ax.get_yaxis_transform(), va="bottom", ha="left", fontsize=7.5)
    ax.set_yticks([])
    ax.set_ylabel("same MAP\nhypothesis?")
    ax.set_ylim(-0.3, n + 0.05)
    ax.set_title("Same MAP hypothesis (green) or not (red), per scan")
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    tol = f"{AGREEMENT_TOLERANCE_KM * 1e3:g} m"
    return ([Patch(color="#a6d96a"), Patch(color="#d7191c"),
             Line2D([], [], ls="none", marker="v", color="black", ms=4.5)],
            [f"same MAP hypothesis: same objects, every object's two estimates within {tol}",
             "MAP hypotheses differ (a red bar at least one scan wide)",
             "different objects (e.g. a birth in one MAP hypothesis), marked above the red bar"])


def plot_comparison(agreements: Mapping, metrics: pd.DataFrame, ospa_settings: OSPASettings, *,
                    labels: Mapping, title: str):
    """ssa15: per-scan agreement (yes/no) of pairs of MAP hypotheses and the OSPA of every tracker.

    ``agreements`` maps ``(tracker_a, tracker_b)`` to :func:`map_agreement` tables; ``labels``
    maps each tracker (values of ``metrics["tracker"]``) to its legend name. All panels share
    one legend, below them.
    """
    n = len(agreements)
    fig, axes = figure_style.subplots(3, 1, height=min(0.4 * n + 4.9, figure_style.MAX_HEIGHT_IN),
                                      sharex=True, gridspec_kw={"height_ratios": [0.38 * n + 0.2, 1.6, 1.6]})
    first = next(iter(labels))
    times = metrics.loc[metrics["tracker"] == first, "time"].to_numpy() / 3600
    strip_handles, strip_names = _agreement_panel(axes[0], agreements, times, labels)
    handles, names = _ospa_panels(axes[1:], metrics, ospa_settings, list(labels), labels)
    # one legend for every panel, below them all, so the panels keep the page's width
    figure_style.legend_below(fig, [*strip_handles, *handles],
                              [lab.replace("\n", " ") for lab in [*strip_names, *names]], ncol=2)
    axes[-1].set_xlabel("time (h)")
    fig.suptitle(figure_style.wrap(title, fig))
    return fig

"""Figures of the ``ssa_catalogue`` experiment: cost against N, groups over time, the catalogue and the radar, the
operator's scorecard.

Sized for a full text width (6.5 in) with ≥ 8 pt labels; legends sit outside the data.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .summary import TRACKER_NAMES, slopes

__all__ = ["plot_cost", "plot_groups", "plot_catalogue", "plot_scorecard"]

_STYLE = {"font.size": 8, "axes.labelsize": 8, "xtick.labelsize": 8, "ytick.labelsize": 8, "legend.fontsize": 8}


def _fs():
    from ...reporting import figure_style

    return figure_style


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(_STYLE)
    return plt


def _save(fig, pdf, png):
    from ...reporting import figure_style

    figure_style.save(fig, pdf, png, width=1.0)  # placed at the full line width; refuses text under 7 pt


def plot_cost(timing: pd.DataFrame, pdf, png):
    """CPU seconds per scan against N (log–log), one line per tracker, its slope in the legend."""
    _plt()  # the report style over the shared one
    sl = slopes(timing)
    fig, ax = _fs().subplots(height=3.0)
    for name, g in timing.groupby("tracker", sort=False):
        g = g.sort_values("n_objects")
        lab = TRACKER_NAMES.get(name, name) + (f" (slope {sl[name]:.2f})" if name in sl else "")
        ax.loglog(g["n_objects"], g["cpu_s_per_scan"], "o-", lw=1.2, ms=3, label=lab)
    ax.set_xlabel("catalogue objects tracked N")
    ax.set_ylabel("CPU seconds per scan")
    ax.grid(alpha=0.3, which="both")
    _fs().legend_below(fig, *ax.get_legend_handles_labels(), ncol=3, frameon=False)
    _save(fig, pdf, png)


def plot_groups(per_scan: pd.DataFrame, pdf, png):
    """Groups per scan and the largest group (objects) over time, factored trackers, largest N."""
    _plt()  # the report style over the shared one
    n = per_scan["n_objects"].max()
    d = per_scan[(per_scan["n_objects"] == n) & per_scan["n_groups"].notna()]
    fig, axes = _fs().subplots(1, 2, height=2.8, sharex=True)
    pairs = []
    for name, g in d.groupby("tracker", sort=False):
        label = TRACKER_NAMES.get(name, name)
        pairs.append((axes[0].plot(g["scan"], g["n_groups"], lw=1.0, label=label)[0],
                      axes[1].step(g["scan"], g["largest_group"], where="mid", lw=1.0, label=label)[0]))
    axes[0].set_ylabel("groups")
    axes[1].set_ylabel("largest group (objects)")
    for ax in axes:
        ax.set_xlabel("scan (10 s)")
        ax.grid(alpha=0.3)
    # trackers whose curves coincide (e.g. the same groups on a short run) are said so in the legend, per panel
    notes = {}
    for ax, panel in zip(axes, ("left", "right")):
        ax.autoscale_view()
        for a, b in _fs().coincident_lines(ax):
            notes.setdefault(a.get_label(), {}).setdefault(b.get_label().split(",")[0], []).append(panel)
    for left, right in pairs:
        name = left.get_label()
        if name in notes:
            said = "; ".join(f"{other} ({' and '.join(p)})" for other, p in notes[name].items())
            for line in (left, right):
                line.set_label(_fs().wrap(f"{name}, coincides with {said}", fig, fraction=0.8))
    _fs().legend_below(fig, *axes[0].get_legend_handles_labels(), ncol=1 if notes else 3, frameon=False)
    _save(fig, pdf, png)


def plot_catalogue(positions_ef: np.ndarray, is_debris: np.ndarray, radar, pdf, png):
    """The catalogue sample at scan 0 (Earth-fixed, longitude–latitude) and the radar's coverage.

    ``positions_ef`` (n, 3) km; the coverage is the field of view's footprint sampled at the
    near and far range and the elevation limits (the sub-points of its edge).
    """
    _plt()  # the report style over the shared one
    r = np.linalg.norm(positions_ef, axis=1)
    lat = np.degrees(np.arcsin(positions_ef[:, 2] / r))
    lon = np.degrees(np.arctan2(positions_ef[:, 1], positions_ef[:, 0]))
    fig, ax = _fs().subplots(height=3.6)
    ax.scatter(lon[~is_debris], lat[~is_debris], s=2, c="tab:blue", label="active satellites")
    ax.scatter(lon[is_debris], lat[is_debris], s=2, c="tab:red", label="debris")
    # field-of-view footprint: sub-satellite points of its boundary at 800 km altitude
    fov = radar.fov
    az = np.deg2rad(np.linspace(fov.az_center_deg - fov.az_width_deg / 2, fov.az_center_deg + fov.az_width_deg / 2, 60))
    pts = []
    for el in (fov.el_max_deg, fov.el_min_deg):
        e = np.deg2rad(el)
        # range to 800 km altitude along (az, el) from a spherical Earth: r² + 2 r R sin e = h(2R + h)
        R, h = 6378.137, 800.0
        rng = -R * np.sin(e) + np.sqrt((R * np.sin(e)) ** 2 + h * (2 * R + h))
        rng = np.clip(rng, fov.r_min_km, fov.r_max_km)
        enu = np.column_stack([rng * np.cos(e) * np.sin(az), rng * np.cos(e) * np.cos(az), np.full_like(az, rng * np.sin(e))])
        pts.append(enu @ radar.site.enu + radar.site.ef)
    ring = np.vstack([pts[0], pts[1][::-1], pts[0][:1]])
    rr = np.linalg.norm(ring, axis=1)
    ax.plot(np.degrees(np.arctan2(ring[:, 1], ring[:, 0])), np.degrees(np.arcsin(ring[:, 2] / rr)), "k-", lw=1.0,
            label="radar field of view at 800 km altitude")
    ax.plot(radar.site.lon_deg, radar.site.lat_deg, "k^", ms=5, label="radar site")
    ax.set_xlabel("longitude (deg)")
    ax.set_ylabel("latitude (deg)")
    ax.set_xlim(-180, 180)
    ax.set_ylim(-90, 90)
    ax.grid(alpha=0.3)
    _fs().legend_below(fig, *ax.get_legend_handles_labels(), ncol=2, frameon=False, markerscale=3)
    _save(fig, pdf, png)


_SHORT = {"glmb": "δ-GLMB", "homht_kbest": "HOMHT", "rfisst": "R-FISST", "gnn": "GNN", "jpda": "JPDA"}


def _bars(ax, names, series, colours, labels, *, log=False):
    """Grouped bars, one group per tracker; a zero bar is marked "0" and a missing one "–" (invisible otherwise);
    the legend above the axes, out of the data."""
    x = np.arange(len(names))
    w = 0.8 / len(series)
    top = 0.0
    for i, (vals, col, lab) in enumerate(zip(series, colours, labels)):
        xi = x + (i - (len(series) - 1) / 2) * w
        v = np.asarray(vals, float)
        ax.bar(xi, np.where(np.isfinite(v), v, 0.0), w, color=col, label=lab)
        top = max(top, float(np.nanmax(v)) if np.isfinite(v).any() else 0.0)
        for xx, vv in zip(xi, v):
            if not np.isfinite(vv) or vv == 0:
                ax.annotate("0" if np.isfinite(vv) else "–", (xx, 0), xytext=(0, 1), textcoords="offset points",
                            ha="center", va="bottom", color=col, fontsize=7)
    ax.set_xticks(x, [_SHORT.get(t, t) for t in names], rotation=45, ha="right", rotation_mode="anchor")
    if log:
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_ylim(0, max(top, 1.0) * 3.0)  # the tallest bar inside the axes on the log part
    if top == 0:  # nothing but zeros or gaps: an axis from 0, not around it
        ax.set_ylim(0, 1)
    ax.grid(alpha=0.3, axis="y")
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), frameon=False, fontsize=7, ncol=len(series),
              handlelength=1.0, columnspacing=0.8, handletextpad=0.4)


def plot_scorecard(table: pd.DataFrame, pdf, png):
    """The operator's scorecard at the largest N, one group of bars per tracker (``table`` of
    :func:`.scorecard.scorecard_table`): returns per 10⁴; false and duplicate entries per 1,000; completeness and
    covariance realism (the 95 % goal dashed); RMS error at re-acquisition (R, I, C); GOSPA per object in view by
    part (stacked); unphysical hypotheses per scan (mean, max; symlog)."""
    plt = _plt()  # noqa: F841 (the report style)
    n = int(table["n_objects"].max())
    t = table[table["n_objects"] == n]
    names = [x for x in TRACKER_NAMES if x in set(t["tracker"])]
    t = t.set_index("tracker").reindex(names)
    fig, ax = _fs().subplots(3, 2, height=6.6)
    a = ax.ravel()
    _bars(a[0], names, [t["cross_tags_per_1e4"], t["orphan_per_1e4"], t["uncorrelated_per_1e4"]],
          ["tab:red", "tab:orange", "tab:gray"], ["cross-tag", "to an unowned track", "uncorrelated"])
    a[0].set_ylabel("object returns per 10$^4$")
    _bars(a[1], names, [t["false_per_1000"], t["duplicate_per_1000"]], ["tab:purple", "tab:brown"],
          ["false", "duplicate"])
    a[1].set_ylabel("entries per 1,000 estimates")
    _bars(a[2], names, [t["completeness"], t["realism_95"]], ["tab:blue", "tab:green"], ["completeness", "realism"])
    a[2].axhline(0.95, color="k", ls="--", lw=0.8)
    a[2].set_ylim(0, 1.05)
    a[2].set_ylabel("share of objects / re-acquisitions")
    _bars(a[3], names, [t["rms_radial_km"], t["rms_intrack_km"], t["rms_crosstrack_km"]],
          ["tab:cyan", "tab:blue", "tab:olive"], ["radial", "in-track", "cross-track"])
    a[3].set_ylabel("RMS error at re-acquisition (km)")
    x = np.arange(len(names))
    bottom = np.zeros(len(names))
    for col, c, lab in (("gospa_localisation_per_object_km", "tab:blue", "localisation"),
                        ("gospa_missed_per_object_km", "tab:orange", "missed"),
                        ("gospa_false_per_object_km", "tab:red", "false")):
        v = t[col].fillna(0.0).to_numpy(float)
        a[4].bar(x, v, 0.6, bottom=bottom, color=c, label=lab)
        bottom += v
    a[4].set_xticks(x, [_SHORT.get(n_, n_) for n_ in names], rotation=45, ha="right", rotation_mode="anchor")
    a[4].set_ylabel("GOSPA per object in view (km)")
    a[4].grid(alpha=0.3, axis="y")
    a[4].legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), frameon=False, fontsize=7, ncol=3, handlelength=1.0,
                columnspacing=0.8, handletextpad=0.4)
    _bars(a[5], names, [t["unphysical_hypotheses_per_scan"], t["unphysical_hypotheses_max"]],
          ["tab:gray", "k"], ["mean", "max"], log=True)
    a[5].set_ylabel("unphysical hypotheses per scan")
    fig.suptitle(f"Operator's scorecard, N = {n} catalogue objects", fontsize=8)
    _save(fig, pdf, png)

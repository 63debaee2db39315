"""The SSA scenario figure (document 000 Fig. 6's setting): Earth, the sensor's field of view, the true
paths, the returns by origin and where each birth first enters the field of view.

Drawn from the tables of the ``ssa`` rule only (truth, scans, and the FOV of the scenario's parameters), so
the figure can be restyled without regenerating the scenario (:mod:`hypotrack.scenarios.ssa` makes them).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...models.orbit import EARTH_RADIUS
from ...models.sensors import FieldOfView
from ...reporting import figure_style
from ...scenarios.tables import CLUTTER, validate_truth

__all__ = ["plot_scenario"]


_BIRTH_COLOURS = ("#ffd21f", "#2ca02c", "#9467bd", "#17becf", "#e377c2", "#8c564b", "#bcbd22", "#7f7f7f",
                  "#1f77b4", "#d62728")
_BIRTH_MARKERS = ("*", "P", "X", "D", "p")


def _birth_style(n: int) -> dict:
    """The n-th birth's marker: colour and shape, so every birth is told apart in the legend."""
    return dict(color=_BIRTH_COLOURS[n % len(_BIRTH_COLOURS)],
                marker=_BIRTH_MARKERS[(n // len(_BIRTH_COLOURS)) % len(_BIRTH_MARKERS)])


def _draw_scenario(ax, truth, scans, fov, known, births, *, zoom):
    from matplotlib.patches import Circle, Wedge

    u = 1e-3  # km -> 10³ km
    ax.add_patch(
        Circle((0, 0), EARTH_RADIUS * u, color="#9cc3e6", ec="#3b6ea5", lw=0.8, zorder=1, label="Earth")
    )
    lo, hi = fov.angle_limits_deg
    ax.add_patch(
        Wedge(
            (0, 0),
            fov.r_max * u,
            lo,
            hi,
            width=(fov.r_max - fov.r_min) * u,
            fc="#fff3c4",
            ec="black",
            lw=1.0,
            zorder=0,
            label=f"sensor FOV ({fov.full_angle_deg:g}° wide, look {fov.look_angle_deg:g}°)",
        )
    )
    for tid, g in truth.groupby("target"):
        is_birth = tid not in known
        ax.plot(
            g["state_0"] * u,
            g["state_1"] * u,
            color="#e07b00" if is_birth else "0.6",
            lw=1.3 if is_birth else 0.6,
            zorder=2,
        )
    ax.plot([], [], color="0.6", lw=0.6, label="true path, object in initial hypothesis")
    if set(truth["target"].unique()) - known:
        ax.plot([], [], color="#e07b00", lw=1.3, label="true path, unknown object (birth)")
    clu = scans[scans["origin"] == CLUTTER]
    det = scans[scans["origin"] != CLUTTER]
    ax.scatter(
        clu["z_0"] * u,
        clu["z_1"] * u,
        s=10 if zoom else 5,
        marker="x",
        color="#d62728",
        lw=0.6,
        alpha=0.7,
        zorder=3,
        label=f"clutter returns ({len(clu)})",
    )
    ax.scatter(
        det["z_0"] * u,
        det["z_1"] * u,
        s=3 if zoom else 1.5,
        color="#1f4e9c",
        zorder=4,
        label=f"returns from objects ({len(det)})",
    )
    for n, (tid, first) in enumerate(births):
        # each birth its own star colour (named in the legend), so no id label sits on the orbits
        # later births smaller and on top: two births entering at one spot show as a ring around a star
        style = _birth_style(n)
        size = (14 if zoom else 10) * max(1.0 - 0.12 * n, 0.4) * (1.0 if style["marker"] == "*" else 0.7)
        ax.plot(first["state_0"] * u, first["state_1"] * u, ls="none", mec="black", mew=0.8, zorder=5 + 0.01 * n,
                ms=size, label=f"birth id {tid}", **style)
    ax.set_aspect("equal")
    ax.set_xlabel("x (10³ km, Earth-centred inertial)")
    ax.set_ylabel("y (10³ km)")
    ax.grid(alpha=0.3)
    if zoom:
        th = np.deg2rad(np.linspace(lo, hi, 50))
        xs = np.concatenate([fov.r_min * np.cos(th), fov.r_max * np.cos(th)]) * u
        ys = np.concatenate([fov.r_min * np.sin(th), fov.r_max * np.sin(th)]) * u
        pad = 0.04 * fov.r_max * u
        ax.set_xlim(xs.min() - pad, xs.max() + pad)
        ax.set_ylim(ys.min() - pad, ys.max() + pad)
    else:
        lim = max(fov.r_max, np.abs(truth[["state_0", "state_1"]].to_numpy()).max(initial=0.0)) * u * 1.05
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)


def plot_scenario(truth: pd.DataFrame, scans: pd.DataFrame, fov: FieldOfView, known_ids, *, title=None):
    """Draw an SSA scenario: Earth, FOV wedge, true paths, returns by origin, births.

    Left panel: the whole orbits; right panel: the FOV enlarged, where the returns are. The
    legend (each birth's marker and the time it enters the FOV) sits below both panels; no text
    is drawn over the data. Drawn only from the
    saved tables (and the FOV), so the figure can be restyled without regenerating the scenario.
    Axes in 10³ km. Returns the matplotlib figure, at the report's line width.
    """
    from matplotlib.lines import Line2D

    truth = validate_truth(truth)
    known = set(np.asarray(known_ids, dtype=int).tolist())
    births = [
        (tid, g[g["in_view"]].iloc[0])
        for tid, g in truth.groupby("target")
        if tid not in known and g["in_view"].any()
    ]
    fig, (ax_all, ax_fov) = figure_style.subplots(1, 2, height=4.6, gridspec_kw={"width_ratios": [1, 1.1]})
    _draw_scenario(ax_all, truth, scans, fov, known, births, zoom=False)
    _draw_scenario(ax_fov, truth, scans, fov, known, births, zoom=True)
    ax_all.set_title("whole orbits")
    ax_fov.set_title("field of view (enlarged)")
    handles, labels = [], []
    for h, lab in zip(*ax_all.get_legend_handles_labels()):
        if not lab.startswith("birth id "):
            handles.append(h)
            labels.append(lab)
    for n, (tid, first) in enumerate(births):
        handles.append(Line2D([], [], ls="none", mec="black", ms=9, **_birth_style(n)))
        labels.append(f"birth id {tid}: first in view at t = {first['time'] / 60:.0f} min")
    figure_style.legend_below(fig, handles, labels, ncol=2)
    n_obj = truth["target"].nunique()
    n_scans = int(truth["scan"].max()) + 1 if len(truth) else 0
    dt_h = (truth["time"].max() if len(truth) else 0.0) / 3600
    fig.suptitle(figure_style.wrap(
        title
        or f"SSA scenario: {n_obj} objects ({len(known)} in the initial hypothesis, "
        f"{n_obj - len(known)} births), {n_scans} scans over {dt_h:.1f} h", fig))
    return fig

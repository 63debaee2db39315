"""The ssa_seeds figure: every seed's value and the quartiles of each metric per case and tracker."""

from __future__ import annotations

import textwrap

import numpy as np
import pandas as pd

from ..ssa import BLIND
from .run import METRICS

__all__ = ["plot_distributions"]


_BIRTH_METRICS = ("births_tracked_end", "birth_latency_mean")  #: undefined for a case without births


def plot_distributions(per_seed: pd.DataFrame, *, title: str):
    """One panel per metric of :data:`METRICS`: every seed's value (dots) and the box of the
    quartiles per case and tracker, so the spread over seeds is seen, not only the mean.

    Horizontal boxes, one row per case and tracker (named once, on the left). A birth metric of
    a case without births (ssa15) is not drawn as 0: its row says "n/a (no births)".
    """
    from ...reporting import figure_style

    groups = [(k, g) for k, g in per_seed.groupby(["case", "tracker"], sort=False) if k[1] != BLIND]
    names = [f"{case}: {g['label'].iloc[0]}" for (case, _), g in groups]
    n_rows = -(-len(METRICS) // 2)
    fig, axes = figure_style.subplots(n_rows, 2, height=min(1.6 + 0.32 * n_rows * len(groups),
                                                            figure_style.MAX_HEIGHT_IN), sharey=True)
    for ax in axes.flat[len(METRICS):]:
        ax.set_axis_off()
    for ax, (metric, what) in zip(axes.flat, METRICS.items()):
        data = []
        for _, g in groups:
            x = g[metric].to_numpy(dtype=float)
            if metric in _BIRTH_METRICS and (g["births"].to_numpy() == 0).all():
                x = np.full_like(x, np.nan)
            data.append(x)
        pos = [i for i, x in enumerate(data) if np.isfinite(x).any()]
        if pos:
            ax.boxplot([data[i][np.isfinite(data[i])] for i in pos], positions=pos, widths=0.5, showfliers=False,
                       orientation="horizontal")
        for i in pos:
            x = data[i][np.isfinite(data[i])]
            jitter = np.linspace(-0.12, 0.12, len(x)) if len(x) > 1 else np.zeros(1)
            ax.plot(x, i + jitter, "o", ms=3, alpha=0.7, color="#2c7bb6")
        for i in set(range(len(groups))) - set(pos):
            why = "n/a (no births)" if metric in _BIRTH_METRICS and (groups[i][1]["births"] == 0).all() else "n/a"
            ax.text(0.02, i, why, transform=ax.get_yaxis_transform(), va="center", color="0.4")
        ax.set_yticks(range(len(names)), names)
        ax.set_ylim(len(names) - 0.4, -0.6)
        ax.set_title(textwrap.fill(what, 30))  # a panel is a third of the page wide
        ax.grid(alpha=0.3, axis="x")
    n = per_seed["seed_index"].nunique()
    fig.suptitle(figure_style.wrap(f"{title}\n{n} scenario seeds; boxes: quartiles, whiskers: 1.5 IQR, dots: "
                                   "one seed each", fig))
    return fig


"""The ssa_seeds figure: every seed's value and the quartiles of each metric per case and tracker, over
scenario seeds and (when run) over chain seeds of the report's realisation."""

from __future__ import annotations

import textwrap

import numpy as np
import pandas as pd

from ..ssa import BLIND
from .run import METRICS

__all__ = ["CHAIN_COLOR", "SEED_COLOR", "plot_distributions"]


_BIRTH_METRICS = ("births_tracked_end", "birth_latency_mean")  #: undefined for a case without births
SEED_COLOR = "#2c7bb6"  #: dots of the scenario seeds
CHAIN_COLOR = "#d7191c"  #: dots of the chain seeds


def _groups(per_seed: pd.DataFrame, per_chain: pd.DataFrame | None) -> list:
    """``(name, rows, colour)`` per drawn row: each case and tracker over scenario seeds, followed by the
    same case and tracker over chain seeds when the chain table has it."""
    chains = {} if per_chain is None else {k: g for k, g in per_chain.groupby(["case", "tracker"], sort=False)
                                           if k[1] != BLIND}
    out = []
    for (case, tracker), g in per_seed.groupby(["case", "tracker"], sort=False):
        if tracker == BLIND:
            continue
        label = g["label"].iloc[0]
        out.append((f"{case}: {label}", g, SEED_COLOR))
        if (case, tracker) in chains:
            out.append((f"{case}: {label}, chain seeds", chains[(case, tracker)], CHAIN_COLOR))
    return out


def plot_distributions(per_seed: pd.DataFrame, *, title: str, per_chain: pd.DataFrame | None = None):
    """One panel per metric of :data:`METRICS`: every seed's value (dots) and the box of the
    quartiles per case and tracker, so the spread over seeds is seen, not only the mean.

    Horizontal boxes, one row per case and tracker (named once, on the left); with ``per_chain`` (the
    table of :func:`.chains.run_chain_seed`) each case and tracker run over chain seeds gets a second
    row under its scenario-seed row, its dots in :data:`CHAIN_COLOR`: the spread of the chain's own
    randomness on the report's realisation beside the spread over realisations. A birth metric of
    a case without births (ssa15) is not drawn as 0: its row says "n/a (no births)".
    """
    from ...reporting import figure_style

    groups = _groups(per_seed, per_chain)
    names = [name for name, _, _ in groups]
    n_rows = -(-len(METRICS) // 2)
    fig, axes = figure_style.subplots(n_rows, 2, height=min(1.6 + 0.32 * n_rows * len(groups),
                                                            figure_style.MAX_HEIGHT_IN), sharey=True)
    for ax in axes.flat[len(METRICS):]:
        ax.set_axis_off()
    for ax, (metric, what) in zip(axes.flat, METRICS.items()):
        data = []
        for _, g, _ in groups:
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
            ax.plot(x, i + jitter, "o", ms=3, alpha=0.7, color=groups[i][2])
        for i in set(range(len(groups))) - set(pos):
            why = "n/a (no births)" if metric in _BIRTH_METRICS and (groups[i][1]["births"] == 0).all() else "n/a"
            ax.text(0.02, i, why, transform=ax.get_yaxis_transform(), va="center", color="0.4")
        ax.set_yticks(range(len(names)), names)
        for tick, (_, _, colour) in zip(ax.get_yticklabels(), groups):
            tick.set_color(colour if colour == CHAIN_COLOR else "black")
        ax.set_ylim(len(names) - 0.4, -0.6)
        ax.set_title(textwrap.fill(what, 30))  # a panel is a third of the page wide
        ax.grid(alpha=0.3, axis="x")
    n = per_seed["seed_index"].nunique()
    over = f"{n} scenario seeds"
    if per_chain is not None and len(per_chain):
        over += (f" (blue); {per_chain['chain_index'].nunique()} chain seeds of the report's realisation, "
                 "the scenario fixed (red)")
    fig.suptitle(figure_style.wrap(f"{title}\n{over}; boxes: quartiles, whiskers: 1.5 IQR, dots: one seed each", fig))
    return fig

"""Document 003 Figs 5.1, 5.2 and 5.3, drawn from the swap curves and rates of :mod:`.run`."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .run import swap_curve

__all__ = ["plot_swap_figures"]


def plot_swap_figures(curves: pd.DataFrame, rates: pd.DataFrame, *, distance: float, n_sensors: int,
                      sigma: float, paths: dict) -> None:
    """Document 003 Figs 5.1, 5.2 and 5.3; ``paths`` maps ``fig51/fig52/fig53`` to ``(pdf, png)``.

    Each is drawn at the 0.6 line width the report places it at, its legend below the axes."""
    from ...reporting import figure_style

    c = swap_curve(curves, distance)
    n = int(c["n_runs"].iloc[0])
    setting = f"{distance:g} m apart, {n_sensors} sensors, σ = {sigma:g} m, {n} runs"

    def figure(key, draw, xlabel, ylabel, title):
        fig, ax = figure_style.subplots(width=0.6, height=3.3)
        draw(ax)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(figure_style.wrap(title, fig, 8.5))
        figure_style.legend_below(fig, ncol=1)
        figure_style.save(fig, *paths[key], width=0.6)

    i_min = int(c["swaps"].to_numpy()[np.argmin(c["rms"].to_numpy())])

    def fig51(ax):
        ax.plot(c["swaps"], c["rms"], "o-", ms=3)
        ax.axvline(i_min, color="gray", ls=":", label=f"minimum at {i_min} swaps")

    def fig52(ax):
        ax.plot(c["swaps"], c["log_prob_single"], "o-", ms=3, label="unique hypothesis")
        ax.plot(c["swaps"], c["log_prob_class"], "s-", ms=3, label="hypothesis class (Eq. 5.22)")

    def fig53(ax):
        ax.plot(rates["distance"], rates["rms_optimal_rate"], "o-", ms=3, label="minimum RMS error (Fig 5.1 criterion)")
        ax.plot(rates["distance"], rates["class_optimal_rate"], "s--", ms=3, label="maximum class posterior (Eq. 5.22)")
        ax.set_ylim(-0.02, 0.55)

    figure("fig51", fig51, "number of random measurement swaps i", "RMS error of the equivalent measurement (m)",
           f"Fig 5.1: equivalent-measurement error vs swaps\n({setting})")
    figure("fig52", fig52, "number of swaps i", "average log posterior probability",
           f"Fig 5.2: single-hypothesis vs class posterior\n({setting})")
    figure("fig53", fig53, "distance between targets (m)", "optimal swap rate i*/N",
           f"Fig 5.3: optimal swap rate vs target separation\n({n_sensors} sensors, σ = {sigma:g} m, "
           f"{n} runs per distance)")


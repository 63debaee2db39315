"""Figures of the closely spaced targets experiment (document 003 Table 6.1, Figs 6.1–6.2), from saved tables,\ndrawn at the report's line width with their legends beside the axes."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .run import LABELLED_IDEAL
from .oracle import ideal_mospa_per_scan

__all__ = ["plot_mospa_vs_scan", "plot_realisation"]

COLOURS = {"ideal": "k", LABELLED_IDEAL: "tab:gray", "PDAF": "tab:red", "MHT": "tab:orange", "ECMHT": "tab:blue"}


def _save(fig, pdf, png) -> None:
    from ...reporting import figure_style

    figure_style.save(fig, pdf, png, width=1.0)


def plot_mospa_vs_scan(curves: pd.DataFrame, table: pd.DataFrame, cfg, pdf, png) -> None:
    """MOSPA over time of every method (Monte Carlo), the ideal's closed form, and the published averages."""
    from ...reporting import figure_style

    fig, ax = figure_style.subplots(height=4.2)
    extra_styles = iter([(":", "tab:purple"), ("-.", "tab:brown"), ("--", "tab:olive")])
    for method, c in curves.groupby("method", sort=False):
        style, colour = ("-", COLOURS[method]) if method in COLOURS else next(extra_styles)
        label = {"PDAF": f"PDAF ({cfg['pdaf_variant']})", LABELLED_IDEAL: "ideal, own targets (labelled)"}.get(method,
                                                                                                          method)
        ax.plot(c["time"], c["mospa"], style, color=colour, label=label, lw=1.2)
    model = {k: cfg[k] for k in ("sigma2", "gamma", "n_scans", "n_sensors", "R", "dt", "initial_variance")}
    t = cfg["dt"] * np.arange(1, cfg["n_scans"])
    ax.plot(t, ideal_mospa_per_scan(**model), "o", ms=2.5, mfc="none", color="k", label="ideal, closed form")
    ax.plot(t, ideal_mospa_per_scan(**model, scoring="labelled"), "s", ms=2.5, mfc="none", color="tab:gray",
            label="labelled, closed form")
    for method, published in zip(table["method"], table["published"]):
        if pd.notna(published) and method in TABLE_METHODS:
            ax.axhline(published, color=COLOURS[method], ls="--", lw=0.8)
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("MOSPA of the one-step prediction X(k|k-1) (m²)")
    n = int(table["n"].iloc[0])
    ax.set_title(f"Two closely spaced OU targets, {cfg['n_sensors']} sensors: MOSPA over time\n"
                 f"(mean of {n} runs; markers: closed form;\ndashed: published Table 6.1 averages)")
    figure_style.legend_right(ax)
    _save(fig, pdf, png)


TABLE_METHODS = ("ideal", "PDAF", "MHT", "ECMHT")


def plot_realisation(table: pd.DataFrame, cfg, paths: dict) -> None:
    """Figs 6.1 and 6.2 from :func:`~.closely_spaced.realisation_table`; ``paths`` maps fig61/fig62 to (pdf, png)."""
    from ...reporting import figure_style

    def figure(other, colour, title, pdf, png):
        fig, ax = figure_style.subplots(height=3.6)
        for j in range(2):
            ax.plot(table["time"], table[f"truth_{j}"], "k-", lw=2, label="truth" if j == 0 else None)
            ax.plot(table["time"], table[f"{other}_{j}"], "--", color=colour,
                    label=f"{other} tracks" if j == 0 else None)
            ax.plot(table["time"], table[f"ECMHT_{j}"], "-", color="tab:blue", lw=1,
                    label="ECMHT tracks" if j == 0 else None)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("position (m)")
        ax.set_title(title)
        figure_style.legend_right(ax)
        _save(fig, pdf, png)

    figure("MHT", "tab:orange", "Fig 6.1: the ECMHT does not show the MHT's track repulsion\n"
           f"(one realisation, {cfg['n_sensors']} sensors, filtered estimates X(k|k))", *paths["fig61"])
    figure("PDAF", "tab:red", "Fig 6.2: the ECMHT does not show the PDAF's track coalescence\n"
           f"(same realisation; PDAF form '{cfg['pdaf_variant']}')", *paths["fig62"])

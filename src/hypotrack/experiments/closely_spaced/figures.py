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


_PANELS = (("ideal filters", ("ideal", LABELLED_IDEAL)), ("PDAF forms", ("PDAF",)), ("MHT", ("MHT",)),
           ("ECMHT", ("ECMHT",)))  #: small multiples: which methods each panel of the MOSPA figure draws


def _panel_of(method: str) -> int:
    """The panel a method's curve goes in: its family (``PDAF[parallel]`` with the PDAF)."""
    family = method.split("[")[0]
    if method == LABELLED_IDEAL:
        return 0
    for i, (_, methods) in enumerate(_PANELS):
        if family in methods:
            return i
    return len(_PANELS) - 1


def plot_mospa_vs_scan(curves: pd.DataFrame, table: pd.DataFrame, cfg, pdf, png) -> None:
    """MOSPA over time of every method (Monte Carlo), the ideal's closed form, and the published averages.

    Small multiples, one panel per family (ideal filters, PDAF forms, MHT, ECMHT) on one shared
    log axis, each with its published Table 6.1 average (dashed) and the ideal filter's Monte
    Carlo curve as a grey reference, so no panel carries more than five series.
    """
    from ...reporting import figure_style

    fig, axes = figure_style.subplots(2, 2, height=5.4, sharex=True, sharey=True)
    axes = axes.ravel()
    extra_styles = iter([(":", "tab:purple"), ("-.", "tab:brown"), ("--", "tab:olive"), (":", "tab:cyan")] * 3)
    ideal = curves[curves["method"] == "ideal"]
    for ax in axes[1:]:
        if len(ideal):
            ax.plot(ideal["time"], ideal["mospa"], "-", color="0.75", lw=2.5, zorder=1,
                    label="ideal (Monte Carlo), for reference")
    for method, c in curves.groupby("method", sort=False):
        style, colour = ("-", COLOURS[method]) if method in COLOURS else next(extra_styles)
        label = {"PDAF": f"PDAF ({cfg['pdaf_variant']})", LABELLED_IDEAL: "ideal, own targets (labelled)"}.get(method,
                                                                                                          method)
        axes[_panel_of(method)].plot(c["time"], c["mospa"], style, color=colour, label=label, lw=1.2, zorder=3)
    model = {k: cfg[k] for k in ("sigma2", "gamma", "n_scans", "n_sensors", "R", "dt", "initial_variance")}
    t = cfg["dt"] * np.arange(1, cfg["n_scans"])
    # closed forms as sparse markers (every 4th scan, offset from each other) over the Monte Carlo lines
    axes[0].plot(t, ideal_mospa_per_scan(**model), "o", ms=3, mfc="none", color="k", markevery=(0, 4), zorder=4,
                 label="ideal, closed form")
    axes[0].plot(t, ideal_mospa_per_scan(**model, scoring="labelled"), "s", ms=3, mfc="none", color="tab:gray",
                 markevery=(2, 4), zorder=4, label="labelled, closed form")
    for method, published in zip(table["method"], table["published"]):
        if pd.notna(published) and method in TABLE_METHODS:
            axes[_panel_of(method)].axhline(published, color=COLOURS[method], ls="--", lw=0.8, zorder=2,
                                            label=f"{method}: published Table 6.1 average")
    for ax, (title, _) in zip(axes, _PANELS):
        ax.set_yscale("log")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[2:]:
        ax.set_xlabel("time (s)")
    for ax in axes[::2]:
        ax.set_ylabel("MOSPA of X(k|k-1) (m²)")
    n = int(table["n"].iloc[0])
    figure_style.legend_below(fig, ncol=2)
    fig.suptitle(figure_style.wrap(f"Two closely spaced OU targets, {cfg['n_sensors']} sensors: MOSPA over time "
                                   f"(mean of {n} runs; dashed: published Table 6.1 averages)", fig))
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

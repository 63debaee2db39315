"""Document 003 Fig. 4.2, drawn from the counts table of :func:`.run.realisation_tables`."""

from __future__ import annotations

import pandas as pd

__all__ = ["plot_realisation"]


def plot_realisation(counts: pd.DataFrame, cfg):
    """Document 003 Fig. 4.2: truth, measured counts and every method's estimated number of targets
    over one realisation (``counts`` from :func:`.run.realisation_tables`; ``cfg`` the config section).

    The Tetris tracker and the count DP often agree exactly, so they differ in every channel: the
    Tetris estimate is a wide pale step line, the count DP dark crosses at every scan on top of it
    (a cross off the line is a scan where they differ). The legend sits below the axes.
    """
    from ...reporting import figure_style

    fig, ax = figure_style.subplots(height=4.0)
    ax.plot(counts["scan"], counts["r"], ".", color="0.6", ms=3, label=r"measured count $r_k$")
    ax.step(counts["scan"], counts["n_true"], "k-", lw=1.4, where="mid", label=r"truth $n_k$")
    ax.step(counts["scan"], counts["cardinality_tracker"], "-", color="tab:blue", lw=3.5, alpha=0.45, where="mid",
            label="cardinality tracker (Tetris): wide pale line")
    ax.plot(counts["scan"], counts["exact_class_map"], "x", color="navy", ms=3.5, mew=0.9,
            label="exact class MAP (count DP): crosses")
    ax.step(counts["scan"], counts["classical_mht"], "-.", color="tab:red", lw=1.2, where="mid",
            label="classical MHT (MAP hypothesis)")
    ax.set_xlabel("scan k")
    ax.set_ylabel("number of targets")
    ax.set_title(f"Fig 4.2: cardinality tracking, truth vs estimated number of targets\n"
                 f"N = {cfg['n_scans']} scans, $p_\\chi$ = {cfg['p_chi']:g}, "
                 f"$\\lambda_b$ = {cfg['lambda_b']:g}, $\\lambda_{{fa}}$ = {cfg['lambda_fa']:g}, $p_D$ = {cfg['p_d']:g}")
    figure_style.legend_below(fig, ncol=2)
    return fig


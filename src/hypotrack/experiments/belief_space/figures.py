"""The belief_space figures: document 001 Eq. 39, Eq. 43 and Sec. V-A, drawn from the tables of :mod:`.run`."""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["plot_eq43", "plot_equivalence", "plot_ratio"]


def _save(fig, paths, width: float = 1.0) -> None:
    """Check the figure is legible at ``width`` × the line width, save it (PDF for the paper, PNG for
    the report) and release it."""
    from ...reporting import figure_style

    pdf, png = paths
    figure_style.save(fig, pdf, png, width=width)


def plot_ratio(ratio: pd.DataFrame, paths, cfg) -> None:
    """Document 001 Eq. 39: the undetected-birth weight ratio against α (top) and which birth model
    makes it exact (bottom); legends beside the panels."""
    from ...reporting import figure_style

    fig, (ax, ax2) = figure_style.subplots(2, 1, height=5.2)
    for i, p_D in enumerate(sorted(ratio["p_D"].unique())):
        d = ratio[ratio["p_D"] == p_D].sort_values("alpha")
        ax.loglog(d["alpha"], d["eq39"], "-", color=f"C{i}", lw=1)
        ax.loglog(d["alpha"], d["engine_poisson_limit"], "o", color=f"C{i}", ms=5, mfc="none", label=f"$p_D$ = {p_D:g}")
        ax.loglog(d["alpha"], d["engine_binomial"], "x", color=f"C{i}", ms=5)
    ax.plot([], [], "k-", lw=1, label="Eq. 39: $(1-p_D)\\alpha$")
    ax.plot([], [], "ko", mfc="none", label="engine, Poisson-limit birth")
    ax.plot([], [], "kx", label="engine, exact binomial birth")
    ax.set_xlabel("birth probability per pixel α (probability)")
    # in words: the symbols' nested scripts (v' under w) would print under 6 pt
    ax.set_ylabel("weight ratio, undetected birth\nover its twin (dimensionless)")
    ax.set_title("Undetected birth vs its twin (document 001 Eq. 39)")
    figure_style.legend_right(ax)
    d = ratio.sort_values("alpha")
    for col, eng, style, label in (("eq39", "engine_poisson_limit", "C0", "Eq. 39 / Eq. 33 (Poisson limit)"),
                                   ("exact_binomial", "engine_binomial", "C3", "exact binomial: 1/(1-α)"),
                                   ("single_event", "engine_single_event", "C2",
                                    f"document 000 Eq. 30:\n1/(1-{int(cfg['n_pixels'])}α-2β)")):
        ax2.semilogx(d["alpha"], d[col] / d["eq39"], "-", color=style, lw=1, label=label + " (formula)")
        ax2.semilogx(d["alpha"], d[eng] / d["eq39"], "o", color=style, ms=4, mfc="none")
    ax2.plot([], [], "ko", mfc="none", label=r"engine (all $p_D$)")
    ax2.set_xlabel("birth probability per pixel α (probability)")
    ax2.set_ylabel("ratio / $(1-p_D)\\alpha$ (dimensionless)")
    ax2.set_title("Which birth model makes Eq. 39 exact")
    figure_style.legend_right(ax2)
    _save(fig, paths)


def plot_eq43(offsets: pd.DataFrame, noise: pd.DataFrame, paths, cfg) -> None:
    """Document 001 Eq. 43 across a pixel (top) and at its centre against the noise (bottom); legends
    beside the panels."""
    from ...reporting import figure_style

    L = float(cfg["pixel_size"])
    fig, (ax, ax2) = figure_style.subplots(2, 1, height=5.4)
    ax.plot(offsets["offset_pixels"], offsets["uniform_formula"], "k-", label="uniform pixel birth (formula)")
    ax.plot(offsets["offset_pixels"], offsets["gaussian_formula"], "C3-", lw=1,
            label="Gaussian (moment-matched)\nbirth (formula)")
    ax.plot(offsets["offset_pixels"], offsets["engine"], "C3o", ms=4, mfc="none", label="engine weights")
    ax.axhline(1, color="grey", lw=0.8, ls="--", label="Eq. 43 bound")
    ax.set_xlabel("offset of z* from the pixel centre (pixel widths)")
    ax.set_ylabel("weight ratio (birth over twin)\n/ $(1-p_D)$ (dimensionless)")  # no nested scripts
    ax.set_title(f"Eq. 43 across a {L:g} m pixel, $\\sigma_R$ = {cfg['measurement_std']:g} m")
    figure_style.legend_right(ax)
    x = noise["spread_over_pixel_area"]
    ax2.semilogx(x, noise["uniform_formula"], "k-", label="uniform pixel birth (formula)")
    ax2.semilogx(x, noise["variance_matched_analytic"], "C0--", lw=1, label="Gaussian, variance $L^2/12$\n(analytic)")
    ax2.semilogx(x, noise["gaussian_formula"], "C3-", lw=1, label="Gaussian, engine's moment\nmatch (formula)")
    ax2.semilogx(x, noise["engine"], "C3o", ms=4, mfc="none", label="engine weights")
    ax2.axhline(1, color="grey", lw=0.8, ls="--")
    ax2.axvline((6 / np.pi - 1) / 12, color="C0", lw=0.8, ls=":", label="threshold $(6/\\pi-1)/12$")
    ax2.set_xlabel("position variance added per axis in one scan / pixel area")
    ax2.set_ylabel("ratio at the pixel centre / $(1-p_D)$")
    ax2.set_title("Eq. 43 at the pixel centre vs noise")
    figure_style.legend_right(ax2)
    _save(fig, paths)


def plot_equivalence(equiv: pd.DataFrame, paths) -> None:
    """Document 001 Sec. V-A: FISST and HOMHT posteriors coincide for a fixed number of targets."""
    from ...reporting import figure_style

    fig, ax = figure_style.subplots(width=0.7, height=3.2)
    for run, d in equiv.groupby("run"):
        lw = np.maximum(d["max_abs_dlogw_fisst_reid"], 1e-17)
        ax.semilogy(d["scan"], lw, "o-", color="C0", ms=3, lw=0.8,
                    label="FISST vs HOMHT: max |Δ log w|" if run == 0 else None)
        ax.semilogy(d["scan"], np.maximum(d["tv_hfisst_reid"], 1e-17), "s--", color="C3", ms=3, lw=0.8,
                    label="H-FISST vs HOMHT: TV distance" if run == 0 else None)
    ax.set_xlabel("scan")
    ax.xaxis.get_major_locator().set_params(integer=True)
    ax.set_ylabel("difference between posteriors (dimensionless)")
    ax.set_title(f"Fixed number of targets: FISST = HOMHT\n(document 001 Sec. V-A; {equiv['run'].nunique()} "
                 "seeded cluttered\nscenarios, exhaustive children)")
    figure_style.legend_below(fig, ncol=1)
    _save(fig, paths, width=0.7)


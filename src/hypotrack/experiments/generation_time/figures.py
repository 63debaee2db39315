"""Figures of the hypothesis-engine experiments (document 000 Fig. 15 and the throughput benchmark), drawn at
the size the report prints them (:mod:`hypotrack.reporting.figure_style`)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting import figure_style

__all__ = ["plot_generation_time", "plot_throughput", "plot_difficulty", "DIFFICULTY_ROWS", "OUTCOME_COLUMNS"]

_STYLE = {
    "homht": dict(color="tab:blue", marker="o", label="HOMHT exhaustive (Reid weights)", short="exhaustive HOMHT"),
    "rfisst": dict(color="tab:green", marker="s", label="R-FISST MCMC (H-FISST weights)", short="R-FISST"),
    "homht_kbest": dict(color="tab:orange", marker="^", label="HOMHT Murty k-best (Reid)",
                        short="Murty k-best HOMHT"),
}

# the columns of the Fig. 15 table that do not depend on the machine (byte-identical reruns)
OUTCOME_COLUMNS = ["method", "n_objects", "n_returns", "log10_hypotheses", "broken", "n_generated",
                   "truth_found", "truth_rank", "map_is_truth", "lsa_is_truth"]


def _save(fig, pdf, png, width: float = 1.0):
    figure_style.save(fig, pdf, png, width=width)


def plot_generation_time(table: pd.DataFrame, pdf, png, *, budget: float, mcmc_steps: int, keep: int):
    """Document 000 Fig. 15 restyled: generation time of one parent's children vs log10 A(M, m).

    The legend sits below the axes and names the two reference lines, so no curve and no "not
    generated" cross is hidden by a label.
    """
    fig, ax = figure_style.subplots(height=4.6)
    square = table["n_objects"] == table["n_returns"]
    for method, style in _STYLE.items():
        d = table[(table["method"] == method) & table["seconds"].notna()].sort_values("log10_hypotheses")
        if d.empty:
            continue
        sq = d[square.loc[d.index]]
        label = style["label"] + (f", {mcmc_steps:,} steps" if method == "rfisst" else "")
        label += f", best {keep}" if method != "rfisst" else ""
        ax.plot(sq["log10_hypotheses"], sq["seconds"], color=style["color"], lw=1.2, marker=style["marker"],
                ms=3.5, label=label + " (M = m)")
        rect = d[~square.loc[d.index]]
        if not rect.empty:
            ax.plot(rect["log10_hypotheses"], rect["seconds"], ls="none", marker=style["marker"], mfc="none",
                    color=style["color"], ms=6, label=style["short"] + " (M ≠ m)")
    missed = table[table["seconds"].notna() & ~table["truth_found"].astype(bool)]
    if not missed.empty:
        names = sorted({_STYLE.get(m, {}).get("short", m) for m in missed["method"]})
        ax.plot(missed["log10_hypotheses"], missed["seconds"], ls="none", marker="x", color="red", ms=9, mew=2,
                zorder=5, label=f"true association not generated (cross drawn on the {', '.join(names)} point)")
    # the two reference lines are named in the legend, so no text sits on the curves
    ax.axvline(np.log10(budget), color="tab:blue", ls="--", lw=1,
               label=f"exhaustive budget {figure_style.pow10(np.log10(budget))} events: HOMHT breaks beyond")
    ax.axvline(33, color="grey", ls=":", lw=1, label="the paper's reach (A ≈ 10³³)")
    ax.set_yscale("log")
    ax.set_xlabel("log10 of the number of possible hypotheses A(M, m) of one parent")
    ax.set_ylabel("hypothesis-generation time per parent (s)")
    ax.set_title("Hypothesis generation time vs number of possible hypotheses (cf. document 000 Fig. 15)")
    ax.grid(True, which="both", alpha=0.3)
    figure_style.legend_below(fig, ncol=2)
    _save(fig, pdf, png)


def plot_throughput(table: pd.DataFrame, pdf, png):
    """Measured throughputs (bars) against the performance targets (red ticks), log scale."""
    d = table[table["per_second"].notna()].reset_index(drop=True)
    fig, ax = figure_style.subplots(height=0.28 * len(d) + 1.6)
    y = np.arange(len(d))
    ax.barh(y, d["per_second"], color="tab:green", alpha=0.8, label="measured")
    labelled = False
    for i, t in enumerate(d["target_per_second"]):
        if np.isfinite(t):
            ax.plot([t, t], [i - 0.4, i + 0.4], color="red", lw=2, label=None if labelled else "target")
            labelled = True
    ax.set_yticks(y, d["label"])
    ax.set_xscale("log")
    ax.set_xlim(1e5, 10 ** np.ceil(np.log10(max(d["per_second"].max(), 1e7) * 1.5)))
    ax.set_xlabel("per second, one core\n(MCMC: proposals; exhaustive: children enumerated + weighted)")
    ax.set_title("Hypothesis-engine throughput vs its performance targets")
    ax.grid(True, axis="x", which="both", alpha=0.3)
    figure_style.legend_below(fig, ncol=2)
    _save(fig, pdf, png)


# drawn in this order: the wide translucent exact line underneath, the completion's large hollow
# diamonds over it, the chain's small filled squares on top: where the three coincide (all find
# the MAP child, say) every one of them stays visible, and the legend says so
_DIFF_STYLE = {
    "murty": dict(color="tab:orange", marker="^", ms=3.5, mfc=None, lw=3.0, ls="-", alpha=0.55,
                  label="exact best k (Murty per detection count), wide band under the others"),
    "chain_completion": dict(color="tab:purple", marker="D", ms=6.5, mfc="none", lw=1.2, ls="--", alpha=1.0,
                             label="R-FISST: chain + neighbour completion (omitted where over its budget); "
                                   "hollow diamonds, visible where it coincides with the others"),
    "chain": dict(color="tab:green", marker="s", ms=3.0, mfc=None, lw=1.0, ls="-", alpha=1.0,
                  label="R-FISST: the paper's chain alone, small squares on top where the series coincide"),
}


DIFFICULTY_ROWS = {
    "mass": ("mass_captured_mean", "posterior mass captured (mean over problems)"),
    "map": ("map_found_rate", "MAP child found (fraction of problems)"),
    "truth": ("truth_found_rate", "true association found (fraction of problems)"),
}  #: the three measures of :func:`plot_difficulty`, one figure each


def plot_difficulty(summary: pd.DataFrame, pdf, png, *, labels: dict, mcmc_steps: int, keep: int,
                    reference_k: int, exhaustive_max_events: int, measure: str = "mass"):
    """One measure (``DIFFICULTY_ROWS``: mass captured, MAP found or truth found) vs log10 A,
    one panel per difficulty (object spacing), the legend in the free panel or below."""
    if measure not in DIFFICULTY_ROWS:
        raise ValueError(f"measure must be one of {sorted(DIFFICULTY_ROWS)}, got {measure!r}")
    col, what = DIFFICULTY_ROWS[measure]
    diffs = [d for d in labels if (summary["difficulty"] == d).any()]
    n_cols = min(3, max(len(diffs), 1))
    spare = -len(diffs) % n_cols
    n_rows = -(-len(diffs) // n_cols)
    fig, axes = figure_style.subplots(n_rows, n_cols, height=1.75 * n_rows + 0.9 + (0.0 if spare else 0.7),
                                      sharex=True, sharey=True, squeeze=False)
    for i, d in enumerate(diffs):
        ax = axes.flat[i]
        sd = summary[summary["difficulty"] == d].sort_values("log10_hypotheses")
        for method, style in _DIFF_STYLE.items():
            m = sd[sd["method"] == method]
            label = style["label"] + (f" ({mcmc_steps:,} steps)" if method != "murty" else f" (k = {keep})")
            ax.plot(m["log10_hypotheses"], m[col], color=style["color"], marker=style["marker"], ms=style["ms"],
                    mfc=style["mfc"], mew=1.0, lw=style["lw"], ls=style["ls"], alpha=style["alpha"], label=label)
        ax.axvline(np.log10(exhaustive_max_events), color="grey", ls=":", lw=1)
        ax.set_ylim(-0.05, 1.05)
        ax.grid(True, alpha=0.3)
        ax.set_title(labels[d])
        if i % n_cols == 0:
            ax.set_ylabel(what.split(" (")[0].replace("posterior ", "posterior\n"))
        if i >= len(diffs) - n_cols:
            ax.set_xlabel("log10 A(M, m)")
            ax.xaxis.set_tick_params(labelbottom=True)
    handles, texts = axes.flat[0].get_legend_handles_labels()
    handles.append(plt_line(color="grey", ls=":"))
    texts.append(f"mass relative to all children left of this line, to the exact best {reference_k} right of it")
    texts = [figure_style.wrap(t, fig, 7.5, 0.31) for t in texts]
    if spare:
        for ax in axes.flat[len(diffs):]:
            ax.axis("off")
        axes.flat[len(diffs)].legend(handles, texts, loc="center", fontsize=7.5)
    else:
        figure_style.legend_below(fig, handles, texts, ncol=2)
    fig.suptitle(figure_style.wrap(f"Hypothesis generation on problems with real ambiguity: {what}", fig))
    figure_style.save(fig, pdf, png, width=1.0)


def plt_line(**style):
    """A legend handle: a line of the given style."""
    from matplotlib.lines import Line2D

    return Line2D([], [], **style)

"""Figures of the hypothesis-engine experiments (seed 000 Fig. 15 and the throughput benchmark)."""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["plot_generation_time", "plot_throughput", "plot_difficulty", "OUTCOME_COLUMNS"]

_STYLE = {
    "homht": dict(color="tab:blue", marker="o", label="HOMHT, exhaustive (Reid weights)", short="exhaustive HOMHT"),
    "rfisst": dict(color="tab:green", marker="s", label="R-FISST, MCMC search (H-FISST weights)", short="R-FISST"),
    "homht_kbest": dict(color="tab:orange", marker="^", label="HOMHT, Murty k-best (Reid weights)",
                        short="Murty k-best HOMHT"),
}

# the columns of the Fig. 15 table that do not depend on the machine (byte-identical reruns)
OUTCOME_COLUMNS = ["method", "n_objects", "n_returns", "log10_hypotheses", "broken", "n_generated",
                   "truth_found", "truth_rank", "map_is_truth", "lsa_is_truth"]


def _save(fig, pdf, png):
    fig.savefig(pdf)
    fig.savefig(png, dpi=150)


def plot_generation_time(table: pd.DataFrame, pdf, png, *, budget: float, mcmc_steps: int, keep: int):
    """Seed 000 Fig. 15 restyled: generation time of one parent's children vs log10 A(M, m)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 5.2), layout="constrained")
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
        ax.plot(missed["log10_hypotheses"], missed["seconds"], ls="none", marker="x", color="red", ms=9, mew=2,
                label="true association not generated")
    ax.axvline(np.log10(budget), color="tab:blue", ls="--", lw=1)
    ax.annotate(f"exhaustive budget {budget:.0e} events:\nHOMHT breaks beyond", xy=(np.log10(budget), 0.98),
                xycoords=("data", "axes fraction"), ha="left", va="top", fontsize=8, color="tab:blue",
                xytext=(4, 0), textcoords="offset points")
    ax.axvline(33, color="grey", ls=":", lw=1)
    ax.annotate("paper's reach\n(A ≈ 1e33)", xy=(33, 0.02), xycoords=("data", "axes fraction"), fontsize=8,
                color="grey", xytext=(4, 0), textcoords="offset points")
    ax.set_yscale("log")
    ax.set_xlabel("log10 of the number of possible hypotheses A(M, m) of one parent")
    ax.set_ylabel("hypothesis-generation time per parent (s)")
    ax.set_title("Hypothesis generation time vs number of possible hypotheses (cf. seed 000 Fig. 15)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    _save(fig, pdf, png)
    plt.close(fig)


def plot_throughput(table: pd.DataFrame, pdf, png):
    """Measured throughputs (bars) against the performance targets (red ticks), log scale."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = table[table["per_second"].notna()].reset_index(drop=True)
    fig, ax = plt.subplots(figsize=(9.5, 4.6), layout="constrained")
    y = np.arange(len(d))
    ax.barh(y, d["per_second"], color="tab:green", alpha=0.8, label="measured")
    labelled = False
    for i, t in enumerate(d["target_per_second"]):
        if np.isfinite(t):
            ax.plot([t, t], [i - 0.4, i + 0.4], color="red", lw=2, label=None if labelled else "target")
            labelled = True
    ax.set_yticks(y, d["label"], fontsize=8)
    ax.set_xscale("log")
    ax.set_xlim(1e5, 10 ** np.ceil(np.log10(max(d["per_second"].max(), 1e7) * 1.5)))
    ax.set_xlabel("per second, one core (MCMC: proposals; exhaustive: children enumerated + weighted)")
    ax.set_title("Hypothesis-engine throughput vs its performance targets")
    ax.grid(True, axis="x", which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    _save(fig, pdf, png)
    plt.close(fig)


# drawn in this order: the wide exact line underneath, the dashed completion over it, the chain on top
_DIFF_STYLE = {
    "murty": dict(color="tab:orange", marker="^", lw=3.0, ls="-", alpha=0.55,
                  label="exact best k (Murty per detection count)"),
    "chain_completion": dict(color="tab:purple", marker="D", lw=1.4, ls="--", alpha=1.0,
                             label="R-FISST: chain + neighbour completion (omitted where over its budget)"),
    "chain": dict(color="tab:green", marker="s", lw=1.2, ls="-", alpha=1.0, label="R-FISST: the paper's chain alone"),
}


def plot_difficulty(summary: pd.DataFrame, pdf, png, *, labels: dict, mcmc_steps: int, keep: int,
                    reference_k: int, exhaustive_max_events: int):
    """Mass captured, MAP-found and truth-found rates vs log10 A, one column per difficulty."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    diffs = [d for d in labels if (summary["difficulty"] == d).any()]
    rows = [("mass_captured_mean", "posterior mass captured\n(mean over problems)"),
            ("map_found_rate", "MAP child found\n(fraction of problems)"),
            ("truth_found_rate", "true association found\n(fraction of problems)")]
    fig, axes = plt.subplots(len(rows), len(diffs), figsize=(3.0 * len(diffs) + 1.0, 7.8), sharex=True,
                             sharey=True, layout="constrained", squeeze=False)
    for c, d in enumerate(diffs):
        sd = summary[summary["difficulty"] == d].sort_values("log10_hypotheses")
        for r, (col, ylabel) in enumerate(rows):
            ax = axes[r, c]
            for method, style in _DIFF_STYLE.items():
                m = sd[sd["method"] == method]
                label = style["label"] + (f" ({mcmc_steps:,} steps)" if method != "murty" else f" (k = {keep})")
                ax.plot(m["log10_hypotheses"], m[col], color=style["color"], marker=style["marker"], ms=3.5,
                        lw=style["lw"], ls=style["ls"], alpha=style["alpha"], label=label)
            ax.axvline(np.log10(exhaustive_max_events), color="grey", ls=":", lw=1)
            ax.set_ylim(-0.05, 1.05)
            ax.grid(True, alpha=0.3)
            if c == 0:
                ax.set_ylabel(ylabel)
            if r == 0:
                ax.set_title(labels[d], fontsize=9)
            if r == len(rows) - 1:
                ax.set_xlabel("log10 A(M, m)")
    handles, texts = axes[0, 0].get_legend_handles_labels()
    handles.append(plt.Line2D([], [], color="grey", ls=":"))
    texts.append(f"mass relative to all children left of this line, to the exact best {reference_k} right of it")
    fig.legend(handles, texts, loc="outside lower center", ncol=2, fontsize=8)
    fig.suptitle("Hypothesis generation on problems with real ambiguity: objects 8 to 1 sigma apart with missed "
                 "detections and Poisson clutter (left: the paper-style problem)", fontsize=10)
    _save(fig, pdf, png)
    plt.close(fig)

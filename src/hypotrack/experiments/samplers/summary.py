"""Figure and ledger rows of the sampler head-to-head (:mod:`.run`)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim

__all__ = ["plot_mass", "sampler_claims", "sampler_macros", "time_to_mass", "compute_claims"]

MASS_TARGET = 0.99  #: "captures the mass": mean fraction captured at least this

_LABELS = {"rfisst_chain": "R-FISST chain (paper proposal)", "rfisst_completion": "R-FISST + completion",
           "gibbs": "GLMB Gibbs (systematic scan)", "murty": "Murty k-best"}


def plot_mass(det: pd.DataFrame, timing: pd.DataFrame, pdf, png):
    """Mass missed vs budget (upper panel of each pair) and vs wall time (lower panel), one pair of
    panels per difficulty, three pairs a row; the legend in the free slot (or below)."""
    import matplotlib.ticker

    from ...reporting import figure_style

    diffs = list(det.difficulty.unique())
    n_cols = min(3, max(len(diffs), 1))
    spare = -len(diffs) % n_cols
    pair_rows = -(-len(diffs) // n_cols)
    fig, axes = figure_style.subplots(2 * pair_rows, n_cols, squeeze=False, sharey=True,
                                      height=min(2.9 * pair_rows + 0.9 + (0 if spare else 0.5),
                                                 figure_style.MAX_HEIGHT_IN))
    t = timing.set_index(["difficulty", "sampler", "budget"])
    styles = figure_style.categorical_styles(4)
    for i, d in enumerate(diffs):
        ax_b, ax_t = axes[2 * (i // n_cols), i % n_cols], axes[2 * (i // n_cols) + 1, i % n_cols]
        for j, (name, g) in enumerate(det[det.difficulty == d].groupby("sampler", sort=False)):
            miss = 1.0 - g.mass_mean.clip(upper=1.0)
            st = styles[j % len(styles)]
            label = _LABELS.get(name, name)
            ax_b.plot(g.budget, np.maximum(miss, 1e-16), ms=3, label=label, **st)
            tt = [t.loc[(d, name, b), "time_mean_s"] for b in g.budget]
            ax_t.plot(tt, np.maximum(miss, 1e-16), ms=3, label=_LABELS.get(name, name), **st)
        ax_b.set_title(_title(d, det))
        ax_b.set_xlabel("budget (proposals per problem)", labelpad=1)
        ax_t.set_xlabel("wall time per problem (s)", labelpad=1)
        for ax in (ax_b, ax_t):
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(numticks=4))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.grid(alpha=0.3, which="major")
            if i % n_cols == 0:
                ax.set_ylabel("mass missed")
    # a sampler drawn exactly over another (both near 1 on a 16-decade axis, say) is named in the legend
    notes = {}
    fig.canvas.draw()
    for ax in axes.flat:
        for a, b in figure_style.coincident_lines(ax):
            where = ax.get_title().replace("\n", " ") or "the panel below"
            notes.setdefault(a.get_label(), []).append(f"{b.get_label()} ({where})")
            a.set_label(f"{a.get_label()} (coincides with {b.get_label()} here)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    labels = [lab.split(" (coincides with")[0] for lab in labels]
    labels = [lab + ("; coincides with " + "; ".join(notes[lab]) if lab in notes else "") for lab in labels]
    labels = [figure_style.wrap(lab, fig, 7.5, 0.3) for lab in labels]  # the legend fits the free slot
    if spare:
        for k in range(len(diffs), n_cols * pair_rows):
            for ax in (axes[2 * (k // n_cols), k % n_cols], axes[2 * (k // n_cols) + 1, k % n_cols]):
                ax.axis("off")
        k = len(diffs)
        axes[2 * (k // n_cols), k % n_cols].legend(handles, labels, loc="upper center",
                                                   title="mass missed = 1 − captured")
    else:
        figure_style.legend_below(fig, handles, labels, ncol=2)
    rec = "; recorded benchmark scans: relative to Murty's top K and every child found" \
        if not det.mass_exact.all() else ""
    fig.suptitle(figure_style.wrap("Posterior mass missed on identical association problems "
                                   f"(mean over problems; exact by exhaustive enumeration{rec})", fig))
    figure_style.save(fig, pdf, png, width=1.0, dpi=150)


def _title(d: str, det: pd.DataFrame) -> str:
    if d == "recorded":
        n = int(det.loc[det.difficulty == d, "n_problems"].max())
        return f"recorded benchmark scans\n({n} problems, largest scans)"
    return f"synthetic problems,\nobjects {d.replace('sigma', ' σ')} apart"


def _dkey(d: str) -> str:
    return d.replace("sigma", "Sigma") if d != "recorded" else "Recorded"


def sampler_claims(det: pd.DataFrame, timing: pd.DataFrame) -> list:
    """Per difficulty, at the largest budget: which sampler captures the most mass, with the
    mass and MAP rate of all four (deterministic; wall times stay in the timing tables)."""
    claims = []
    b = det.budget.max()
    for d, g in det[det.budget == b].groupby("difficulty", sort=False):
        g = g.set_index("sampler")
        best = g.mass_mean.idxmax()
        # deterministic: mass and MAP only (wall times are in summary_timing.csv and timing_macros.csv)
        note = "; ".join(f"{s}: mass {g.loc[s, 'mass_mean']:.4g} +/- {g.loc[s, 'mass_se']:.2g}, MAP found "
                         f"{g.loc[s, 'map_found']:.0%}" for s in g.index)
        key = "Mass" + _dkey(d)
        exact = bool(g.mass_exact.all())
        if not exact:
            note += "; mass relative to Murty's top K and every child any sampler found (a lower bound of the total)"
        # the verdict names the sampler and its mass (mean +/- s.e. over the problems), so the ledger shows both
        verdict = (f"{best}: {g.loc[best, 'mass_mean']:.4g} +/- {g.loc[best, 'mass_se']:.2g} of the mass "
                   f"({int(g.n_problems.iloc[0])} problems)")
        claims.append(Claim("samplers", f"{d}: sampler capturing the most posterior mass at equal proposals "
                            "(largest budget)", "extension", "--", verdict, "--", "extension", note,
                            "brute force" if exact else "measurement", key=key))
    return claims


def sampler_macros(det: pd.DataFrame, timing: pd.DataFrame) -> tuple[dict, dict]:
    """Per difficulty and sampler at the largest budget: mass captured and MAP found rate (with
    the largest budget and the number of problems); and, apart (not deterministic), the wall time (ms)."""
    b = det.budget.max()
    t = timing.set_index(["difficulty", "sampler", "budget"])
    synthetic = det[det.difficulty != "recorded"]
    out = {"Budget": int(b), "NProblems": int((synthetic if len(synthetic) else det).n_problems.min())}
    if (det.difficulty == "recorded").any():
        out["NRecorded"] = int(det.loc[det.difficulty == "recorded", "n_problems"].max())
    # equal proposals, Gibbs against the paper's chain: in how many (difficulty, budget) cells it captures more
    piv = det.pivot_table(index=["difficulty", "budget"], columns="sampler", values="mass_mean")
    if {"gibbs", "rfisst_chain"} <= set(piv.columns):
        out["GibbsAboveChainCells"] = int((piv["gibbs"] > piv["rfisst_chain"]).sum())
        out["Cells"] = len(piv)
    times = {}
    for d, g in det[det.budget == b].groupby("difficulty", sort=False):
        best = g.set_index("sampler").mass_mean.idxmax()
        out[f"MostMass{_dkey(d)}"] = _LABELS.get(best, best)
    for _, r in det[det.budget == b].iterrows():
        name = "At" + _dkey(r.difficulty) + "".join(p.capitalize() for p in r.sampler.split("_"))
        out[f"{name}Mass"] = f"{r.mass_mean:.4g}"
        out[f"{name}Map"] = f"{100 * r.map_found:.0f}"
        times[f"{name}Ms"] = f"{1e3 * t.loc[(r.difficulty, r.sampler, b), 'time_mean_s']:.3g}"
    return out, times


def time_to_mass(det: pd.DataFrame, timing: pd.DataFrame, target: float = MASS_TARGET) -> pd.DataFrame:
    """Per difficulty and sampler: the least mean wall time (s) of a budget whose mean mass captured
    is at least ``target`` (NaN when no budget reaches it) — compute per unit of mass."""
    t = timing.set_index(["difficulty", "sampler", "budget"])["time_mean_s"]
    rows = []
    for (d, s), g in det.groupby(["difficulty", "sampler"], sort=False):
        ok = g[g.mass_mean >= target]
        times = [t.loc[(d, s, b)] for b in ok.budget]
        rows.append({"difficulty": d, "sampler": s, "time_to_mass_s": min(times) if times else np.nan,
                     "budget": int(ok.budget.iloc[int(np.argmin(times))]) if times else -1})
    return pd.DataFrame(rows)


def compute_claims(det: pd.DataFrame, timing: pd.DataFrame) -> tuple[list, dict]:
    """Per difficulty: which sampler captures ``MASS_TARGET`` of the posterior mass in the least
    wall time (timing rows: not byte-reproducible), and the macros (ms per sampler, the winner)."""
    ttm = time_to_mass(det, timing)
    claims, macros = [], {}
    for d, g in ttm.groupby("difficulty", sort=False):
        g = g.set_index("sampler")
        reached = g.time_to_mass_s.dropna()
        best = reached.idxmin() if len(reached) else "none"
        note = "; ".join(f"{s}: {1e3 * g.loc[s, 'time_to_mass_s']:.3g} ms ({g.loc[s, 'budget']} proposals)"
                         if np.isfinite(g.loc[s, "time_to_mass_s"]) else f"{s}: not reached at the largest budget"
                         for s in g.index)
        verdict = f"{best}: {1e3 * reached.min():.3g} ms per problem" if len(reached) else \
            "none within the largest budget"
        claims.append(Claim("samplers", f"{d}: sampler capturing {MASS_TARGET:.0%} of the posterior mass in the "
                            "least wall time", "extension", "--", verdict, "--", "extension", note, "measurement",
                            key="Fastest" + _dkey(d)))
        macros[f"Fastest{_dkey(d)}"] = _LABELS.get(best, "no method within the largest budget")
        for s in g.index:
            v = g.loc[s, "time_to_mass_s"]
            macros[f"TimeToMass{_dkey(d)}{''.join(p.capitalize() for p in s.split('_'))}Ms"] = \
                f"{1e3 * v:.3g}" if np.isfinite(v) else "not reached"
    return claims, macros

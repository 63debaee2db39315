"""Sensitivity of ssa50's "P(N = 50) = 1 at the end" to the parameters document 000 does not state.

Document 000 Sec. IV-A gives neither the clutter rate λ (returns per scan), the probability of
detection p_D, nor the birth and death probabilities α, β behind Fig. 11, whose end holds the whole
weight on the 50-object hypotheses. This experiment measures P(N = 50) and E[N] at the end of the
run over a grid of λ × p_D, with the ledger's Monte Carlo rule
(:func:`hypotrack.reporting.verdict.monte_carlo_verdict`) applied at every setting: which readings,
if any, reproduce the number.

Runs per setting are **scenario seeds** (realisation ``i`` uses child ``i`` of
``experiment_seeds(seed, "ssa50_sensitivity")``, the same at every setting): the claim is about
what R-FISST does on such a problem, not on one draw of it, and the spread over realisations
(which objects cross the clutter, when the births enter) is the one the paper's single figure
hides. Because :func:`hypotrack.scenarios.ssa.simulate_ssa` draws the orbits, the process noise
and the measurements from separate streams, every setting sees the same orbits and truth; only the
returns differ. The tracker's model uses the setting's p_D; H-FISST's weights (document 000 Eq. 8)
hold no clutter *rate* — clutter enters only through its density 1/V and the count term
``C(m, k) k!`` — so λ acts on R-FISST through the data alone. The blind tracker
(:func:`~.controls.blind_run`) runs on every realisation as the negative control: it never holds
a birth, so P(N = 50) = 0.

Steps: :func:`grid` lists the settings (one shard each), :func:`run_setting` runs the seeds of
one setting, :func:`sensitivity_table` applies the rule per setting, :func:`sensitivity_claims`
writes the ledger row and macros, :func:`plot_sensitivity` the figure.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import pandas as pd

from ..._validation import check_int, check_probability
from ...reporting.ledger import Claim
from ...reporting.verdict import monte_carlo_verdict
from ...scenarios.ssa import params_from_config, simulate_ssa
from ..seeds import experiment_seeds
from ..stepping import Clocks
from .controls import blind_run
from .scenario import catalogue_mask
from .trackers import TrackerSettings, make_tracker
from .run import run_tracker

__all__ = ["RUN_COLUMNS", "grid", "plot_sensitivity", "run_setting", "sensitivity_claims", "sensitivity_table"]

RUN_COLUMNS = ["setting", "clutter_rate", "p_D", "seed_index", "tracker", "n_true_end", "p_n_end",
               "expected_number_end", "p_more_end", "p_less_end"]


def grid(section: Mapping) -> pd.DataFrame:
    """The settings ``setting, clutter_rate, p_D`` of ``ssa50.sensitivity`` (λ varies fastest).

    ``clutter_rates`` must be >= 0 and ``p_D`` in (0, 1], both non-empty and without repeats.
    """
    lam = [float(x) for x in section["clutter_rates"]]
    pds = [check_probability(x, "p_D", low_open=True) for x in section["p_D"]]
    if not lam or not pds:
        raise ValueError("clutter_rates and p_D must each hold at least one value")
    if min(lam) < 0:
        raise ValueError(f"clutter_rates must be >= 0 (returns per scan), got {lam}")
    if len(set(lam)) != len(lam) or len(set(pds)) != len(pds):
        raise ValueError("clutter_rates and p_D must not repeat a value")
    rows = [(p, lam_) for p in pds for lam_ in lam]
    return pd.DataFrame({"setting": range(len(rows)), "clutter_rate": [r[1] for r in rows],
                         "p_D": [r[0] for r in rows]})


def _scenario(config: Mapping, clutter_rate: float, p_d: float, index: int):
    """Realisation ``index`` at one setting (the ssa section with the setting's λ and p_D)."""
    own = config["ssa50"]["sensitivity"]
    section = {**config["ssa"], "clutter_rate": clutter_rate, "p_D": p_d}
    if own.get("n_scans"):
        section["n_scans"] = own["n_scans"]
    params = params_from_config(section, "ssa50")
    return simulate_ssa(params, experiment_seeds(config["seed"], "ssa50_sensitivity", index + 1)[index])


def run_setting(config: Mapping, setting: int, progress: Callable[[str], None] | None = print) -> tuple:
    """Every scenario seed of one setting: the configured tracker and the blind tracker.

    Returns ``(rows, timing)``: :data:`RUN_COLUMNS` rows (deterministic given the config) and
    ``setting, seed_index, seconds, cpu_seconds`` of the tracker runs.
    """
    own = config["ssa50"]["sensitivity"]
    g = grid(own)
    setting = check_int(setting, "setting", minimum=0)
    if setting >= len(g):
        raise ValueError(f"setting must lie in [0, {len(g) - 1}], got {setting}")
    lam, p_d = float(g.loc[setting, "clutter_rate"]), float(g.loc[setting, "p_D"])
    settings = TrackerSettings.from_config(config["ssa50"], own["tracker"])
    if own.get("n_steps") and settings.kind == "rfisst":
        settings = settings.with_options(n_steps=int(own["n_steps"]))
    rows, timing = [], []
    for i in range(check_int(own["n_seeds"], "n_seeds", minimum=1)):
        scenario = _scenario(config, lam, p_d, i)
        rng = np.random.default_rng(experiment_seeds(config["seed"], f"ssa50_sensitivity/{setting}/{i}", 1)[0])
        with Clocks() as clocks:
            run = run_tracker(make_tracker(scenario, settings, rng), scenario,
                              name=f"λ = {lam:g}, p_D = {p_d:g}, seed {i}", progress=progress, n_progress=2)
        timing.append({"setting": setting, "seed_index": i, "seconds": clocks.wall, "cpu_seconds": clocks.cpu})
        n_true = int(catalogue_mask(scenario)[-1].sum())  # known objects and every birth seen by the end
        for name, r in ((own["tracker"], run), ("blind", blind_run(scenario))):
            last = int(r.summary["scan"].max())
            card = r.cardinality[r.cardinality["scan"] == last]
            rows.append({"setting": setting, "clutter_rate": lam, "p_D": p_d, "seed_index": i, "tracker": name,
                         "n_true_end": n_true,
                         "p_n_end": float(card.loc[card["n_objects"] == n_true, "probability"].sum()),
                         "expected_number_end": float(r.summary["expected_number"].iloc[-1]),
                         "p_more_end": float(card.loc[card["n_objects"] > n_true, "probability"].sum()),
                         "p_less_end": float(card.loc[card["n_objects"] < n_true, "probability"].sum())})
    return pd.DataFrame(rows, columns=RUN_COLUMNS), pd.DataFrame(timing)


def sensitivity_table(runs: pd.DataFrame, *, tracker: str, tolerance: float, published: float = 1.0) -> pd.DataFrame:
    """Per setting: P(N = 50) at the end over seeds (n, mean, s.e., the rule's 99.73 % interval and
    verdict against ``published`` ± ``tolerance``), mean E[N], P(N > 50), P(N < 50), and the blind
    tracker's mean P(N = 50) with its verdict (the control: it must not reproduce)."""
    tol = check_probability(tolerance, "tolerance")
    out = []
    for setting, g in runs.groupby("setting", sort=True):
        t, b = g[g["tracker"] == tracker], g[g["tracker"] == "blind"]
        x = t["p_n_end"].to_numpy(dtype=float)
        row = {"setting": int(setting), "clutter_rate": float(g["clutter_rate"].iloc[0]),
               "p_D": float(g["p_D"].iloc[0]), "n": len(x), "p_n_end_mean": float(x.mean()) if len(x) else np.nan}
        if len(x) >= 2:
            se = float(x.std(ddof=1) / np.sqrt(len(x)))
            v = monte_carlo_verdict(float(x.mean()), se, published, tol, len(x))
            row.update(p_n_end_se=se, low=v.low, high=v.high, status=v.status)
        else:
            row.update(p_n_end_se=np.nan, low=np.nan, high=np.nan, status="inconclusive")
        bx = b["p_n_end"].to_numpy(dtype=float)
        control = "inconclusive"
        if len(bx) >= 2:
            control = monte_carlo_verdict(float(bx.mean()), float(bx.std(ddof=1) / np.sqrt(len(bx))), published, tol,
                                          len(bx)).status
        row.update(p_n_end_min=float(x.min()) if len(x) else np.nan, p_n_end_max=float(x.max()) if len(x) else np.nan,
                   expected_number_end_mean=float(t["expected_number_end"].mean()),
                   p_more_end_mean=float(t["p_more_end"].mean()), p_less_end_mean=float(t["p_less_end"].mean()),
                   control_p_n_end_mean=float(bx.mean()) if len(bx) else np.nan, control_status=control)
        out.append(row)
    return pd.DataFrame(out)


def _fmt(x: float) -> str:
    return f"{x:g}"


def sensitivity_claims(table: pd.DataFrame, *, tolerance: float, configured: tuple[float, float]):
    """The ledger row (an extension: a reading of numbers the document leaves out) and the macros.

    ``configured`` is the ``(clutter_rate, p_D)`` of the ssa section, the reading the ssa50 rows use.
    Returns ``(claims, macros)``.
    """
    ok = table[table["status"] == "reproduced"]
    settings = "; ".join(f"λ = {_fmt(r.clutter_rate)}, p_D = {_fmt(r.p_D)}: {r.p_n_end_mean:.3f} ({r.status})"
                         for r in table.itertuples())
    where = ", ".join(f"(λ = {_fmt(r.clutter_rate)}, p_D = {_fmt(r.p_D)})" for r in ok.itertuples()) or "none"
    n = int(table["n"].min()) if len(table) else 0
    conf = table[(table["clutter_rate"] == configured[0]) & (table["p_D"] == configured[1])]
    claims = [Claim("ssa_sensitivity", "P(N = 50) at the end of the 50-object run over the unstated clutter rate "
                    "λ and p_D", "extension (000 Fig. 11's claim)", "1 (λ, p_D not stated)",
                    f"reproduced at {len(ok)} of {len(table)} settings: {where}",
                    f"99.73 % interval within +/- {tolerance:g}, {n} scenario seeds per setting", "extension",
                    f"{settings}; blind tracker (the control) reproduces at "
                    f"{int((table['control_status'] == 'reproduced').sum())} settings", "measurement",
                    key="PEndGrid")]
    # the paper's text is typeset by pdflatex: the list names the settings in words, without Greek letters
    in_words = ", ".join(f"clutter rate {_fmt(r.clutter_rate)} with p_D {_fmt(r.p_D)}" for r in ok.itertuples())
    macros = {"NReproduced": len(ok), "NSettings": len(table), "NSeeds": n,
              "Reproduced": in_words or "none",
              "PEndMin": f"{table['p_n_end_mean'].min():.3f}", "PEndMax": f"{table['p_n_end_mean'].max():.3f}"}
    if len(conf):
        macros.update(PEndConfigured=f"{conf['p_n_end_mean'].iloc[0]:.3f}", StatusConfigured=conf["status"].iloc[0])
    zero = table[table["clutter_rate"] == 0]
    if len(zero):
        macros.update(PEndNoClutterMin=f"{zero['p_n_end_mean'].min():.3f}",
                      PEndNoClutterMax=f"{zero['p_n_end_mean'].max():.3f}")
    return claims, macros


def plot_sensitivity(table: pd.DataFrame, *, tolerance: float, published: float = 1.0, title: str = ""):
    """P(N = 50) at the end against λ, one line per p_D, with the rule's 99.73 % intervals and the
    tolerance band; the verdict of each setting is written at its point (legend outside the data)."""
    import matplotlib.pyplot as plt

    from ...reporting import figure_style

    fig, ax = figure_style.subplots(height=3.4)  # placed at the full line width (figure_style.save checks it)
    ax.axhspan(published - tolerance, published + tolerance, color="#cccccc", alpha=0.5,
               label=f"published {published:g} ± {tolerance:g}")
    pds = sorted(table["p_D"].unique())
    offsets = np.linspace(-0.03, 0.03, len(pds)) if len(pds) > 1 else [0.0]
    marks = {"reproduced": "o", "not reproduced": "x", "inconclusive": "s"}
    for off, p, color in zip(offsets, pds, plt.cm.viridis(np.linspace(0, 0.85, len(pds)))):
        g = table[table["p_D"] == p].sort_values("clutter_rate")
        x = g["clutter_rate"].to_numpy() + off
        y = g["p_n_end_mean"].to_numpy()
        lo = np.clip(y - g["low"].fillna(g["p_n_end_mean"]).to_numpy(), 0, None)
        hi = np.clip(g["high"].fillna(g["p_n_end_mean"]).to_numpy() - y, 0, None)
        ax.errorbar(x, y, yerr=[lo, hi], color=color, lw=1.2, capsize=3, label=f"$p_D$ = {p:g}")
        for xi, yi, s in zip(x, y, g["status"]):
            ax.plot(xi, yi, marks.get(s, "s"), color=color, ms=6, mfc="white" if s != "reproduced" else color)
    for s, m in marks.items():
        ax.plot([], [], m, color="black", mfc="white" if s != "reproduced" else "black", label=s)
    ax.set_xlabel("clutter rate λ (returns per scan)", fontsize=9)
    ax.set_ylabel("P(N = 50) at the end", fontsize=9)
    ax.tick_params(labelsize=8)
    low = float(np.nanmin(table["low"].fillna(table["p_n_end_mean"])))
    ax.set_ylim(max(-0.02, min(0.5, low - 0.02)), published + tolerance + 0.01)  # intervals beyond are clipped
    ax.grid(alpha=0.3)
    figure_style.legend_right(ax, fontsize=8, frameon=False)
    n = int(table["n"].min()) if len(table) else 0
    ax.set_title(title or f"P(N = 50) at the end over λ and $p_D$\n{n} scenario seeds each; bars: 99.73 % intervals",
                 fontsize=9)
    return fig

"""Tables, figures and ledger rows of the GLMB benchmark (:mod:`.run`)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim

__all__ = ["summary_table", "curves", "plot_benchmark", "benchmark_claims", "follow_score", "follow_claims",
           "benchmark_macros"]


def summary_table(per_scan: pd.DataFrame, implementations: dict | None = None):
    """One row per tracker: mean OSPA and mean |N̂ − N| over scans and runs with standard errors
    across runs (columns ``*_mc``: the same under the demo's extraction, when the per-scan table has
    it), and the mean run time per scan; ``implementations`` (tracker -> label) names
    whose code ran. Returns (deterministic table, timing table)."""
    per_scan = per_scan.assign(card_err=(per_scan.n_est - per_scan.n_true).abs())
    cols = ["ospa", "ospa_loc", "ospa_card", "card_err"]
    if "n_est_mc" in per_scan:  # the demo's extraction (MAP cardinality, then the heaviest of it)
        per_scan = per_scan.assign(card_err_mc=(per_scan.n_est_mc - per_scan.n_true).abs())
        cols += ["ospa_mc", "ospa_loc_mc", "ospa_card_mc", "card_err_mc"]
    per_run = per_scan.groupby(["tracker", "run"], sort=False)[[*cols, "time_s"]].mean()
    rows, timing = [], []
    for name, g in per_run.groupby(level="tracker", sort=False):
        n = len(g)
        row = {"tracker": name, "implementation": (implementations or {}).get(name, "hypotrack engine"),
               "n_runs": n}
        for col in cols:
            row[f"{col}_mean"] = g[col].mean()
            row[f"{col}_se"] = g[col].std(ddof=1) / np.sqrt(n) if n > 1 else np.nan
        rows.append(row)
        timing.append({"tracker": name, "n_runs": n, "time_per_scan_s": g["time_s"].mean(),
                       "time_per_scan_se": g["time_s"].std(ddof=1) / np.sqrt(n) if n > 1 else np.nan})
    return pd.DataFrame(rows), pd.DataFrame(timing)


def curves(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Per tracker and scan: mean OSPA and parts, mean ± std of the estimated number, truth."""
    g = per_scan.groupby(["tracker", "scan"], sort=False)
    out = g[["ospa", "ospa_loc", "ospa_card", "n_true"]].mean()
    out["n_est_mean"] = g["n_est"].mean()
    out["n_est_std"] = g["n_est"].std(ddof=1).fillna(0.0)
    return out.reset_index()


def plot_benchmark(curve: pd.DataFrame, pdf, png, labels: dict | None = None):
    """OSPA, its localisation and cardinality parts, and the number of objects over time, one line
    style per tracker; one legend for all four panels, below them."""
    from ...reporting import figure_style

    fig, axes = figure_style.subplots(2, 2, height=5.2, sharex=True)
    panels = [("ospa", "OSPA (m)"), ("ospa_loc", "OSPA localisation part (m)"),
              ("ospa_card", "OSPA cardinality part (m)")]
    styles = dict(zip(curve.tracker.unique(), ["-", "--", "-.", ":", (0, (5, 1)), (0, (1, 3))] * 3))
    labels = {name: (labels or {}).get(name, name) for name in curve.tracker.unique()}
    for ax, (col, label) in zip(axes.flat, panels):
        for name, g in curve.groupby("tracker", sort=False):
            ax.plot(g.scan, g[col], label=labels[name], lw=1.4, ls=styles[name])
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax = axes.flat[3]
    first = True
    for name, g in curve.groupby("tracker", sort=False):
        line, = ax.plot(g.scan, g.n_est_mean, lw=1.4, ls=styles[name], label=labels[name])
        ax.fill_between(g.scan, g.n_est_mean - g.n_est_std, g.n_est_mean + g.n_est_std, color=line.get_color(),
                        alpha=0.15)
        if first:
            ax.step(g.scan, g.n_true, where="mid", color="k", lw=1.5, label="truth")
            first = False
    ax.set_ylabel("number of objects (mean ± std)")
    ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("scan (T = 1 s)")
    figure_style.legend_below(fig, *axes.flat[3].get_legend_handles_labels(), ncol=3)
    n = int(curve.attrs.get("n_runs", 0))
    fig.suptitle(figure_style.wrap("Linear-Gaussian GLMB benchmark: OSPA (c = 100 m, p = 1) and cardinality over time"
                                   + (f", {n} Monte Carlo runs" if n else ""), fig))
    figure_style.save(fig, pdf, png, width=1.0)


def benchmark_claims(summary: pd.DataFrame, reference: str, controls=()) -> list:
    """Extension rows: each tracker's mean OSPA and cardinality error against the ``reference``
    tracker (difference and its standard error), and, for the engine's trackers, the same under the
    demo's extraction (MAP cardinality, then the heaviest hypothesis of it; key suffix ``MapCard``).
    Trackers named in ``controls`` (negative controls) get no row. Times per scan are measured, so they are no input
    of these rows (the timing macros and table carry them): the ledger is byte-identical across runs."""
    ref = summary.set_index("tracker").loc[reference]
    claims = []
    for _, row in summary.iterrows():
        name = row.tracker
        if name in controls:
            continue
        d = row.ospa_mean - ref.ospa_mean
        se = float(np.hypot(row.ospa_se, ref.ospa_se))
        note = (f"mean OSPA {row.ospa_mean:.2f} +/- {row.ospa_se:.2f} m, |N error| {row.card_err_mean:.3f} "
                f"+/- {row.card_err_se:.3f}")
        if name != reference:
            note += f"; OSPA minus {reference}: {d:+.2f} +/- {se:.2f} m"
        key = "Ospa" + _camel(name)
        engine = row.get("implementation", "hypotrack engine") == "hypotrack engine"
        who = name if engine else f"{name} ({row.implementation})"
        claims.append(Claim("glmb_benchmark", f"{who}: mean OSPA on the GLMB linear-Gaussian benchmark",
                            "extension (Vo, Vo & Hoang 2017 scenario)", "--", f"{row.ospa_mean:.4g}", "--",
                            "extension", note, "measurement", n=str(int(row.n_runs)), mean=f"{row.ospa_mean:.4g}",
                            se=f"{row.ospa_se:.3g}", key=key))
        if engine and "ospa_mc_mean" in row and np.isfinite(row.ospa_mc_mean):
            note = (f"mean OSPA {row.ospa_mc_mean:.2f} ± {row.ospa_mc_se:.2f} m, |N error| {row.card_err_mc_mean:.3f} "
                    f"± {row.card_err_mc_se:.3f}; heaviest-hypothesis extraction: {row.ospa_mean:.2f} ± "
                    f"{row.ospa_se:.2f} m")
            claims.append(Claim("glmb_benchmark", f"{who}: mean OSPA on the GLMB linear-Gaussian benchmark, the demo's "
                                "extraction (MAP cardinality, then the heaviest hypothesis of that cardinality)",
                                "extension (Vo, Vo & Hoang 2017 scenario and extraction)", "--",
                                f"{row.ospa_mc_mean:.4g}", "--", "extension", note, "measurement",
                                n=str(int(row.n_runs)), mean=f"{row.ospa_mc_mean:.4g}", se=f"{row.ospa_mc_se:.3g}",
                                key=key + "MapCard"))
    return claims


def follow_score(per_scan: pd.DataFrame, tracker: str, lag: int, rule: str = "heaviest") -> tuple[float, float]:
    """How well ``tracker``'s estimated number follows the truth (the published cardinality curve's shape).

    The true number changes at the births and deaths; the scans ``k .. k + lag − 1`` from each change
    ``k`` (scan 1 included when objects are present from the start) are its windows. Returns
    ``(outside, gap)``: the mean over runs and over the scans outside every window of ``|N̂ − N|``, and
    the largest ``|mean N̂ − N|`` (mean over runs) at the last scan of a window."""
    lag = int(lag)
    if lag < 1:
        raise ValueError(f"lag must be an integer >= 1, got {lag}")
    col = "n_est" + ("_mc" if rule == "map_cardinality" else "")
    g = per_scan[per_scan.tracker == tracker]
    if g.empty:
        raise ValueError(f"tracker {tracker!r} has no rows in the per-scan table")
    truth = g.groupby("scan").n_true.first().sort_index()
    prev = np.r_[0, truth.to_numpy()[:-1]]
    changes = truth.index[truth.to_numpy() != prev]
    in_window = np.zeros(len(truth), dtype=bool)
    last = []
    for k in changes:
        in_window |= (truth.index >= k) & (truth.index < k + lag)
        last.append(min(k + lag - 1, truth.index.max()))
    outside = set(truth.index[~in_window])
    err = (g[col] - g.n_true).abs()
    mean_out = float(err[g.scan.isin(outside)].mean()) if outside else 0.0
    mean_n = g.groupby("scan")[col].mean()
    gap = float(max(abs(mean_n.loc[k] - truth.loc[k]) for k in last)) if last else 0.0
    return mean_out, gap


def follow_claims(per_scan: pd.DataFrame, checked: dict, control: str, lag: int, tolerance: float,
                  peer: str | None = None) -> list:
    """Qualitative rows: the δ-GLMB's estimated number follows the truth, within ``lag`` scans of every
    birth and death (Vo, Vo & Hoang 2017 Sec. V's cardinality curve on this scenario): away from the
    changes the mean ``|N̂ − N|`` is at most ``tolerance`` and at the end of each change's window the
    mean ``N̂`` is within half an object of the truth (:func:`follow_score`). ``checked`` maps a tracker
    to its extraction rule. The negative control, the ``control`` tracker (fed empty scans), is scored the
    same way and must fail; ``peer`` (the GM-PHD), when given, is scored too and named in the note."""
    from ...reporting.verdict import with_control

    def passes(out, gap):
        return out <= tolerance and gap < 0.5

    c_out, c_gap = follow_score(per_scan, control, lag)
    claims = []
    for name, rule in checked.items():
        out, gap = follow_score(per_scan, name, lag, rule)
        ok = passes(out, gap)
        n = per_scan[per_scan.tracker == name].run.nunique()
        note = f"{n} runs; extraction: {rule.replace('_', ' ')}"
        if peer is not None:
            p_out, p_gap = follow_score(per_scan, peer, lag)
            note += (f"; {peer} scored the same way: {p_out:.3f} away from the changes, gap {p_gap:.2f} "
                     f"({'passes' if passes(p_out, p_gap) else 'fails'})")
        claim = Claim("glmb_benchmark", f"{name}: the estimated number follows the truth, reaching it within {lag} "
                      "scans of every birth and death", "Vo, Vo & Hoang 2017 Sec. V (cardinality curve, this scenario)",
                      "follows the truth",
                      f"mean |N̂ − N| {out:.3f} away from the changes; largest gap {gap:.2f} at a window's end",
                      f"≤ {tolerance:g} away from the changes; gap < 0.5",
                      "qualitative" if ok else "not reproduced", note, "measurement", key="Follows" + _camel(name),
                      # a budget-truncated filter failing is this project's truncation choice; the reference
                      # settings' failing is not yet diagnosed
                      cause="" if ok or name.endswith("reference") else "project choice")
        claims.append(with_control(claim, f"{control} (the same tracker fed empty scans)",
                                   f"{c_out:.2f} away from the changes, gap {c_gap:.2f}", passes(c_out, c_gap)))
    return claims


def _camel(name: str) -> str:
    return "".join(p.capitalize() for p in name.split("_"))


def benchmark_macros(summary: pd.DataFrame, timing: pd.DataFrame) -> tuple[dict, dict]:
    """Numbers the paper quotes beside the claims: per tracker the OSPA parts and the cardinality
    error (suffix ``Mc``: under the demo's extraction), its number of runs (``NRuns``: the largest); and, apart (not deterministic), the time per scan (ms)."""
    t = timing.set_index("tracker")
    out = {"NRuns": int(summary.n_runs.max())}
    times = {}
    for _, r in summary.iterrows():
        c = _camel(r.tracker)
        out[f"{c}NRuns"] = int(r.n_runs)
        if "ospa_mc_mean" in r:  # the demo's extraction
            out[f"{c}OspaMc"] = f"{r.ospa_mc_mean:.2f}"
            out[f"{c}OspaMcSe"] = f"{r.ospa_mc_se:.2f}"
            out[f"{c}CardErrMc"] = f"{r.card_err_mc_mean:.3f}"
        out[f"{c}Ospa"] = f"{r.ospa_mean:.2f}"
        out[f"{c}OspaSe"] = f"{r.ospa_se:.2f}"
        out[f"{c}Loc"] = f"{r.ospa_loc_mean:.2f}"
        out[f"{c}Card"] = f"{r.ospa_card_mean:.2f}"
        out[f"{c}CardErr"] = f"{r.card_err_mean:.3f}"
        out[f"{c}CardErrSe"] = f"{r.card_err_se:.3f}"
        times[f"{c}MsPerScan"] = f"{1e3 * t.loc[r.tracker, 'time_per_scan_s']:.0f}"
    return out, times

"""Tables, figure and ledger rows of the Williams-2015 scenario (:mod:`.run`).

Two averages are reported. The *mean GOSPA* is the mean over scans of each run's GOSPA, then mean ±
standard error over runs. The PMBM paper's figures show the *RMS GOSPA*: ``√(mean over runs of d²)``
per step (García-Fernández et al. 2018, Sec. VI; its code's ``rms_gospa_t``), and its decomposition
with ``α = 2``: ``d² = localisation + missed + false`` (Rahmathullah et al. 2017, Eq. 3), each part the
square root of its mean over runs. Both are here; the parts add up in squares.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim

__all__ = ["settled", "summary_table", "curves", "trajectory_table", "plot_gospa", "williams_claims", "williams_macros", "camel"]

PARTS = ("gospa_loc", "gospa_missed", "gospa_false")


def _se(x) -> float:
    x = np.asarray(x, dtype=float)
    return float(x.std(ddof=1) / np.sqrt(len(x))) if len(x) > 1 else float("nan")


def settled(per_scan: pd.DataFrame, settled_after: int) -> pd.DataFrame:
    """``per_scan`` with column ``gospa_settled``: the GOSPA at steps after ``settled_after``, NaN before
    (the trackers start with no objects, the reference with its prior: the first steps measure initiation)."""
    return per_scan.assign(gospa_settled=per_scan.gospa.where(per_scan.scan > settled_after))


def summary_table(per_scan: pd.DataFrame, per_run: pd.DataFrame, settled_after: int = 10):
    """One row per tracker: mean GOSPA and its squared parts (mean ± s.e. over runs of each run's
    mean over scans), the mean GOSPA after step ``settled_after`` (:func:`settled`), the RMS GOSPA over
    all runs and steps, mean numbers of missed and false objects per scan, the trajectory GOSPA (mean ±
    s.e. over runs) with its switches. Returns ``(deterministic table, timing table)`` (time per scan,
    mean ± s.e. over runs)."""
    cols = ["gospa", *PARTS, "gospa_settled", "n_missed", "n_false"]
    per_scan = settled(per_scan, settled_after)
    by_run = per_scan.assign(gospa2=per_scan.gospa**2).groupby(["tracker", "run"], sort=False)[[*cols, "gospa2", "time_s"]].mean()
    rows, timing = [], []
    for name, g in by_run.groupby(level="tracker", sort=False):
        row = {"tracker": name, "n_runs": len(g)}
        for col in cols:
            row[f"{col}_mean"] = g[col].mean()
            row[f"{col}_se"] = _se(g[col])
        row["rms_gospa"] = float(np.sqrt(g["gospa2"].mean()))
        t = per_run[per_run.tracker == name]
        row["tgospa_mean"] = t.tgospa.mean()
        row["tgospa_se"] = _se(t.tgospa)
        row["n_switches_mean"] = t.n_switches.mean()
        rows.append(row)
        timing.append({"tracker": name, "n_runs": len(g), "time_per_scan_s": g["time_s"].mean(),
                       "time_per_scan_se": _se(g["time_s"])})
    return pd.DataFrame(rows), pd.DataFrame(timing)


def curves(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Per tracker and step: the RMS GOSPA and the square roots of the mean parts over runs (the paper's
    curves), the mean GOSPA, the mean estimated and true numbers."""
    g = per_scan.assign(gospa2=per_scan.gospa**2).groupby(["tracker", "scan"], sort=False)
    out = g[["gospa", "n_est", "n_true"]].mean()
    out["rms_gospa"] = np.sqrt(g["gospa2"].mean())
    for col in PARTS:
        out[f"rms_{col}"] = np.sqrt(g[col].mean())
    out["n_runs"] = g["run"].nunique()
    return out.reset_index()


def trajectory_table(per_run: pd.DataFrame) -> pd.DataFrame:
    """Per run and tracker: trajectory GOSPA and its parts (the deterministic per-run table)."""
    return per_run.sort_values(["tracker", "run"], kind="stable").reset_index(drop=True)


def plot_gospa(curve: pd.DataFrame, pdf, png, c: float, n_runs: int):
    """RMS GOSPA and its three parts over time, one line per tracker (the PMBM paper's Fig. 3-4 layout)."""
    from ...reporting import figure_style

    fig, axes = figure_style.subplots(2, 2, height=5.2, sharex=True)
    panels = [("rms_gospa", "RMS GOSPA (m)"), ("rms_gospa_loc", "localisation part (m)"),
              ("rms_gospa_missed", "missed-object part (m)"), ("rms_gospa_false", "false-object part (m)")]
    styles = dict(zip(curve.tracker.unique(), ["-", "--", "-.", ":", (0, (5, 1)), (0, (1, 3)), (0, (3, 1, 1, 1))] * 3))
    for ax, (col, label) in zip(axes.flat, panels):
        lines = {name: ax.plot(g.scan, g[col], label=name, lw=1.3, ls=styles[name])[0]
                 for name, g in curve.groupby("tracker", sort=False)}
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.autoscale_view()
        # trackers whose curves coincide in this panel (e.g. no false objects at all) are named above it
        same = figure_style.coincident_lines(ax, list(lines.values()))
        for a, b in same:
            a.set_label(f"{a.get_label()} (coincides with {b.get_label().split(' (')[0]} here)")
        if same:
            ax.set_title(figure_style.wrap("same curve: " + "; ".join(" = ".join(g) for g in _groups(same)), fig,
                                           7.0, 0.4), fontsize=7.0)
        ax.axvline((curve.scan.max() + 1) / 2, color="0.5", lw=0.8)
    for ax in axes[1]:
        ax.set_xlabel("time step (T = 1 s)")
    handles, _ = axes.flat[0].get_legend_handles_labels()
    figure_style.legend_below(fig, handles, [h.get_label().split(" (")[0] for h in handles], ncol=4)
    fig.suptitle(figure_style.wrap(
        f"Williams-2015 scenario: GOSPA (c = {c:g} m, p = 2, α = 2) over time, {n_runs} Monte Carlo runs; "
        "parts add up in squares; grey line: the objects meet and one dies", fig))
    figure_style.save(fig, pdf, png, width=1.0)


def _groups(pairs) -> list[list[str]]:
    """The trackers of coinciding line pairs as groups of names (a = b and b = c: one group a = b = c)."""
    group = {}
    for a, b in pairs:
        na, nb = (ln.get_label().split(" (")[0] for ln in (a, b))
        merged = group.get(na, {na}) | group.get(nb, {nb})
        for n in merged:
            group[n] = merged
    return sorted({tuple(sorted(g)) for g in group.values()})


def camel(name: str) -> str:
    return "".join(p.capitalize() for p in name.split("_"))


def williams_claims(summary: pd.DataFrame) -> list:
    """Extension rows: each tracker's mean GOSPA and mean trajectory GOSPA on the scenario (no published
    value is compared: the paper plots the PMBM filters only). Times are no input (deterministic rows)."""
    claims = []
    for _, r in summary.iterrows():
        note = (f"GOSPA² parts per scan: localisation {r.gospa_loc_mean:.2f}, missed {r.gospa_missed_mean:.2f}, "
                f"false {r.gospa_false_mean:.2f} m²; RMS GOSPA {r.rms_gospa:.2f} m")
        claims.append(Claim("williams2015", f"{r.tracker}: mean GOSPA on the Williams-2015 scenario",
                            "extension (García-Fernández et al. 2018 Sec. VI scenario)", "--", f"{r.gospa_mean:.4g}",
                            "--", "extension", note, "measurement", n=str(int(r.n_runs)), mean=f"{r.gospa_mean:.4g}",
                            se=f"{r.gospa_se:.3g}", key="Gospa" + camel(r.tracker)))
        claims.append(Claim("williams2015", f"{r.tracker}: mean trajectory GOSPA on the Williams-2015 scenario",
                            "extension (García-Fernández, Rahmathullah & Svensson 2020 metric)", "--",
                            f"{r.tgospa_mean:.4g}", "--", "extension",
                            f"{r.n_switches_mean:.1f} switches per run on average", "measurement",
                            n=str(int(r.n_runs)), mean=f"{r.tgospa_mean:.4g}", se=f"{r.tgospa_se:.3g}",
                            key="TrajGospa" + camel(r.tracker)))
    return claims


def williams_macros(summary: pd.DataFrame, timing: pd.DataFrame) -> tuple[dict, dict]:
    """Numbers the paper may quote (per tracker: ``Gospa``, ``GospaSe``, ``RmsGospa``, ``TrajGospa``), and,
    apart (not deterministic), the time per scan (ms, ``MsPerScan``)."""
    t = timing.set_index("tracker")
    out, times = {"NRuns": int(summary.n_runs.max())}, {}
    for _, r in summary.iterrows():
        c = camel(r.tracker)
        out.update({f"{c}Gospa": f"{r.gospa_mean:.2f}", f"{c}GospaSe": f"{r.gospa_se:.2f}",
                    f"{c}RmsGospa": f"{r.rms_gospa:.2f}", f"{c}TrajGospa": f"{r.tgospa_mean:.1f}"})
        times[f"{c}MsPerScan"] = f"{1e3 * t.loc[r.tracker, 'time_per_scan_s']:.1f}"
    return out, times

"""Tables, figures and ledger rows of the GLMB benchmark (:mod:`.run`)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim

__all__ = ["summary_table", "curves", "plot_benchmark", "benchmark_claims", "benchmark_macros"]


def summary_table(per_scan: pd.DataFrame, implementations: dict | None = None):
    """One row per tracker: mean OSPA and mean |N̂ − N| over scans and runs with standard errors
    across runs, and the mean run time per scan; ``implementations`` (tracker -> label) names
    whose code ran. Returns (deterministic table, timing table)."""
    per_scan = per_scan.assign(card_err=(per_scan.n_est - per_scan.n_true).abs())
    per_run = per_scan.groupby(["tracker", "run"], sort=False)[["ospa", "ospa_loc", "ospa_card", "card_err",
                                                                "time_s"]].mean()
    rows, timing = [], []
    for name, g in per_run.groupby(level="tracker", sort=False):
        n = len(g)
        row = {"tracker": name, "implementation": (implementations or {}).get(name, "hypotrack engine"),
               "n_runs": n}
        for col in ("ospa", "ospa_loc", "ospa_card", "card_err"):
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


def benchmark_claims(summary: pd.DataFrame, reference: str) -> list:
    """Extension rows: each tracker's mean OSPA and cardinality error against the ``reference``
    tracker (difference and its standard error). Times per scan are measured, so they are no input
    of these rows (the timing macros and table carry them): the ledger is byte-identical across runs."""
    ref = summary.set_index("tracker").loc[reference]
    claims = []
    for _, row in summary.iterrows():
        name = row.tracker
        d = row.ospa_mean - ref.ospa_mean
        se = float(np.hypot(row.ospa_se, ref.ospa_se))
        note = (f"mean OSPA {row.ospa_mean:.2f} +/- {row.ospa_se:.2f} m, |N error| {row.card_err_mean:.3f} "
                f"+/- {row.card_err_se:.3f}")
        if name != reference:
            note += f"; OSPA minus {reference}: {d:+.2f} +/- {se:.2f} m"
        key = "Ospa" + "".join(p.capitalize() for p in name.split("_"))
        who = name if row.get("implementation", "hypotrack engine") == "hypotrack engine" else \
            f"{name} ({row.implementation})"
        claims.append(Claim("glmb_benchmark", f"{who}: mean OSPA on the GLMB linear-Gaussian benchmark",
                            "extension (Vo, Vo & Hoang 2017 scenario)", "--", f"{row.ospa_mean:.4g}", "--",
                            "extension", note, "measurement", n=str(int(row.n_runs)), mean=f"{row.ospa_mean:.4g}",
                            se=f"{row.ospa_se:.3g}", key=key))
    return claims


def _camel(name: str) -> str:
    return "".join(p.capitalize() for p in name.split("_"))


def benchmark_macros(summary: pd.DataFrame, timing: pd.DataFrame) -> tuple[dict, dict]:
    """Numbers the paper quotes beside the claims: per tracker the OSPA parts and the cardinality
    error, the number of runs; and, apart (not deterministic), the time per scan (ms)."""
    t = timing.set_index("tracker")
    out = {"NRuns": int(summary.n_runs.min())}
    times = {}
    for _, r in summary.iterrows():
        c = _camel(r.tracker)
        out[f"{c}Ospa"] = f"{r.ospa_mean:.2f}"
        out[f"{c}OspaSe"] = f"{r.ospa_se:.2f}"
        out[f"{c}Loc"] = f"{r.ospa_loc_mean:.2f}"
        out[f"{c}Card"] = f"{r.ospa_card_mean:.2f}"
        out[f"{c}CardErr"] = f"{r.card_err_mean:.3f}"
        out[f"{c}CardErrSe"] = f"{r.card_err_se:.3f}"
        times[f"{c}MsPerScan"] = f"{1e3 * t.loc[r.tracker, 'time_per_scan_s']:.0f}"
    return out, times

"""The reference PMBM filter (:mod:`.reference`) beside this project's trackers on the same runs.

The reference's estimates (García-Fernández et al. 2018's code under Octave, its estimator 1: the
heaviest global hypothesis's Bernoulli components with existence above 0.4) are scored by the same
GOSPA (:func:`.run.score_estimates`) against the same truth as every configured tracker; the table
holds only the runs the reference ran, so every row averages identical scans.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim
from .reference import read_estimates, read_labels
from .run import score_estimates, trajectory_row, truth_for
from .summary import settled

__all__ = ["REFERENCE_NAME", "reference_per_scan", "reference_trajectories", "reference_comparison", "reference_claims"]

REFERENCE_NAME = "pmbm_reference"
_COLS = ["gospa", "gospa_loc", "gospa_missed", "gospa_false", "gospa_settled", "n_missed", "n_false"]


def reference_per_scan(cfg, seed: int, estimates: pd.DataFrame, times: pd.DataFrame) -> pd.DataFrame:
    """Per run and scan: the reference's GOSPA and parts (as :func:`.run.score_estimates`) and CPU time."""
    model, truth = truth_for(cfg, seed)
    c, p = float(cfg["gospa_c"]), float(cfg["gospa_p"])
    parts = []
    for r in sorted(times.run.unique()):
        df = score_estimates(read_estimates(estimates, r, model.n_steps), truth, c, p)
        df.insert(0, "tracker", REFERENCE_NAME)
        df.insert(0, "run", int(r))
        t = times[times.run == r].set_index("scan").cpu_s
        df["time_s"] = t.reindex(df.scan).to_numpy()
        parts.append(df)
    return pd.concat(parts, ignore_index=True)


def reference_trajectories(cfg, seed: int, estimates: pd.DataFrame) -> pd.DataFrame:
    """Per run: the reference's trajectory GOSPA (its estimates linked by their Bernoulli tags, as its own
    trajectory estimator links them), as :func:`.run.trajectory_row`."""
    model, truth = truth_for(cfg, seed)
    c, p, gamma = float(cfg["gospa_c"]), float(cfg["gospa_p"]), float(cfg["trajectory_gamma"])
    rows = []
    for r in sorted(estimates.run.unique()):
        row = trajectory_row(read_labels(estimates, r, model.n_steps), read_estimates(estimates, r, model.n_steps),
                             truth, c, p, gamma)
        rows.append({"run": int(r), "tracker": REFERENCE_NAME, **row})
    return pd.DataFrame(rows)


def reference_comparison(cfg, seed: int, per_scan: pd.DataFrame, estimates: pd.DataFrame, times: pd.DataFrame,
                         per_run: pd.DataFrame | None = None):
    """One row per tracker (the reference first) on the reference's runs: mean GOSPA and its squared parts
    over those runs and scans, and after step ``settled_after`` (the reference starts from its prior of
    ``λ₀ = 3`` objects, the trackers from none), with the s.e. over runs; with ``per_run`` (the trackers'
    trajectory GOSPA) and the reference's labels, the mean trajectory GOSPA and switches too. Returns ``(table, timing)`` (time per scan: the
    reference's CPU time under Octave, the others' wall time of the step)."""
    ref = reference_per_scan(cfg, seed, estimates, times)
    runs = sorted(ref.run.unique())
    both = settled(pd.concat([ref, per_scan[per_scan.run.isin(runs)]], ignore_index=True), int(cfg["settled_after"]))
    traj = None
    if per_run is not None and "label" in estimates:
        traj = pd.concat([reference_trajectories(cfg, seed, estimates[estimates.run.isin(runs)]),
                          per_run[per_run.run.isin(runs)]], ignore_index=True)
    rows, timing = [], []
    for name, g in both.groupby("tracker", sort=False):
        by_run = g.groupby("run")[[*_COLS, "time_s"]].mean()
        n = len(by_run)
        row = {"tracker": name, "implementation": ("García-Fernández's PMBM code under GNU Octave, peer implementation"
                                                   if name == REFERENCE_NAME else "hypotrack"), "n_runs": n,
               "runs": " ".join(str(int(r)) for r in by_run.index)}
        for col in _COLS:
            row[f"{col}_mean"] = by_run[col].mean()
            row[f"{col}_se"] = by_run[col].std(ddof=1) / np.sqrt(n) if n > 1 else np.nan
        if traj is not None:
            t = traj[traj.tracker == name]
            row.update({"tgospa_mean": t.tgospa.mean(), "tgospa_se": t.tgospa.std(ddof=1) / np.sqrt(len(t)) if len(t) > 1
                        else np.nan, "n_switches_mean": t.n_switches.mean()})
        rows.append(row)
        timing.append({"tracker": name, "n_runs": n, "time_per_scan_s": by_run.time_s.mean(),
                       "clock": "CPU (Octave)" if name == REFERENCE_NAME else "wall (perf_counter)"})
    return pd.DataFrame(rows), pd.DataFrame(timing)


def reference_claims(comparison: pd.DataFrame) -> list:
    """One extension row: the reference PMBM's mean GOSPA on its runs, with every tracker's on the same runs
    in the note (no published number: the paper plots RMS curves over 100 runs)."""
    ref = comparison[comparison.tracker == REFERENCE_NAME].iloc[0]
    others = "; ".join(f"{r.tracker} {r.gospa_mean:.2f} ({r.gospa_settled_mean:.2f})" for _, r in comparison.iterrows()
                       if r.tracker != REFERENCE_NAME)
    if "tgospa_mean" in comparison:
        others += "; trajectory GOSPA: " + "; ".join(f"{r.tracker} {r.tgospa_mean:.1f}" for _, r in comparison.iterrows())
    se = "" if not np.isfinite(ref.gospa_se) else f"{ref.gospa_se:.3g}"
    return [Claim("williams2015", "the PMBM paper's own filter (García-Fernández et al. 2018 code, GNU Octave): mean "
                  "GOSPA on the Williams-2015 scenario, on the same scans as this project's trackers",
                  "extension (García-Fernández et al. 2018 Sec. VI scenario and code)", "--", f"{ref.gospa_mean:.4g}",
                  "--", "extension", f"runs {ref.runs}; after the first steps: {ref.gospa_settled_mean:.2f}; the same runs "
                  f"(after the first steps): {others}", "peer implementation",
                  # one run has no standard error: the row then gives the value alone
                  **({"n": str(int(ref.n_runs)), "mean": f"{ref.gospa_mean:.4g}", "se": se} if se else {}),
                  key="GospaPmbmReference")]


def comparison_macros(comparison: pd.DataFrame, timing: pd.DataFrame) -> tuple[dict, dict]:
    """The paper's numbers of the reference comparison: ``(values, times)``. ``values``: the number of runs
    compared, and per implementation (the reference ``Reference``, every tracker by its CamelCase name) the mean
    GOSPA on those runs, after the first steps, and its trajectory GOSPA; ``times``: the reference's CPU time
    per scan and each tracker's time per scan on the same runs as a ratio to it (timing: not byte-reproducible)."""
    def name(tracker):
        return "Reference" if tracker == REFERENCE_NAME else "".join(p.capitalize() for p in tracker.split("_"))

    values = {"RefNRuns": int(comparison.n_runs.iloc[0])}
    for r in comparison.itertuples():
        values[f"Ref{name(r.tracker)}Gospa"] = f"{r.gospa_mean:.2f}"
        values[f"Ref{name(r.tracker)}GospaSettled"] = f"{r.gospa_settled_mean:.2f}"
        if "tgospa_mean" in comparison:
            values[f"Ref{name(r.tracker)}TrajGospa"] = f"{r.tgospa_mean:.1f}"
    t = timing.set_index("tracker").time_per_scan_s
    times = {"RefReferenceMsPerScan": f"{1e3 * t[REFERENCE_NAME]:.0f}"}
    for tracker, secs in t.items():
        if tracker != REFERENCE_NAME:
            times[f"Ref{name(tracker)}SpeedUp"] = f"{t[REFERENCE_NAME] / secs:.0f}"
    return values, times

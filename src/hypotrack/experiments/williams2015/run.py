"""Monte Carlo shards of the Williams-2015 scenario: every configured tracker on identical scans.

Each run draws its returns from its own seed (the truth is common to all runs, :func:`.scenario.draw_truth`
from the experiment's truth seed); every tracker named in the config (a :mod:`hypotrack.registry`
specification, validated there) is built on :func:`.scenario.make_problem` with its own seeded stream
and stepped through the same scans. Per scan: GOSPA (``c``, ``p``, ``α = 2``; García-Fernández's
``GOSPA`` of Rahmathullah, García-Fernández & Svensson 2017, Eq. 2) on positions with its
decomposition ``d^p = localisation + missed + false`` (:func:`hypotrack.metrics.gospa`), and the
time of the step. Per run: the trajectory GOSPA of the tracker's labelled estimates against the true
trajectories (García-Fernández, Rahmathullah & Svensson 2020, LP relaxation;
:func:`hypotrack.metrics_trajectory.trajectory_gospa`).
"""

from __future__ import annotations

import time
import zlib

import numpy as np
import pandas as pd

from ..._validation import check_int
from ...metrics import gospa
from ..seeds import experiment_seeds
from ...metrics_trajectory import trajectories_from_estimates, trajectory_gospa
from ...registry import build
from .scenario import draw_truth, make_problem, scenario, simulate_scans, truth_at

__all__ = ["truth_for", "run_seeds", "scans_of_run", "tracker_seed", "run_tracker", "run_shard", "score_estimates", "trajectory_row"]


def truth_for(cfg, master_seed: int):
    """The scenario and its truth ``(n, T, 4)`` (NaN where absent), drawn from the truth's own stream."""
    model = scenario(cfg)
    return model, draw_truth(model, np.random.default_rng(experiment_seeds(master_seed, "williams2015_truth", 1)[0]))


def run_seeds(master_seed: int, run: int):
    """The seed sequence of Monte Carlo run ``run``: the same whatever the number of runs or shards, so
    run ``r`` has the same scans in every config with the same scenario (the reference's record relies on it)."""
    return experiment_seeds(master_seed, "williams2015", run + 1)[run]


def scans_of_run(model, truth, master_seed: int, run: int) -> list[np.ndarray]:
    """The returns of run ``run`` (its first spawned stream; the trackers' streams follow)."""
    return simulate_scans(model, truth, np.random.default_rng(run_seeds(master_seed, run).spawn(1)[0]))


def score_estimates(positions_per_scan, truth: np.ndarray, c: float, p: float) -> pd.DataFrame:
    """Per scan: GOSPA and its parts (each already a p-th power, summing to ``gospa**p``), the numbers
    of missed and false objects and of estimates, the true number. ``positions_per_scan``: ``(n_k, 2)``."""
    rows = []
    for k, est in enumerate(positions_per_scan):
        x, _ = truth_at(truth, k)
        g = gospa(np.asarray(est, dtype=float).reshape(-1, 2), x[:, :2], c=c, p=p, alpha=2.0)
        rows.append({"scan": k + 1, "n_true": len(x), "n_est": len(est), "gospa": g.value,
                     "gospa_loc": g.localisation, "gospa_missed": g.missed, "gospa_false": g.false,
                     "n_missed": g.n_missed, "n_false": g.n_false})
    return pd.DataFrame(rows)


def trajectory_row(labels_per_scan, positions_per_scan, truth: np.ndarray, c: float, p: float, gamma: float) -> dict:
    """Trajectory GOSPA of one run's labelled estimates against the truth, with its decomposition."""
    from ...protocol import TrackEstimates

    steps = [TrackEstimates(float(k), np.asarray(lab, dtype=np.int64), np.asarray(x, dtype=float).reshape(-1, 2))
             for k, (lab, x) in enumerate(zip(labels_per_scan, positions_per_scan))]
    _, X = trajectories_from_estimates(steps)
    if X.shape[0] == 0:
        X = np.zeros((0, truth.shape[1], 2))
    r = trajectory_gospa(X, truth[:, :, :2], c=c, p=p, gamma=gamma)
    return {"tgospa": r.value, "tgospa_loc": r.localisation, "tgospa_missed": r.missed, "tgospa_false": r.false,
            "tgospa_switches": r.switches, "n_switches": r.n_switches, "n_tracks": int(X.shape[0]),
            "integral": bool(r.integral)}


def tracker_seed(master_seed: int, run: int, name: str) -> np.random.SeedSequence:
    """The stream of tracker ``name`` in run ``run`` (from the names, not the config's order)."""
    return np.random.SeedSequence([check_int(master_seed, "seed", minimum=0), zlib.crc32(b"williams2015"), run,
                                   zlib.crc32(name.encode())])


def run_tracker(tracker, scans):
    """Step ``tracker`` through ``scans`` (scan ``k`` at time ``k``, 1-based); returns per scan the
    labels, the positions of its estimates and the time of the step (s)."""
    labels, positions, times = [], [], []
    for k, Z in enumerate(scans, start=1):
        t0 = time.perf_counter()
        tracker.step(Z, float(k))
        est = tracker.estimates()
        times.append(time.perf_counter() - t0)
        labels.append(np.asarray(est.labels, dtype=np.int64))
        positions.append(np.asarray(est.x, dtype=float)[:, :2])
    return labels, positions, times


def run_shard(cfg, master_seed: int, first_run: int, n_runs: int):
    """Per scan and per run tables of every configured tracker on runs ``first_run .. first_run + n_runs − 1``.

    Returns ``(per_scan, per_run)``; ``per_scan.time_s`` is the time of each step (keep it out of
    deterministic tables)."""
    model, truth = truth_for(cfg, master_seed)
    problem = make_problem(model)
    c, p, gamma = float(cfg["gospa_c"]), float(cfg["gospa_p"]), float(cfg["trajectory_gamma"])
    scan_parts, run_rows = [], []
    for r in range(first_run, first_run + n_runs):
        scans = scans_of_run(model, truth, master_seed, r)
        # each tracker's stream from its name: adding a tracker to the config changes no other's draws
        for name, spec in cfg["trackers"].items():
            ts = tracker_seed(master_seed, r, name)
            print(f"williams2015 run {r}: {name}", flush=True)
            tracker = build(dict(spec), problem, seed=np.random.default_rng(ts), where=f"williams2015.trackers ({name})")
            labels, positions, times = run_tracker(tracker, scans)
            df = score_estimates(positions, truth, c, p)
            df.insert(0, "tracker", name)
            df.insert(0, "run", r)
            df["time_s"] = times
            scan_parts.append(df)
            run_rows.append({"run": r, "tracker": name,
                             **trajectory_row(labels, positions, truth, c, p, gamma)})
    return pd.concat(scan_parts, ignore_index=True), pd.DataFrame(run_rows)

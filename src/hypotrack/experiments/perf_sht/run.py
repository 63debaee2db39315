"""Per-scan timing of hypotrack's GNN and JPDA trackers, and the tables of the ``perf_sht`` rule.

The benchmark (speed-up targets) runs hypotrack and a peer implementation side by side in one process on
the same scenarios: a formation of closely spaced constant-velocity targets
(:func:`hypotrack.scenarios.cluttered.closely_spaced_targets`) in Poisson clutter, tracked from
known initial tracks (no initiation), so every scan costs one prediction, gating, association
and update of every track. A scan's time is the wall-clock time of that whole cycle; the
reported figure is the median over the timed scans (the first scan is a warm-up and not timed).

This module holds the hypotrack side and the tables; the lock-step timing loop is
:func:`hypotrack.experiments.stepping.run_side_by_side`, the figure is in :mod:`.figures`, the
ledger rows in :mod:`.claims`. The peer (Stone Soup) side lives in the workflow script, because
Stone Soup is a benchmark/test-only dependency that the library never imports.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...models.motion import ConstantVelocity
from ...scenarios.cluttered import closely_spaced_targets
from ...trackers._sht_common import ScanModel
from ..stepping import SHTStepper

__all__ = [
    "formation",
    "HypotrackStepper",
    "speedup_table",
    "largest_within",
    "NumpyGNNStepper",
    "BASELINE",
]

#: Name of the minimal numpy + SciPy GNN (:class:`NumpyGNNStepper`), the speed floor of the GNN.
BASELINE = "numpy_scipy_gnn"


def formation(n_targets, clutter_rate, cfg, seed):
    """The benchmark scenario: ``n_targets`` closely spaced targets in clutter (see ``perf_sht`` config)."""
    return closely_spaced_targets(
        n_targets, spacing=cfg["spacing"], speed=cfg["speed"], n_scans=cfg["n_scans"], dt=cfg["dt"],
        q_truth=cfg["q_truth"], sigma=cfg["sigma"], p_D=cfg["p_D"], clutter_rate=clutter_rate,
        margin=cfg["margin"], rng=seed,
    )


def scan_model(scenario, cfg) -> ScanModel:
    return ScanModel.from_sensor(scenario.sensor, p_gate=cfg["p_gate"])


def prior_covariance(cfg) -> np.ndarray:
    return np.diag([cfg["prior_position_std"] ** 2] * 2 + [cfg["prior_velocity_std"] ** 2] * 2)


class HypotrackStepper(SHTStepper):
    """hypotrack's tracker (``algorithm`` "gnn" or "jpda") on ``scenario``, one scan per :meth:`step`
    (:class:`~hypotrack.experiments.stepping.SHTStepper` with the benchmark's motion, scan model and
    prior, recording the largest cluster).

    GNN uses the unsquared-Mahalanobis criterion with missed distance ``sqrt(gate)`` (the
    criterion of Stone Soup's ``GNNWith2DAssignment`` + ``DistanceHypothesiser``), so both
    implementations solve the same problem and their associations can be compared. Tracks are
    never deleted (known tracks only), as on the peer side.
    """

    def __init__(self, scenario, algorithm, cfg):
        n = len(scenario.initial_states)
        super().__init__(ConstantVelocity(cfg["q"]), scan_model(scenario, cfg), algorithm, scenario.initial_states,
                         np.broadcast_to(prior_covariance(cfg), (n, 4, 4)), scenario.times[0], scenario.scan_list(),
                         clusters=True)


def speedup_table(timings: pd.DataFrame, targets: dict, goal_n_targets: dict | None = None) -> pd.DataFrame:
    """hypotrack vs each peer implementation at equal (algorithm, n_targets, clutter_rate).

    ``timings`` has columns ``algorithm, implementation, n_targets, clutter_rate, median_ms``;
    ``targets`` maps a peer implementation to the speed-up goal (e.g. 40 for GNNWith2DAssignment);
    ``goal_n_targets`` maps a peer to the ``[smallest, largest]`` formation the goal is set for
    (other sizes are timed and tabled without a goal); a peer not in it has its goal at every size.
    """
    goal_n_targets = goal_n_targets or {}
    ours = timings[timings["implementation"] == "hypotrack"]
    rows = []
    for _, peer in timings[timings["implementation"] != "hypotrack"].iterrows():
        match = ours[(ours["algorithm"] == peer["algorithm"]) & (ours["n_targets"] == peer["n_targets"])
                     & (ours["clutter_rate"] == peer["clutter_rate"])]
        if match.empty or not np.isfinite(peer["median_ms"]):
            continue
        h = float(match["median_ms"].iloc[0])
        ratio = peer["median_ms"] / h
        goal = targets.get(peer["implementation"], np.nan)
        lo_n, hi_n = goal_n_targets.get(peer["implementation"], (-np.inf, np.inf))
        if not lo_n <= peer["n_targets"] <= hi_n:
            goal = np.nan
        rows.append((peer["algorithm"], peer["implementation"], peer["n_targets"], peer["clutter_rate"], h,
                     peer["median_ms"], ratio, h / peer["median_ms"], goal,
                     bool(ratio >= goal) if np.isfinite(goal) else None))
    return pd.DataFrame(rows, columns=["algorithm", "peer", "n_targets", "clutter_rate", "hypotrack_ms", "peer_ms",
                                       "speedup", "hypotrack_over_peer", "goal", "goal_met"])


def largest_within(rows: pd.DataFrame, limit_ms: float) -> pd.DataFrame:
    """Per (algorithm, implementation): the largest formation (and its largest cluster) under ``limit_ms`` per scan."""
    out = []
    for (alg, impl), g in rows.groupby(["algorithm", "implementation"], sort=True):
        ok = g[g["median_ms"] <= limit_ms]
        bad = g[g["median_ms"] > limit_ms]
        best = ok.loc[ok["n_targets"].idxmax()] if len(ok) else None
        out.append((alg, impl, int(best["n_targets"]) if best is not None else 0,
                    int(best["max_cluster"]) if best is not None else 0,
                    float(best["median_ms"]) if best is not None else np.nan,
                    int(bad["n_targets"].min()) if len(bad) else np.nan,
                    int(g["n_targets"].max())))
    return pd.DataFrame(out, columns=["algorithm", "implementation", "largest_n_targets", "largest_cluster_tracks",
                                      "ms_per_scan", "first_n_over_limit", "largest_n_tried"])


class NumpyGNNStepper:
    """The speed floor: a minimal numpy + SciPy GNN doing the same work as :class:`HypotrackStepper`.

    A benchmark baseline, not a library path (no validation, no clustering, no initiation, no
    track bookkeeping): predict every track with one batched constant-velocity prediction,
    compute every (return, track) Mahalanobis distance, solve one
    ``scipy.optimize.linear_sum_assignment`` on Stone Soup's criterion (unsquared distance,
    ``g = sqrt(gate)`` per target left unassigned, pairs with ``d < g`` only: the criterion of
    hypotrack's ``gnn_score="mahalanobis"``) and apply the Joseph-form update to the assigned
    tracks. Its associations and states must equal hypotrack's (checked in the table).
    """

    def __init__(self, scenario, cfg):
        from scipy.optimize import linear_sum_assignment

        self._lsa = linear_sum_assignment
        model = scan_model(scenario, cfg)
        cv = ConstantVelocity(cfg["q"])
        self.H, self.R, self.g = model.H, model.R, float(np.sqrt(model.gate))
        self.cv = cv
        n = len(scenario.initial_states)
        self.x = np.array(scenario.initial_states, dtype=float)
        self.P = np.broadcast_to(prior_covariance(cfg), (n, 4, 4)).copy()
        self.scans = scenario.scan_list()
        self.t = scenario.times[0]
        self.a = np.zeros(0, dtype=np.int64)

    def step(self, k):
        t, Z = self.scans[k]
        dt, self.t = t - self.t, t
        F, Q, H, R = self.cv.F(dt), self.cv.Q(dt), self.H, self.R
        x = self.x @ F.T
        P = F @ self.P @ F.T + Q
        S = H @ P @ H.T + R
        Si = np.linalg.inv(S)
        K = P @ H.T @ Si
        nu = Z[:, None, :] - (x @ H.T)[None, :, :]  # (m, n, 2)
        d = np.sqrt(np.einsum("mni,nij,mnj->mn", nu, Si, nu))
        m, n = d.shape
        a = np.full(m, -1, dtype=np.int64)
        if m and n:
            # Gains g - d of the allowed pairs (d < g); a pair of gain <= 0 is as good as none.
            allowed = d < self.g
            rows, cols = self._lsa(np.where(allowed, d - self.g, 0.0))
            hit = allowed[rows, cols]
            r, j = rows[hit], cols[hit]
            a[r] = j
            Kj = K[j]
            x[j] = x[j] + np.einsum("ndp,np->nd", Kj, nu[r, j])
            IKH = np.eye(4) - Kj @ H
            P[j] = IKH @ P[j] @ IKH.transpose(0, 2, 1) + Kj @ R @ Kj.transpose(0, 2, 1)
        self.x, self.P, self.a = x, P, a

    def record(self, run):
        run.outputs.append(self.a.copy())
        run.states.append((self.x.copy(), self.P.copy()))

"""Per-scan timing of hypotrack's GNN and JPDA trackers, and the tables of the ``perf_sht`` rule.

The benchmark (speed-up targets) runs hypotrack and a peer implementation side by side in one process on
the same scenarios: a formation of closely spaced constant-velocity targets
(:func:`hypotrack.scenarios.cluttered.closely_spaced_targets`) in Poisson clutter, tracked from
known initial tracks (no initiation), so every scan costs one prediction, gating, association
and update of every track. A scan's time is the wall-clock time of that whole cycle; the
reported figure is the median over the timed scans (the first scan is a warm-up and not timed).

This module holds the hypotrack side and the bookkeeping; the peer (Stone Soup) side lives in
the workflow script, because Stone Soup is a benchmark/test-only dependency that the library
never imports.
"""

from __future__ import annotations

import re

import time

import numpy as np
import pandas as pd

from ...association import find_clusters
from ...models.motion import ConstantVelocity
from ...scenarios.cluttered import closely_spaced_targets
from ...trackers._sht_common import ScanModel
from ...reporting.ledger import Claim
from ...trackers.tracker import SingleHypothesisTracker

__all__ = [
    "formation",
    "BenchmarkRun",
    "HypotrackStepper",
    "run_side_by_side",
    "max_abs_difference",
    "speedup_table",
    "largest_within",
    "plot_benchmark",
    "perf_sht_claims",
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


class BenchmarkRun:
    """Per-scan times (s) and outputs of one implementation on one scenario.

    Attributes
    ----------
    times : list of float
        Wall-clock seconds of each timed scan.
    outputs : list
        Per timed scan: the event vector (GNN) or the ``β`` matrix ``(n, m + 1)`` (JPDA), rows
        in target order, columns in return order.
    states : list of (x (n, 4), P (n, 4, 4))
        Updated tracks after each timed scan, hypotrack state order ``[x, y, vx, vy]``.
    max_cluster : int
        Largest number of tracks in one cluster met in the timed scans.
    """

    def __init__(self):
        self.times, self.outputs, self.states = [], [], []
        self.max_cluster = 0
        self.done = False

    @property
    def median_ms(self) -> float:
        return 1e3 * float(np.median(self.times)) if self.times else float("nan")


class HypotrackStepper:
    """hypotrack's tracker (``algorithm`` "gnn" or "jpda") on ``scenario``, one scan per :meth:`step`.

    GNN uses the unsquared-Mahalanobis criterion with missed distance ``sqrt(gate)`` (the
    criterion of Stone Soup's ``GNNWith2DAssignment`` + ``DistanceHypothesiser``), so both
    implementations solve the same problem and their associations can be compared. Tracks are
    never deleted (known tracks only), as on the peer side.
    """

    def __init__(self, scenario, algorithm, cfg):
        model = scan_model(scenario, cfg)
        self.tracker = SingleHypothesisTracker(
            ConstantVelocity(cfg["q"]), model, association=algorithm, gnn_score="mahalanobis", max_misses=10**9
        )
        n = len(scenario.initial_states)
        self.tracker.initialise(
            scenario.initial_states, np.broadcast_to(prior_covariance(cfg), (n, 4, 4)), time=scenario.times[0]
        )
        self.scans = scenario.scan_list()

    def step(self, k):
        t, Z = self.scans[k]
        self.tracker.step(Z, t)

    def record(self, run: "BenchmarkRun"):
        tr = self.tracker
        run.outputs.append(np.array(tr.last_association, copy=True))
        run.states.append((tr.x.copy(), tr.P.copy()))
        run.max_cluster = max([run.max_cluster, *(len(c.tracks) for c in find_clusters(tr.last_gated.valid))])


def run_side_by_side(steppers: dict, n_scans: int, *, max_scans=None, budget_s=None, warmup=True) -> dict:
    """Step several implementations through the same scans in lock-step and time each scan.

    ``steppers`` maps a name to an object with ``step(k)`` (process scan ``k``) and
    ``record(run)`` (append its outputs to a :class:`BenchmarkRun`). Interleaving scan by scan,
    in alternating order, exposes every implementation to the same machine load. With
    ``warmup`` scan 1 is not timed; an implementation stops after ``max_scans`` timed scans or
    once it has spent ``budget_s`` seconds.
    """
    runs = {name: BenchmarkRun() for name in steppers}
    names = list(steppers)
    for k in range(1, n_scans):
        active = [nm for nm in names if not runs[nm].done]
        if not active:
            break
        for nm in active if k % 2 else active[::-1]:
            t0 = time.perf_counter()
            steppers[nm].step(k)
            dt = time.perf_counter() - t0
            if warmup and k == 1:
                continue
            run = runs[nm]
            run.times.append(dt)
            steppers[nm].record(run)
            run.done = (max_scans is not None and len(run.times) >= max_scans) or (
                budget_s is not None and sum(run.times) > budget_s
            )
    return runs


def max_abs_difference(a: BenchmarkRun, b: BenchmarkRun):
    """Largest |difference| of the outputs and of the updated states over the scans both timed."""
    k = min(len(a.outputs), len(b.outputs))
    if k == 0:
        return float("nan"), float("nan")
    out = max(float(np.max(np.abs(np.asarray(x, float) - np.asarray(y, float)), initial=0.0))
              for x, y in zip(a.outputs[:k], b.outputs[:k]))
    st = max(max(float(np.max(np.abs(xa - xb), initial=0.0)), float(np.max(np.abs(Pa - Pb), initial=0.0)))
             for (xa, Pa), (xb, Pb) in zip(a.states[:k], b.states[:k]))
    return out, st


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


_STYLE = {
    "hypotrack": dict(color="tab:red", marker="o"),
    "GNNWith2DAssignment": dict(color="tab:blue", marker="s"),
    "JPDAwithEHM2": dict(color="tab:blue", marker="s"),
    "JPDA": dict(color="tab:green", marker="^"),
    "numpy_scipy_gnn": dict(color="0.3", marker="x", ls="--"),
}


def plot_benchmark(timings: pd.DataFrame, ratios: pd.DataFrame, pdf, png):
    """Per-scan time vs number of targets (GNN; JPDA at each clutter rate) and the speed-ups, with
    the goals as dotted lines named in the legend (below the panels, never over the data)."""
    from ...reporting import figure_style

    rates = sorted(timings.loc[timings["algorithm"] == "jpda", "clutter_rate"].unique())
    n_panels = 2 + len(rates)
    nrows = (n_panels + 1) // 2
    fig, grid = figure_style.subplots(nrows, 2, height=min(2.2 * nrows + 1.4, figure_style.MAX_HEIGHT_IN),
                                      squeeze=False)
    axes = grid.ravel()[:n_panels]
    for extra in grid.ravel()[n_panels:]:
        extra.set_visible(False)
    panels = [("gnn", None, axes[0])] + [("jpda", r, ax) for r, ax in zip(rates, axes[1:])]
    for alg, rate, ax in panels:
        g = timings[timings["algorithm"] == alg]
        if rate is not None:
            g = g[g["clutter_rate"] == rate]
        for impl, h in g.groupby("implementation"):
            h = h.sort_values("n_targets")
            name = {"hypotrack": impl, BASELINE: "minimal numpy + SciPy GNN (baseline)"}.get(impl, f"Stone Soup {impl}")
            ax.plot(h["n_targets"], h["median_ms"], label=name, **_STYLE.get(impl, {}))
        ax.set_yscale("log")
        ax.set_xlabel("number of closely spaced targets")
        ax.set_ylabel("median time per scan (ms)")
        clutter = f"{rate:g} clutter returns/scan" if rate is not None else f"{g['clutter_rate'].iloc[0]:g} clutter/scan"
        ax.set_title(f"{alg.upper()}: predict + associate + update,\n{clutter}")
        ax.grid(True, which="both", alpha=0.3)
    ax = axes[-1]
    # speed-up lines: dashed, in colours and markers no timing line uses (their legend entries stay apart)
    ratio_styles = [dict(color=c, marker=m, ls="--") for c, m in zip(
        ["tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "tab:gray"] * 4, ["D", "v", "P", "X", "*", "h"] * 4)]
    for ((alg, peer, rate), g), style in zip(ratios.groupby(["algorithm", "peer", "clutter_rate"]), ratio_styles):
        g = g.sort_values("n_targets")
        ax.plot(g["n_targets"], g["speedup"], label=f"speed-up: {alg.upper()} vs {peer} ({rate:g} clutter/scan)", **style)
    for goal, ls in zip(sorted(ratios["goal"].dropna().unique()), [":", "--", "-."] * 4):
        sizes = ratios.loc[ratios["goal"] == goal, "n_targets"]
        ax.axhline(goal, color="k", ls=ls, lw=1, label=f"goal {goal:.3g}× ({sizes.min()}–{sizes.max()} targets)")
    ax.set_yscale("log")
    ax.set_xlabel("number of closely spaced targets")
    ax.set_ylabel("speed-up (peer time / hypotrack time)")
    ax.set_title("hypotrack speed-up over each peer\n(< 1: slower than it)")
    ax.grid(True, which="both", alpha=0.3)
    figure_style.legend_below(fig, ncol=2)
    fig.suptitle("Single-hypothesis trackers: hypotrack vs Stone Soup, same scenarios, one run")
    figure_style.save(fig, pdf, png, width=1.0)


#: Largest difference from Stone Soup's outputs and states accepted as agreement (rounding only).
PEER_TOL = 1e-9


def perf_sht_claims(speedups: pd.DataFrame, largest: pd.DataFrame, timings: pd.DataFrame | None = None) -> list:
    """Ledger rows (extensions) for the speed of GNN/JPDA against Stone Soup, measured side by side, and
    (from ``timings``) the largest difference of their outputs (associations or marginals) and states on
    the same scans: the peer-implementation evidence that the timed trackers compute the same thing."""
    claims = []
    if timings is not None:
        for algorithm, g in timings.groupby("algorithm", sort=True):
            out, state = float(g["max_abs_output_diff"].max()), float(g["max_abs_state_diff"].max())
            claims.append(Claim(
                "perf_sht", f"{algorithm.upper()} agrees with Stone Soup on the timed scans", "extension",
                # the scans timed depend on the time budget, so the row states the bound, not the last digits
                "--", f"max |difference| below {PEER_TOL:g} (associations/marginals and states)"
                if max(out, state) <= PEER_TOL else f"max |difference| {max(out, state):.1e}", f"{PEER_TOL:g}",
                "extension" if max(out, state) <= PEER_TOL else "not reproduced",
                ", ".join(sorted(set(g["implementation"]) - {"hypotrack"})), "peer implementation",
                key=f"{algorithm}_peer_agreement"))
    for (algorithm, peer), g in speedups[speedups["goal"].notna()].groupby(["algorithm", "peer"]):
        goal = float(g["goal"].iloc[0])
        lo, hi = float(g["speedup"].min()), float(g["speedup"].max())
        if peer == BASELINE:  # the floor: hypotrack's time over the baseline's, at most 1 / goal
            slow = g["hypotrack_over_peer"]
            claims.append(Claim(
                "perf_sht", "GNN per-scan time over a minimal numpy + SciPy GNN doing the same work", "extension "
                "(speed-floor target)", f"<= {1 / goal:.3g}x", f"{slow.min():.2f}x to {slow.max():.2f}x",
                f"{int(g['n_targets'].min())}-{int(g['n_targets'].max())} targets", "extension",
                f"target {'met' if bool(g['goal_met'].all()) else 'not met'}; identical associations; same run",
                "measurement", key="GnnFloor"))
            continue
        met = bool((g["speedup"] >= goal).all())
        claims.append(Claim(
            "perf_sht", f"{algorithm.upper()} per-scan speed-up vs Stone Soup {peer}", "extension (speed-up target)",
            f">= {goal:g}x", f"{lo:.0f}x to {hi:.0f}x", f"{int(g['n_targets'].min())}-{int(g['n_targets'].max())} targets",
            "extension", f"target {'met' if met else 'not met'} at the goal's formation sizes; identical "
            "associations/marginals; ratios from one run, same scenarios", "measurement",
            key=f"{algorithm}_speedup_{re.sub('[^A-Za-z0-9]', '', peer)}"))
    lg = largest.set_index(["algorithm", "implementation"])
    for algorithm in sorted(largest["algorithm"].unique()):
        parts = [f"{impl}: {int(r.largest_cluster_tracks)}" for (alg, impl), r in lg.iterrows() if alg == algorithm]
        claims.append(Claim("perf_sht", f"largest {algorithm.upper()} cluster within 1 s per scan", "extension",
                            "--", "; ".join(parts), "--", "extension", "tracks in one cluster", "measurement",
                            key=f"{algorithm}_largest_cluster"))
    return claims


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

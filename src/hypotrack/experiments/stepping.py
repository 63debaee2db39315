"""Timing shared by the experiments: clocks, best-of-repeats timing, and steppers timed side by side.

Several experiments time a tracker's steps the same way; they take the pieces from here instead of
from one another:

* :class:`Clocks` — wall (``time.perf_counter``) and CPU (``time.process_time``, this process only,
  which other jobs on a shared machine do not inflate) seconds of a block;
* :func:`best_time` — the fastest of several runs of one call (the usual guard against a loaded
  machine), with the result of the last run;
* :func:`run_side_by_side` — several implementations stepped through the same scans in lock-step,
  each scan timed, into a :class:`BenchmarkRun` per implementation; :func:`max_abs_difference`
  compares two runs' outputs and states;
* :class:`SHTStepper` — hypotrack's GNN or JPDA from known tracks, one scan per ``step(k)``, as
  :func:`run_side_by_side` steps it (the hypotrack side of every peer benchmark).
"""

from __future__ import annotations

import time

import numpy as np

from ..association import find_clusters
from ..trackers.tracker import SingleHypothesisTracker

__all__ = ["BenchmarkRun", "Clocks", "SHTStepper", "best_time", "max_abs_difference", "run_side_by_side"]


class Clocks:
    """Wall and CPU seconds of a ``with`` block: ``with Clocks() as c: ...`` then ``c.wall``, ``c.cpu``."""

    __slots__ = ("wall", "cpu", "_w0", "_c0")

    def __init__(self):
        self.wall = self.cpu = float("nan")

    def __enter__(self) -> Clocks:
        self._c0, self._w0 = time.process_time(), time.perf_counter()
        return self

    def __exit__(self, *exc) -> bool:
        self.wall = time.perf_counter() - self._w0
        self.cpu = time.process_time() - self._c0
        return False


def best_time(fn, repeats: int, *, cpu: bool = False):
    """``(result, seconds)``: ``fn()`` run ``repeats`` times (at least once), the result of the last
    run and the least time of one run, wall clock (or this process's CPU time with ``cpu``). An
    exception of ``fn`` propagates at once."""
    clock = time.process_time if cpu else time.perf_counter
    best, result = np.inf, None
    for _ in range(max(1, int(repeats))):
        t0 = clock()
        result = fn()
        best = min(best, clock() - t0)
    return result, best


class BenchmarkRun:
    """Per-scan times (s) and outputs of one implementation on one scenario.

    Attributes
    ----------
    times : list of float
        Wall-clock seconds of each timed scan.
    outputs : list
        Per timed scan: the event vector (GNN) or the ``β`` matrix ``(n, m + 1)`` (JPDA), rows
        in target order, columns in return order.
    states : list of (x (n, d), P (n, d, d))
        Updated tracks after each timed scan, hypotrack state order.
    max_cluster : int
        Largest number of tracks in one cluster met in the timed scans (0 when not recorded).
    """

    def __init__(self):
        self.times, self.outputs, self.states = [], [], []
        self.max_cluster = 0
        self.done = False

    @property
    def median_ms(self) -> float:
        return 1e3 * float(np.median(self.times)) if self.times else float("nan")


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


class SHTStepper:
    """hypotrack's GNN or JPDA (``algorithm``) over ``scans`` (``[(time, returns)]``) from known tracks,
    one scan per :meth:`step`, for :func:`run_side_by_side`.

    As a peer implementation runs them: no initiation, no deletion, GNN on Stone Soup's
    unsquared-Mahalanobis criterion (``GNNWith2DAssignment`` + ``DistanceHypothesiser``; missed
    distance the square root of the gate), so both solve the same problem and their associations
    can be compared. ``clusters`` also records the largest cluster of tracks met
    (:attr:`BenchmarkRun.max_cluster`).
    """

    def __init__(self, motion, model, algorithm: str, initial_states, initial_covs, start_time: float, scans, *,
                 clusters: bool = False):
        if algorithm not in ("gnn", "jpda"):
            raise ValueError(f"algorithm must be 'gnn' or 'jpda', got {algorithm!r}")
        self.tracker = SingleHypothesisTracker(motion, model, association=algorithm, gnn_score="mahalanobis",
                                               max_misses=10**9, block_pairs=None)  # record() reads last_gated
        self.tracker.initialise(initial_states, initial_covs, time=start_time)
        self.scans = scans
        self.clusters = clusters

    def step(self, k):
        t, Z = self.scans[k]
        self.tracker.step(Z, t)

    def record(self, run: BenchmarkRun):
        tr = self.tracker
        run.outputs.append(np.array(tr.last_association, copy=True))
        run.states.append((tr.x.copy(), tr.P.copy()))
        if self.clusters:
            run.max_cluster = max([run.max_cluster, *(len(c.tracks) for c in find_clusters(tr.last_gated.valid))])

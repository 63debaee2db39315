"""Murty's k best assignments: this project's :func:`~hypotrack.association.murty_k_best` beside nrl-tracker's.

nrl-tracker (PyPI; imported as ``pytcl``) is a Python port of the NRL Tracker Component Library; its
``pytcl.assignment_algorithms.two_dimensional.kbest.murty(cost, k)`` ranks the ``k`` cheapest complete
assignments of a cost matrix (Murty 1968). Both run on the same random ``n × n`` costs (this project's
on the scores ``−C``): the ``k`` best sums must agree, and each is timed (best of ``repeats``, the two
interleaved so the machine's load falls on both alike).
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ...association.assignment import murty_k_best

__all__ = ["peer_murty", "kbest_problems", "kbest_benchmark"]


def peer_murty():
    """nrl-tracker's ``murty(cost, k)``, or ``None`` when the package is not installed."""
    try:
        from pytcl.assignment_algorithms.two_dimensional.kbest import murty
    except ImportError:
        return None
    return murty


def kbest_problems(n: int, n_problems: int, rng) -> list[np.ndarray]:
    """``n_problems`` cost matrices ``n × n`` with entries uniform on [0, 100)."""
    return [rng.uniform(0.0, 100.0, size=(n, n)) for _ in range(n_problems)]


def _timed(fn, *args):
    """(wall s, CPU s of this process, result): on a shared machine the CPU time is the steadier one."""
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn(*args)
    return np.array([time.perf_counter() - t0, time.process_time() - c0]), out


def kbest_benchmark(n: int, k: int, n_problems: int, repeats: int, rng, target_ms: float) -> pd.DataFrame:
    """Per problem: both implementations' ``k`` best sums compared (largest absolute difference) and
    their wall and CPU times (ms, best of ``repeats``; each repetition times one then the other), the
    ratios peer / hypotrack and whether hypotrack's CPU time met ``target_ms`` (after one untimed call of each on another
    problem). Without nrl-tracker the peer's columns are
    NaN (``peer`` says so)."""
    murty = peer_murty()
    warm = rng.uniform(0.0, 100.0, size=(n, n))  # first calls pay imports and compilation: not timed
    murty_k_best(-warm, k)
    if murty is not None:
        murty(warm, k)
    rows = []
    for i, C in enumerate(kbest_problems(n, n_problems, rng)):
        t_own = t_peer = np.full(2, np.inf)
        for _ in range(repeats):
            t, own = _timed(murty_k_best, -C, k)
            t_own = np.minimum(t_own, t)
            if murty is not None:
                t, res = _timed(murty, C, k)
                t_peer = np.minimum(t_peer, t)
        sums = np.array([-s for s, _ in own])
        row = {"problem": i, "n": n, "k": k, "n_found": len(own), "hypotrack_ms": 1e3 * t_own[0],
               "hypotrack_cpu_ms": 1e3 * t_own[1], "target_ms": target_ms, "target_met": 1e3 * t_own[1] <= target_ms,
               "peer": "nrl-tracker (pytcl) murty" if murty else "nrl-tracker not installed"}
        if murty is not None:
            peer_sums = np.asarray(res.costs, dtype=float)
            agree = len(peer_sums) == len(sums)
            row.update({"peer_ms": 1e3 * t_peer[0], "peer_cpu_ms": 1e3 * t_peer[1],
                        "ratio_peer_over_hypotrack": t_peer[0] / t_own[0],
                        "cpu_ratio_peer_over_hypotrack": t_peer[1] / t_own[1],
                        "max_abs_sum_difference": float(np.max(np.abs(peer_sums - sums))) if agree else np.inf,
                        "same_k_best_sums": bool(agree and np.allclose(peer_sums, sums, rtol=0, atol=1e-9))})
        else:
            row.update({"peer_ms": np.nan, "peer_cpu_ms": np.nan, "ratio_peer_over_hypotrack": np.nan,
                        "cpu_ratio_peer_over_hypotrack": np.nan, "max_abs_sum_difference": np.nan,
                        "same_k_best_sums": np.nan})
        rows.append(row)
    return pd.DataFrame(rows)

"""The factored engine's fast path measured on the catalogue's scans: :func:`fast_path_timing`.

The fast path (:mod:`hypotrack.hypotheses.factored.fast_path`, option ``fast_path``) steps the lone
tracks with one return nothing else gates in one batch. It changes no number of the posterior, so
the measure is the CPU time alone: the same scans through each factored tracker with the fast path
off and on, stepped in lockstep (scan ``k`` of both in turn, the order alternated each scan, so a
change of the machine's load hits both alike), the posteriors compared bit for bit at every scan.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from .lockstep import same_scans
from .run import make_tracker

__all__ = ["fast_path_timing"]


def fast_path_timing(cfg, n: int, seed: int, trackers=("glmb", "homht_kbest"), *, n_scans: int | None = None,
                     warm_scans: int = 2, scenario=None, factored=None, warm_run: bool = True) -> pd.DataFrame:
    """CPU per object in view per scan of each factored tracker with the fast path off and on.

    Parameters
    ----------
    cfg : the ``ssa_catalogue`` config section (its ``trackers``, ``model``, ``radar``, ...).
    n, seed : population size and seed (:func:`~.run.build_scenario`), unless ``scenario`` is given.
    trackers : names of factored trackers of ``cfg["trackers"]``.
    n_scans : scans stepped (default: all of the scenario's).
    warm_scans : first scans stepped but not timed (first compiled calls).
    factored : factored options overriding the config's (e.g. ``{"min_weight": 0.002}``), both runs alike.
    warm_run : step a general-path tracker through the scans first, untimed, so that every compiled
        kernel the scans need is compiled before the timed pair runs (whichever of the pair met a new
        kernel first would otherwise pay its compilation).

    Returns
    -------
    DataFrame, one row per (tracker, fast_path): scans timed, objects in view per scan (mean), CPU
    seconds per scan, µs per object in view per scan, the share of touched components the fast path
    took, the speed-up over the general path, ``identical`` (bit-for-bit the same posterior as the
    general path at every scan) and ``stopped``: empty, or the scan and error at which the engine refused
    a state (both paths alike), the scans before it timed.
    """
    lock = same_scans(cfg, n, seed, scenario, n_scans)
    problem, in_view, n_scans = lock.problem, lock.in_view, len(lock.scans)
    rows = []
    for name in trackers:
        pair = [make_tracker(name, cfg, problem, int(seed), **{**(factored or {}), "fast_path": on})
                for on in (False, True)]
        if warm_run:
            _warm(make_tracker(name, cfg, problem, int(seed), **{**(factored or {}), "fast_path": False}), lock)
        cpu, fast, touched, view, identical, done, error = [0.0, 0.0], 0, 0, 0, True, 0, ""
        for k in range(n_scans):
            t_k, Zt = lock.returns(k)
            used = [0.0, 0.0]
            try:
                for i in (np.arange(2) if k % 2 == 0 else np.arange(2)[::-1]):
                    c0 = time.process_time()
                    pair[i].step(Zt, t_k)
                    used[i] = time.process_time() - c0
            except ValueError as err:  # the engine refused a state (both paths hold the same posterior)
                error = f"scan {k}: {err}"
                break
            identical &= pair[0].same_posterior(pair[1])
            if k >= warm_scans:
                cpu = [c + u for c, u in zip(cpu, used)]
                st = pair[1].last_stats
                fast += st["n_fast_path"]
                touched += st["n_touched"]
                view += int(in_view.get(k, 0))
                done += 1
        K = max(done, 1)
        for i, on in enumerate((False, True)):
            rows.append(dict(tracker=name, n_objects=int(n), fast_path=on, n_scans=done, in_view_per_scan=view / K,
                             cpu_s_per_scan=cpu[i] / K, us_per_object_in_view=1e6 * cpu[i] / max(view, 1),
                             fast_share=fast / max(touched, 1) if on else 0.0, speedup=cpu[0] / max(cpu[i], 1e-12),
                             identical=bool(identical), stopped=error))
    return pd.DataFrame(rows)


def _warm(tracker, lock):
    """``tracker`` stepped through the scans of ``lock`` (until the engine refuses a state), untimed."""
    for k in range(len(lock.scans)):
        t_k, Zt = lock.returns(k)
        try:
            tracker.step(Zt, t_k)
        except ValueError:
            return

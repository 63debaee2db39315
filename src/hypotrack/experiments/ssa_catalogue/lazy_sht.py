"""GNN and JPDA with lazy prediction measured on the catalogue's scans: :func:`lazy_sht_timing`.

With ``lazy`` (:mod:`hypotrack.trackers.deferred`) a track out of the radar's view is not predicted
each scan; it is predicted over the scans it missed, scan by scan, when it may be seen again. Its
posterior is the eager tracker's with ``gate_out_of_view=False`` (a track whose predicted mean is out
of view takes no return, ``p_D = 0`` there). Three runs per tracker on the same scans, stepped in
lockstep (scan ``k`` of each in turn, the order rotated each scan, so a change of the machine's load
hits all alike): ``eager`` (every track gated, the lecture's rule), ``eager_in_view`` (only tracks in
view gated), ``lazy`` (deferred tracks replayed scan by scan: the eager posterior) and ``lazy_gap``
(deferred tracks predicted once over their gap: the factored engine's lane, an approximation); the
in-view estimates of each compared with ``eager_in_view``'s at every scan, every track's mean and
covariance at the last.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from .lockstep import same_scans
from .run import tracker_spec
from ...registry import build
from ...registry.spec import TrackerSpec

__all__ = ["MODES", "lazy_sht_timing"]

#: The runs of :func:`lazy_sht_timing`: (name, tracker options).
MODES = (("eager", {"lazy": False, "gate_out_of_view": True}),
         ("eager_in_view", {"lazy": False, "gate_out_of_view": False}),
         ("lazy", {"lazy": True, "gate_out_of_view": None, "lazy_prediction": "replay"}),
         ("lazy_gap", {"lazy": True, "gate_out_of_view": None, "lazy_prediction": "gap"}))


_SAME = 1e-9  # km, km/s: rounding, not another association


def _make(name, cfg, problem, opts):
    spec = tracker_spec(cfg, name)
    return build(TrackerSpec(spec.kind, {**spec.options, **opts}), problem, seed=0)


def _in_view(tracker, in_view):
    e = tracker.estimates(covariances=False)
    inv = in_view(e.x) if len(e) else np.zeros(0, bool)
    return e.labels[inv], e.x[inv]


def lazy_sht_timing(cfg, n: int, seed: int, trackers=("gnn", "jpda"), *, n_scans: int | None = None,
                    warm_scans: int = 2, scenario=None) -> pd.DataFrame:
    """CPU per scan and per object in view of GNN/JPDA eager, eager gating in view only, and lazy.

    Returns one row per (tracker, mode): scans timed, objects in view per scan, CPU s per scan, µs per
    object in view per scan, tracks predicted per scan, the speed-up over ``eager``, and each mode against
    ``eager_in_view``: ``same_in_view`` (the same labels of the estimates in view at every scan),
    ``max_in_view_diff`` (the largest difference of their means, km or km/s), ``max_x_diff``/``max_P_diff`` (km, km² or (km/s)²: every track's mean and covariance after
    the last scan, the lazy tracker's deferred ones predicted to it) and ``scans_differ_from_eager``
    (scans at which the in-view estimates of ``eager_in_view`` differ from the every-track-gated tracker's:
    other labels, or means more than 1e-9 apart).
    """
    lock = same_scans(cfg, n, seed, scenario, n_scans)
    problem, in_view_count, n_scans = lock.problem, lock.in_view, len(lock.scans)
    rows = []
    for name in trackers:
        runs = [_make(name, cfg, problem, opts) for _, opts in MODES]
        cpu, pred = np.zeros(len(runs)), np.zeros(len(runs))
        same, diff_view = np.ones(len(runs), bool), np.zeros(len(runs))
        view, done, differ = 0, 0, 0
        for k in range(n_scans):
            t_k, Zt = lock.returns(k)
            used = np.zeros(len(runs))
            for i in np.roll(np.arange(len(runs)), -k):
                c0 = time.process_time()
                runs[i].step(Zt, t_k)
                used[i] = time.process_time() - c0
            est = [_in_view(r, problem.in_view) for r in runs]
            for i in range(len(runs)):
                same[i] &= np.array_equal(est[1][0], est[i][0])
                if same[i]:
                    diff_view[i] = max(diff_view[i], float(np.abs(est[1][1] - est[i][1]).max(initial=0.0)))
            differ += not (np.array_equal(est[0][0], est[1][0])
                           and float(np.abs(est[0][1] - est[1][1]).max(initial=0.0)) <= _SAME)
            if k >= warm_scans:
                cpu += used
                pred += [r.last_predicted for r in runs]
                view += int(in_view_count.get(k, 0))
                done += 1
        final = [r.estimates() for r in runs]
        a = final[1]
        K = max(done, 1)
        for i, (mode, _) in enumerate(MODES):
            b = final[i]
            ok = np.array_equal(a.labels, b.labels)
            dx = float(np.abs(a.x - b.x).max(initial=0.0)) if ok else np.inf
            dP = float(np.abs(a.P - b.P).max(initial=0.0)) if ok else np.inf
            rows.append(dict(tracker=name, n_objects=int(n), mode=mode, n_scans=done, in_view_per_scan=view / K,
                             cpu_s_per_scan=cpu[i] / K, us_per_object_in_view=1e6 * cpu[i] / max(view, 1),
                             predicted_per_scan=pred[i] / K, speedup=cpu[0] / max(cpu[i], 1e-12),
                             same_in_view=bool(same[i]), max_in_view_diff=diff_view[i] if same[i] else np.inf,
                             max_x_diff=dx, max_P_diff=dP,
                             scans_differ_from_eager=int(differ)))
    return pd.DataFrame(rows)

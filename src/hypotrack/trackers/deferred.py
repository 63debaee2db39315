"""Deferred prediction of the single-hypothesis trackers' tracks out of view (``lazy=True``).

A track whose predicted mean is out of the sensor's field of view takes no return (``p_D = 0`` there)
and is not missed, so a scan changes it by its prediction only. With ``lazy`` such a track is not
predicted each scan: it keeps its moments ``(x, P)`` at the scan it was last predicted to, and only its
mean is advanced each scan (one short propagation per track, no state-transition matrix, no covariance)
to decide whether it may be seen. When it may (or when the estimates are asked for) the scans it missed
are *replayed*: the same EKF predictions, scan by scan, the eager tracker would have made,

    x_{j+1} = f(x_j, Δt_j),   P_{j+1} = sym(Φ_j P_j Φ_jᵀ + Q(Δt_j)),   Φ_j = ∂f/∂x (x_j),

so the posterior is the eager tracker's (the same products in the same order, row by row). One
prediction over the whole gap would not be: ``Q(kΔ) ≠ Σ Φ Q(Δ) Φᵀ``, and a numerically integrated
orbit (:class:`~hypotrack.models.orbit3d.J2Orbit3D`) steps differently over a longer interval.

What this saves is the prediction of tracks that are not seen again before the run ends, and the
batch work of every scan on all of them; a track coming back costs the predictions it deferred. The
replay runs all the tracks woken at a scan together, the longest-deferred first, so a scan costs as
many array passes as its longest gap, each over the tracks deferred that long.

When it pays: a pass costs a fixed Python/numpy overhead (a J2 EKF prediction of a few rows: ~0.1–0.2
ms) whatever its rows, so a scan at which an object first seen after ``k`` scans comes into view costs
``k`` such overheads. On the whole catalogue (N = 10,855, the default radar; an object enters the view
every scan or so, most of them deferred since scan 0) lazy GNN/JPDA were measured 3.0×/2.8× faster
than eager with in-view gating over the first 40 scans and 1.7×/1.6× over 120, but 2.7× slower over
720 scans
(:func:`hypotrack.experiments.ssa_catalogue.lazy_sht.lazy_sht_timing`): exactness forbids replacing
the ``k`` predictions by one, as the factored engine's lazy lane does (an approximation there).

:func:`predict_gap` is that approximation, offered to GNN and JPDA (``lazy_prediction="gap"``) so that every
tracker of a catalogue run defers alike: a deferred track is predicted once over its whole gap,
``x = f(x_s, t − t_s)``, ``P = Φ P_s Φᵀ + Q(t − t_s)`` — one batch per scan whatever the gaps, where the
replay costs a pass per deferred scan. For the white-noise-acceleration models ``Q(kΔ) = Σ_j Φ^j Q(Δ) Φ^jᵀ``
holds exactly (the continuous-time noise integrates over the gap either way), so the two differ by the
motion model's integration only; for the catalogue's two-body + J2 EKF, by the linearisation along one
long step instead of ``k`` short ones. Measured on the whole catalogue (N = 10,855, 720 scans, GNN, one run
on a loaded machine): 10.9 ms per scan against 18.1 eager with in-view gating, 38.2 eager and 50.9 replayed;
at N = 1,000 the gap costs more than not deferring (3.6 against 2.5 ms: the catch-up integrates each gap in
30-s steps) and moves GNN's mean GOSPA from 8.98 to 9.07 km.
"""

from __future__ import annotations

import numpy as np

from ..hypotheses.factored.lane import predict_each

__all__ = ["ScanTimes", "replay", "predict_gap"]


class ScanTimes:
    """The times of the scans since the oldest deferred track's last prediction, numbered from 0 at
    the tracker's first time (an absolute scan index survives trimming the head)."""

    def __init__(self):
        self._times: list[float] = []
        self._base = 0  # absolute index of self._times[0]

    def __len__(self) -> int:
        return self._base + len(self._times)

    @property
    def now(self) -> int:
        """Absolute index of the last time recorded."""
        return len(self) - 1

    def append(self, time: float) -> None:
        self._times.append(float(time))

    def pop(self) -> None:
        """Forget the last time (a scan that failed)."""
        self._times.pop()

    def since(self, first: int) -> np.ndarray:
        """The times from absolute index ``first`` to now."""
        return np.asarray(self._times[first - self._base:])

    def trim(self, oldest: int) -> None:
        """Forget the times before absolute index ``oldest`` (no track is deferred from earlier)."""
        k = oldest - self._base
        if k >= 64:  # the list is short; trimming it now and then is enough
            del self._times[:k]
            self._base = oldest


def replay(predict, x, P, since, times: ScanTimes):
    """Predict tracks ``x, P`` (``(r, d)``, ``(r, d, d)``), each valid at scan ``since[i]``, scan by scan
    to the last scan of ``times`` (module docstring).

    ``predict(x, P, dt)`` is the tracker's own per-scan prediction, applied to the rows deferred at
    each scan in one batch (rows sorted by ``since``: a prefix); a zero interval predicts nothing, as
    in the eager tracker. Returns new arrays in the rows' order.
    """
    since = np.asarray(since, dtype=np.int64)
    if len(since) == 0 or since.min() == times.now:
        return x.copy(), P.copy()
    order = np.argsort(since, kind="stable")
    s = since[order]
    t = times.since(int(s[0]))
    xo, Po = x[order], P[order]
    first = int(s[0])
    for j in range(first, times.now):
        dt = t[j + 1 - first] - t[j - first]
        if dt == 0:
            continue
        a = int(np.searchsorted(s, j, side="right"))  # rows deferred at scan j or earlier
        if a == len(s):
            xo, Po = predict(xo, Po, dt)
        else:
            xa, Pa = predict(xo[:a], Po[:a], dt)
            xo, Po = np.concatenate([xa, xo[a:]]), np.concatenate([Pa, Po[a:]])
    out_x, out_P = np.empty_like(xo), np.empty_like(Po)
    out_x[order], out_P[order] = xo, Po
    return out_x, out_P


def predict_gap(motion, x, P, since, times: ScanTimes):
    """Predict tracks ``x, P`` (``(r, d)``, ``(r, d, d)``), each valid at scan ``since[i]``, to the last scan of
    ``times`` in one step each (module docstring): :func:`hypotrack.hypotheses.factored.lane.predict_each`
    over the intervals ``t_now − t_since``, the factored engine's lazy prediction. Returns new arrays."""
    since = np.asarray(since, dtype=np.int64)
    if len(since) == 0:
        return x.copy(), P.copy()
    first = int(since.min())
    t = times.since(first)
    gap = t[-1] - t[since - first]
    return predict_each(motion, x, P, gap)

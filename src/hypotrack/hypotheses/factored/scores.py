"""A scan's scores of the returns against the predicted tracks, dense or gated pairs only (:class:`Scores`).

The engine's :meth:`~..filter.HypothesisFilter.track_scores` makes ``(m, n)`` matrices: at 10⁵–10⁶ objects
(10³–10⁴ returns against as many tracks in view) that is 10⁶–10⁸ pairs, gigabytes of temporaries and
seconds a scan, where each track gates a handful of returns. :func:`score_tracks` gives the same numbers
for the pairs that matter: with a gate and more than ``dense_pairs`` pairs, the returns each track may gate
are found with a k-d tree over the returns (a pair in the gate, ``d² = rᵀ S⁻¹ r ≤ γ``, has
``|r|² ≤ γ λ_max(S) ≤ γ tr S``: the ball of that radius holds every return the track gates), and the
squared Mahalanobis distances, gate decisions and log-likelihoods are computed on those candidates alone —
by the engine's own ``track_scores`` on sub-blocks of returns × tracks, whose every entry is the full
matrix's entry bit for bit (its kernels are elementwise over the pairs), so the gated pairs' numbers are
the engine's. Pairs outside the gate are then not stored; the association steps never read them (every
consumer masks the log-likelihoods with the gate), and :meth:`Scores.block` gives them ``−inf``.
Smaller scans keep the dense matrices, exactly as the engine makes them.

A measurement model without a fixed ``H`` (an EKF in the sensor frame, e.g. the catalogue radar's
``(ρ, az, el, ρ̇)`` with its azimuth wrapped) has no ball of plain differences; :func:`sensor_frame_pairs`
finds its candidates with a bound that cannot drop a gated pair (Cauchy–Schwarz in the ``S⁻¹`` inner
product): ``d² = νᵀS⁻¹ν ≥ ν_i² / S_ii`` for every component ``i``, so a pair with ``|ν_i| > √(γ S_ii)`` for
some ``i`` is outside the gate. The first component (range) gives a band found by binary search on the sorted
returns, the others a box checked on the band's pairs; the pairs left are scored with the engine's arithmetic
(the innovation of every track in one batch, as the dense call makes it; the residual, ``L⁻¹ν`` and its squared
norm per pair by the same kernels), bit for bit the dense matrix's entries (tests compare them).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ...association.gating import box_candidates, gate_threshold
from ...gaussian import innovation_unchecked
from ...models.measurement import ExtendedMeasurement
from ..detection import state_p_detect
from ..filter import HypothesisFilter
from ..tracks import TrackStore

__all__ = ["Scores", "score_tracks", "sensor_frame_pairs", "DENSE_PAIRS"]

#: pairs up to which a scan's scores are the engine's dense matrices
DENSE_PAIRS = 200_000
#: tracks whose candidate returns are scored in one block
_BLOCK = 256


@dataclass(frozen=True, eq=False)
class Scores:
    """A scan's scores: ``p_detect`` (n,), ``p_survive`` (n,) or ``None`` (the population's one ``p_S``),
    and either the dense ``loglik``/``allowed`` (m, n) or the gated pairs alone — ``rows``, ``cols``
    (row-major order, as ``np.nonzero`` of the gate) and their ``pair_loglik``."""

    m: int
    p_detect: np.ndarray
    p_survive: np.ndarray | None
    loglik: np.ndarray | None = None
    allowed: np.ndarray | None = None
    rows: np.ndarray | None = None
    cols: np.ndarray | None = None
    pair_loglik: np.ndarray | None = None

    @property
    def n(self) -> int:
        return len(self.p_detect)

    def gated(self) -> tuple[np.ndarray, np.ndarray]:
        """``(rows, cols)`` of the gated pairs, row-major."""
        return np.nonzero(self.allowed) if self.loglik is not None else (self.rows, self.cols)

    def at(self, rows, cols) -> np.ndarray:
        """Log-likelihoods of gated pairs ``(rows[k], cols[k])``."""
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        if self.loglik is not None:
            return self.loglik[rows, cols]
        keys = self.rows * self.n + self.cols
        k = np.searchsorted(keys, rows * self.n + cols)
        if len(k) and not np.array_equal(keys[np.minimum(k, len(keys) - 1)], rows * self.n + cols):
            raise KeyError("a pair asked for is not in the gate")
        return self.pair_loglik[k]

    def block(self, rows, cols):
        """``(loglik (r, c), allowed (r, c), p_detect (c,), p_survive (c,) or None)`` of returns ``rows``
        against tracks ``cols`` (the engine's matrices' entries; a pair outside the gate of the sparse
        form has log-likelihood ``−inf``)."""
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        ps = None if self.p_survive is None else self.p_survive[cols]
        if self.loglik is not None:
            ix = np.ix_(rows, cols)
            return self.loglik[ix], self.allowed[ix], self.p_detect[cols], ps
        loglik = np.full((len(rows), len(cols)), -np.inf)
        allowed = np.zeros((len(rows), len(cols)), dtype=bool)
        r_of = np.full(self.m, -1, dtype=np.int64)
        r_of[rows] = np.arange(len(rows))
        c_of = np.full(self.n, -1, dtype=np.int64)
        c_of[cols] = np.arange(len(cols))
        sel = (r_of[self.rows] >= 0) & (c_of[self.cols] >= 0)
        i, j = r_of[self.rows[sel]], c_of[self.cols[sel]]
        loglik[i, j], allowed[i, j] = self.pair_loglik[sel], True
        return loglik, allowed, self.p_detect[cols], ps


def score_tracks(engine, pred, Z, *, gate_out_of_view: bool = True, survival=None, dense_pairs=None) -> Scores:
    """Every return ``Z`` (m, p) against the predicted tracks ``pred`` (module docstring): the engine's
    :meth:`~..filter.HypothesisFilter.track_scores` — dense up to ``dense_pairs`` pairs or without a gate,
    else the gated pairs found through a k-d tree (``None``: :data:`DENSE_PAIRS`). ``gate_out_of_view=False``:
    a track with ``p_D = 0`` gates nothing. ``survival``: the population's ``track_survival`` (or ``None``)."""
    n, m = len(pred), len(Z)
    dense_pairs = DENSE_PAIRS if dense_pairs is None else dense_pairs
    p_survive = None if survival is None else survival(pred)
    if engine.gate_probability is not None and m * n > dense_pairs and engine.H is None and _frame_model(engine):
        return sensor_frame_pairs(engine, pred, Z, gate_out_of_view=gate_out_of_view, p_survive=p_survive)
    # the k-d tree's balls compare plain differences of H x: another measurement model without a fixed H is
    # scored densely
    if engine.gate_probability is None or m * n <= dense_pairs or engine.H is None:
        loglik, allowed, p_detect = engine.track_scores(pred, Z)
        p_detect = state_p_detect(engine.sensor.detection, pred.means, p_detect, pred.covs)
        if not gate_out_of_view:
            allowed = allowed & (p_detect > 0)[None, :]
        return Scores(m, p_detect, p_survive, loglik=loglik, allowed=allowed)
    _, _, p_detect = engine.track_scores(pred, Z[:0])  # the engine's p_D of every track (no return scored)
    p_detect = state_p_detect(engine.sensor.detection, pred.means, p_detect, pred.covs)
    # the balls holding every return a track may gate, |r|² ≤ γ λ_max(S) ≤ γ tr S (a margin for rounding), for
    # a measurement z = H x + v compared by plain differences: a measurement model of another form needs its
    # own predicted measurements and innovation covariances here (the scores themselves are the engine's)
    z_pred, S, _ = innovation_unchecked(pred.means, pred.covs, engine.H, engine.R)
    gamma = gate_threshold(engine.gate_probability, z_pred.shape[1])
    cols = np.arange(n) if gate_out_of_view else np.flatnonzero(p_detect > 0)
    radius = np.sqrt(gamma * np.trace(S[cols], axis1=1, axis2=2)) * (1 + 1e-6) + 1e-9
    near = cKDTree(Z).query_ball_point(z_pred[cols], radius)
    out_r, out_c, out_ll = [], [], []
    for a in range(0, len(cols), _BLOCK):
        c = cols[a:a + _BLOCK]
        r = np.unique(np.concatenate([np.asarray(x, dtype=np.int64) for x in near[a:a + _BLOCK]] + [np.zeros(0, np.int64)]))
        if len(r) == 0:
            continue
        # the engine's scores of a sub-block of returns x tracks: its matrices' entries, bit for bit
        loglik, allowed, _ = engine.track_scores(TrackStore(pred.means[c], pred.covs[c], pred.labels[c]), Z[r])
        i, j = np.nonzero(allowed)
        out_r.append(r[i])
        out_c.append(c[j])
        out_ll.append(loglik[i, j])
    rows = np.concatenate(out_r + [np.zeros(0, np.int64)])
    cols_g = np.concatenate(out_c + [np.zeros(0, np.int64)])
    ll = np.concatenate(out_ll + [np.zeros(0)])
    order = np.lexsort((cols_g, rows))  # row-major, as np.nonzero of the dense gate
    return Scores(m, p_detect, p_survive, rows=rows[order], cols=cols_g[order], pair_loglik=ll[order])


def _frame_model(engine) -> bool:
    """Whether :func:`sensor_frame_pairs` reproduces the engine's ``track_scores``: the engine's own method and an
    extended measurement model's own Mahalanobis distances and residuals (module docstring)."""
    meas = engine.measurement
    return (type(engine).track_scores is HypothesisFilter.track_scores and isinstance(meas, ExtendedMeasurement)
            and type(meas).mahalanobis2 is ExtendedMeasurement.mahalanobis2
            and type(meas).residual_rows is ExtendedMeasurement.residual_rows)


def sensor_frame_pairs(engine, pred, Z, *, gate_out_of_view: bool, p_survive=None) -> Scores:
    """The gated pairs of returns ``Z`` (m, p) and predicted tracks ``pred`` under an extended measurement model
    (module docstring): the entries of the engine's ``track_scores`` matrices, bit for bit, at the pairs in the
    gate; ``p_detect`` as :func:`score_tracks` gives it."""
    meas, n, m = engine.measurement, len(pred), len(Z)
    z_pred, S, _, _ = meas.innovation(pred.means, pred.covs)  # one batch, as track_scores
    in_view = np.asarray(engine.sensor.detection.in_view(meas.view_points(pred.means, z_pred)), dtype=bool)
    p_detect = state_p_detect(engine.sensor.detection, pred.means, np.where(in_view, engine.p_D, 0.0),
                              pred.covs)
    Linv, logdet = np.zeros((n, meas.dim, meas.dim)), np.zeros(n)
    if n:
        L = np.linalg.cholesky(S)  # as ExtendedMeasurement.mahalanobis2
        logdet = 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
        Linv = np.linalg.inv(L)
    gamma = gate_threshold(engine.gate_probability, engine.meas_dim)
    cols = np.arange(n) if gate_out_of_view else np.flatnonzero(p_detect > 0)
    half = np.sqrt(gamma * np.diagonal(S[cols], axis1=1, axis2=2)) * (1 + 1e-6)  # a margin for rounding
    r, k = box_candidates(Z, z_pred[cols], half, meas.residual_rows)
    c = cols[k]
    # the dense path's arithmetic per pair: the residual, u = L⁻¹ν summed over k in order (as the dense einsum
    # over (m, n, p) sums; the einsum of a (pairs, p) layout may pair the terms differently), d² its squared norm
    nu, Li = meas.residual_rows(Z[r], z_pred[c]), Linv[c]
    u = Li[:, :, 0] * nu[:, None, 0]
    for j in range(1, nu.shape[1]):
        u = u + Li[:, :, j] * nu[:, None, j]
    d2 = np.sum(u * u, axis=-1)
    ll = -0.5 * (d2 + logdet[c] + engine.meas_dim * np.log(2 * np.pi))
    gated = d2 <= gamma
    r, c, ll = r[gated], c[gated], ll[gated]
    o = np.lexsort((c, r))  # row-major, as np.nonzero of the dense gate
    return Scores(m, p_detect, p_survive, rows=r[o].astype(np.int64), cols=c[o].astype(np.int64), pair_loglik=ll[o])


"""The fast path's rule for a lone track with Reid's births seeded at its return as a mixture (HOMHT k-best on the
catalogue: one seeded option per admissible-region component, :mod:`..seeded`).

The general step (:meth:`~..filter.HypothesisFilter.advance`) of a lane singleton (existence ``r``, survival ``p_S``)
with one return ``z`` whose birth mixture has ``K`` components of weights ``w_c`` makes, relative to the
parent's ``r p_S`` (Reid's factors, document 001 Eq. 30 and 35; the "died" twins Eq. 59):

==============================  =========================================  ==============================
child                           log-weight (constants common to all out)   store pairs (tracks)
==============================  =========================================  ==============================
detected                        ``log p_D + ℓ``                            the updated track
missed, ``z`` clutter           ``log(1 − p_D) + log λ_C``                 the predicted track
missed, ``z`` born in ``c``     ``log(1 − p_D) + log λ_B + log w_c``       the predicted track, newborn c
died/not, ``z`` clutter         ``e + log λ_C``                            none
died/not, ``z`` born in ``c``   ``e + log λ_B + log w_c``                  newborn c
==============================  =========================================  ==============================

``e = log(1 − r p_S) − log(r p_S)``: the "died" twin of the parent "exists" (weight ``r (1 − p_S)``) and the
same child of the parent "not" (``1 − r``) are duplicates, merged (:mod:`..duplicates`); with ``r p_S = 1`` there
are none. That is ``1 + 2 (1 + K)`` distinct children, ``2 + K`` of them association children of "exists" and
``1 + K`` of "not". When the generator makes them all (exhaustive, or Murty with ``min(k, H∞) ≥ 2 + K``) and the
cap keeps them all (``H∞ ≥ 3 + 2K``: the parents' own caps and the merged set's), the step keeps every valid child
and normalises over them; the factored filter's pruning then keeps the detected child alone — the track's
update, weight 1, a singleton of ``r = 1`` again — exactly when every other child's normalised weight lies below
``min_weight`` (by the fast path's relative margin, :data:`.fast_path.MARGIN`, so rounding cannot decide). The
children kept by the cap and then pruned still numbered their newborn tracks: one label per component ``c``
held by a valid child (:meth:`~..filter.HypothesisFilter._materialise`), which the fast path counts
(:attr:`.fast_path.FastBatch.n_new`).

With the engine's validity test a child holding a failing track is not kept nor counted: the missed children
need the predicted track valid, a newborn child its component's mean (the decision's total and the label count
follow). The detected child's update must pass, else the general path takes the track.
"""

from __future__ import annotations

import numpy as np

from ..seeded import mixture_table

__all__ = ["mixture_takes"]


def mixture_takes(rule, loglik, p_detect, pred_means, Z, extra=None, updated_ok=None):
    """Whether each lone track keeps only its detected child, and the labels its step uses.

    Parameters
    ----------
    rule : :class:`.fast_path.FastRule`
        With ``seeded_density`` a mixture (``components(z)``), ``alt_offsets = [log λ_C, log λ_B]`` and
        ``seeded_children`` (association children the generator makes per parent).
    loglik, p_detect : (n,) float
        Each track's return's log-likelihood and the track's ``p_D``.
    pred_means : (n, d) float
        The predicted tracks (the missed children's, for the validity test).
    Z : (n, p) float
        Each track's return.
    extra : (n,) float, optional
        ``e`` of the module docstring (the lane's Bernoulli singletons); ``None``: no "died"/"not" children.
    updated_ok : (n,) bool, optional
        Whether each detected child's track passes the validity test (``None``: no test).

    Returns
    -------
    take : (n,) bool; n_new : (n,) int64, the labels each track's step uses.
    """
    n = len(Z)
    if n == 0:
        return np.zeros(0, dtype=bool), np.zeros(0, dtype=np.int64)
    K, w_all, means_all = mixture_table(rule.seeded_density, Z)  # (no covariance: no track is made here)
    A = 1 + int(K.max(initial=0))
    offsets = np.full((n, A), -np.inf)
    offsets[:, 0] = rule.alt_offsets[0]
    seed_ok = np.zeros((n, A), dtype=bool)  # column 1 + c: component c exists (and its mean passes the test)
    rows = np.repeat(np.arange(n), K)
    cols = 1 + np.arange(len(rows)) - np.repeat(np.cumsum(K) - K, K)
    if len(rows):
        offsets[rows, cols] = rule.alt_offsets[1] + np.log(w_all)
        seed_ok[rows, cols] = True if rule.validity is None else _valid(rule.validity, means_all)  # one test
    pred_ok = np.ones(n, dtype=bool) if rule.validity is None else _valid(rule.validity, pred_means)
    ok = (p_detect > 0) & (p_detect < 1) & np.isfinite(loglik) & (True if updated_ok is None else updated_ok)
    p = np.where(ok, p_detect, 0.5)
    det = np.log(p) + np.where(ok, loglik, 0.0) - rule.det_offset
    missed_ok = pred_ok[:, None] & seed_ok
    missed_ok[:, 0] = pred_ok
    alt = np.where(missed_ok, np.log1p(-p)[:, None] + offsets, -np.inf)
    died = np.zeros(n, dtype=bool)
    if extra is not None:
        e = np.asarray(extra, dtype=float)
        died = e > -np.inf  # r p_S < 1: the "died"/"not" children exist
        ext_ok = seed_ok.copy()
        ext_ok[:, 0] = True  # "died"/"not" with clutter holds no track
        alt = np.concatenate([alt, np.where(ext_ok, e[:, None] + offsets, -np.inf)], axis=1)
    with np.errstate(invalid="ignore"):  # (an infinite e: no merging, the general path)
        total = np.logaddexp(det, np.logaddexp.reduce(alt, axis=1))
        light = np.all(alt - total[:, None] < rule.log_threshold, axis=1)
    fits = (3 + 2 * K <= rule.max_hypotheses) & (2 + K <= rule.seeded_children)
    n_new = (seed_ok[:, 1:] & (pred_ok | died)[:, None]).sum(axis=1).astype(np.int64)
    return ok & light & fits, n_new


def _valid(validity, means) -> np.ndarray:
    """``validity(means)`` as a bool per row."""
    ok = np.asarray(validity(means), dtype=bool)
    if ok.shape != (len(means),):
        raise ValueError(f"validity must return one bool per track, shape ({len(means)},), got {ok.shape}")
    return ok

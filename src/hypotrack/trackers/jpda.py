"""Joint probabilistic data association (JPDA) and its one-target case, the PDAF.

Lecture notes 004, "Joint Probabilistic Data Association (JPDA) Filter": with the past summarised
by one hypothesis and a fixed number of targets (no new-target hypotheses), compute for every
target ``T_j`` the marginal probabilities ``P(T_j ↔ y_i)`` and ``P(T_j ↔ ∅)`` (Eq. (1)) and update
each target with the PDA formulas using them. The joint event weight follows from the
fundamental theorem of TT without NT terms: dividing by ``β_FA^m Π_j (1 − P_D P_G)``, an event
weighs ``Π_{detected j} P_D p_j(y_θ⁻¹(j)) / (β_FA (1 − P_D P_G))``, so per target

    missed: ``1 − P_D P_G``,  return i: ``P_D N(y_i; ẑ_j, S_j) / β_FA``  (gated pairs only),

the weights of Stone Soup's ``PDAHypothesiser`` with an explicit ``clutter_spatial_density``.
Probabilities factorise over the clusters of the validation matrix (the lecture's clusters
{T1, T2}, {T3}): a target that shares no return with another is its own PDAF problem with the
closed form ``β_i = L_i / (1 − P_D P_G + Σ_k L_k)`` (Bar-Shalom, Daum & Huang 2009, Eq. 29–30);
the others go to the exact recursion of :func:`hypotrack.association.marginals.jpda_marginals`,
which handles each cluster in turn — or, with ``marginals="lbp"``, to the loopy belief propagation
approximation of :func:`hypotrack.association.lbp.lbp_marginals` (Williams & Lau 2014), whose cost per
pass is linear in the gated pairs however dense the cluster.

The PDA update (Bar-Shalom, Daum & Huang 2009, Eqs. 35–40) with combined innovation
``ν = Σ_i β_i ν_i``:

    x⁺ = x⁻ + K ν,
    P⁺ = β_0 P⁻ + (1 − β_0) P_c + K (Σ_i β_i ν_i ν_iᵀ − ν νᵀ) Kᵀ,

``P_c`` the Kalman-updated covariance (Joseph form here) and the last term the *spread of the
innovations* that accounts for not knowing which return is the target's. Targets sharing
returns are pulled toward each other's returns — the track coalescence of JPDA on crossing
targets (lecture 004, Fitzgerald 1986), which the ``sht`` experiment shows.
"""

from __future__ import annotations

import numpy as np

from ..association.lbp import lbp_marginals
from ..association.marginals import jpda_marginals
from ..gaussian import joseph_covariance_unchecked, symmetrize
from ._sht_common import GatedTracks, ScanModel

__all__ = ["jpda_log_weights", "pdaf_probabilities", "jpda_probabilities", "pda_update"]


def jpda_log_weights(gated: GatedTracks, model: ScanModel) -> np.ndarray:
    """Per-target log weights ``(n, m + 1)``: column 0 missed, column ``1 + i`` return i.

    ``log(1 − P_D P_G)`` and ``log(P_D N(y_i; ẑ_j, S_j) / β_FA)``; ``−∞`` outside the gate.
    """
    n = gated.n_tracks
    lw = np.empty((n, gated.n_meas + 1))
    lw[:, 0] = model.log_missed
    det = np.log(np.reshape(model.p_D, (-1, 1))) - np.log(model.clutter_density) + gated.log_likelihood().T
    lw[:, 1:] = np.where(gated.valid.T, det, -np.inf)
    return lw


def pdaf_probabilities(log_weights) -> np.ndarray:
    """PDAF association probabilities of each target on its own (other targets ignored).

    ``β_i = L_i / (1 − P_D P_G + Σ_k L_k)``, ``β_0 = (1 − P_D P_G) / (…)`` — a row-wise softmax
    of :func:`jpda_log_weights` (Bar-Shalom, Daum & Huang 2009, Eqs. 29–30). For a single
    target (or one that shares no return) this *is* the JPDA marginal.
    """
    lw = np.asarray(log_weights, dtype=float)
    if lw.ndim != 2:
        raise ValueError(f"log_weights must have shape (n, m + 1), got {lw.shape}")
    if len(lw) == 0:
        return np.zeros(lw.shape)
    # Log-sum-exp by hand: scipy's logsumexp costs more per call than the whole softmax here.
    w = np.exp(lw - lw.max(axis=1, keepdims=True))
    return w / w.sum(axis=1, keepdims=True)


_MARGINALS = ("exact", "lbp")


def jpda_probabilities(gated: GatedTracks, model: ScanModel, *, log_weights=None, marginals: str = "exact",
                       lbp_tol: float = 1e-10, lbp_max_iter: int = 1000) -> np.ndarray:
    """JPDA marginal association probabilities ``β`` (n, m + 1) of every target, per cluster.

    Parameters
    ----------
    gated : GatedTracks
    model : ScanModel
    log_weights : (n, m + 1) array_like, optional
        Precomputed :func:`jpda_log_weights`.
    marginals : {"exact", "lbp"}, optional
        How the targets that share returns get their marginals: ``"exact"`` (default) by the
        exact recursion :func:`hypotrack.association.marginals.jpda_marginals`; ``"lbp"`` by loopy
        belief propagation, :func:`hypotrack.association.lbp.lbp_marginals` (approximate on
        clusters with cycles, exact on tree-shaped ones; needs ``P_D P_G < 1``).
    lbp_tol, lbp_max_iter : float, int
        ``tol`` and ``max_iter`` of :func:`~hypotrack.association.lbp.lbp_marginals` (``"lbp"`` only).

    Returns
    -------
    beta : (n, m + 1) ndarray
        ``beta[j, 0] = P(T_j ↔ ∅)``, ``beta[j, 1 + i] = P(T_j ↔ y_i)`` (lecture 004, Eq. (1)).
    """
    if marginals not in _MARGINALS:
        raise ValueError(f"marginals must be one of {_MARGINALS}, got {marginals!r}")
    lw = jpda_log_weights(gated, model) if log_weights is None else np.asarray(log_weights, dtype=float)
    valid = gated.valid
    # Targets that share no gated return with another target are single-target PDAF problems.
    contested = valid.sum(axis=1) > 1
    shared_track = (valid & contested[:, None]).any(axis=0)
    beta = pdaf_probabilities(lw)
    if shared_track.any():
        # The EHM recursion walks the clusters one after another (its track order keeps each
        # connected component contiguous) and its state empties between them, so one call over
        # all targets that share returns *is* the per-cluster computation, without the cost of
        # finding the clusters first.
        tracks = np.flatnonzero(shared_track)
        meas = np.flatnonzero(valid[:, tracks].any(axis=1))
        cols = np.concatenate([[0], 1 + meas])
        sub = lw[np.ix_(tracks, cols)]
        beta[np.ix_(tracks, cols)] = (
            jpda_marginals(sub) if marginals == "exact" else lbp_marginals(sub, tol=lbp_tol, max_iter=lbp_max_iter).beta
        )
    return beta


def pda_update(gated: GatedTracks, beta, model: ScanModel):
    """PDA update of every target with its association probabilities (spread of innovations included).

    Parameters
    ----------
    gated : GatedTracks
    beta : (n, m + 1) array_like
        From :func:`jpda_probabilities` or :func:`pdaf_probabilities`.
    model : ScanModel

    Returns
    -------
    x, P : (n, d), (n, d, d)
        Updated means and covariances.
    """
    beta = np.asarray(beta, dtype=float)
    x, P, K = gated.x, gated.P, gated.K
    if gated.n_tracks == 0:
        return x.copy(), P.copy()
    n, p = gated.z_pred.shape
    b0 = beta[:, 0]
    # Only pairs with β > 0 (inside the gates) contribute: work on those, not all n × m pairs.
    t_idx, i_idx = np.nonzero(beta[:, 1:] > 0)
    w = beta[t_idx, 1 + i_idx]
    nu = model.residual_rows(gated.Z[i_idx], gated.z_pred[t_idx])  # (pairs, p) innovations ν_i of each target
    nu_bar = np.stack([np.bincount(t_idx, w * nu[:, a], minlength=n) for a in range(p)], axis=1)
    second = np.stack(
        [np.bincount(t_idx, w * nu[:, a] * nu[:, b], minlength=n) for a in range(p) for b in range(p)], axis=1
    ).reshape(n, p, p)
    spread = second - nu_bar[:, :, None] * nu_bar[:, None, :]
    x_upd = x + np.einsum("ndp,np->nd", K, nu_bar)
    P_c = joseph_covariance_unchecked(P, K, model.H_of(gated, slice(None)), model.R)
    P_upd = b0[:, None, None] * P + (1 - b0)[:, None, None] * P_c + K @ spread @ np.swapaxes(K, -1, -2)
    return x_upd, symmetrize(P_upd)

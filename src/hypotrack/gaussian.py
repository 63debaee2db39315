"""Gaussian densities and the Kalman / extended Kalman filter, batched over tracks.

Every function accepts either a single track (mean ``(d,)``, covariance ``(d, d)``) or a
batch of ``n`` tracks (means ``(n, d)``, covariances ``(n, d, d)``) and returns arrays of the
same batch form. The update uses the Joseph form and symmetrises its output, so covariances
stay symmetric positive definite; the log predictive likelihood ``log N(z; H x̂, S)`` is
evaluated through a Cholesky factor of ``S``, never an explicit inverse.

The public functions check their input (finite, matching shapes, ``P``, ``Q``, ``R``
positive semi-definite and ``S`` positive definite, by Cholesky) and raise ``ValueError``
naming the argument: a covariance with a negative variance would otherwise come out as a
zero or negative variance, and a NaN as a NaN likelihood. The trackers call the unchecked
batched forms (``predict_unchecked``, ``predict_with_unchecked``, ``innovation_unchecked``,
``update_unchecked``, ``mahalanobis2_unchecked``, ``joseph_covariance_unchecked``) once per scan on states they built themselves and checked at their
own boundary (construction, ``initialise``, ``step``).

References
----------
Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and Navigation*
(2001), §5.2 (Kalman filter) and §5.2.3 (Joseph form).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._validation import check_covariance, check_finite_array, check_psd

__all__ = [
    "GaussianState",
    "predict",
    "predict_with",
    "innovation",
    "update",
    "joseph_covariance",
    "log_likelihood",
    "log_likelihood_matrix",
    "mahalanobis2_matrix",
    "symmetrize",
]

_LOG_2PI = float(np.log(2.0 * np.pi))


def symmetrize(P: np.ndarray) -> np.ndarray:
    """Return ``(P + Pᵀ) / 2`` over the last two axes."""
    return 0.5 * (P + np.swapaxes(P, -1, -2))


@dataclass(frozen=True)
class GaussianState:
    """A Gaussian state estimate ``N(mean, cov)``; validated on construction."""

    mean: np.ndarray
    cov: np.ndarray

    def __post_init__(self):
        mean = check_finite_array(self.mean, "mean", ndim=1)
        cov = check_covariance(self.cov, "cov", dim=mean.shape[0])
        object.__setattr__(self, "mean", mean)
        object.__setattr__(self, "cov", cov)

    @property
    def dim(self) -> int:
        return self.mean.shape[0]


def _batch(x, P):
    x = np.asarray(x, dtype=float)
    P = np.asarray(P, dtype=float)
    single = x.ndim == 1
    if single:
        x, P = x[None], P[None]
    if x.ndim != 2 or P.ndim != 3 or P.shape[0] != x.shape[0] or P.shape[1:] != (x.shape[1], x.shape[1]):
        raise ValueError(f"means x (n, d) and covariances P (n, d, d) do not match: {x.shape} vs {P.shape}")
    return x, P, single


def _checked_batch(x, P):
    """``_batch`` plus the checks of every public function: finite means, PSD covariances."""
    x, P, single = _batch(x, P)
    check_finite_array(x, "x")
    check_psd(P, "P", what="P (state covariance)")
    return x, P, single


def _matrix(A, name, shape, n):
    """A matrix of ``shape`` shared by all ``n`` tracks, or one per track ``(n, *shape)``."""
    if np.shape(A) not in (shape, (n, *shape)):
        want = f"({shape[0]}, {shape[1]}) or ({n}, {shape[0]}, {shape[1]})"
        raise ValueError(f"{name} must have shape {want}, got {np.shape(A)}")
    return check_finite_array(A, name)


def _measurement_model(H, R, d):
    if np.ndim(H) != 2 or np.shape(H)[1] != d:
        raise ValueError(f"H must have shape (p, {d}) for {d}-dimensional states, got {np.shape(H)}")
    H = check_finite_array(H, "H")
    p = H.shape[0]
    if np.shape(R) != (p, p):
        raise ValueError(f"R must have shape ({p}, {p}) for H of shape {H.shape}, got {np.shape(R)}")
    return H, check_psd(R, "R", what="R (measurement-noise covariance)")


def _unbatch(single, *arrays):
    return tuple(a[0] for a in arrays) if single else arrays


def predict_unchecked(x, P, F, Q):
    """Unchecked batched prediction (``x`` (n, d), ``P`` (n, d, d))."""
    x_pred = np.einsum("...ij,...j->...i", F, x) if F.ndim == 3 else x @ F.T
    return x_pred, symmetrize(F @ P @ np.swapaxes(F, -1, -2) + Q)


def predict(x, P, F, Q):
    """Kalman prediction ``x⁻ = F x``, ``P⁻ = F P Fᵀ + Q``.

    Parameters
    ----------
    x, P : array_like
        Mean ``(d,)`` / ``(n, d)`` and covariance ``(d, d)`` / ``(n, d, d)``.
    F, Q : array_like
        Transition matrix and process-noise covariance, ``(d, d)`` shared by all tracks or
        ``(n, d, d)`` per track (as for an EKF, where F is each track's Jacobian/STM).
        ``P`` and ``Q`` must be positive semi-definite.

    Returns
    -------
    x_pred, P_pred
    """
    x, P, single = _checked_batch(x, P)
    n, d = x.shape
    F = _matrix(F, "F", (d, d), n)
    Q = check_psd(_matrix(Q, "Q", (d, d), n), "Q", what="Q (process-noise covariance)")
    return _unbatch(single, *predict_unchecked(x, P, F, Q))


def predict_with_unchecked(model, x, P, dt):
    """Unchecked batched (E)KF prediction through a motion model; one with ``replay_each`` (the J2 orbit's compiled
    EKF step, :mod:`hypotrack.models.orbit3d_replay`: the same arithmetic) takes it for ``dt >= 0``."""
    if getattr(model, "replay_each", None) is not None and len(x) and dt >= 0:
        n = len(x)
        return model.replay_each(x, P, np.full(n, float(dt)), np.ones(n, dtype=np.int64))
    x_pred, F = model.transition(x, dt)
    return x_pred, symmetrize(F @ P @ np.swapaxes(F, -1, -2) + model.Q(dt))


def predict_with(model, x, P, dt):
    """(Extended) Kalman prediction through a motion model's ``transition`` and ``Q``.

    For a linear model this is :func:`predict`; for a nonlinear one the means are propagated
    through the dynamics and the covariances through the state-transition matrices (EKF).
    """
    x, P, single = _checked_batch(x, P)
    return _unbatch(single, *predict_with_unchecked(model, x, P, dt))


def innovation_unchecked(x, P, H, R):
    """Unchecked batched ``(z_pred, S, K)``; ``S`` must be positive definite."""
    z_pred = x @ H.T
    PHt = P @ H.T
    S = symmetrize(H @ PHt + R)
    # K = P Hᵀ S⁻¹, solved (S symmetric) rather than inverted.
    K = np.swapaxes(np.linalg.solve(S, np.swapaxes(PHt, -1, -2)), -1, -2) if len(S) else PHt
    return z_pred, S, K


def _checked_innovation(x, P, H, R):
    x, P, single = _checked_batch(x, P)
    H, R = _measurement_model(H, R, x.shape[1])
    check_psd(symmetrize(H @ P @ H.T + R), "S", definite=True, what="S = H P Hᵀ + R (innovation covariance)")
    return x, P, H, R, single


def innovation(x, P, H, R):
    """Predicted measurement ``H x``, innovation covariance ``S = H P Hᵀ + R`` and gain ``K``.

    Returns ``(z_pred, S, K)`` in the batch form of ``x``.
    """
    x, P, H, R, single = _checked_innovation(x, P, H, R)
    return _unbatch(single, *innovation_unchecked(x, P, H, R))


def update_unchecked(x, P, z, H, R):
    """Unchecked batched Joseph-form update; ``z`` (n, p)."""
    z_pred, _, K = innovation_unchecked(x, P, H, R)
    x_upd = x + np.einsum("nij,nj->ni", K, z - z_pred)
    return x_upd, joseph_covariance_unchecked(P, K, H, R)


def update(x, P, z, H, R):
    """Kalman update with the Joseph-form covariance.

    ``x⁺ = x + K (z − H x)``, ``P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ``.

    Parameters
    ----------
    x, P : array_like
        Predicted mean(s) and covariance(s) (``P`` positive semi-definite).
    z : array_like
        Measurement ``(p,)`` or one per track ``(n, p)``.
    H, R : array_like
        Measurement matrix ``(p, d)`` and noise covariance ``(p, p)`` (positive semi-definite,
        with ``S = H P Hᵀ + R`` positive definite).

    Returns
    -------
    x_upd, P_upd
    """
    x, P, H, R, single = _checked_innovation(x, P, H, R)
    n, p = x.shape[0], H.shape[0]
    z = np.asarray(z, dtype=float)
    if z.shape == (p,):
        z = np.broadcast_to(z, (n, p))
    elif z.shape != (n, p):
        raise ValueError(f"z must have shape ({p},) or ({n}, {p}), got {z.shape}")
    check_finite_array(z, "z")
    return _unbatch(single, *update_unchecked(x, P, z, H, R))


def joseph_covariance_unchecked(P, K, H, R):
    I_KH = np.eye(P.shape[-1]) - K @ H
    return symmetrize(I_KH @ P @ np.swapaxes(I_KH, -1, -2) + K @ R @ np.swapaxes(K, -1, -2))


def joseph_covariance(P, K, H, R):
    """Updated covariances ``(I − K H) P (I − K H)ᵀ + K R Kᵀ`` (Joseph form, symmetrised), batched.

    Valid for any gain ``K`` (not only the optimal one) and positive semi-definite by
    construction (for ``P`` and ``R`` positive semi-definite, which is checked), which is why
    every update in hypotrack goes through it. Callers that already hold the gains (e.g. from
    :func:`innovation`) use it directly instead of :func:`update`.
    """
    P = check_psd(P, "P", what="P (state covariance)")
    d = P.shape[-1]
    H, R = _measurement_model(H, R, d)
    K = check_finite_array(K, "K")
    if K.shape[-2:] != (d, H.shape[0]):
        raise ValueError(f"K must have shape (..., {d}, {H.shape[0]}), got {K.shape}")
    return joseph_covariance_unchecked(P, K, H, R)


def _chol_logdet(S, name="S"):
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name} must be positive definite (Cholesky failed)") from None
    return L, 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)


def _check_pairs(z, z_pred, S, z_name):
    S = np.asarray(S, dtype=float)
    if S.ndim not in (2, 3) or S.shape[-1] != S.shape[-2]:
        raise ValueError(f"S must have shape (p, p) or (n, p, p), got {S.shape}")
    p = S.shape[-1]
    z_pred = check_finite_array(np.atleast_2d(np.asarray(z_pred, dtype=float)), "z_pred")
    if z_pred.shape[-1] != p or (S.ndim == 3 and z_pred.shape[0] != S.shape[0]):
        raise ValueError(f"z_pred must have shape (n, {p}) matching S {S.shape}, got {z_pred.shape}")
    z = check_finite_array(np.asarray(z, dtype=float), z_name)
    if z.size and z.shape[-1] != p:
        raise ValueError(f"{z_name} must have {p} components per measurement, got shape {z.shape}")
    check_psd(S, "S", definite=True, what="S (innovation covariance)")
    return z, z_pred, S


def log_likelihood(z, z_pred, S):
    """Log density ``log N(z; z_pred, S)`` for matched batches (or a single pair)."""
    z, z_pred, S = _check_pairs(z, z_pred, S, "z")
    z = np.atleast_2d(z)
    single = S.ndim == 2
    if single:
        S = S[None]
    L, logdet = _chol_logdet(S)
    u = np.einsum("njk,nk->nj", np.linalg.inv(L), z - z_pred)
    out = -0.5 * (np.sum(u * u, axis=-1) + logdet + S.shape[-1] * _LOG_2PI)
    return float(out[0]) if single else out


def mahalanobis2_unchecked(Z, z_pred, S):
    """Unchecked :func:`mahalanobis2_matrix` (``Z`` (m, p), ``z_pred`` (n, p), ``S`` (n, p, p))."""
    n = z_pred.shape[0]
    if n == 0 or Z.shape[0] == 0:
        return np.zeros((Z.shape[0], n)), (np.zeros(0) if n == 0 else _chol_logdet(S)[1])
    L, logdet = _chol_logdet(S)
    r = Z[:, None, :] - z_pred[None, :, :]  # (m, n, p)
    # Whitening with the (small, p×p) inverse Cholesky factor, vectorised over all pairs.
    u = np.einsum("njk,mnk->mnj", np.linalg.inv(L), r)
    return np.sum(u * u, axis=-1), logdet


def mahalanobis2_matrix(Z, z_pred, S):
    """Squared Mahalanobis distances ``d²[i, j] = (z_i − ẑ_j)ᵀ S_j⁻¹ (z_i − ẑ_j)``.

    Parameters
    ----------
    Z : (m, p) measurements.
    z_pred : (n, p) predicted measurements of n tracks.
    S : (n, p, p) innovation covariances (positive definite).

    Returns
    -------
    d2 : (m, n) array, and ``logdet`` : (n,) log-determinants of S.
    """
    p = np.shape(z_pred)[-1] if np.ndim(z_pred) else 1
    Z = np.asarray(Z, dtype=float)
    Z = Z.reshape(-1, p) if Z.size or Z.ndim < 2 else Z.reshape(0, p)
    S = np.asarray(S, dtype=float).reshape(-1, p, p)
    Z, z_pred, S = _check_pairs(Z, np.asarray(z_pred, dtype=float).reshape(-1, p), S, "Z")
    return mahalanobis2_unchecked(Z, z_pred, S)


def log_likelihood_matrix(Z, z_pred, S):
    """``L[i, j] = log N(z_i; ẑ_j, S_j)`` for all measurement/track pairs, shape (m, n)."""
    d2, logdet = mahalanobis2_matrix(Z, z_pred, S)
    p = np.shape(z_pred)[-1]
    return -0.5 * (d2 + logdet[None, :] + p * _LOG_2PI)

"""Gaussian densities and the Kalman / extended Kalman filter, batched over tracks.

Every function accepts either a single track (mean ``(d,)``, covariance ``(d, d)``) or a
batch of ``n`` tracks (means ``(n, d)``, covariances ``(n, d, d)``) and returns arrays of the
same batch form. The update uses the Joseph form and symmetrises its output, so covariances
stay symmetric positive definite; the log predictive likelihood ``log N(z; H x̂, S)`` is
evaluated through a Cholesky factor of ``S``, never an explicit inverse.

References
----------
Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and Navigation*
(2001), §5.2 (Kalman filter) and §5.2.3 (Joseph form).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from ._validation import check_covariance, check_finite_array

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
        raise ValueError(f"means (n, d) and covariances (n, d, d) do not match: {x.shape} vs {P.shape}")
    return x, P, single


def _unbatch(single, *arrays):
    return tuple(a[0] for a in arrays) if single else arrays


def predict(x, P, F, Q):
    """Kalman prediction ``x⁻ = F x``, ``P⁻ = F P Fᵀ + Q``.

    Parameters
    ----------
    x, P : array_like
        Mean ``(d,)`` / ``(n, d)`` and covariance ``(d, d)`` / ``(n, d, d)``.
    F, Q : array_like
        Transition matrix and process-noise covariance, ``(d, d)`` shared by all tracks or
        ``(n, d, d)`` per track (as for an EKF, where F is each track's Jacobian/STM).

    Returns
    -------
    x_pred, P_pred
    """
    x, P, single = _batch(x, P)
    F = np.asarray(F, dtype=float)
    Q = np.asarray(Q, dtype=float)
    x_pred = np.einsum("...ij,...j->...i", F, x) if F.ndim == 3 else x @ F.T
    P_pred = symmetrize(F @ P @ np.swapaxes(F, -1, -2) + Q)
    return _unbatch(single, x_pred, P_pred)


def predict_with(model, x, P, dt):
    """(Extended) Kalman prediction through a motion model's ``transition`` and ``Q``.

    For a linear model this is :func:`predict`; for a nonlinear one the means are propagated
    through the dynamics and the covariances through the state-transition matrices (EKF).
    """
    x, P, single = _batch(x, P)
    x_pred, F = model.transition(x, dt)
    P_pred = symmetrize(F @ P @ np.swapaxes(F, -1, -2) + model.Q(dt))
    return _unbatch(single, x_pred, P_pred)


def innovation(x, P, H, R):
    """Predicted measurement ``H x``, innovation covariance ``S = H P Hᵀ + R`` and gain ``K``.

    Returns ``(z_pred, S, K)`` in the batch form of ``x``.
    """
    x, P, single = _batch(x, P)
    H = np.asarray(H, dtype=float)
    R = np.asarray(R, dtype=float)
    z_pred = x @ H.T
    PHt = P @ H.T
    S = symmetrize(H @ PHt + R)
    # K = P Hᵀ S⁻¹, solved (S symmetric) rather than inverted.
    K = np.swapaxes(np.linalg.solve(S, np.swapaxes(PHt, -1, -2)), -1, -2) if len(S) else PHt
    return _unbatch(single, z_pred, S, K)


def update(x, P, z, H, R):
    """Kalman update with the Joseph-form covariance.

    ``x⁺ = x + K (z − H x)``, ``P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ``.

    Parameters
    ----------
    x, P : array_like
        Predicted mean(s) and covariance(s).
    z : array_like
        Measurement ``(p,)`` or one per track ``(n, p)``.
    H, R : array_like
        Measurement matrix ``(p, d)`` and noise covariance ``(p, p)``.

    Returns
    -------
    x_upd, P_upd
    """
    x, P, single = _batch(x, P)
    z = np.asarray(z, dtype=float)
    if z.ndim == 1:
        z = np.broadcast_to(z, (x.shape[0], z.shape[0]))
    if not np.all(np.isfinite(z)):
        raise ValueError("z must be finite (no NaN or inf)")
    H = np.asarray(H, dtype=float)
    R = np.asarray(R, dtype=float)
    z_pred, S, K = innovation(x, P, H, R)
    x_upd = x + np.einsum("nij,nj->ni", K, z - z_pred)
    return _unbatch(single, x_upd, joseph_covariance(P, K, H, R))


def joseph_covariance(P, K, H, R):
    """Updated covariances ``(I − K H) P (I − K H)ᵀ + K R Kᵀ`` (Joseph form, symmetrised), batched.

    Valid for any gain ``K`` (not only the optimal one) and positive semi-definite by
    construction, which is why every update in hypotrack goes through it. Callers that already
    hold the gains (e.g. from :func:`innovation`) use it directly instead of :func:`update`.
    """
    P = np.asarray(P, dtype=float)
    I_KH = np.eye(P.shape[-1]) - K @ H
    return symmetrize(I_KH @ P @ np.swapaxes(I_KH, -1, -2) + K @ R @ np.swapaxes(K, -1, -2))


def _chol_logdet(S):
    L = np.linalg.cholesky(S)
    return L, 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)


def log_likelihood(z, z_pred, S):
    """Log density ``log N(z; z_pred, S)`` for matched batches (or a single pair)."""
    z = np.atleast_2d(np.asarray(z, dtype=float))
    z_pred = np.atleast_2d(np.asarray(z_pred, dtype=float))
    S = np.asarray(S, dtype=float)
    single = S.ndim == 2
    if single:
        S = S[None]
    L, logdet = _chol_logdet(S)
    u = np.einsum("njk,nk->nj", np.linalg.inv(L), z - z_pred)
    out = -0.5 * (np.sum(u * u, axis=-1) + logdet + S.shape[-1] * _LOG_2PI)
    return float(out[0]) if single else out


def mahalanobis2_matrix(Z, z_pred, S):
    """Squared Mahalanobis distances ``d²[i, j] = (z_i − ẑ_j)ᵀ S_j⁻¹ (z_i − ẑ_j)``.

    Parameters
    ----------
    Z : (m, p) measurements.
    z_pred : (n, p) predicted measurements of n tracks.
    S : (n, p, p) innovation covariances.

    Returns
    -------
    d2 : (m, n) array, and ``logdet`` : (n,) log-determinants of S.
    """
    Z = np.asarray(Z, dtype=float).reshape(-1, np.shape(z_pred)[-1] if np.ndim(z_pred) else 1)
    z_pred = np.asarray(z_pred, dtype=float)
    S = np.asarray(S, dtype=float)
    n, p = z_pred.shape
    if n == 0 or Z.shape[0] == 0:
        return np.zeros((Z.shape[0], n)), (np.zeros(0) if n == 0 else _chol_logdet(S)[1])
    L, logdet = _chol_logdet(S)
    r = Z[:, None, :] - z_pred[None, :, :]  # (m, n, p)
    # Whitening with the (small, p×p) inverse Cholesky factor, vectorised over all pairs.
    u = np.einsum("njk,mnk->mnj", np.linalg.inv(L), r)
    return np.sum(u * u, axis=-1), logdet


def log_likelihood_matrix(Z, z_pred, S):
    """``L[i, j] = log N(z_i; ẑ_j, S_j)`` for all measurement/track pairs, shape (m, n)."""
    d2, logdet = mahalanobis2_matrix(Z, z_pred, S)
    p = np.shape(z_pred)[-1]
    return -0.5 * (d2 + logdet[None, :] + p * _LOG_2PI)

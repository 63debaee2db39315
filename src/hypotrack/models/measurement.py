"""Measurement models as one small surface for every tracker: linear (``z = H x + v``) and extended.

Every tracker of the project (the hypothesis engine and its factored form, the birth terms, GNN,
JPDA and their initiator) asks four things of the measurement model, batched over tracks:

* :meth:`innovation` ``(means (n, d), covs (n, d, d)) -> (z_pred (n, p), S (n, p, p), K (n, d, p),
  H (n, p, d))`` — the predicted return, innovation covariance ``S = H P Hᵀ + R``, gain
  ``K = P Hᵀ S⁻¹`` and the measurement matrix of each track;
* :meth:`residual` ``(Z (m, p), z_pred (n, p)) -> (m, n, p)`` — ``z_i − ẑ_j``, with the angle
  components wrapped into ``[−π, π)`` for an extended model whose ``wrapped`` lists them;
* :meth:`mahalanobis2` ``(Z, z_pred, S) -> (d² (m, n), log det S (n,))``;
* :meth:`update` ``(means, covs, Z_rows (n, p)) -> (means⁺, covs⁺)`` — the Joseph-form update
  (Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and Navigation*, 2001,
  Sec. 5.2.3) of each track with its own return.

:class:`LinearMeasurement` ``(H, R)`` calls exactly the functions the trackers called before
(:func:`hypotrack.gaussian.innovation_unchecked`, :func:`~hypotrack.gaussian.update_unchecked`,
:func:`~hypotrack.gaussian.mahalanobis2_unchecked`), so its numbers are bit for bit the previous ones.
:class:`ExtendedMeasurement` is the extended Kalman filter's linearisation (ibid. Sec. 10.3.2): a
subclass gives ``h(x)`` (``(n, p)``), its Jacobian ``(n, p, d)`` and a constant ``R``; the update is
``x⁺ = x + K ν`` with ``ν = z − h(x)`` (wrapped) and ``P⁺ = (I − K H_j) P (I − K H_j)ᵀ + K R Kᵀ``,
``H_j = ∂h/∂x(x̂_j)``. The ground radar of the catalogue experiments
(:class:`hypotrack.scenarios.catalogue.radar_model.RadarMeasurement`) is one.

:func:`as_measurement` turns what a sensor exposes as ``sensor.measurement`` into one of these: an
object that already is one is returned, anything with ``H`` and ``R`` attributes becomes a
:class:`LinearMeasurement`.
"""

from __future__ import annotations

import numba
import numpy as np

from .._validation import check_covariance, check_finite_array
from ..gaussian import innovation_unchecked, mahalanobis2_unchecked, symmetrize, update_unchecked

__all__ = ["LinearMeasurement", "ExtendedMeasurement", "as_measurement", "wrap_pi", "wrapped_residual"]

_LOG_2PI = float(np.log(2.0 * np.pi))


def wrap_pi(a):
    """Angles wrapped into ``[−π, π)``."""
    return (np.asarray(a, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi


class LinearMeasurement:
    """``z = H x + v``, ``v ~ N(0, R)`` (module docstring). ``H`` (p, d), ``R`` (p, p) positive definite."""

    linear = True

    def __init__(self, H, R):
        self.H = check_finite_array(np.atleast_2d(np.asarray(H, dtype=float)), "H", ndim=2)
        self.R = check_covariance(np.atleast_2d(np.asarray(R, dtype=float)), "R", dim=self.H.shape[0])

    @property
    def dim(self) -> int:
        """Measurement dimension ``p``."""
        return self.H.shape[0]

    @property
    def ndim_state(self) -> int:
        return self.H.shape[1]

    def predict(self, means) -> np.ndarray:
        """``H x`` of each mean ``(n, d)``."""
        return means @ self.H.T

    def innovation(self, means, covs):
        """``(z_pred, S, K, H)`` of each track; ``H`` broadcast to ``(n, p, d)`` (a view, no copy)."""
        z_pred, S, K = innovation_unchecked(means, covs, self.H, self.R)
        return z_pred, S, K, np.broadcast_to(self.H, (len(means), *self.H.shape))

    @staticmethod
    def residual(Z, z_pred) -> np.ndarray:
        """``z_i − ẑ_j`` ``(m, n, p)``."""
        return np.asarray(Z)[:, None, :] - np.asarray(z_pred)[None, :, :]

    @staticmethod
    def residual_rows(Z_rows, z_pred) -> np.ndarray:
        """``z_j − ẑ_j`` ``(n, p)`` (one return per track)."""
        return Z_rows - z_pred

    @staticmethod
    def mahalanobis2(Z, z_pred, S):
        """``(d² (m, n), log det S (n,))`` (:func:`hypotrack.gaussian.mahalanobis2_unchecked`)."""
        return mahalanobis2_unchecked(Z, z_pred, S)

    def update(self, means, covs, Z_rows):
        """Joseph-form Kalman update of each track with its own return ``Z_rows`` (n, p)."""
        return update_unchecked(means, covs, Z_rows, self.H, self.R)

    def view_points(self, means, z_pred=None) -> np.ndarray:
        """What the sensor's ``detection.in_view`` is given: the predicted returns ``H x``."""
        return self.predict(means) if z_pred is None else z_pred


class ExtendedMeasurement:
    """Base of a nonlinear measurement ``z = h(x) + v``, ``v ~ N(0, R)``, filtered by the EKF (module docstring).

    A subclass defines :meth:`h` ``(n, d) -> (n, p)``, :meth:`jacobian` ``(n, d) -> (n, p, d)``, the
    attribute ``R`` ``(p, p)`` and ``wrapped``: the indices of the angle components whose residuals are
    wrapped into ``[−π, π)``. :meth:`view_points` (what ``detection.in_view`` is given) defaults to the
    state's first three components (a position).
    """

    linear = False
    wrapped: tuple = ()
    R: np.ndarray
    #: Second-order EKF (Bar-Shalom, Li & Kirubarajan 2001, Sec. 10.3.3): the predicted return gets the bias
    #: ``½ tr(∂²h_a/∂x² P)`` and the innovation covariance the term ``½ tr(∂²h_a P ∂²h_b P)``, which the update
    #: treats as extra measurement noise (Joseph form with ``R + S₂``). For a track whose prior is wide across a
    #: curved measurement (a one-point birth seen by a radar: tens of km across the line of sight make a range
    #: bias of ``δ²/(2ρ)``, kilometres against a 30-m σ) the first-order filter's gate misses the true return.
    second_order: bool = False
    #: Central-difference steps (per state component) of the Hessian from :meth:`jacobian` (:meth:`hessian`).
    hessian_steps: tuple = ()

    def h(self, means) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def jacobian(self, means) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def dim(self) -> int:
        return self.R.shape[0]

    def predict(self, means) -> np.ndarray:
        return self.h(means)

    def hessian(self, means) -> np.ndarray:
        """``∂²h_a/∂x_k∂x_l`` ``(n, p, d, d)`` by central differences of :meth:`jacobian` (steps :attr:`hessian_steps`)."""
        X = np.asarray(means, dtype=float)
        n, d = X.shape
        steps = np.asarray(self.hessian_steps, dtype=float)
        # all 2d shifted copies of the means in one call of the Jacobian (row by row the same arithmetic as
        # one call per step): X[0, k] = means + h_k e_k, X[1, k] = means − h_k e_k
        shifted = np.broadcast_to(X, (2, d, n, d)).copy()
        k = np.arange(d)
        shifted[0, k, :, k] += steps[:, None]
        shifted[1, k, :, k] -= steps[:, None]
        J = self.jacobian(shifted.reshape(-1, d)).reshape(2, d, n, self.dim, d)
        out = np.moveaxis((J[0] - J[1]) / (2 * steps[:, None, None, None]), 0, -1)  # (n, p, d, d): [..., l, k]
        return 0.5 * (out + np.swapaxes(out, 2, 3))

    def _moments(self, means, covs):
        """``(z_pred, H, R_eff)``: first order ``(h(x), ∂h/∂x, R)``, or with :attr:`second_order` the bias and the
        extra covariance added (class docstring)."""
        H, z_pred = self.jacobian(means), self.h(means)
        if not self.second_order:
            return z_pred, H, self.R
        Hxx = self.hessian(means)
        A = Hxx @ covs[:, None]  # (n, p, d, d): ∂²h_a P
        z_pred = z_pred + 0.5 * np.trace(A, axis1=2, axis2=3)
        S2 = 0.5 * np.einsum("nakl,nblk->nab", A, A)
        return z_pred, H, self.R + symmetrize(S2)

    def innovation(self, means, covs):
        """``(z_pred, S, K, H)`` with ``H_j = ∂h/∂x(x̂_j)``, ``S_j = H_j P_j H_jᵀ + R``, ``K_j = P_j H_jᵀ S_j⁻¹``
        (second order: the bias in ``z_pred`` and ``S₂`` in ``S``, class docstring)."""
        n = len(means)
        if n == 0:
            p = self.dim
            d = np.shape(means)[-1]
            return np.zeros((0, p)), np.zeros((0, p, p)), np.zeros((0, d, p)), np.zeros((0, p, d))
        z_pred, H, R = self._moments(means, covs)
        PHt = covs @ np.swapaxes(H, 1, 2)
        S = symmetrize(H @ PHt + R)
        K = np.swapaxes(np.linalg.solve(S, np.swapaxes(PHt, 1, 2)), 1, 2)
        return z_pred, S, K, H

    def _wrap(self, r):
        for i in self.wrapped:
            r[..., i] = wrap_pi(r[..., i])
        return r

    def residual(self, Z, z_pred) -> np.ndarray:
        """``z_i − ẑ_j`` ``(m, n, p)``, angle components wrapped into ``[−π, π)``."""
        return self._wrap(np.asarray(Z, dtype=float)[:, None, :] - np.asarray(z_pred, dtype=float)[None, :, :])

    def residual_rows(self, Z_rows, z_pred) -> np.ndarray:
        """``z_j − ẑ_j`` ``(n, p)``, angle components wrapped."""
        return self._wrap(np.asarray(Z_rows, dtype=float) - z_pred)

    def mahalanobis2(self, Z, z_pred, S):
        """``(d² (m, n), log det S (n,))`` of the wrapped residuals (Cholesky of ``S``)."""
        n, m = len(z_pred), len(Z)
        if n == 0 or m == 0:
            return np.zeros((m, n)), (np.zeros(0) if n == 0 else 2.0 * np.sum(
                np.log(np.diagonal(np.linalg.cholesky(S), axis1=-2, axis2=-1)), axis=-1))
        L = np.linalg.cholesky(S)
        logdet = 2.0 * np.sum(np.log(np.diagonal(L, axis1=-2, axis2=-1)), axis=-1)
        # u = L⁻¹ν and |u|² of every pair in one compiled pass: the residual wrapped as numpy wraps it, u summed over
        # k in order and |u|² left to right, as the einsum over (m, n, p) and np.sum round them (bit for bit)
        wrapped = np.zeros(self.dim, dtype=np.bool_)
        wrapped[list(self.wrapped)] = True
        return _pair_distances(np.ascontiguousarray(Z, dtype=float), np.ascontiguousarray(z_pred, dtype=float),
                               np.linalg.inv(L), wrapped), logdet

    def update(self, means, covs, Z_rows):
        """EKF update of each track with its own return (Joseph form, residual wrapped)."""
        if len(means) == 0:
            return means.copy(), covs.copy()
        z_pred, H, R = self._moments(means, covs)
        PHt = covs @ np.swapaxes(H, 1, 2)
        S = symmetrize(H @ PHt + R)
        K = np.swapaxes(np.linalg.solve(S, np.swapaxes(PHt, 1, 2)), 1, 2)
        nu = self.residual_rows(Z_rows, z_pred)
        x = means + np.einsum("nij,nj->ni", K, nu)
        IKH = np.eye(means.shape[1]) - K @ H
        P = IKH @ covs @ np.swapaxes(IKH, 1, 2) + K @ R @ np.swapaxes(K, 1, 2)
        return x, symmetrize(P)

    def view_points(self, means, z_pred=None) -> np.ndarray:
        """The state's position ``(n, 3)``: what ``detection.in_view`` of a position sensor tests."""
        return np.asarray(means)[:, :3]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def wrapped_residual(v, two_pi):
    """``v`` wrapped into ``[−π, π)`` as :func:`wrap_pi` rounds it (numpy's floating remainder)."""
    x = v + np.pi
    if not 0.0 <= x < two_pi:  # (inside, fmod leaves x as it is)
        x = np.fmod(x, two_pi)
        if x != 0.0:
            if x < 0.0:
                x += two_pi
        else:
            x = 0.0
    return x - np.pi


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _pair_distances(Z, z_pred, Linv, wrapped):
    """``d²[i, j] = |L_j⁻¹ ν_ij|²`` with ``ν_ij = Z_i − ẑ_j`` (the ``wrapped`` components into ``[−π, π)`` as
    :func:`wrap_pi`: numpy's floating remainder), :meth:`ExtendedMeasurement.mahalanobis2`'s pairs.

    The radar's four components (``p = 4``) in scalars, each track's ``L⁻¹`` read once for all returns: the same
    operations in the same order as the general loop (``u`` summed over ``k`` in order, ``|u|²`` left to right),
    ~3× faster (the residual no longer goes through memory and the rows of ``L⁻¹`` stay in registers)."""
    m, p = Z.shape
    n = z_pred.shape[0]
    out = np.empty((m, n))
    two_pi = 2.0 * np.pi
    if p == 4:
        w0, w1, w2, w3 = wrapped[0], wrapped[1], wrapped[2], wrapped[3]
        for j in range(n):
            y0, y1, y2, y3 = z_pred[j, 0], z_pred[j, 1], z_pred[j, 2], z_pred[j, 3]
            a00, a01, a02, a03 = Linv[j, 0, 0], Linv[j, 0, 1], Linv[j, 0, 2], Linv[j, 0, 3]
            a10, a11, a12, a13 = Linv[j, 1, 0], Linv[j, 1, 1], Linv[j, 1, 2], Linv[j, 1, 3]
            a20, a21, a22, a23 = Linv[j, 2, 0], Linv[j, 2, 1], Linv[j, 2, 2], Linv[j, 2, 3]
            a30, a31, a32, a33 = Linv[j, 3, 0], Linv[j, 3, 1], Linv[j, 3, 2], Linv[j, 3, 3]
            for i in range(m):
                r0, r1, r2, r3 = Z[i, 0] - y0, Z[i, 1] - y1, Z[i, 2] - y2, Z[i, 3] - y3
                if w0:
                    r0 = wrapped_residual(r0, two_pi)
                if w1:
                    r1 = wrapped_residual(r1, two_pi)
                if w2:
                    r2 = wrapped_residual(r2, two_pi)
                if w3:
                    r3 = wrapped_residual(r3, two_pi)
                u0 = ((a00 * r0 + a01 * r1) + a02 * r2) + a03 * r3
                u1 = ((a10 * r0 + a11 * r1) + a12 * r2) + a13 * r3
                u2 = ((a20 * r0 + a21 * r1) + a22 * r2) + a23 * r3
                u3 = ((a30 * r0 + a31 * r1) + a32 * r2) + a33 * r3
                out[i, j] = (((0.0 + u0 * u0) + u1 * u1) + u2 * u2) + u3 * u3
        return out
    r = np.empty(p)
    for i in range(m):
        for j in range(n):
            for k in range(p):
                v = Z[i, k] - z_pred[j, k]
                r[k] = wrapped_residual(v, two_pi) if wrapped[k] else v
            s = 0.0
            for a in range(p):
                u = Linv[j, a, 0] * r[0]
                for k in range(1, p):
                    u = u + Linv[j, a, k] * r[k]
                s = s + u * u
            out[i, j] = s
    return out


def as_measurement(m):
    """``m`` itself when it has :meth:`~LinearMeasurement.innovation` and :meth:`~LinearMeasurement.update`;
    otherwise a :class:`LinearMeasurement` of its ``H`` and ``R``."""
    if hasattr(m, "innovation") and hasattr(m, "update") and hasattr(m, "residual"):
        return m
    if not (hasattr(m, "H") and hasattr(m, "R")):
        raise TypeError(f"a sensor's measurement must have H and R, or be a measurement model, got {type(m).__name__}")
    return LinearMeasurement(m.H, m.R)

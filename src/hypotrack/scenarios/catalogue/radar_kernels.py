"""Compiled EKF moments of the radar (:class:`~.radar_model.RadarMeasurement`): a batch of tracks in one call.

The second-order EKF of the ``(ρ, az, el, ρ̇)`` radar (:class:`~...models.measurement.ExtendedMeasurement`, Bar-Shalom,
Li & Kirubarajan 2001, Sec. 10.3.3) linearises every track at its mean: ``h(x)`` (:func:`~.radar_model.rae_rate`), the
analytic Jacobian ``H = ∂h/∂x`` (:func:`~.radar_model.rae_rate_jacobian`), the Hessian ``∂²h_a/∂x²`` by central
differences of the Jacobian (steps ``hessian_steps``, symmetrised), the predicted return's bias ``½ tr(∂²h_a P)`` and
the extra covariance ``S₂ = ½ tr(∂²h_a P ∂²h_b P)``; then the innovation covariance ``S = sym(H P Hᵀ + R + sym(S₂))``,
the gain ``K = P Hᵀ S⁻¹`` and the Joseph update ``P⁺ = sym((I − K H) P (I − K H)ᵀ + K R_eff Kᵀ)``,
``x⁺ = x + K ν`` (``ν`` the residual, azimuth wrapped into ``[−π, π)``). In array passes that is ~60 numpy calls per
batch (twelve shifted copies of every state for the Hessian), whatever the batch's size, and every birth term and
engine step calls it on one to a few tracks. :func:`radar_moments` runs the same formulas row by row in one compiled
pass.

The same formulas, written out term for term as the array passes evaluate them; the 3 × 3 and 6 × 6 products as a
chain of fused multiply-adds in the inner index's order (as OpenBLAS's small products round,
:mod:`~...models.orbit3d_replay`), so that ``h``, the Jacobian and the Hessian are those of the array passes (the
Hessian's differences of nearly equal Jacobians would magnify any other rounding). The 4 × 4 solve of the gain is an
LU factorisation with partial pivoting (LAPACK's ``gesv`` algorithm, not its operation order), the einsum of ``S₂``
summed in its own order: the moments agree with the array passes to rounding (tests: ~1e-15 of their scale), not bit
for bit. Every row is computed alone, so a row's numbers do not depend on the batch it is in.

Two more passes over rows: :func:`radar_jacobian` (the Jacobian alone, bit for bit
:func:`~.radar_model.rae_rate_jacobian`) and :func:`teme_near`, the range and horizon test with which
:meth:`~.sensors.GroundRadar.in_view` first narrows the points whose angles it computes (the factored filter asks it
of every singleton's mean every scan: 10⁴-10⁶ points), bit for bit the array passes' decisions.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ...models.measurement import wrapped_residual
from ...models.orbit3d_replay import fused_multiply_add as _fma

__all__ = ["radar_moments", "radar_jacobian", "teme_near", "MOMENTS", "INNOVATION", "UPDATE"]

#: what :func:`radar_moments` returns: ``(z_pred, H, R_eff)``, ``(z_pred, S, K, H)`` or ``(x⁺, P⁺)``
MOMENTS, INNOVATION, UPDATE = 0, 1, 2

_TWO_PI = 2.0 * math.pi


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wrap(a, center):
    """``np.mod(a − center + π, 2π) − π + center`` (:func:`~.frames.wrap_angle`), numpy's floating ``mod``: the
    measurement model's wrapped residual of ``a − center``, the same operations in the same order."""
    return wrapped_residual(a - center, _TWO_PI) + center


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wrap_pi(a):
    """``(a + π) % 2π − π`` (:func:`~...models.measurement.wrap_pi`)."""
    return _wrap(a, 0.0)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _jacobian(x, s, sdot, M, J):
    """:func:`~.radar_model.rae_rate_jacobian` of one state ``x`` (6,) into ``J`` (4, 6)."""
    d0, d1, d2 = x[0] - s[0], x[1] - s[1], x[2] - s[2]
    w0, w1, w2 = x[3] - sdot[0], x[4] - sdot[1], x[5] - sdot[2]
    e = _fma(d2, M[0, 2], _fma(d1, M[0, 1], d0 * M[0, 0]))  # d @ M.T
    nn = _fma(d2, M[1, 2], _fma(d1, M[1, 1], d0 * M[1, 0]))
    u = _fma(d2, M[2, 2], _fma(d1, M[2, 1], d0 * M[2, 0]))
    rho2 = d0 * d0 + d1 * d1 + d2 * d2
    rho = math.sqrt(rho2)
    hz2 = e * e + nn * nn
    hz = math.sqrt(hz2)
    rdot = (d0 * w0 + d1 * w1 + d2 * w2) / rho
    a0, a1 = nn / hz2, -e / hz2
    den = rho2 * hz
    b0, b1, b2 = (-e * u) / den, (-nn * u) / den, hz2 / den
    dd = (d0, d1, d2)
    ww = (w0, w1, w2)
    for j in range(3):
        J[0, j] = dd[j] / rho
        J[0, 3 + j] = 0.0
        J[1, j] = _fma(0.0, M[2, j], _fma(a1, M[1, j], a0 * M[0, j]))
        J[1, 3 + j] = 0.0
        J[2, j] = _fma(b2, M[2, j], _fma(b1, M[1, j], b0 * M[0, j]))
        J[2, 3 + j] = 0.0
        J[3, j] = (ww[j] - rdot * dd[j] / rho) / rho
        J[3, 3 + j] = dd[j] / rho


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _h(x, s, sdot, M, az_center, z):
    """:func:`~.radar_model.rae_rate` of one state ``x`` into ``z`` (4,)."""
    d0, d1, d2 = x[0] - s[0], x[1] - s[1], x[2] - s[2]
    w0, w1, w2 = x[3] - sdot[0], x[4] - sdot[1], x[5] - sdot[2]
    e = _fma(d2, M[0, 2], _fma(d1, M[0, 1], d0 * M[0, 0]))
    nn = _fma(d2, M[1, 2], _fma(d1, M[1, 1], d0 * M[1, 0]))
    u = _fma(d2, M[2, 2], _fma(d1, M[2, 1], d0 * M[2, 0]))
    rho = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    z[0] = rho
    z[1] = _wrap(math.atan2(e, nn), az_center)
    z[2] = math.atan2(u, math.hypot(e, nn))
    z[3] = (d0 * w0 + d1 * w1 + d2 * w2) / rho


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rate_row(x, s, sdot, d0, d1, d2, rho, J3):
    """The range rate's position derivatives ``J[3, :3]`` of :func:`_jacobian` at state ``x`` whose position
    differences ``d`` and range ``ρ`` are given (the same expressions, so the same bits)."""
    w0, w1, w2 = x[3] - sdot[0], x[4] - sdot[1], x[5] - sdot[2]
    rdot = (d0 * w0 + d1 * w1 + d2 * w2) / rho
    J3[0] = (w0 - rdot * d0 / rho) / rho
    J3[1] = (w1 - rdot * d1 / rho) / rho
    J3[2] = (w2 - rdot * d2 / rho) / rho


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _differences(x, s, sdot, M, steps, H, Jp, Jm, xs, A):
    """The Jacobian's central differences ``A[a, l, k] = (J(x + h_k e_k) − J(x − h_k e_k))[a, l] / 2h_k`` (the
    Hessian before symmetrising), ``H = J(x)`` given. A velocity step (``k ≥ 3``) moves only the range rate's
    position derivatives ``J[3, :3]`` (``ρ̇ = d·w/ρ``: the only entries holding ``w``); every other entry of the
    shifted Jacobians is computed from the unshifted position by the same expressions as ``H``'s, so it is ``H``'s
    own bits and its difference is ``H``'s entry minus itself: the same numbers (a zero, or a NaN where ``H`` has
    one) as differencing two full Jacobians, with six of the twelve Jacobians reduced to three entries."""
    for k in range(3):  # a position step: every entry moves
        for c in range(6):
            xs[c] = x[c]
        xs[k] = x[k] + steps[k]
        _jacobian(xs, s, sdot, M, Jp)
        xs[k] = x[k] - steps[k]
        _jacobian(xs, s, sdot, M, Jm)
        two = 2.0 * steps[k]
        for a in range(4):
            for l in range(6):
                A[a, l, k] = (Jp[a, l] - Jm[a, l]) / two
    d0, d1, d2 = x[0] - s[0], x[1] - s[1], x[2] - s[2]
    rho = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    for k in range(3, 6):
        for c in range(6):
            xs[c] = x[c]
        xs[k] = x[k] + steps[k]
        _rate_row(xs, s, sdot, d0, d1, d2, rho, Jp[3])
        xs[k] = x[k] - steps[k]
        _rate_row(xs, s, sdot, d0, d1, d2, rho, Jm[3])
        two = 2.0 * steps[k]
        for a in range(4):
            for l in range(6):
                A[a, l, k] = (H[a, l] - H[a, l]) / two
        for l in range(3):
            A[3, l, k] = (Jp[3, l] - Jm[3, l]) / two


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _row(x, P, s, sdot, M, steps, R, az_center, second, z, H, Re, Jp, Jm, Hxx, A, xs):
    """``(z_pred, H, R_eff)`` of one track into ``z``, ``H``, ``Re`` (the scratch ``Jp``, ``Jm``, ``Hxx``, ``A``,
    ``xs``): :meth:`~...models.measurement.ExtendedMeasurement._moments`."""
    _jacobian(x, s, sdot, M, H)
    _h(x, s, sdot, M, az_center, z)
    for a in range(4):
        for b in range(4):
            Re[a, b] = R[a, b]
    if not second:
        return
    _differences(x, s, sdot, M, steps, H, Jp, Jm, xs, A)
    for a in range(4):
        for l in range(6):
            for k in range(6):
                Hxx[a, l, k] = 0.5 * (A[a, l, k] + A[a, k, l])
    # A_a = Hxx_a P, each entry the 6 x 6 product's fused chain over l; the chains of a row side by side (the loop
    # over j innermost), so they overlap instead of waiting on one another: each entry's operations and order unchanged
    for a in range(4):
        for i in range(6):
            for j in range(6):
                A[a, i, j] = 0.0
            for l in range(6):
                h = Hxx[a, i, l]
                for j in range(6):
                    A[a, i, j] = _fma(h, P[l, j], A[a, i, j])
    for a in range(4):
        tr = A[a, 0, 0]
        for i in range(1, 6):
            tr += A[a, i, i]
        z[a] = z[a] + 0.5 * tr
    # T[u, v] = Σ_kl A_u[k, l] A_v[l, k] over k then l, as one sum each; all sixteen side by side (Jp's room)
    T = Jp.reshape(24)
    for p in range(16):
        T[p] = 0.0
    for k in range(6):
        for l in range(6):
            for u in range(4):
                g = A[u, k, l]
                for w in range(4):
                    T[4 * u + w] += g * A[w, l, k]
    for a in range(4):  # S2[a, b] = ½ Σ_kl A_a[k, l] A_b[l, k], symmetrised
        for b in range(a, 4):
            sab = T[4 * a + b]
            sba = T[4 * b + a]
            v = 0.5 * (0.5 * sab + 0.5 * sba)
            Re[a, b] = R[a, b] + v
            Re[b, a] = R[b, a] + v


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _gain(P, H, Re, S, PHt, K, LU, piv, y):
    """``S = sym(H P Hᵀ + R_eff)`` and ``K = P Hᵀ S⁻¹`` (LU with partial pivoting) of one track; ``False`` when ``S``
    is singular."""
    for i in range(6):  # PHt = P Hᵀ
        for a in range(4):
            acc = 0.0
            for l in range(6):
                acc = _fma(P[i, l], H[a, l], acc)
            PHt[i, a] = acc
    for a in range(4):  # H PHt + R_eff
        for b in range(4):
            acc = 0.0
            for l in range(6):
                acc = _fma(H[a, l], PHt[l, b], acc)
            LU[a, b] = acc + Re[a, b]
    for a in range(4):
        for b in range(4):
            S[a, b] = 0.5 * (LU[a, b] + LU[b, a])
    for a in range(4):
        for b in range(4):
            LU[a, b] = S[a, b]
    for c in range(4):  # LU = P S, partial pivoting
        p = c
        for r in range(c + 1, 4):
            if abs(LU[r, c]) > abs(LU[p, c]):
                p = r
        piv[c] = p
        if LU[p, c] == 0.0:
            return False
        if p != c:
            for b in range(4):
                LU[c, b], LU[p, b] = LU[p, b], LU[c, b]
        for r in range(c + 1, 4):
            LU[r, c] /= LU[c, c]
            for b in range(c + 1, 4):
                LU[r, b] -= LU[r, c] * LU[c, b]
    for i in range(6):  # row i of K solves S k = PHt[i] (S symmetric: K = P Hᵀ S⁻¹ = (S⁻¹ H P)ᵀ)
        for a in range(4):
            y[a] = PHt[i, a]
        for c in range(4):
            p = piv[c]
            if p != c:
                y[c], y[p] = y[p], y[c]
        for a in range(4):
            for b in range(a):
                y[a] -= LU[a, b] * y[b]
        for a in range(3, -1, -1):
            for b in range(a + 1, 4):
                y[a] -= LU[a, b] * y[b]
            y[a] /= LU[a, a]
        for a in range(4):
            K[i, a] = y[a]
    return True


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _batch(X, P, Zr, s, sdot, M, steps, R, az_center, second, mode):
    n = X.shape[0]
    z_pred = np.empty((n, 4))
    H = np.empty((n, 4, 6))
    Re = np.empty((n, 4, 4))
    S = np.empty((n, 4, 4))
    K = np.empty((n, 6, 4))
    xo = np.empty((n, 6))
    Po = np.empty((n, 6, 6))
    Jp, Jm = np.empty((4, 6)), np.empty((4, 6))
    Hxx, A = np.empty((4, 6, 6)), np.empty((4, 6, 6))
    xs, PHt, LU, y = np.empty(6), np.empty((6, 4)), np.empty((4, 4)), np.empty(4)
    piv = np.empty(4, np.int64)
    IKH, B, KR = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 4))
    nu = np.empty(4)
    bad = -1
    for i in range(n):
        _row(X[i], P[i], s, sdot, M, steps, R, az_center, second, z_pred[i], H[i], Re[i], Jp, Jm, Hxx, A, xs)
        if mode == MOMENTS:
            continue
        if not _gain(P[i], H[i], Re[i], S[i], PHt, K[i], LU, piv, y):
            bad = i
            break
        if mode == INNOVATION:
            continue
        _joseph(X[i], P[i], Zr[i], z_pred[i], H[i], Re[i], K[i], xo[i], Po[i], nu, IKH, B, KR)
    return z_pred, H, Re, S, K, xo, Po, bad


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _joseph(x, P, zr, z, H, Re, K, xo, Po, nu, IKH, B, KR):
    """The EKF update of one row written into ``xo``, ``Po``: ``x + K ν`` (the azimuth's innovation wrapped) and the
    Joseph form ``(I − K H) P (I − K H)ᵀ + K R_eff Kᵀ`` symmetrised; ``nu``, ``IKH``, ``B``, ``KR`` are scratch."""
    for a in range(4):
        nu[a] = zr[a] - z[a]
    nu[1] = _wrap_pi(nu[1])
    for r in range(6):
        acc = 0.0
        for a in range(4):
            acc += K[r, a] * nu[a]
        xo[r] = x[r] + acc
    for r in range(6):  # IKH = I - K H
        for c in range(6):
            acc = 0.0
            for a in range(4):
                acc = _fma(K[r, a], H[a, c], acc)
            IKH[r, c] = (1.0 if r == c else 0.0) - acc
    for r in range(6):  # B = IKH P
        for c in range(6):
            acc = 0.0
            for l in range(6):
                acc = _fma(IKH[r, l], P[l, c], acc)
            B[r, c] = acc
    for r in range(6):  # KR = K R_eff
        for c in range(4):
            acc = 0.0
            for l in range(4):
                acc = _fma(K[r, l], Re[l, c], acc)
            KR[r, c] = acc
    for r in range(6):  # B IKHᵀ + KR Kᵀ
        for c in range(6):
            acc = 0.0
            for l in range(6):
                acc = _fma(B[r, l], IKH[c, l], acc)
            acc2 = 0.0
            for l in range(4):
                acc2 = _fma(KR[r, l], K[c, l], acc2)
            Po[r, c] = acc + acc2
    for r in range(6):
        for c in range(r, 6):
            v = 0.5 * (Po[r, c] + Po[c, r])
            Po[r, c] = v
            Po[c, r] = v


_NO_RETURNS = np.zeros((0, 4))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _jacobians(X, s, sdot, M):
    out = np.empty((X.shape[0], 4, 6))
    for i in range(X.shape[0]):
        _jacobian(X[i], s, sdot, M, out[i])
    return out


def radar_jacobian(X, site_teme, sdot, M):
    """``∂h/∂x`` ``(n, 4, 6)`` of TEME states ``X`` ``(n, 6)`` (:func:`~.radar_model.rae_rate_jacobian`, bit for bit)."""
    f = np.ascontiguousarray
    return _jacobians(f(X, dtype=float).reshape(-1, 6), f(site_teme, dtype=float), f(sdot, dtype=float), f(M, dtype=float))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _update_known(X, P, Zr, Xi, Pi, mX, mP, keys, order, mz, mH, mRe, mK, s, sdot, M, steps, R, az_center, second):
    """:func:`_batch`'s update (mode ``UPDATE``) of rows ``X``, ``P`` with returns ``Zr``, taking a row's ``ẑ``, ``H``,
    ``R_eff`` and ``K`` from the last innovation's batch (``mX``, ``mP``, ``mz``, ``mH``, ``mRe``, ``mK``; ``keys`` its
    first components sorted, ``order`` their rows) when the row's bits (``Xi``, ``Pi``: ``X``, ``P`` as int64, and the
    batch's as ``mX``, ``mP``) are the same — the same numbers :func:`_row` and :func:`_gain` would compute, a row's
    moments depending on that row alone — else computing them; then the Joseph update, the same statements as
    :func:`_batch`'s. Returns ``(x⁺, P⁺, bad, n_known)``."""
    n = X.shape[0]
    xo = np.empty((n, 6))
    Po = np.empty((n, 6, 6))
    z = np.empty(4)
    H = np.empty((4, 6))
    Re = np.empty((4, 4))
    S = np.empty((4, 4))
    K = np.empty((6, 4))
    Jp, Jm = np.empty((4, 6)), np.empty((4, 6))
    Hxx, A = np.empty((4, 6, 6)), np.empty((4, 6, 6))
    xs, PHt, LU, y = np.empty(6), np.empty((6, 4)), np.empty((4, 4)), np.empty(4)
    piv = np.empty(4, np.int64)
    IKH, B, KR = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 4))
    nu = np.empty(4)
    bad, n_known = -1, 0
    for i in range(n):
        found = -1
        q = np.searchsorted(keys, X[i, 0])
        while found < 0 and q < len(keys) and keys[q] == X[i, 0]:
            j = order[q]
            same = True
            for a in range(6):
                if Xi[i, a] != mX[j, a]:
                    same = False
            for a in range(6):
                for b in range(6):
                    if Pi[i, a, b] != mP[j, a, b]:
                        same = False
            if same:
                found = j
            q += 1
        if found >= 0:
            n_known += 1
            z[:] = mz[found]
            H[:, :] = mH[found]
            Re[:, :] = mRe[found]
            K[:, :] = mK[found]
        else:
            _row(X[i], P[i], s, sdot, M, steps, R, az_center, second, z, H, Re, Jp, Jm, Hxx, A, xs)
            if not _gain(P[i], H, Re, S, PHt, K, LU, piv, y):
                bad = i
                break
        _joseph(X[i], P[i], Zr[i], z, H, Re, K, xo[i], Po[i], nu, IKH, B, KR)
    return xo, Po, bad, n_known


#: The last innovation batch of :func:`radar_moments` (its geometry, rows and moments), which an update of the same
#: rows under the same geometry reuses (the fast path updates the tracks the scan's scores just linearised).
_LAST_INNOVATION = [None]


def _same_geometry(a, b) -> bool:
    """The same site, rotation, steps, ``R``, centre and order (bit for bit: the arrays' bytes)."""
    for x, y in zip(a, b):
        if isinstance(x, np.ndarray):
            if not (x.shape == y.shape and x.tobytes() == y.tobytes()):
                return False
        elif x != y:
            return False
    return True


def radar_moments(X, P, Z, site_teme, sdot, M, steps, R, az_center, second_order, mode):
    """The radar's EKF moments of tracks ``X`` (n, 6), ``P`` (n, 6, 6) (module docstring): ``mode``
    :data:`MOMENTS` ``(z_pred, H, R_eff)``, :data:`INNOVATION` ``(z_pred, S, K, H)`` or :data:`UPDATE` ``(x⁺, P⁺)``
    with returns ``Z`` (n, 4); the site's TEME position ``site_teme`` and velocity ``sdot``, ``M = E R3(θ)``
    (:func:`~.radar_model.site_teme`), the Hessian's ``steps`` (6,), ``R`` (4, 4) and the azimuth's centre.
    Raises ``numpy.linalg.LinAlgError`` for a singular innovation covariance, as the array passes' solve does.

    An update reuses the linearisation (``ẑ``, ``H``, ``R_eff``, ``K``) of each row the last innovation batch held
    with the same bits under the same geometry (:func:`_update_known`: the numbers it would compute again)."""
    f = np.ascontiguousarray
    Zr = _NO_RETURNS if Z is None else f(Z, dtype=float)
    X, P = f(X, dtype=float), f(P, dtype=float)
    geo = (f(site_teme, dtype=float), f(sdot, dtype=float), f(M, dtype=float), f(steps, dtype=float),
           f(R, dtype=float), float(az_center), bool(second_order))
    last = _LAST_INNOVATION[0]
    if mode == UPDATE and last is not None and len(X) and X.shape[1:] == (6,) and _same_geometry(last[0], geo):
        _, mX, mP, keys, order, mz, mH, mRe, mK = last
        xo, Po, bad, _ = _update_known(X, P, Zr, X.view(np.int64), P.view(np.int64), mX, mP, keys, order, mz, mH,
                                       mRe, mK, *geo)
        if bad >= 0:
            raise np.linalg.LinAlgError("Singular matrix")
        return xo, Po
    z_pred, H, Re, S, K, xo, Po, bad = _batch(X, P, Zr, *geo, int(mode))
    if bad >= 0:
        raise np.linalg.LinAlgError("Singular matrix")
    if mode == MOMENTS:
        return z_pred, H, Re
    if mode == INNOVATION:
        if len(X) and X.shape[1:] == (6,):  # kept as copies: the caller may change what it is given
            keys_order = np.argsort(X[:, 0], kind="stable")
            _LAST_INNOVATION[0] = (tuple(g.copy() if isinstance(g, np.ndarray) else g for g in geo),
                                   X.view(np.int64).copy(), P.view(np.int64).copy(), X[keys_order, 0].copy(),
                                   keys_order, z_pred.copy(), H.copy(), Re.copy(), K.copy())
        return z_pred, S, K, H
    return xo, Po


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _near(X, R3, site_ef, enu, r2_max, above):
    n = X.shape[0]
    loc = np.empty((n, 3))
    near = np.empty(n, dtype=np.bool_)
    for i in range(n):
        x0, x1, x2 = X[i, 0], X[i, 1], X[i, 2]
        # r_ef = r R3ᵀ, then r_ef − s_ef
        d0 = _fma(x2, R3[0, 2], _fma(x1, R3[0, 1], x0 * R3[0, 0])) - site_ef[0]
        d1 = _fma(x2, R3[1, 2], _fma(x1, R3[1, 1], x0 * R3[1, 0])) - site_ef[1]
        d2 = _fma(x2, R3[2, 2], _fma(x1, R3[2, 1], x0 * R3[2, 0])) - site_ef[2]
        e = _fma(d2, enu[0, 2], _fma(d1, enu[0, 1], d0 * enu[0, 0]))  # loc = (r_ef − s_ef) Eᵀ
        nn = _fma(d2, enu[1, 2], _fma(d1, enu[1, 1], d0 * enu[1, 0]))
        u = _fma(d2, enu[2, 2], _fma(d1, enu[2, 1], d0 * enu[2, 0]))
        loc[i, 0], loc[i, 1], loc[i, 2] = e, nn, u
        near[i] = (e * e + nn * nn) + u * u <= r2_max and (u > 0.0 or not above)
    return loc, near


def teme_near(X, R3, site_ef, enu, r_max_km, above_horizon):
    """``(loc (n, 3), near (n,))`` of TEME positions ``X`` (n, ≥ 3): the site's local east-north-up coordinates
    ``loc = (X R3ᵀ − s_ef) Eᵀ`` (``R3 = R3(θ)``, ``E`` the site's ENU rows; the products rounded as numpy's BLAS
    rounds them, :mod:`~...models.orbit3d_replay`) and whether each is within ``r_max_km`` (``|loc|² ≤ (r_max (1 +
    1e-9))²``) and, with ``above_horizon``, above the horizon: the points whose angles
    :meth:`~.sensors.GroundRadar.in_view` then tests, the same decisions in one pass over the rows."""
    f = np.ascontiguousarray  # X as given: the kernel reads its first three columns (a slice of means is not copied)
    X = np.asarray(X, dtype=float)
    return _near(X if X.ndim == 2 and X.strides[1] == X.itemsize else f(X), f(R3, dtype=float), f(site_ef, dtype=float), f(enu, dtype=float),
                 float((r_max_km * (1 + 1e-9)) ** 2), bool(above_horizon))

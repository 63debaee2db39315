"""Compiled EKF replay of :class:`~.orbit3d.J2Orbit3D`: many tracks, each predicted over its own gap in its own
number of equal steps, mean, state-transition matrix and covariance, in one kernel call.

The lazy factored filter's replay (:func:`hypotrack.hypotheses.factored.lane.predict_each` with ``step``) predicts a
track woken after a gap of ``k`` scans in ``k`` EKF steps ``x ← f(x)``, ``P ← sym(Φ P Φᵀ + Q(h))``
(``sym(A) = (A + Aᵀ)/2``, ``Q`` the white-acceleration noise ``q [[h³/3 I, h²/2 I], [h²/2 I, h I]]``,
:meth:`~.orbit.TwoBodyOrbit.Q`). In array passes that is one numpy batch per step: ~30 array operations on the
complex-step rows each, so a track re-acquired after an orbit out of view (~570 scans of 10 s) costs ~570 Python
round trips. :func:`replay_j2` runs the same arithmetic row by row in one compiled pass.

The same arithmetic: ``Φ`` is the complex-step derivative of the RK4 map (:meth:`~.orbit3d.J2Orbit3D.transition`:
six copies of the state, copy ``j`` perturbed by ``i·h`` in component ``j``, through the same RK4 steps, ``Φ[:, j]``
their imaginary parts over ``h``), written out on (real, imaginary) pairs with numpy's complex formulas —
product ``(ac − bd, ad + bc)``, quotient by Smith's scaling (``rat = d/c``, ``scl = 1/(c + d·rat)``, as numpy's
loop), square root ``t = sqrt((a + hypot(a, b))/2)``, ``b/(2t)`` — and the mean is the real part of the first copy,
as there. What differs from the array passes is rounding only: numpy's vectorised complex loops and OpenBLAS's
6 × 6 products may fuse multiply-adds where this kernel does not, so the moments agree to rounding (the
tests hold them to 1e-12 of their scale after hundreds of steps), not bit for bit.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["replay_j2"]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _cmul(ar, ai, br, bi):
    return ar * br - ai * bi, ar * bi + ai * br


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _acc(xr, xi, yr, yi, zr, zi, mu, c_j2):
    """:func:`~.orbit3d._j2_acceleration` of one complex position, operation for operation."""
    a, b = _cmul(xr, xi, xr, xi)
    c, d = _cmul(yr, yi, yr, yi)
    a, b = a + c, b + d
    c, d = _cmul(zr, zi, zr, zi)
    dr, di = a + c, b + d
    # 1 / (dr + i di), numpy's complex quotient (Smith), numerator 1 + 0i
    if abs(dr) >= abs(di):
        rat = di / dr
        scl = 1.0 / (dr + di * rat)
        ir2r, ir2i = (1.0 + 0.0 * rat) * scl, (0.0 - 1.0 * rat) * scl
    else:
        rat = dr / di
        scl = 1.0 / (di + dr * rat)
        ir2r, ir2i = (1.0 * rat + 0.0) * scl, (0.0 * rat - 1.0) * scl
    # sqrt(ir2), principal branch (ir2 has a positive real part here)
    t = math.sqrt((ir2r + math.hypot(ir2r, ir2i)) * 0.5)
    sr, si = t, ir2i / (2.0 * t)
    ir3r, ir3i = _cmul(ir2r, ir2i, sr, si)
    kjr, kji = c_j2 * ir2r, c_j2 * ir2i
    a, b = _cmul(5.0 * zr, 5.0 * zi, zr, zi)
    s_r, s_i = _cmul(a, b, ir2r, ir2i)
    a, b = _cmul(kjr, kji, s_r - 1.0, s_i)
    fr, fi = _cmul(ir3r, ir3i, a - mu, b)
    a, b = _cmul(kjr, kji, s_r - 3.0, s_i)
    a, b = _cmul(ir3r, ir3i, a - mu, b)
    axr, axi = _cmul(xr, xi, fr, fi)
    ayr, ayi = _cmul(yr, yi, fr, fi)
    azr, azi = _cmul(zr, zi, a, b)
    return axr, axi, ayr, ayi, azr, azi


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rk4(Zr, Zi, c, hk, mu, c_j2):
    """One RK4 step of ``hk`` of complex copy ``c`` (rows of ``Zr``, ``Zi``), in place: the array passes'
    :func:`~.orbit3d._rk4_j2_arrays` step, the real scalars ``hk/2``, ``hk/6`` scaling both parts."""
    hk2, hk6 = hk / 2, hk / 6
    rx, rxi, ry, ryi, rz, rzi = Zr[c, 0], Zi[c, 0], Zr[c, 1], Zi[c, 1], Zr[c, 2], Zi[c, 2]
    vx, vxi, vy, vyi, vz, vzi = Zr[c, 3], Zi[c, 3], Zr[c, 4], Zi[c, 4], Zr[c, 5], Zi[c, 5]
    a1x, a1xi, a1y, a1yi, a1z, a1zi = _acc(rx, rxi, ry, ryi, rz, rzi, mu, c_j2)
    v2x, v2xi, v2y, v2yi, v2z, v2zi = (vx + hk2 * a1x, vxi + hk2 * a1xi, vy + hk2 * a1y, vyi + hk2 * a1yi,
                                       vz + hk2 * a1z, vzi + hk2 * a1zi)
    a2x, a2xi, a2y, a2yi, a2z, a2zi = _acc(rx + hk2 * vx, rxi + hk2 * vxi, ry + hk2 * vy, ryi + hk2 * vyi,
                                           rz + hk2 * vz, rzi + hk2 * vzi, mu, c_j2)
    v3x, v3xi, v3y, v3yi, v3z, v3zi = (vx + hk2 * a2x, vxi + hk2 * a2xi, vy + hk2 * a2y, vyi + hk2 * a2yi,
                                       vz + hk2 * a2z, vzi + hk2 * a2zi)
    a3x, a3xi, a3y, a3yi, a3z, a3zi = _acc(rx + hk2 * v2x, rxi + hk2 * v2xi, ry + hk2 * v2y, ryi + hk2 * v2yi,
                                           rz + hk2 * v2z, rzi + hk2 * v2zi, mu, c_j2)
    v4x, v4xi, v4y, v4yi, v4z, v4zi = (vx + hk * a3x, vxi + hk * a3xi, vy + hk * a3y, vyi + hk * a3yi,
                                       vz + hk * a3z, vzi + hk * a3zi)
    a4x, a4xi, a4y, a4yi, a4z, a4zi = _acc(rx + hk * v3x, rxi + hk * v3xi, ry + hk * v3y, ryi + hk * v3yi,
                                           rz + hk * v3z, rzi + hk * v3zi, mu, c_j2)
    Zr[c, 0] = rx + hk6 * ((vx + 2 * (v2x + v3x)) + v4x)
    Zi[c, 0] = rxi + hk6 * ((vxi + 2 * (v2xi + v3xi)) + v4xi)
    Zr[c, 1] = ry + hk6 * ((vy + 2 * (v2y + v3y)) + v4y)
    Zi[c, 1] = ryi + hk6 * ((vyi + 2 * (v2yi + v3yi)) + v4yi)
    Zr[c, 2] = rz + hk6 * ((vz + 2 * (v2z + v3z)) + v4z)
    Zi[c, 2] = rzi + hk6 * ((vzi + 2 * (v2zi + v3zi)) + v4zi)
    Zr[c, 3] = vx + hk6 * ((a1x + 2 * (a2x + a3x)) + a4x)
    Zi[c, 3] = vxi + hk6 * ((a1xi + 2 * (a2xi + a3xi)) + a4xi)
    Zr[c, 4] = vy + hk6 * ((a1y + 2 * (a2y + a3y)) + a4y)
    Zi[c, 4] = vyi + hk6 * ((a1yi + 2 * (a2yi + a3yi)) + a4yi)
    Zr[c, 5] = vz + hk6 * ((a1z + 2 * (a2z + a3z)) + a4z)
    Zi[c, 5] = vzi + hk6 * ((a1zi + 2 * (a2zi + a3zi)) + a4zi)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _replay(X, P, h, k, max_step, q, mu, c_j2, hstep):
    """Rows ``X`` ``(n, 6)``, ``P`` ``(n, 6, 6)``: row ``i`` in ``k[i]`` EKF steps of ``h[i]`` (module docstring).
    Returns ``(x, P, bad)``: ``bad`` the first row whose prediction is not finite (−1: none)."""
    n = X.shape[0]
    xo, Po = X.copy(), P.copy()
    Zr, Zi = np.empty((6, 6)), np.empty((6, 6))
    F, A, B = np.empty((6, 6)), np.empty((6, 6)), np.empty((6, 6))
    for i in range(n):
        hi = h[i]
        m = int(math.ceil(abs(hi) / max_step))
        hs = hi / max(m, 1)
        h3, h2 = q * (hi ** 3.0 / 3), q * (hi ** 2.0 / 2)
        h1 = q * hi
        for _ in range(k[i]):
            for c in range(6):
                for j in range(6):
                    Zr[c, j] = xo[i, j]
                    Zi[c, j] = 0.0
                Zi[c, c] = hstep
            for c in range(6):
                for _s in range(m):
                    _rk4(Zr, Zi, c, hs, mu, c_j2)
            for a in range(6):
                xo[i, a] = Zr[0, a]
                for b in range(6):
                    F[a, b] = Zi[b, a] / hstep
            for a in range(6):  # B = F P
                for b in range(6):
                    s = 0.0
                    for j in range(6):
                        s += F[a, j] * Po[i, j, b]
                    B[a, b] = s
            for a in range(6):  # A = B Fᵀ + Q
                for b in range(6):
                    s = 0.0
                    for j in range(6):
                        s += B[a, j] * F[b, j]
                    A[a, b] = s
            for a in range(3):
                A[a, a] += h3
                A[a, a + 3] += h2
                A[a + 3, a] += h2
                A[a + 3, a + 3] += h1
            for a in range(6):
                for b in range(6):
                    Po[i, a, b] = 0.5 * (A[a, b] + A[b, a])
            for a in range(6):
                if not math.isfinite(xo[i, a]):
                    return xo, Po, i
                for b in range(6):
                    if not math.isfinite(F[a, b]):
                        return xo, Po, i
    return xo, Po, -1


def replay_j2(model, x, P, h, k):
    """EKF prediction of ``(x, P)`` (``(n, 6)``, ``(n, 6, 6)``) through :class:`~.orbit3d.J2Orbit3D` ``model``, row
    ``i`` in ``k[i]`` (≥ 0) steps of ``h[i]`` (≥ 0) s each: ``(x, P)``. Raises ``ValueError`` as
    :meth:`~.orbit3d.J2Orbit3D.transition` does for a state propagating to a non-finite one."""
    from .orbit import _H_STEP

    X = np.ascontiguousarray(x, dtype=float)
    if len(X) == 0:
        return X.copy(), np.array(P, dtype=float)
    xo, Po, bad = _replay(X, np.ascontiguousarray(P, dtype=float), np.ascontiguousarray(h, dtype=float),
                          np.ascontiguousarray(k, dtype=np.int64), float(model.max_step), float(model.q),
                          float(model.mu), float(1.5 * model.j2 * model.mu * model.radius**2), _H_STEP)
    if bad >= 0:
        r = float(np.linalg.norm(X[bad, :3]))
        raise ValueError(f"x: state {bad} (position radius {r:.6g} km) propagates to a non-finite state: it is at or "
                         "falls through the Earth's centre, where the two-body + J2 acceleration is singular")
    return xo, Po

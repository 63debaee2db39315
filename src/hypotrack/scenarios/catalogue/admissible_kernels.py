"""The admissible-region birth mixtures of a scan's returns in one compiled pass (:func:`admissible_components`).

:meth:`~.admissible.AdmissibleRegionBirth.components_batch` builds every return's mixture (module docstring of
:mod:`.admissible`, steps 1-5) in ~100 array passes whatever the number of returns — the fixed cost of a scan's
births at catalogue scale, where a scan leaves one to a few returns unexplained. This kernel runs the same steps
return by return, cell by cell:

1. the state of an attributable ``(ρ, az, el, ρ̇, α̇, ε̇)``: ``r = s + Mᵀ l``, ``v = Mᵀ l̇ + ω ẑ × r``
   (:func:`~.radar_model.attributable_to_state`, the products by ``M`` rounded as numpy's BLAS rounds them);
2. the rate box ``V = sqrt((v_esc + |ω × r|)² − ρ̇²)``, ``α̇_max = V/(ρ max(cos el, 10⁻⁶))``, ``ε̇_max = V/ρ``;
3. the grid edges as :func:`numpy.linspace` makes them, the centres, each cell's state affine in its rates
   (``v₀ + α̇ (v_α − v₀) + ε̇ (v_ε − v₀)``, the batch's arithmetic) and the plausibility test of its centre and
   four corners (:func:`~...models.plausibility.plausible_orbits`, operation for operation);
4. each block's centroid and scatter over its admissible cells, summed as numpy sums a block of ``cells²``
   contiguous values (eight running sums, :func:`_pairwise`), plus the cell's ``Δ²/12``, times ``spread²``;
5. each component's mean and covariance ``J diag(R, C_rates) Jᵀ``: the Jacobian ``∂x/∂y`` of step 1 in closed
   form (the batch takes it by complex step, exact to rounding: the two agree to rounding).

The plausibility verdicts are those of the array passes but where a cell's state sits within rounding of the
region's boundary (sines and cosines of numpy and of the C library may differ in the last bit); the moments
agree to rounding (the tests compare every weight, mean and covariance to 1e-12, and the components one for one).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ...models.orbit3d_replay import fused_multiply_add as _fma

__all__ = ["admissible_components"]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _mul_m(l0, l1, l2, M, j):
    """``(l Mᵀ... )``: component ``j`` of ``l @ M`` (a row vector times ``M``), the BLAS chain."""
    return _fma(l2, M[2, j], _fma(l1, M[1, j], l0 * M[0, j]))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _state(rho, az, el, rd, azd, eld, s, M, omega, out):
    """:func:`~.radar_model.attributable_to_state` of one real attributable into ``out`` (6,)."""
    ce, se, ca, sa = math.cos(el), math.sin(el), math.cos(az), math.sin(az)
    u0, u1, u2 = ce * sa, ce * ca, se
    a0, a1, a2 = ce * ca, -ce * sa, 0.0
    e0, e1, e2 = -se * sa, -se * ca, ce
    l0, l1, l2 = rho * u0, rho * u1, rho * u2
    d0 = rd * u0 + rho * (azd * a0 + eld * e0)
    d1 = rd * u1 + rho * (azd * a1 + eld * e1)
    d2 = rd * u2 + rho * (azd * a2 + eld * e2)
    for j in range(3):
        out[j] = s[j] + _mul_m(l0, l1, l2, M, j)
    wx, wy = omega * -out[1], omega * out[0]
    out[3] = _mul_m(d0, d1, d2, M, 0) + wx
    out[4] = _mul_m(d0, d1, d2, M, 1) + wy
    out[5] = _mul_m(d0, d1, d2, M, 2) + 0.0


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _jacobian(rho, az, el, rd, azd, eld, M, omega, J):
    """``∂x/∂y`` (6, 6) of :func:`_state` at one attributable, in closed form (rows: state, columns: ``y``)."""
    ce, se, ca, sa = math.cos(el), math.sin(el), math.cos(az), math.sin(az)
    u = (ce * sa, ce * ca, se)
    u_a = (ce * ca, -ce * sa, 0.0)
    u_e = (-se * sa, -se * ca, ce)
    u_aa = (-ce * sa, -ce * ca, 0.0)
    u_ae = (-se * ca, se * sa, 0.0)
    u_ee = (-ce * sa, -ce * ca, -se)
    # columns of ∂l/∂y and ∂l̇/∂y in the local frame
    dl = np.zeros((6, 3))
    dld = np.zeros((6, 3))
    for k in range(3):
        dl[0, k] = u[k]
        dl[1, k] = rho * u_a[k]
        dl[2, k] = rho * u_e[k]
        dld[0, k] = azd * u_a[k] + eld * u_e[k]
        dld[1, k] = rd * u_a[k] + rho * (azd * u_aa[k] + eld * u_ae[k])
        dld[2, k] = rd * u_e[k] + rho * (azd * u_ae[k] + eld * u_ee[k])
        dld[3, k] = u[k]
        dld[4, k] = rho * u_a[k]
        dld[5, k] = rho * u_e[k]
    for c in range(6):
        r0 = dl[c, 0] * M[0, 0] + dl[c, 1] * M[1, 0] + dl[c, 2] * M[2, 0]
        r1 = dl[c, 0] * M[0, 1] + dl[c, 1] * M[1, 1] + dl[c, 2] * M[2, 1]
        r2 = dl[c, 0] * M[0, 2] + dl[c, 1] * M[1, 2] + dl[c, 2] * M[2, 2]
        J[0, c], J[1, c], J[2, c] = r0, r1, r2
        J[3, c] = dld[c, 0] * M[0, 0] + dld[c, 1] * M[1, 0] + dld[c, 2] * M[2, 0] - omega * r1
        J[4, c] = dld[c, 0] * M[0, 1] + dld[c, 1] * M[1, 1] + dld[c, 2] * M[2, 1] + omega * r0
        J[5, c] = dld[c, 0] * M[0, 2] + dld[c, 1] * M[1, 2] + dld[c, 2] * M[2, 2]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _pairwise(a, n):
    """``np.sum`` of ``a[:n]`` (contiguous, ``n ≤ 128``): numpy's pairwise sum, eight running sums."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[i]
        return res
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - (n % 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return res


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _plausible(x, mu, mu2, floor):
    """:func:`~...models.plausibility.plausible_orbits` of one state, operation for operation."""
    rx, ry, rz, vx, vy, vz = x[0], x[1], x[2], x[3], x[4], x[5]
    ep = 0.5 * ((vx * vx + vy * vy) + vz * vz) - mu / np.sqrt((rx * rx + ry * ry) + rz * rz)
    hx, hy, hz = ry * vz - rz * vy, rz * vx - rx * vz, rx * vy - ry * vx
    h2 = (hx * hx + hy * hy) + hz * hz
    t = 1.0 + 2.0 * ep * h2 / mu2
    if t <= 0.0:
        t = 0.0
    return ep < 0.0 and h2 / (mu * (1.0 + np.sqrt(t))) >= floor


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _linspace(a, N, out):
    """``np.linspace(−a, a, N + 1)``: ``k·step + start``, the last point ``a`` itself."""
    start, stop = -a, a
    delta = stop - start
    step = delta / N
    for k in range(N + 1):
        out[k] = (k / N) * delta + start if step == 0.0 else k * step + start
    out[N] = stop


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _components(Z, s, M, R, omega, mu_earth, mu, mu2, floor, nb, c, spread):
    m = Z.shape[0]
    N = nb * c
    x, b0, b1, b2 = np.empty(6), np.empty(6), np.empty(6), np.empty(6)
    a_edges, e_edges = np.empty(N + 1), np.empty(N + 1)
    ac, ec = np.empty(N), np.empty(N)
    corner = np.empty((N + 1, N + 1), dtype=np.bool_)
    ok = np.empty((N, N), dtype=np.bool_)
    cap = m * nb * nb
    w_out, means, covs = np.empty(cap), np.empty((cap, 6)), np.empty((cap, 6, 6))
    owner = np.empty(cap, dtype=np.int64)
    cnts = np.empty(cap)
    fa, fe, fo = np.empty(c * c), np.empty(c * c), np.empty(c * c)
    J, JC, Cy = np.empty((6, 6)), np.empty((6, 6)), np.zeros((6, 6))
    for a in range(4):
        for b in range(4):
            Cy[a, b] = R[a, b]
    K = 0
    for q in range(m):
        rho, az, el, rd = Z[q, 0], Z[q, 1], Z[q, 2], Z[q, 3]
        # step 2: the rate box of the return
        _state(rho, az, el, rd, 0.0, 0.0, s, M, omega, x)
        rn = np.sqrt((x[0] * x[0] + x[1] * x[1]) + x[2] * x[2])
        V2 = (np.sqrt(2 * mu_earth / rn) + omega * math.hypot(x[0], x[1])) ** 2 - rd ** 2
        V = np.sqrt(V2 if V2 > 0.0 else 0.0)
        a_max = V / (rho * max(np.cos(el), 1e-6))
        e_max = V / rho
        # step 3: the grid, each cell's state affine in its rates
        _linspace(a_max, N, a_edges)
        _linspace(e_max, N, e_edges)
        for k in range(N):
            ac[k] = (a_edges[k] + a_edges[k + 1]) / 2
            ec[k] = (e_edges[k] + e_edges[k + 1]) / 2
        _state(rho, az, el, rd, 1.0, 0.0, s, M, omega, b1)
        _state(rho, az, el, rd, 0.0, 1.0, s, M, omega, b2)
        for j in range(6):
            b0[j] = x[j]
        for i in range(N + 1):
            for j in range(N + 1):
                for t in range(3):
                    x[3 + t] = (b0[3 + t] + a_edges[i] * (b1[3 + t] - b0[3 + t])) + e_edges[j] * (b2[3 + t] - b0[3 + t])
                corner[i, j] = _plausible(x, mu, mu2, floor)
        for i in range(N):
            for j in range(N):
                for t in range(3):
                    x[3 + t] = (b0[3 + t] + ac[i] * (b1[3 + t] - b0[3 + t])) + ec[j] * (b2[3 + t] - b0[3 + t])
                ok[i, j] = (_plausible(x, mu, mu2, floor) and corner[i, j] and corner[i + 1, j] and corner[i, j + 1]
                            and corner[i + 1, j + 1])
        # step 4: one component per block with an admissible cell
        first = K
        cell_a = (2 * a_max / N) ** 2 / 12.0
        cell_e = (2 * e_max / N) ** 2 / 12.0
        for bi in range(nb):
            for bj in range(nb):
                n_ok = 0
                for ci in range(c):
                    for cj in range(c):
                        f = 1.0 if ok[bi * c + ci, bj * c + cj] else 0.0
                        fo[ci * c + cj] = f
                        n_ok += int(f)
                if n_ok == 0:
                    continue
                cnt = _pairwise(fo, c * c)
                for ci in range(c):
                    for cj in range(c):
                        fa[ci * c + cj] = ac[bi * c + ci] * fo[ci * c + cj]
                        fe[ci * c + cj] = ec[bj * c + cj] * fo[ci * c + cj]
                mu_a = _pairwise(fa, c * c) / cnt
                mu_e = _pairwise(fe, c * c) / cnt
                for ci in range(c):
                    for cj in range(c):
                        k = ci * c + cj
                        da = (ac[bi * c + ci] - mu_a) * fo[k]
                        de = (ec[bj * c + cj] - mu_e) * fo[k]
                        fa[k], fe[k], fo[k] = da * da, de * de, da * de
                Cy[4, 4] = (_pairwise(fa, c * c) / cnt + cell_a) * spread ** 2
                Cy[5, 5] = (_pairwise(fe, c * c) / cnt + cell_e) * spread ** 2
                Cy[4, 5] = Cy[5, 4] = _pairwise(fo, c * c) / cnt * spread ** 2
                # step 5: the component in the state space
                _state(rho, az, el, rd, mu_a, mu_e, s, M, omega, means[K])
                _jacobian(rho, az, el, rd, mu_a, mu_e, M, omega, J)
                for a in range(6):
                    for b in range(6):
                        acc = 0.0
                        for t in range(6):
                            acc = _fma(J[a, t], Cy[t, b], acc)
                        JC[a, b] = acc
                for a in range(6):
                    for b in range(6):
                        acc = 0.0
                        for t in range(6):
                            acc = _fma(JC[a, t], J[b, t], acc)
                        covs[K, a, b] = acc
                for a in range(6):
                    for b in range(a, 6):
                        v = 0.5 * (covs[K, a, b] + covs[K, b, a])
                        covs[K, a, b] = v
                        covs[K, b, a] = v
                cnts[K] = cnt
                owner[K] = q
                K += 1
        total = 0.0
        for k in range(first, K):
            total += cnts[k]
        for k in range(first, K):
            w_out[k] = cnts[k] / total
    return w_out[:K].copy(), means[:K].copy(), covs[:K].copy(), owner[:K].copy()


def admissible_components(Z, site_teme, M, R, omega, mu_earth, mu, floor, n_blocks, cells, spread):
    """``(weights (K,), means (K, 6), covs (K, 6, 6), owner (K,))`` of the admissible-region mixtures of returns
    ``Z`` (m, 4) (module docstring; :meth:`~.admissible.AdmissibleRegionBirth.components_batch`'s result): the site's
    TEME position ``site_teme``, ``M = E R3(θ)``, the returns' noise ``R``, the Earth's rotation ``omega``, the
    ``mu_earth`` of the rate box and the ``mu`` and perigee radius ``floor`` of the plausibility test, the grid
    (``n_blocks``, ``cells``) and ``spread``."""
    f = np.ascontiguousarray
    return _components(f(Z, dtype=float), f(site_teme, dtype=float), f(M, dtype=float), f(R, dtype=float),
                       float(omega), float(mu_earth), float(mu), float(mu) ** 2, float(floor), int(n_blocks), int(cells),
                       float(spread))

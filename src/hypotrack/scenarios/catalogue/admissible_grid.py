"""Steps 3–4 of the admissible-region birth (:mod:`.admissible`) for many returns in one compiled pass.

:meth:`.admissible.AdmissibleRegionBirth.components_batch` tests every corner and centre of every return's
``N × N`` rate grid with :func:`hypotrack.models.plausibility.plausible_orbits` and sums each block's admissible
cells. In numpy that is ``(m, (N + 1)² + N², 6)`` states and a dozen temporaries of that size: ~55 µs per return
at the catalogue's ``N = 24``, most of it memory traffic. :func:`block_sums` does the same arithmetic point by
point, and **the same operations in the same order**, so it gives the same bits:

* a grid state is ``x(z, 0, 0) + α̇ (x(z, 1, 0) − x(z, 0, 0)) + ε̇ (x(z, 0, 1) − x(z, 0, 0))`` (step 1 is affine
  in the rates; numpy evaluates ``(b₀ + α̇ d₁) + ε̇ d₂`` left to right);
* its verdict is :func:`~hypotrack.models.plausibility._energy_perigee`'s expressions, parenthesised as numpy
  evaluates them (``((x² + y²) + z²)``, ``((2 ε) h²) / μ²``, ...; only ``+ − × ÷ √``, each correctly rounded, and
  no fused multiply-add: numba does not contract without ``fastmath``); the position terms (``μ/|r|``) are the
  same for every rate of one return and computed once;
* a block's sums ``Σ α̇ ok``, ``Σ ok``, ``Σ (α̇ − μ_α) ok (ε̇ − μ_ε) ok``, ... are numpy's pairwise summation of the
  block's ``cells²`` products in row-major order (:func:`_pairwise`: numpy's ``pairwise_sum``, eight partial sums
  up to 128 terms, halves beyond), which is what ``np.sum(·, axis=(1, 2))`` of a C-ordered ``(K, c, c)`` array
  does. (The numpy construction's ``Σ d_ε²`` is not always C-ordered: its operands' memory layout, which numpy
  picks by heuristics, turns it column-major past ~512 components in a batch, so that construction's values
  already depended on the batch to rounding. Here every sum is row-major, whatever the batch.)

The verdicts and counts are therefore exactly numpy's, and the sums the same bits wherever numpy's operands are
C-ordered (else equal to rounding, ~1e-16 relative); the tests compare with the numpy construction on the catalogue's returns
and on random grids (``tests/unit/scenarios/catalogue/test_admissible_grid.py``).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["block_sums", "segment_sums"]


@numba.njit(cache=True, nogil=True)
def _pairwise_leaf(a, s, n):
    """numpy's ``pairwise_sum`` of ``a[s:s + n]`` for ``n <= 128``: one sum below 8 terms, else eight partial sums."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[s + i]
        return res
    r0, r1, r2, r3 = a[s], a[s + 1], a[s + 2], a[s + 3]
    r4, r5, r6, r7 = a[s + 4], a[s + 5], a[s + 6], a[s + 7]
    i = 8
    while i < n - n % 8:
        r0 += a[s + i]
        r1 += a[s + i + 1]
        r2 += a[s + i + 2]
        r3 += a[s + i + 3]
        r4 += a[s + i + 4]
        r5 += a[s + i + 5]
        r6 += a[s + i + 6]
        r7 += a[s + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[s + i]
        i += 1
    return res


@numba.njit(cache=True, nogil=True)
def _pairwise(a, s, n):
    """numpy's ``pairwise_sum`` of ``a[s:s + n]`` (module docstring): the order numpy adds a reduction's terms in.
    Past 128 terms numpy adds the sums of two halves (the first a multiple of 8 long), recursively; here the same
    tree walked with an explicit stack (a cached numba function must not recurse)."""
    if n <= 128:
        return _pairwise_leaf(a, s, n)
    fs, fn, expanded = np.empty(64, np.int64), np.empty(64, np.int64), np.zeros(64, np.bool_)
    vals = np.empty(64)
    top, nv = 0, 0
    fs[0], fn[0] = s, n
    while top >= 0:
        if expanded[top]:  # both halves summed, the left below the right: their sum
            nv -= 1
            vals[nv - 1] = vals[nv - 1] + vals[nv]
            top -= 1
        elif fn[top] <= 128:
            vals[nv] = _pairwise_leaf(a, fs[top], fn[top])
            nv += 1
            top -= 1
        else:
            expanded[top] = True
            n2 = fn[top] // 2
            n2 -= n2 % 8
            fs[top + 1], fn[top + 1], expanded[top + 1] = fs[top] + n2, fn[top] - n2, False  # the right half
            fs[top + 2], fn[top + 2], expanded[top + 2] = fs[top], n2, False  # the left half, on top: first
            top += 2
    return vals[0]


@numba.njit(cache=True, nogil=True, inline="always")
def _plausible(rx, ry, rz, mu_r, vx, vy, vz, mu, mu2, rp_min):
    """``plausible_orbits`` of one state (``mu_r = μ / |r|`` of its position), the expressions of ``_energy_perigee``."""
    eps = 0.5 * ((vx * vx + vy * vy) + vz * vz) - mu_r
    if not eps < 0:  # (the perigee cannot make it plausible)
        return False
    hx, hy, hz = ry * vz - rz * vy, rz * vx - rx * vz, rx * vy - ry * vx
    h2 = (hx * hx + hy * hy) + hz * hz
    q = 1.0 + 2.0 * eps * h2 / mu2
    if q < 0.0:  # np.maximum(0.0, q) (a NaN stays NaN)
        q = 0.0
    return h2 / (mu * (1.0 + np.sqrt(q))) >= rp_min


@numba.njit(cache=True, nogil=True)
def block_sums(base, a_edges, e_edges, ac, ec, n_blocks, cells, mu, mu2, rp_min):
    """Each block's admissible-cell sums for returns ``m`` (module docstring).

    Parameters
    ----------
    base : (m, 3, 6) float
        ``x(z, 0, 0)``, ``x(z, 1, 0)``, ``x(z, 0, 1)`` of each return (TEME states at unit angle rates).
    a_edges, e_edges : (m, N + 1) float
        Cell edges of each return's azimuth- and elevation-rate axes (``N = n_blocks · cells``).
    ac, ec : (m, N) float
        Cell centres.
    mu, mu2, rp_min : float
        ``μ``, ``μ ** 2`` (as Python computes it) and the perigee floor radius ``R_E + h_min`` (km).

    Returns
    -------
    sums : (m, n_blocks, n_blocks, 6) float
        Per block: ``Σ ok``, ``Σ α̇ ok``, ``Σ ε̇ ok``, ``Σ d_α²``, ``Σ d_ε²``, ``Σ d_α d_ε`` with
        ``d_α = (α̇ − μ_α) ok``, ``μ_α = Σ α̇ ok / Σ ok`` (zeros for a block with no admissible cell).
    """
    m = base.shape[0]
    N = n_blocks * cells
    cc = cells * cells
    out = np.zeros((m, n_blocks, n_blocks, 6))
    corner = np.empty((N + 1, N + 1), dtype=np.bool_)
    ok = np.empty((N, N), dtype=np.bool_)
    buf = np.empty((6, cc))
    for r in range(m):
        rx, ry, rz = base[r, 0, 0], base[r, 0, 1], base[r, 0, 2]
        mu_r = mu / np.sqrt((rx * rx + ry * ry) + rz * rz)
        b0x, b0y, b0z = base[r, 0, 3], base[r, 0, 4], base[r, 0, 5]
        d1x, d1y, d1z = base[r, 1, 3] - b0x, base[r, 1, 4] - b0y, base[r, 1, 5] - b0z
        d2x, d2y, d2z = base[r, 2, 3] - b0x, base[r, 2, 4] - b0y, base[r, 2, 5] - b0z
        for i in range(N + 1):
            a = a_edges[r, i]
            for j in range(N + 1):
                e = e_edges[r, j]
                corner[i, j] = _plausible(rx, ry, rz, mu_r, (b0x + a * d1x) + e * d2x, (b0y + a * d1y) + e * d2y,
                                          (b0z + a * d1z) + e * d2z, mu, mu2, rp_min)
        for i in range(N):
            a = ac[r, i]
            for j in range(N):
                if corner[i, j] and corner[i + 1, j] and corner[i, j + 1] and corner[i + 1, j + 1]:
                    e = ec[r, j]
                    ok[i, j] = _plausible(rx, ry, rz, mu_r, (b0x + a * d1x) + e * d2x, (b0y + a * d1y) + e * d2y,
                                          (b0z + a * d1z) + e * d2z, mu, mu2, rp_min)
                else:
                    ok[i, j] = False
        for bi in range(n_blocks):
            for bj in range(n_blocks):
                n_ok = 0
                for p in range(cells):
                    for q in range(cells):
                        w = 1.0 if ok[bi * cells + p, bj * cells + q] else 0.0
                        n_ok += int(w)
                        buf[0, p * cells + q] = w
                        buf[1, p * cells + q] = ac[r, bi * cells + p] * w
                        buf[2, p * cells + q] = ec[r, bj * cells + q] * w
                if n_ok == 0:
                    continue
                cnt = _pairwise(buf[0], 0, cc)
                sa, se = 0.0 + _pairwise(buf[1], 0, cc), 0.0 + _pairwise(buf[2], 0, cc)
                mu_a, mu_e = sa / cnt, se / cnt
                for p in range(cells):
                    for q in range(cells):
                        w = buf[0, p * cells + q]
                        da = (ac[r, bi * cells + p] - mu_a) * w
                        de = (ec[r, bj * cells + q] - mu_e) * w
                        buf[3, p * cells + q] = da * da
                        buf[4, p * cells + q] = de * de
                        buf[5, p * cells + q] = da * de
                out[r, bi, bj, 0] = cnt
                out[r, bi, bj, 1], out[r, bi, bj, 2] = sa, se
                for k in range(3, 6):
                    out[r, bi, bj, k] = 0.0 + _pairwise(buf[k], 0, cc)
    return out


@numba.njit(cache=True, nogil=True)
def segment_sums(values, cut):
    """``values[cut[i]:cut[i + 1]].sum()`` for each ``i`` as numpy sums them (:func:`_pairwise`: the same bits)."""
    out = np.empty(len(cut) - 1)
    for i in range(len(cut) - 1):
        out[i] = 0.0 + _pairwise(values, cut[i], cut[i + 1] - cut[i])
    return out

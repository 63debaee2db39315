"""The birth likelihoods' band test in one compiled pass (:func:`band_pairs_compiled`, for :func:`.births.band_pairs`).

Per birth term ``b`` the returns of its band on the first component (``order[lo[b]:hi[b]]``, :mod:`.births`) are
tested on every component's bound ``|ν_i| ≤ half[b, i]`` with the residual ``ν = z − ẑ_b`` of
:meth:`~...models.measurement.ExtendedMeasurement.residual`: a plain difference, the ``wrapped`` components into
``[−π, π)`` as :func:`~...models.measurement.wrap_pi` wraps them — numpy's floating remainder
``(ν + π) mod 2π − π`` (``fmod``, then ``+ 2π`` when its sign differs from ``2π``'s, a zero remainder ``+0``), the
same IEEE operations, so every residual and every decision is the array passes' own, bit for bit. In array passes
that is ~10 numpy calls per term with returns in its band (the catalogue's admissible-region terms: most of them,
every scan).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["band_pairs_compiled"]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _band(Z, order, lo, hi, z_pred, half, wrapped):
    B, p = z_pred.shape
    n_max = 0
    for b in range(B):
        if hi[b] > lo[b]:
            n_max += hi[b] - lo[b]
    terms = np.empty(B, np.int64)
    starts = np.zeros(B + 1, np.int64)
    rows = np.empty(n_max, np.int64)
    resid = np.empty((n_max, p))
    two_pi = 2.0 * np.pi
    n_terms, n = 0, 0
    for b in range(B):
        first = n
        for q in range(lo[b], hi[b]):
            r = order[q]
            ok = True
            for k in range(p):
                v = Z[r, k] - z_pred[b, k]
                if wrapped[k]:
                    x = v + np.pi
                    m = np.fmod(x, two_pi)  # numpy's floating remainder (npy_divmod)
                    if m != 0.0:
                        if m < 0.0:
                            m += two_pi
                    else:
                        m = 0.0
                    v = m - np.pi
                resid[n, k] = v
                if not abs(v) <= half[b, k]:
                    ok = False
            if ok:
                rows[n] = r
                n += 1
        if n > first:
            terms[n_terms] = b
            n_terms += 1
            starts[n_terms] = n
    return terms[:n_terms], starts[:n_terms + 1], rows[:n], resid[:n]


def band_pairs_compiled(Z, order, lo, hi, z_pred, half, wrapped):
    """``(terms, starts, rows, resid)``: the terms with a return passing the bound (ascending), the start of each
    one's rows in ``rows``/``resid`` (``starts[t]:starts[t + 1]``), the returns (band order) and their residuals."""
    f = np.ascontiguousarray
    return _band(f(Z, dtype=float), f(order, dtype=np.int64), f(lo, dtype=np.int64), f(hi, dtype=np.int64),
                 f(z_pred, dtype=float), f(half, dtype=float), f(wrapped, dtype=np.bool_))

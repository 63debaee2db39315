"""A certificate that an innovation covariance is well conditioned, so :func:`~.planner.scorable` skips its
eigenvalues (``numpy.linalg.eigvalsh``, ~1 µs a matrix: at scale a tenth of a millisecond a scan, for the ~100
tracks in view whose covariances are all far from singular).

For ``C = D^-1/2 S D^-1/2`` (unit diagonal) with Cholesky pivots ``d_k > 0``, ``det C = Π d_k``, ``λ_max ≤ ‖C‖_F``
and ``λ_min ≥ det C / λ_max^(p−1)``, so ``cond C ≤ ‖C‖_F^p / det C``. A matrix whose bound is below
:data:`CERTIFIED_CONDITION` (1e7, three orders under the scan's limit 1e10) passes the eigenvalue test whatever the
rounding: Cholesky's pivots and LAPACK's eigenvalues are exact for matrices within a few ulps of ``C``, which moves a
condition number of 1e7 by ~1e-8 of itself. Every other matrix (a pivot ≤ 0, a larger bound) goes to
``eigvalsh`` as before, so the verdicts are those of the eigenvalues alone, bit for bit. A certified matrix also
passes :func:`~.planner.scorable`'s Cholesky test: LAPACK's factorisation of ``S = D^1/2 C D^1/2`` completes when
``λ_min(C)`` exceeds ~``p² ε`` (Demmel 1989, Cholesky's error bounds are invariant under diagonal scaling), and
certified, ``λ_min(C) ≥ ‖C‖_F / 1e7 ≥ 1e-7``; so a scan whose matrices are all certified skips that call too."""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["CERTIFIED_CONDITION", "certify"]

#: The condition-number bound below which a scaled innovation covariance needs no eigenvalues (module docstring).
CERTIFIED_CONDITION = 1e7


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _certify(S, bound):
    """Per matrix of ``S`` (n, p, p): 0 not finite or a diagonal entry not positive (not scorable), 1 certified
    (condition bound below ``bound``), 2 undecided (the eigenvalues decide)."""
    n, p = S.shape[0], S.shape[1]
    out = np.empty(n, np.int8)
    C = np.empty((p, p))
    s = np.empty(p)
    for i in range(n):
        st = 1
        for a in range(p):
            for b in range(p):
                if not math.isfinite(S[i, a, b]):
                    st = 0
        for a in range(p):
            if not S[i, a, a] > 0:
                st = 0
        if st == 0:
            out[i] = 0
            continue
        for a in range(p):
            s[a] = 1.0 / math.sqrt(S[i, a, a])
        f2 = 0.0
        for a in range(p):
            for b in range(p):
                C[a, b] = S[i, a, b] * s[a] * s[b]
                f2 += C[a, b] * C[a, b]
        det = 1.0
        for k in range(p):  # Cholesky in place (lower), its pivots' product the determinant
            v = C[k, k]
            for j in range(k):
                v -= C[k, j] * C[k, j]
            if not v > 0:
                st = 2
                break
            det *= v
            r = math.sqrt(v)
            C[k, k] = r
            for a in range(k + 1, p):
                w = C[a, k]
                for j in range(k):
                    w -= C[a, j] * C[k, j]
                C[a, k] = w / r
        if st == 1 and not math.sqrt(f2) ** p < bound * det:
            st = 2
        out[i] = st
    return out


def certify(S) -> np.ndarray:
    """:func:`_certify` of ``S`` (n, p, p) with :data:`CERTIFIED_CONDITION`: 0 not scorable, 1 certified, 2 undecided."""
    return _certify(np.ascontiguousarray(S, dtype=float), CERTIFIED_CONDITION)

"""Ellipsoidal (chi-square) gating and the validation matrix.

A return ``z_i`` lies in track ``j``'s gate when its squared Mahalanobis distance
``d²_ij = (z_i − ẑ_j)ᵀ S_j⁻¹ (z_i − ẑ_j)`` does not exceed ``γ``, the ``p_gate`` quantile of a
chi-square distribution with ``dim`` degrees of freedom (under the track's predictive density
``d²`` is χ²-distributed, so a true return falls inside with probability ``P_G = p_gate``).
The gate results form the validation matrix of paper 004 ("Gating"): rows are returns,
columns tracks.

References
----------
Bar-Shalom, Willett & Tian, *Tracking and Data Fusion* (2011), §2.3 (validation regions);
paper 004 (lecture notes), "Gating" and "Validation Matrix".
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.special import gammaincinv

from .._validation import (
    check_covariance,
    check_finite_array,
    check_int,
    check_measurements,
    check_positive,
    check_probability,
)
from ..gaussian import mahalanobis2_matrix

__all__ = ["gate_threshold", "validation_matrix", "gate_measurements", "box_candidates"]


def gate_threshold(p_gate: float, dim: int) -> float:
    """Gate size ``γ`` with ``P(χ²_dim ≤ γ) = p_gate``.

    Parameters
    ----------
    p_gate : float
        Gate probability ``P_G`` in (0, 1]; ``1`` gives ``inf`` (no gating).
    dim : int
        Measurement dimension, ``>= 1``.

    Returns
    -------
    float
        The threshold on the squared Mahalanobis distance, e.g. 9.21 for ``p_gate=0.99, dim=2``.
    """
    p = check_probability(p_gate, "p_gate", low_open=True)
    d = check_int(dim, "dim", minimum=1)
    return math.inf if p == 1.0 else _chi2_quantile(p, d)


@lru_cache(maxsize=256)
def _chi2_quantile(p: float, d: int) -> float:
    # asked for by every track set, birth term and scan (SciPy's ppf costs ~0.3 ms a call): computed once each
    # chi2.ppf's own formula (scipy.stats._continuous_distns.chi2_gen._ppf), bit for bit; scipy.special
    # alone keeps scipy.stats (~1 s) out of every import of the association package
    return float(2.0 * gammaincinv(d / 2.0, p))


def validation_matrix(d2, threshold: float) -> np.ndarray:
    """Validation matrix ``V[i, j] = d2[i, j] <= threshold``.

    Parameters
    ----------
    d2 : (m, n) array_like
        Squared Mahalanobis distances of returns (rows) to tracks (columns), as returned by
        :func:`hypotrack.gaussian.mahalanobis2_matrix`; ``+inf`` is allowed (never gated).
    threshold : float
        Gate size ``γ > 0`` (may be ``inf``), e.g. from :func:`gate_threshold`.

    Returns
    -------
    (m, n) ndarray of bool
    """
    arr = np.asarray(d2, dtype=float)
    if arr.ndim != 2:
        raise ValueError(f"d2 must be a 2-D (m, n) array, got shape {arr.shape}")
    if np.isnan(arr).any() or (arr < 0).any():
        raise ValueError("d2 must hold squared distances: >= 0 and not NaN")
    # An infinite gate (p_gate = 1) is legitimate; every other threshold must be finite and > 0.
    is_inf = isinstance(threshold, (float, np.floating)) and threshold == math.inf
    gamma = math.inf if is_inf else check_positive(threshold, "threshold")
    return arr <= gamma


def gate_measurements(Z, z_pred, S, p_gate: float) -> tuple[np.ndarray, np.ndarray]:
    """Gate a scan against ``n`` tracks' predicted measurements.

    Parameters
    ----------
    Z : (m, p) array_like
        The scan (``m = 0`` allowed).
    z_pred : (n, p) array_like
        Predicted measurements ``ẑ_j = H x̂_j⁻`` (``n = 0`` allowed).
    S : (n, p, p) array_like
        Innovation covariances, symmetric positive definite.
    p_gate : float
        Gate probability in (0, 1].

    Returns
    -------
    validation : (m, n) ndarray of bool
    d2 : (m, n) ndarray
        The squared Mahalanobis distances the gate was applied to.
    """
    z_pred = check_finite_array(z_pred, "z_pred", ndim=2)
    n, p = z_pred.shape
    Z = check_measurements(Z, "Z", p)
    if n:
        S = check_covariance(S, "S", p, batched=True)
        if S.shape[0] != n:
            raise ValueError(f"S must have shape ({n}, {p}, {p}) to match z_pred, got {S.shape}")
    else:
        S = np.zeros((0, p, p))
    gamma = gate_threshold(p_gate, p)
    d2, _ = mahalanobis2_matrix(Z, z_pred, S)
    return validation_matrix(d2, gamma), d2


def box_candidates(Z, z_pred, half, residual_rows) -> tuple[np.ndarray, np.ndarray]:
    """``(rows, cols)`` of the (return, track) pairs whose every innovation component lies within the track's
    half-widths: ``|ν_a| ≤ half[j, a]`` with ``ν = residual_rows(Z[i], z_pred[j])``, rows sorted by the first
    component within each track (tracks in order).

    With ``half[j, a] = √(γ S_j,aa)`` (a margin for rounding) every pair in the gate ``νᵀ S⁻¹ ν ≤ γ`` is among them:
    ``νᵀ S⁻¹ ν ≥ ν_a² / S_aa`` for every component (Cauchy–Schwarz in the ``S⁻¹`` inner product). The first
    component's band is found by binary search on the sorted returns, the others checked on the band's pairs, so
    the cost is that of the band's pairs, not of all ``m n``. ``residual_rows`` may wrap angles; the band uses
    the first component's plain difference, so that component must not be an angle.
    """
    half = np.asarray(half, dtype=float)
    order = np.argsort(Z[:, 0], kind="stable")
    z0 = Z[order, 0]
    lo = np.searchsorted(z0, z_pred[:, 0] - half[:, 0], side="left")
    cnt = np.maximum(np.searchsorted(z0, z_pred[:, 0] + half[:, 0], side="right") - lo, 0)
    k = np.repeat(np.arange(len(z_pred)), cnt)  # candidate pairs: each track's band of returns
    r = order[lo[k] + np.arange(len(k)) - np.repeat(np.cumsum(cnt) - cnt, cnt)]
    box = np.all(np.abs(residual_rows(Z[r], z_pred[k])) <= half[k], axis=1)
    return r[box].astype(np.int64), k[box].astype(np.int64)

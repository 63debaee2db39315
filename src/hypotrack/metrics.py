"""Multi-target miss distances: OSPA and GOSPA.

Both compare two finite sets of points, ``X`` (estimates) and ``Y`` (ground truth), with a
cut-off ``c > 0`` on the base (Euclidean) distance and an order ``p >= 1``:

* OSPA (Schuhmacher, Vo & Vo 2008, Eq. 3), for ``|X| = m <= n = |Y|`` (else swap):
  ``d_p^(c)(X, Y) = ( (min_π Σ_{i≤m} min(d(x_i, y_π(i)), c)^p + c^p (n − m)) / n )^(1/p)``,
  ``0`` for two empty sets, and for ``p = ∞`` the bottleneck ``min_π max_i min(d, c)`` when
  ``m = n`` and ``c`` otherwise.
* GOSPA (Rahmathullah, García-Fernández & Svensson 2017), with ``α = 2`` written as an
  assignment problem: ``( min_γ Σ_{(i,j)∈γ} d(x_i, y_j)^p + c^p/2 (|X| + |Y| − 2|γ|) )^(1/p)``
  over partial assignments γ. It splits into localisation (assigned pairs), missed targets
  (unassigned truths) and false targets (unassigned estimates).

Both optimisations are solved by one :func:`scipy.optimize.linear_sum_assignment` on
``min(d, c)^p``. Assigning on ``min(d, c)`` instead (as some implementations do) gives a
wrong permutation for ``p > 1``, because the sum of p-th powers and the sum of distances need not
share a minimiser.

References
----------
D. Schuhmacher, B.-T. Vo & B.-N. Vo, "A consistent metric for performance evaluation of
multi-object filters", IEEE Trans. Signal Processing 56(8), 2008.
A. S. Rahmathullah, Á. F. García-Fernández & L. Svensson, "Generalized optimal sub-pattern
assignment metric", FUSION 2017.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.sparse import csr_array
from scipy.sparse.csgraph import maximum_bipartite_matching
from scipy.spatial.distance import cdist

from ._validation import check_positive

__all__ = ["GospaResult", "ospa", "gospa", "ospa_series"]


@dataclass(frozen=True)
class GospaResult:
    """GOSPA value and its decomposition.

    For finite ``p`` the parts add up to the p-th power of the value:
    ``localisation + missed + false == value**p``. For ``p = inf`` they are the limits of
    their p-th roots and combine by maximum: ``value == max(localisation, missed, false)``.

    Attributes
    ----------
    value : float
        The GOSPA distance.
    localisation : float
        ``Σ d(x_i, y_j)^p`` over the assigned pairs (``p = inf``: their largest distance).
    missed : float
        ``c^p/α`` per ground-truth point left unassigned (``p = inf``: ``c`` if any).
    false : float
        ``c^p/α`` per estimate left unassigned (``p = inf``: ``c`` if any).
    assignment : (k, 2) ndarray of int
        Assigned pairs ``(i, j)``: estimate ``X[i]`` matched with truth ``Y[j]``.
    n_missed, n_false : int
        Numbers of unassigned truths and estimates.
    """

    value: float
    localisation: float
    missed: float
    false: float
    assignment: np.ndarray
    n_missed: int
    n_false: int


def _check_order(p) -> float:
    if isinstance(p, bool) or not isinstance(p, (int, float, np.integer, np.floating)):
        raise TypeError(f"p must be a real number >= 1 or inf, got {type(p).__name__}")
    p = float(p)
    if not p >= 1:  # also rejects NaN
        raise ValueError(f"p must be >= 1 (or inf), got {p!r}")
    return p


def _check_sets(X, Y) -> tuple[np.ndarray, np.ndarray]:
    """Both sets as (k, d) arrays; a 1-D input is a set of scalars, an empty input has k = 0."""
    arrays = []
    for name, S in (("X", X), ("Y", Y)):
        arr = np.asarray(S, dtype=float)
        if arr.size == 0:
            arr = arr.reshape(0, arr.shape[-1] if arr.ndim == 2 else 0)
        elif arr.ndim == 1:
            arr = arr[:, None]
        if arr.ndim != 2:
            raise ValueError(f"{name} must be an (n, d) array of points, got shape {np.shape(S)}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite (no NaN or inf)")
        arrays.append(arr)
    X, Y = arrays
    if X.shape[0] and Y.shape[0] and X.shape[1] != Y.shape[1]:
        raise ValueError(f"X and Y must have points of the same dimension, got {X.shape[1]} and {Y.shape[1]}")
    return X, Y


def _cut_distances(X: np.ndarray, Y: np.ndarray, c: float) -> np.ndarray:
    if X.shape[0] == 0 or Y.shape[0] == 0:
        return np.zeros((X.shape[0], Y.shape[0]))
    return np.minimum(cdist(X, Y), c)


def _min_power_assignment(D: np.ndarray, p: float) -> tuple[np.ndarray, np.ndarray]:
    """Assignment of min(|X|, |Y|) pairs minimising Σ D^p (D already cut off at c)."""
    if D.size == 0:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty
    return linear_sum_assignment(D**p)


def _bottleneck_assignment(D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Assignment of min(|X|, |Y|) pairs minimising the largest D (the p = ∞ case).

    Binary search over the distinct entries of ``D`` for the smallest threshold whose
    ``D <= t`` graph still has a matching that saturates the smaller side.
    """
    if D.size == 0:
        empty = np.zeros(0, dtype=np.intp)
        return empty, empty
    transpose = D.shape[0] > D.shape[1]
    E = D.T if transpose else D  # rows = smaller side
    levels = np.unique(E)
    lo, hi = 0, levels.size - 1
    best = None
    while lo <= hi:
        mid = (lo + hi) // 2
        match = maximum_bipartite_matching(csr_array(E <= levels[mid]), perm_type="column")
        if np.all(match >= 0):
            best, hi = match, mid - 1
        else:
            lo = mid + 1
    rows = np.arange(E.shape[0])
    return (best, rows) if transpose else (rows, best)


def ospa(X, Y, c: float, p: float = 1.0) -> float:
    """Optimal sub-pattern assignment distance (Schuhmacher, Vo & Vo 2008).

    Parameters
    ----------
    X, Y : (n, d) and (m, d) array_like
        Point sets; either may be empty. A 1-D array is a set of scalars.
    c : float
        Cut-off, ``c > 0``: the distance charged for a cardinality error.
    p : float, optional
        Order, ``1 <= p <= inf``.

    Returns
    -------
    float
        In ``[0, c]``; ``0`` when both sets are empty, ``c`` when exactly one is.

    Examples
    --------
    >>> ospa([0.5, 1.5, 2.5, 3.5], [0, 1, 2, 3, 4], c=10, p=1)
    2.4

    (four pairs at 0.5, one point unpaired at ``c``: ``(4 × 0.5 + 10) / 5``). In the plane, a
    3-4-5 pair, and one empty set:

    >>> ospa([[0.0, 0.0]], [[3.0, 4.0]], c=10, p=2)
    5.0
    >>> ospa([[0.0, 0.0], [6.0, 8.0]], [[3.0, 4.0]], c=10, p=2) ** 2   # (5² + 10²) / 2
    62.5
    >>> ospa(np.zeros((0, 2)), [[1.0, 1.0]], c=10)
    10.0
    """
    X, Y = _check_sets(X, Y)
    c = check_positive(c, "c")
    p = _check_order(p)
    n = max(X.shape[0], Y.shape[0])
    k = min(X.shape[0], Y.shape[0])
    if n == 0:
        return 0.0
    if math.isinf(p):
        if k != n:
            return c
        D = _cut_distances(X, Y, c)
        rows, cols = _bottleneck_assignment(D)
        return float(D[rows, cols].max())
    D = _cut_distances(X, Y, c)
    rows, cols = _min_power_assignment(D, p)
    total = float(np.sum(D[rows, cols] ** p)) + c**p * (n - k)
    return (total / n) ** (1.0 / p)


def gospa(X, Y, c: float, p: float = 1.0, alpha: float = 2.0) -> GospaResult:
    """Generalised OSPA with its localisation / missed / false decomposition.

    Parameters
    ----------
    X : (n, d) array_like
        Estimated points (unassigned ones are *false* targets).
    Y : (m, d) array_like
        Ground-truth points (unassigned ones are *missed* targets).
    c : float
        Cut-off, ``c > 0``.
    p : float, optional
        Order, ``1 <= p <= inf``.
    alpha : float, optional
        Cardinality-mismatch weight in ``(0, 2]``. Only ``alpha = 2`` has the
        assignment-based decomposition: pairs at distance ``>= c`` are then left unassigned
        and charged as one missed plus one false target. For ``alpha < 2`` every one of the
        ``min(n, m)`` optimally paired points counts as assigned (at ``min(d, c)^p``) and only
        the surplus is missed or false, at ``c^p/alpha`` each.

    Returns
    -------
    GospaResult

    Examples
    --------
    >>> r = gospa([0.5, 1.5, 2.5, 3.5], [0, 1, 2, 3, 4], c=10, p=1)
    >>> r.value, r.localisation, r.missed, r.false
    (7.0, 2.0, 5.0, 0.0)

    (four pairs at 0.5; one missed truth point at ``c / α = 5``). In the plane, one estimate 5 from
    the truth and one false estimate, and a pair farther apart than ``c`` (one missed plus one false):

    >>> r = gospa([[0.0, 0.0], [30.0, 40.0]], [[3.0, 4.0]], c=10, p=1)
    >>> r.value, r.localisation, r.missed, r.false, r.assignment.tolist()
    (10.0, 5.0, 0.0, 5.0, [[0, 0]])
    >>> r = gospa([[30.0, 40.0]], [[0.0, 0.0]], c=10, p=2)
    >>> r.value ** 2, r.n_missed, r.n_false   # 10²/2 + 10²/2
    (100.0, 1, 1)
    """
    X, Y = _check_sets(X, Y)
    c = check_positive(c, "c")
    p = _check_order(p)
    if isinstance(alpha, bool) or not isinstance(alpha, (int, float, np.integer, np.floating)):
        raise TypeError(f"alpha must be a real number in (0, 2], got {type(alpha).__name__}")
    alpha = float(alpha)
    if not 0 < alpha <= 2:
        raise ValueError(f"alpha must lie in (0, 2], got {alpha!r}")
    D = _cut_distances(X, Y, c)
    rows, cols = _bottleneck_assignment(D) if math.isinf(p) else _min_power_assignment(D, p)
    if alpha == 2:
        # A pair at the cut-off costs c^p either way; report it as unassigned (missed + false).
        keep = D[rows, cols] < c
        rows, cols = rows[keep], cols[keep]
    n_false = X.shape[0] - rows.size
    n_missed = Y.shape[0] - cols.size
    d = D[rows, cols]
    assignment = np.column_stack([rows, cols]).astype(np.intp).reshape(-1, 2)
    if math.isinf(p):
        # Limits of the p-th roots of the parts; for alpha < 2, (c^p/alpha)^(1/p) -> c too.
        loc = float(d.max()) if d.size else 0.0
        missed = c if n_missed else 0.0
        false = c if n_false else 0.0
        value = max(loc, missed, false)
    else:
        loc = float(np.sum(d**p))
        missed = c**p / alpha * n_missed
        false = c**p / alpha * n_false
        value = (loc + missed + false) ** (1.0 / p)
    return GospaResult(value, loc, missed, false, assignment, n_missed, n_false)


def ospa_series(X_seq: Sequence, Y_seq: Sequence, c: float, p: float = 1.0) -> np.ndarray:
    """OSPA at each time step of two equally long sequences of point sets.

    Parameters
    ----------
    X_seq, Y_seq : sequences of (n_k, d) array_like
        Estimated and true sets per time step (empty sets allowed).
    c, p : float
        As for :func:`ospa`.

    Returns
    -------
    (K,) ndarray
    """
    if len(X_seq) != len(Y_seq):
        raise ValueError(f"X_seq and Y_seq must have the same length, got {len(X_seq)} and {len(Y_seq)}")
    c = check_positive(c, "c")
    p = _check_order(p)
    return np.array([ospa(X, Y, c, p) for X, Y in zip(X_seq, Y_seq)], dtype=float)

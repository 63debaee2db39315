"""Exact counts of data-association events (hypotheses).

An *association event* for ``M`` objects and ``m`` returns assigns each return either to a
distinct object or to clutter (see :mod:`hypotrack.association.enumeration`). Counting them
tells a caller, before anything is allocated, whether exhaustive enumeration is affordable.

All counts are exact Python integers: they overflow 64 bits already for ``A(20, 20)``.

References
----------
Faber, Chakravorty & Hussein, "A randomized sampling based approach to multi-object tracking
with comparison to HOMHT" (paper 000), Eq. 4 and Sec. II-C.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int
from .clustering import check_validation, component_labels

__all__ = ["as_validation", "count_associations", "count_children", "count_gated_associations", "count_gated_capped"]

# Exact component counts by the frontier dynamic programme are cheap while at most this many
# columns are open at once (2**20 states at worst); wider components are counted up to a cap.
_EXACT_FRONTIER_BITS = 20


def count_associations(M: int, m: int) -> int:
    """Number of association events for ``M`` objects and ``m`` returns (paper 000, Eq. 4).

    ``A(M, m) = Σ_{n=0}^{min(M, m)} C(M, n) C(m, n) n!``: choose the ``n`` detected objects,
    the ``n`` returns they produced, and a one-to-one pairing; every other return is clutter.

    Parameters
    ----------
    M : int
        Number of objects (tracks), ``M >= 0``.
    m : int
        Number of returns in the scan, ``m >= 0``.

    Returns
    -------
    int
        Exact count (a Python int, arbitrary precision). ``A(M, m) = A(m, M)``.

    Examples
    --------
    >>> count_associations(10, 5)
    63591

    By hand: two objects and two returns give ``1 + 2·2 + 2 = 7`` events (none detected, one of
    two objects on one of two returns, both detected in one of two pairings); three objects and
    two returns ``1 + 3·2 + 3·1·2 = 13``, as two objects and three returns:

    >>> count_associations(2, 2), count_associations(3, 2), count_associations(2, 3)
    (7, 13, 13)
    >>> count_associations(0, 4), count_associations(1, 1)
    (1, 2)
    """
    M = check_int(M, "M", minimum=0)
    m = check_int(m, "m", minimum=0)
    return _count_complete(M, m)


def _count_complete(M: int, m: int) -> int:
    # Running product C(M,n) C(m,n) n! = C(M,n) * m!/(m-n)! keeps every term an exact int.
    total = 0
    term = 1
    for n in range(min(M, m) + 1):
        if n:
            term = term * (M - n + 1) * (m - n + 1) // n
        total += term
    return total


def count_children(M: int, m: int, n_birth_regions: int = 0, n_deaths: int = 0) -> int:
    """Children of one parent hypothesis under the single birth/death model (paper 000, Sec. II-C).

    ``A(M, m) + M_b A(M + 1, m) + M_d A(M − 1, m)``: no population event, one birth in one of
    ``M_b`` regions, or the death of one of ``M_d`` objects (the last term only when ``M >= 1``).

    Parameters
    ----------
    M, m : int
        Objects in the parent hypothesis and returns in the scan, both ``>= 0``.
    n_birth_regions : int, optional
        ``M_b >= 0``, the number of birth regions.
    n_deaths : int, optional
        ``M_d``, the number of objects that may die, ``0 <= M_d <= M``.

    Returns
    -------
    int
        Exact count.
    """
    M = check_int(M, "M", minimum=0)
    m = check_int(m, "m", minimum=0)
    M_b = check_int(n_birth_regions, "n_birth_regions", minimum=0)
    M_d = check_int(n_deaths, "n_deaths", minimum=0, maximum=M)
    total = _count_complete(M, m) + M_b * _count_complete(M + 1, m)
    if M >= 1:
        total += M_d * _count_complete(M - 1, m)
    return total


def as_validation(allowed, n_tracks: int, n_meas: int) -> np.ndarray:
    """The validated ``(n_meas, n_tracks)`` bool validation (gating) matrix ``allowed``; a wrong shape is an
    error naming both shapes."""
    arr = check_validation(allowed, "allowed")
    if arr.shape != (n_meas, n_tracks):
        raise ValueError(
            f"allowed must have shape (n_meas, n_tracks) = ({n_meas}, {n_tracks}), got {arr.shape}"
        )
    return arr


def _frontier_plan(block: np.ndarray):
    """Row order for the counting DP and, after each row, the columns later rows still use.

    Rows are sorted by their first and last gated column, so that on banded (spatially local)
    gating few columns are "open" at a time. Returns the reordered block, the per-row masks of
    columns needed by later rows (as Python ints) and the largest number of open columns, which
    bounds the DP to ``2**width`` states.
    """
    first = np.argmax(block, axis=1)
    last = block.shape[1] - 1 - np.argmax(block[:, ::-1], axis=1)
    ordered = block[np.lexsort((last, first))]
    later = np.zeros_like(ordered)
    later[:-1] = np.logical_or.accumulate(ordered[::-1], axis=0)[::-1][1:]
    seen = np.logical_or.accumulate(ordered, axis=0)
    width = int((seen & later).sum(axis=1).max())
    weights = [1 << j for j in range(ordered.shape[1])]
    keep = [sum(w for w, f in zip(weights, row) if f) for row in later]
    return ordered, keep, width


def _component_plan(block: np.ndarray):
    """The orientation (rows = returns or rows = tracks) with the narrower frontier."""
    plans = [_frontier_plan(block), _frontier_plan(block.T)]
    return min(plans, key=lambda plan: plan[2])


def _count_component(plan, cap: int | None) -> tuple[int, bool]:
    """Matchings (of any size) in one bipartite block, and whether the count is exact.

    Stops early (inexact, but already ``> cap``) once the count exceeds ``cap``.

    Dynamic programming over rows, the state being the set of *open* columns already used
    (columns no later row can take are forgotten, merging states). The running total never
    decreases from one row to the next (every state survives via the "unmatched" option), so
    stopping once it exceeds ``cap`` is sound.
    """
    ordered, keep, _ = plan
    states = {0: 1}
    for row, keep_mask in zip(ordered, keep):
        nbrs = np.flatnonzero(row).tolist()
        new: dict[int, int] = {}
        for mask, c in states.items():
            key = mask & keep_mask
            new[key] = new.get(key, 0) + c
            for j in nbrs:
                bit = 1 << j
                if not mask & bit:
                    key = (mask | bit) & keep_mask
                    new[key] = new.get(key, 0) + c
        states = new
        if cap is not None and sum(states.values()) > cap:
            return sum(states.values()), False
    return sum(states.values()), True


def count_gated_associations(allowed, cap: int | None = None) -> int:
    """Number of association events permitted by a validation (gating) matrix.

    Counts the vectors ``a`` with ``a[i] = -1`` (clutter) or ``a[i] = j`` where
    ``allowed[i, j]``, non-negative entries distinct. The count factorises over the connected
    components of the bipartite return–track graph; a component whose block is fully gated uses
    the closed form :func:`count_associations`, any other one a dynamic programme over its rows
    whose state is the set of used columns that later rows could still take.

    Parameters
    ----------
    allowed : (m, n) array of bool
        ``allowed[i, j]`` is True when return ``i`` may be assigned to object ``j``.
    cap : int, optional
        If given, the caller only needs to know whether the count exceeds ``cap``: the work
        stops once it does and some value ``> cap`` (not necessarily exact) is returned.
        Without it the count is exact, which can be expensive for a large, sparse component.

    Returns
    -------
    int
        The count (exact when ``cap`` is None or the count is ``<= cap``).
    """
    return count_gated_capped(allowed, cap)[0]


def count_gated_capped(allowed, cap: int | None) -> tuple[int, bool]:
    """:func:`count_gated_associations` plus a flag telling whether the count is exact (``False``: a wide
    component was counted only up to ``cap``, and the count is a lower bound above ``cap``)."""
    arr = check_validation(allowed, "allowed")
    if cap is not None:
        cap = check_int(cap, "cap", minimum=0)
    m, n = arr.shape
    if m == 0 or n == 0 or not arr.any():
        return 1, True
    _, labels = component_labels(arr)
    row_lab, col_lab = labels[:m], labels[m:]
    total, exact_total = 1, True
    for comp in np.unique(row_lab[arr.any(axis=1)]):
        block = arr[np.ix_(row_lab == comp, col_lab == comp)]
        if block.all():
            total *= _count_complete(*block.shape)
            continue
        plan = _component_plan(block)
        exact = cap is None or plan[2] <= _EXACT_FRONTIER_BITS
        # Stopping this component once total * count > cap needs count > cap // total.
        count, exact_count = _count_component(plan, None if exact else cap // total)
        total *= count
        exact_total &= exact_count
    return total, exact_total


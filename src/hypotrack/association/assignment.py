"""Best and k-best assignments, and the score matrix of the event-with-clutter problem.

The assignment problem (paper 004, "Assignment Problem"): given an ``(m, N)`` score matrix with
``m <= N``, pick one column per row, all columns distinct, maximising the summed score; ``-inf``
marks a forbidden pairing (outside a gate). For association events the standard extended
matrix (paper 004, "assignment matrix") has the ``n`` object columns followed by ``m`` clutter
columns, one per return on the diagonal, so that the assignments of that matrix and the events
``a`` correspond one to one and a log-weight ``Σ_i score(i, a_i)`` is the assignment total.

References
----------
K. G. Murty, "An algorithm for ranking all the assignments in order of increasing cost",
Operations Research 16(3), 1968.
M. L. Miller, H. S. Stone & I. J. Cox, "Optimizing Murty's ranked assignment method",
IEEE Trans. AES 33(3), 1997.
"""

from __future__ import annotations

import heapq
import itertools

import numpy as np
from scipy.optimize import linear_sum_assignment

from .._validation import check_finite_array, check_int
from .clustering import graph_components
from .enumeration import event_dtype

__all__ = [
    "best_assignment",
    "murty_k_best",
    "association_score_matrix",
    "columns_to_event",
    "k_best_events",
]


def _check_score(score, name: str = "score") -> np.ndarray:
    arr = np.asarray(score, dtype=float)
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D (m, N) array, got shape {arr.shape}")
    if np.isnan(arr).any() or np.isposinf(arr).any():
        raise ValueError(f"{name} entries must be finite or -inf (forbidden); NaN and +inf are not allowed")
    if arr.shape[0] > arr.shape[1]:
        raise ValueError(f"{name} must have no more rows than columns (m <= N), got shape {arr.shape}")
    return arr


def _solve(score: np.ndarray):
    """Optimal assignment of a validated matrix, or None when no feasible assignment exists."""
    if score.shape[0] == 0:
        return 0.0, np.zeros(0, dtype=np.intp)
    if not np.isfinite(score).any(axis=1).all():
        return None
    try:
        rows, cols = linear_sum_assignment(score, maximize=True)
    except ValueError:  # scipy: "cost matrix is infeasible"
        return None
    total = float(score[rows, cols].sum())
    if not np.isfinite(total):
        return None
    return total, cols


def best_assignment(score) -> tuple[float, np.ndarray]:
    """The assignment maximising ``Σ_i score[i, cols[i]]`` with distinct columns.

    Parameters
    ----------
    score : (m, N) array_like, ``m <= N``
        Scores (e.g. log-likelihoods); ``-inf`` forbids a pairing.

    Returns
    -------
    total : float
        The maximal total score.
    cols : (m,) ndarray of int
        ``cols[i]`` is the column assigned to row ``i``.

    Raises
    ------
    ValueError
        If the matrix is malformed or no feasible assignment exists.

    Notes
    -----
    Solved by :func:`scipy.optimize.linear_sum_assignment` (a shortest augmenting path method).
    """
    arr = _check_score(score)
    solution = _solve(arr)
    if solution is None:
        raise ValueError("score admits no feasible assignment: every complete assignment uses a -inf entry")
    return solution


def murty_k_best(score, k: int) -> list[tuple[float, np.ndarray]]:
    """The ``k`` best assignments, best first (Murty 1968).

    Parameters
    ----------
    score : (m, N) array_like, ``m <= N``
        Scores; ``-inf`` forbids a pairing.
    k : int
        Number of assignments wanted, ``k >= 0``.

    Returns
    -------
    list of (total, cols)
        At most ``k`` distinct assignments in order of non-increasing total; fewer when fewer
        feasible assignments exist (none when the problem is infeasible).

    Notes
    -----
    Murty's partitioning: each time the best remaining assignment is taken from a priority
    queue, its subproblem is split into disjoint children, child ``t`` forbidding the ``t``-th
    free row's current column and pinning the rows before it to their current columns. A child
    is solved on the reduced matrix of its free rows and columns only, so later children are
    small. As in Miller, Stone & Cox (1997), the partition order is chosen so that the children
    most likely to be split again are the small ones: rows are taken in order of decreasing slack
    (best minus second-best score of the row, a cheap proxy for the cost increase of forbidding
    its column), so the children with a small cost increase come last, with most rows pinned.
    Their other optimisation (re-using the parent's dual variables) is not available through
    scipy's solver. Ties among equal totals are broken by creation order (deterministic output).

    Independent blocks. Rows that share no allowed column (through any chain of rows) are
    independent problems: an assignment is one assignment per block and its total the sum of
    theirs. The matrix is split into these blocks, each block's ``k`` best ranked on its own (by
    Murty, or by enumeration when it has at most ``k`` assignments), and the ``k`` best sums of one
    entry per block kept, block by block. A gated association problem is mostly such blocks — a
    return's clutter and birth columns are its own — where Murty on the whole matrix solves
    ``O(k m)`` assignment problems of the full size and ranks the product of the blocks.
    """
    arr = _check_score(score)
    k = check_int(k, "k", minimum=0)
    if k == 0:
        return []
    first = _solve(arr)
    if first is None:
        return []
    blocks = _row_blocks(arr) if arr.shape[0] > 1 else None
    if blocks is not None and len(blocks) > 1:
        return _blocks_k_best(arr, blocks, k, first)
    return _murty(arr, k, first)


def _row_blocks(arr: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """``(rows, columns)`` of each independent block (rows linked by a shared allowed column),
    in the order of their first row; a block's columns are those allowed to one of its rows."""
    fin = np.isfinite(arr)
    m = arr.shape[0]
    r, c = np.nonzero(fin)
    _, lab = graph_components(m + arr.shape[1], r, m + c)
    out = []
    for x in dict.fromkeys(lab[:m].tolist()):  # first-row order
        rows = np.flatnonzero(lab[:m] == x)
        out.append((rows, np.flatnonzero(fin[rows].any(axis=0))))
    return out


def _blocks_k_best(arr, blocks, k, first):
    """The ``k`` best assignments of a matrix split into independent ``blocks`` (best first; the
    solver's optimum ``first`` of the whole matrix leads, as in :func:`_murty`)."""
    tot, pick = np.zeros(1), np.zeros((1, 0), dtype=np.intp)
    ranked = []
    for rows, cols in blocks:
        sub = arr[np.ix_(rows, cols)]
        if len(rows) == 1:  # a lone row: its entries, best first
            order = np.argsort(-sub[0], kind="stable")[:k]
            best = [(float(sub[0, j]), np.array([j], dtype=np.intp)) for j in order]
        else:
            best = _murty(sub, k, _solve(sub))
        ranked.append(best)
        t = np.array([b[0] for b in best])
        both = (tot[:, None] + t[None, :]).ravel()
        keep = np.argsort(-both, kind="stable")[:k]
        tot = both[keep]
        pick = np.column_stack([pick[keep // len(t)], keep % len(t)])
    m = arr.shape[0]
    C = np.empty((len(pick), m), dtype=np.intp)
    for b, ((rows, cols), best) in enumerate(zip(blocks, ranked)):
        C[:, rows] = cols[np.array([c for _, c in best])][pick[:, b]]
    totals = arr[np.arange(m), C].sum(axis=1)
    out = [(float(totals[i]), C[i]) for i in np.argsort(-totals, kind="stable")]
    # (stable: the blocks' summed totals equal these to rounding)
    # the solver's optimum first, as Murty's (a tie may have put another optimum there)
    rest = [(t, c) for t, c in out if not np.array_equal(c, first[1])]
    return ([first] + rest)[:k]


def _murty(arr, k, first):
    """Murty's k best of a validated, feasible matrix whose optimum (:func:`_solve`) is ``first``."""
    every = _all_assignments(arr, k)
    if every is not None:  # at most k feasible assignments: all of them are the k best (one LAP, not Murty's)
        # the solver's optimum first, as Murty's (a near-tie within rounding keeps the solver's pick)
        return [first] + [(t, c) for t, c in every if not np.array_equal(c, first[1])]
    m = arr.shape[0]
    rows = np.arange(m)
    slack = _row_slack(arr)
    counter = itertools.count()
    # Queue entries: (-total, tiebreak, cols, pinned-row mask, forbidden (row, col) pairs).
    heap = [(-first[0], next(counter), first[1], np.zeros(m, dtype=bool), ())]
    results = []
    while heap and len(results) < k:
        neg_total, _, cols, pinned, forbidden = heapq.heappop(heap)
        results.append((-neg_total, cols))
        if len(results) == k:
            break
        work = arr.copy()
        for r, c in forbidden:
            work[r, c] = -np.inf
        row_free = ~pinned
        col_free = np.ones(arr.shape[1], dtype=bool)
        col_free[cols[pinned]] = False
        free = rows[row_free]
        for row in free[np.argsort(-slack[free], kind="stable")]:
            col = cols[row]
            work[row, col] = -np.inf
            solution = _solve(work[row_free][:, col_free])  # boolean slices: ~5× cheaper than np.ix_
            if solution is not None:
                child = cols.copy()
                child[row_free] = np.flatnonzero(col_free)[solution[1]]
                total = float(arr[rows, child].sum())
                child_forbidden = forbidden + ((int(row), int(col)),)
                heapq.heappush(heap, (-total, next(counter), child, ~row_free, child_forbidden))
            # The next children keep this row on its current column.
            work[row, col] = arr[row, col]
            row_free[row] = False
            col_free[col] = False
    return results


def _all_assignments(score: np.ndarray, limit: int):
    """Every feasible assignment, best first (ties in enumeration order), when there are at most
    ``limit`` of them; ``None`` as soon as there are more. The common case of a small gated
    problem (one return, a few options) costs a depth-first walk instead of Murty's LAPs."""
    m = score.shape[0]
    options = [np.flatnonzero(np.isfinite(score[i])) for i in range(m)]
    if m == 0:
        return [(0.0, np.zeros(0, dtype=np.intp))]
    if any(len(o) == 0 for o in options):
        return []
    found = []
    cols = np.empty(m, dtype=np.intp)
    used = set()

    def walk(i):
        if i == m:
            found.append(cols.copy())
            return len(found) <= limit
        for c in options[i]:
            if c not in used:
                cols[i] = c
                used.add(c)
                ok = walk(i + 1)
                used.discard(c)
                if not ok:
                    return False
        return True

    if not walk(0):
        return None
    rows = np.arange(m)
    totals = [float(score[rows, c].sum()) for c in found]
    order = sorted(range(len(found)), key=lambda j: -totals[j])
    return [(totals[j], found[j]) for j in order]


def _row_slack(score: np.ndarray) -> np.ndarray:
    """Best minus second-best entry of each row (inf when a row has a single finite entry)."""
    if score.shape[1] < 2:
        return np.full(score.shape[0], np.inf)
    top2 = -np.partition(-score, 1, axis=1)[:, :2]
    with np.errstate(invalid="ignore"):
        slack = top2[:, 0] - top2[:, 1]
    return np.nan_to_num(slack, nan=np.inf, posinf=np.inf)


def association_score_matrix(target_scores, clutter_scores) -> np.ndarray:
    """The extended ``(m, n + m)`` score matrix of the association-with-clutter problem.

    Parameters
    ----------
    target_scores : (m, n) array_like
        ``target_scores[i, j]``: log-score of return ``i`` coming from object ``j`` (``-inf``
        where gated out), e.g. paper 004's ``ℓ_ij = log(P_D p(y_i) / (1 − P_D P_G))``.
    clutter_scores : (m,) array_like
        Finite log-score of return ``i`` being clutter (e.g. ``log β_EX``).

    Returns
    -------
    (m, n + m) ndarray
        Columns ``0..n-1`` are ``target_scores``; columns ``n..n+m-1`` hold ``clutter_scores``
        on their diagonal and ``-inf`` elsewhere (paper 004, "assignment matrix").

    See Also
    --------
    columns_to_event : map an assignment of this matrix back to an event vector.
    """
    clutter = check_finite_array(clutter_scores, "clutter_scores", ndim=1)
    targets = np.asarray(target_scores, dtype=float)
    m = clutter.shape[0]
    if targets.ndim != 2 or targets.shape[0] != m:
        raise ValueError(
            f"target_scores must have shape (m, n) with m = len(clutter_scores) = {m}, got {targets.shape}"
        )
    if np.isnan(targets).any() or np.isposinf(targets).any():
        raise ValueError(
            "target_scores entries must be finite or -inf (gated out); NaN and +inf are not allowed"
        )
    n = targets.shape[1]
    out = np.full((m, n + m), -np.inf)
    out[:, :n] = targets
    out[np.arange(m), n + np.arange(m)] = clutter
    return out


def columns_to_event(cols, n_tracks: int) -> np.ndarray:
    """Event vector of an assignment of :func:`association_score_matrix`: column ``>= n`` → ``-1``."""
    n = check_int(n_tracks, "n_tracks", minimum=0)
    arr = np.asarray(cols)
    if arr.ndim != 1 or (arr.size and not np.issubdtype(arr.dtype, np.integer)):
        raise ValueError(f"cols must be a 1-D integer array, got shape {arr.shape} and dtype {arr.dtype}")
    if arr.size and arr.min() < 0:
        raise ValueError("cols must be non-negative column indices")
    return np.where(arr < n, arr, -1).astype(event_dtype(n))


def k_best_events(target_scores, clutter_scores, k: int) -> list[tuple[float, np.ndarray]]:
    """The ``k`` highest-scoring association events, best first.

    The score of an event ``a`` is ``Σ_{i: a_i ≥ 0} target_scores[i, a_i] + Σ_{i: a_i = −1}
    clutter_scores[i]``; this is Murty on :func:`association_score_matrix`.

    Returns
    -------
    list of (score, event)
        ``event`` is an ``(m,)`` vector in the project's event convention.
    """
    matrix = association_score_matrix(target_scores, clutter_scores)
    n = matrix.shape[1] - matrix.shape[0]
    return [(total, columns_to_event(cols, n)) for total, cols in murty_k_best(matrix, k)]

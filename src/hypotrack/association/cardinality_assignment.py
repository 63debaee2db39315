"""Exact MAP and k best association events when the weight has a count term (H-FISST).

The log-weight of an event (DESIGN.md §4.2) is a sum of association-matrix entries plus a term
``φ[k, b]`` in the number ``k`` of returns on object columns and ``b`` on birth columns — for
H-FISST ``φ = −log(C(m, k) k!)`` (document 000 Eq. 8), the ``p_D^k (1 − p_D)^{M−k}`` being in the
entries. ``φ`` does not split over the returns, so a plain assignment solver ranks events by
the wrong total; but within a *block* of events with the same ``(k, b)`` it is a constant.
Hence:

* **MAP.** For every ``(k, b)`` solve the assignment with exactly ``k`` object and ``b`` birth
  detections; the exact MAP is the best block optimum plus ``φ[k, b]``.
* **k best.** Murty's partitioning within each block, merged best first across blocks (the
  blocks partition the events, so the merged list is the exact top ``k``).

A block is a square assignment problem. Rows: the ``C = M + B`` exclusive columns of the
problem (objects, birth regions) and ``m − k − b`` *clutter* rows; columns: the ``m`` returns,
``M − k`` *missed* columns and ``B − b`` *unused-birth* columns. An object row takes a return
(score ``target[j, i]``) or a missed column (0); a clutter row takes a return (its clutter
score); clutter rows never take missed columns. A perfect matching is exactly an event with
``k`` detections and ``b`` births. The dummies are interchangeable, so Murty's partition is
made on the real (object, return) pairs only: all events of a block have ``k + b`` such pairs,
so "contains pairs ``p_1 … p_{t−1}``, not ``p_t``" for ``t = 1 … k + b`` partitions the block
without duplicates.

Cost: all block optima come from one chain of shortest augmenting paths (going from ``(k, b)``
to ``(k + 1, b)`` removes one clutter row and one missed column and re-augments once, the
successive-shortest-path method), and every Murty child is one augmenting path from its
parent's solution and dual potentials (Miller, Stone & Cox 1997) — ``O(N²)`` each with
``N = C + m − k − b``, compiled with numba.

References
----------
K. G. Murty, Operations Research 16(3), 1968. M. L. Miller, H. S. Stone & I. J. Cox, "Optimizing
Murty's ranked assignment method", IEEE Trans. AES 33(3), 1997. R. Jonker & A. Volgenant,
Computing 38, 1987 (shortest augmenting paths with potentials).
"""

from __future__ import annotations

import heapq
import itertools

import numba
import numpy as np

from .._validation import check_int

__all__ = ["cardinality_k_best", "cardinality_map"]


@numba.njit(cache=True, nogil=True)
def _augment(cost, forb, row_act, col_act, u, v, row4col, col4row, i0):
    """One shortest augmenting path (Dijkstra on reduced costs) from free row ``i0`` to a free
    active column; updates potentials and matching in place. False when no path exists."""
    n = cost.shape[0]
    minv = np.full(n, np.inf)
    way = np.full(n, -1, dtype=np.int64)
    used = np.zeros(n, dtype=np.bool_)
    jcur = -1
    while True:
        i = i0 if jcur < 0 else row4col[jcur]
        if jcur >= 0:
            used[jcur] = True
        delta = np.inf
        j1 = -1
        for j in range(n):
            if not col_act[j] or used[j]:
                continue
            c = cost[i, j]
            if c < np.inf and not forb[i, j]:
                cur = c - u[i] - v[j]
                if cur < minv[j]:
                    minv[j] = cur
                    way[j] = jcur
            if minv[j] < delta:
                delta = minv[j]
                j1 = j
        if j1 < 0 or delta == np.inf:
            return False
        u[i0] += delta
        for j in range(n):
            if not col_act[j]:
                continue
            if used[j]:
                u[row4col[j]] += delta
                v[j] -= delta
            else:
                minv[j] -= delta
        jcur = j1
        if row4col[jcur] < 0:
            break
    while True:
        jprev = way[jcur]
        r = i0 if jprev < 0 else row4col[jprev]
        row4col[jcur] = r
        col4row[r] = jcur
        if jprev < 0:
            return True
        jcur = jprev


@numba.njit(cache=True, nogil=True)
def _value(cost, row4col, m):
    """Summed score of the matching over the returns (dummy columns score 0)."""
    total = 0.0
    for j in range(m):
        total -= cost[row4col[j], j]
    return total


@numba.njit(cache=True, nogil=True)
def _children(cost, forb, row_act, col_act, u, v, row4col, col4row, pair_rows, pair_cols, m):
    """Murty's children of a node: child ``t`` forbids pair ``t`` and keeps pairs ``< t``.

    Returns per child: ok flag, value, and its state (row4col, col4row, u, v, row/col masks)."""
    n = cost.shape[0]
    T = len(pair_rows)
    ok = np.zeros(T, dtype=np.bool_)
    values = np.full(T, -np.inf)
    R4C = np.empty((T, n), dtype=np.int64)
    C4R = np.empty((T, n), dtype=np.int64)
    U = np.empty((T, n))
    V = np.empty((T, n))
    RA = np.empty((T, n), dtype=np.bool_)
    CA = np.empty((T, n), dtype=np.bool_)
    ra = row_act.copy()
    ca = col_act.copy()
    for t in range(T):
        i, j = pair_rows[t], pair_cols[t]
        r4c = row4col.copy()
        c4r = col4row.copy()
        uu = u.copy()
        vv = v.copy()
        r4c[j] = -1
        c4r[i] = -1
        forb[i, j] = True
        if _augment(cost, forb, ra, ca, uu, vv, r4c, c4r, i):
            ok[t] = True
            values[t] = _value(cost, r4c, m)
            R4C[t] = r4c
            C4R[t] = c4r
            U[t] = uu
            V[t] = vv
            RA[t] = ra
            CA[t] = ca
        forb[i, j] = False
        ra[i] = False  # later children keep pair t: its row and column leave the problem
        ca[j] = False
    return ok, values, R4C, C4R, U, V, RA, CA


def _block_matrix(target, clutter, n_objects):
    """Cost matrix (minimisation) of the largest block ``(0, 0)``; see the module docstring."""
    m, C = target.shape
    n = C + m
    cost = np.full((n, n), np.inf)
    cost[:C, :m] = -target.T
    cost[:n_objects, m:m + n_objects] = 0.0
    cost[n_objects:C, m + n_objects:] = 0.0
    cost[C:, :m] = -clutter[None, :]
    row4col = np.concatenate([np.arange(C, n), np.arange(C)]).astype(np.int64)
    col4row = np.empty(n, dtype=np.int64)
    col4row[row4col] = np.arange(n)
    # Feasible potentials for the trivial matching (objects missed, returns clutter): reduced
    # costs are >= 0 everywhere and 0 on the matching (the interchangeable dummies force
    # equal potentials within each kind of row).
    v = np.zeros(n)
    u = np.zeros(n)
    v[:m] = -clutter
    gain = clutter[:, None] - target  # reduced cost of (return j, column r) before shifting
    for lo, hi, dlo in ((0, n_objects, m), (n_objects, C, m + n_objects)):
        g = gain[:, lo:hi]
        g = g[np.isfinite(g)]
        shift = float(g.min()) if g.size else 0.0
        u[lo:hi] = shift
        v[dlo:dlo + hi - lo] = -shift
    return cost, u, v, row4col, col4row


def _step(state, cost, dummy_col_range, C):
    """From block (k, b) to (k + 1, b) or (k, b + 1): drop one clutter row and one dummy column
    of the given kind, then re-augment once. Returns the new state or None (infeasible)."""
    r4c, c4r, u, v, ra, ca = (a.copy() for a in state)
    lo, hi = dummy_col_range
    rows = np.flatnonzero(ra[C:]) + C
    cols = np.flatnonzero(ca[lo:hi]) + lo
    if not len(rows) or not len(cols):
        return None
    d, c = rows[0], cols[0]
    j, i = c4r[d], r4c[c]
    ra[d] = ca[c] = False
    r4c[j] = -1
    c4r[i] = -1
    forb = np.zeros(cost.shape, dtype=bool)
    if not _augment(cost, forb, ra, ca, u, v, r4c, c4r, i):
        return None
    return r4c, c4r, u, v, ra, ca


def _block_roots(cost, u, v, row4col, col4row, m, n_objects, count_term):
    """Optimal state of every feasible block ``(k, b)`` with finite ``φ[k, b]``."""
    C = cost.shape[0] - m
    B = C - n_objects
    n = cost.shape[0]
    start = (row4col, col4row, u, v, np.ones(n, dtype=bool), np.ones(n, dtype=bool))
    roots = {}
    for b in range(B + 1):
        if b:
            start = _step(start, cost, (m + n_objects, n), C)
            if start is None:
                break
        state = start
        for k in range(n_objects + 1):
            if k:
                state = _step(state, cost, (m, m + n_objects), C)
                if state is None:
                    break
            if np.isfinite(count_term[k, b]):
                roots[(k, b)] = state
    return roots


def _event(row4col, m, C):
    r = row4col[:m]
    return np.where(r < C, r, -1)


def _prepare(target_scores, clutter_scores, n_objects, count_term):
    target = np.asarray(target_scores, dtype=float)
    clutter = np.asarray(clutter_scores, dtype=float)
    if target.ndim != 2 or clutter.shape != (target.shape[0],):
        raise ValueError(f"target_scores must be (m, C) and clutter_scores (m,), got {target.shape}, {clutter.shape}")
    if np.isnan(target).any() or np.isposinf(target).any():
        raise ValueError("target_scores entries must be finite or -inf (gated out)")
    if not np.isfinite(clutter).all():
        raise ValueError("clutter_scores must be finite")
    M = check_int(n_objects, "n_objects", minimum=0, maximum=target.shape[1])
    phi = np.asarray(count_term, dtype=float)
    if phi.shape != (M + 1, target.shape[1] - M + 1):
        raise ValueError(f"count_term must have shape {(M + 1, target.shape[1] - M + 1)}, got {phi.shape}")
    return target, clutter, M, phi


def cardinality_k_best(target_scores, clutter_scores, n_objects, count_term, k):
    """The ``k`` heaviest events under ``Σ_i score[i, a_i] + φ[k, b]``, best first, exactly.

    Parameters
    ----------
    target_scores : (m, C) array_like
        Scores of returns on exclusive columns (``n_objects`` objects, then birth columns);
        ``-inf`` where gated out.
    clutter_scores : (m,) array_like
        Finite score of each return being clutter.
    n_objects : int
        ``M``; columns ``>= M`` are birth columns.
    count_term : (M + 1, C − M + 1) array_like
        ``φ[k, b]``; ``-inf`` forbids a count.
    k : int
        Number of events wanted (``>= 1``); fewer are returned when fewer are feasible.

    Returns
    -------
    events : (E, m) int32
        ``a_i`` the exclusive column of return ``i`` or ``-1`` (clutter).
    log_weights : (E,) float
        ``Σ_i score[i, a_i] + φ[k, b]`` (no constant), non-increasing.
    """
    target, clutter, M, phi = _prepare(target_scores, clutter_scores, n_objects, count_term)
    k = check_int(k, "k", minimum=1)
    m, C = target.shape
    if m == 0:  # the one event "nothing detected"
        n_ev = int(np.isfinite(phi[0, 0]))
        return np.zeros((n_ev, 0), dtype=np.int32), np.full(n_ev, phi[0, 0])
    cost, u, v, r4c, c4r = _block_matrix(target, clutter, M)
    roots = _block_roots(cost, u, v, r4c, c4r, m, M, phi)
    counter = itertools.count()
    heap = []
    for (kk, b), state in roots.items():
        val = _value(cost, state[0], m) + phi[kk, b]
        heapq.heappush(heap, (-val, next(counter), kk, b, state, ()))
    events, weights = [], []
    n = cost.shape[0]
    while heap and len(events) < k:
        neg, _, kk, b, state, forbidden = heapq.heappop(heap)
        r4c, c4r, u, v, ra, ca = state
        events.append(_event(r4c, m, C))
        weights.append(-neg)
        if len(events) == k:
            break
        rows = np.flatnonzero(ra[:C])
        rows = rows[c4r[rows] < m]  # active real pairs (object or birth row on a return)
        if not len(rows):
            continue
        cols = c4r[rows]
        forb = np.zeros((n, n), dtype=bool)
        for i, j in forbidden:
            forb[i, j] = True
        ok, vals, R4C, C4R, U, V, RA, CA = _children(cost, forb, ra, ca, u, v, r4c, c4r, rows, cols, m)
        for t in np.flatnonzero(ok):
            child = (R4C[t], C4R[t], U[t], V[t], RA[t], CA[t])
            heapq.heappush(heap, (-(vals[t] + phi[kk, b]), next(counter), kk, b, child,
                                  forbidden + ((int(rows[t]), int(cols[t])),)))
    if not events:
        return np.zeros((0, m), dtype=np.int32), np.zeros(0)
    return np.array(events, dtype=np.int32), np.array(weights)


def cardinality_map(target_scores, clutter_scores, n_objects, count_term):
    """The exact MAP event and its log-weight (see :func:`cardinality_k_best`); ``(None, -inf)``
    when no event is feasible."""
    ev, lw = cardinality_k_best(target_scores, clutter_scores, n_objects, count_term, 1)
    return (ev[0], float(lw[0])) if len(lw) else (None, -np.inf)

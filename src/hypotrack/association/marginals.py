"""Exact JPDA marginal association probabilities, without enumerating the joint events.

For ``n`` tracks and ``m`` returns, a feasible joint association event gives every track
either "missed" or one of its gated returns, no return to two tracks. With per-track weights
``w[t, 0]`` (missed) and ``w[t, 1 + j]`` (track t produced return j), the event weight is the
product of the chosen entries and the JPDA marginal is

    β[t, c] = Σ_{events with t ↦ c} Π_s w[s, a_s]  /  Σ_{all events} Π_s w[s, a_s]

(lecture notes 004, "JPDAF": P(T_j ↔ y_i) and P(T_j ↔ ∅), Eq. (1); Fortmann, Bar-Shalom &
Scheffe 1983). The number of joint events grows combinatorially with the cluster, so instead of
materialising them this module runs the *efficient hypothesis management* recursion (Maskell,
Briers & Wright 2004; the forward–backward form of Horridge & Maskell 2006):

* the tracks are put in an order that keeps the "frontier" small (reverse Cuthill–McKee on the
  track–track conflict graph — the ordering of :func:`scipy.sparse.csgraph.reverse_cuthill_mckee`,
  written here inside the compiled kernel because building the sparse matrix for scipy costs
  ten times more than the whole recursion on a typical cluster);
* after deciding tracks ``0..k`` the only thing later tracks need to know is which of the returns
  they can still use have been taken — a subset of the frontier returns (gated by some decided
  track *and* some later one). Partial events with the same subset are merged into one node, so
  the work is the number of distinct subsets, not the number of events;
* a forward pass accumulates the summed weight reaching each node, a backward pass the summed
  weight from each node to the end, and each marginal is Σ forward · w · backward over the edges
  of its option.

Returns gated by only one track never constrain anything; they are folded, with the missed
option, into one "free" option per track and split back out at the end. Forward and backward
weights are rescaled level by level, so no product over- or underflows however large the
cluster. A node's state is a bit set over the frontier returns (as many 64-bit words as the
widest frontier needs), merged through a hash table. The kernel is compiled with numba; explicit
node and edge budgets turn a hopeless cluster into a ValueError instead of exhausting memory.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .._validation import check_int

__all__ = ["jpda_marginals", "track_order", "MarginalsBudgetError"]

DEFAULT_MAX_NODES = 2_000_000
DEFAULT_MAX_EDGES = 10_000_000


class MarginalsBudgetError(ValueError):
    """The exact recursion would need more nodes or edges than the budget (memory) allows."""


def jpda_marginals(
    log_weights,
    *,
    return_log_total: bool = False,
    max_nodes: int = DEFAULT_MAX_NODES,
    max_edges: int = DEFAULT_MAX_EDGES,
):
    """Exact marginal association probabilities of a group of tracks (one JPDA cluster).

    Parameters
    ----------
    log_weights : (n, m + 1) array_like
        Column 0: log weight of track ``t`` being *missed*; column ``1 + j``: log weight of track
        ``t`` having produced return ``j``, ``-inf`` where the return is outside the track's gate.
        For the standard JPDA these are ``log(1 − P_D P_G)`` and ``log(P_D N(z_j; ẑ_t, S_t) / λ)``
        with λ the clutter spatial density (lecture 004, fundamental theorem of TT with no new
        targets); any constant added to a row cancels.
    return_log_total : bool
        Also return ``log Σ_events Π w`` (the normalising constant), which tests compare with
        exhaustive enumeration.
    max_nodes, max_edges : int
        Budget of merged partial events (nodes) and of their transitions (edges, 24 bytes each)
        over the whole cluster; exceeding either raises :class:`MarginalsBudgetError`.

    Returns
    -------
    beta : (n, m + 1) ndarray
        ``beta[t, 0]`` = P(track t missed), ``beta[t, 1 + j]`` = P(track t ↔ return j); every row
        sums to one and every column ``1 + j`` sums to at most one.
    log_total : float
        Only with ``return_log_total``.

    Raises
    ------
    ValueError
        On NaN or ``+inf`` weights, a wrong shape, a track with no finite option, or no feasible
        joint event (possible only when missed weights are zero).
    MarginalsBudgetError
        (A ValueError.) When the cluster needs more than ``max_nodes`` nodes or ``max_edges`` edges.

    Notes
    -----
    Cost: the number of distinct (decided-track depth, frontier returns taken) nodes times the
    options per track — for tracks strung along a line this is linear in the cluster size,
    where the number of joint events is exponential.
    """
    lw = np.asarray(log_weights, dtype=float)
    if lw.ndim != 2 or lw.shape[1] < 1:
        raise ValueError(f"log_weights must have shape (n, m + 1), got {lw.shape}")
    if np.isnan(lw).any() or np.isposinf(lw).any():
        raise ValueError("log_weights must not contain NaN or +inf (use -inf for gated-out pairs)")
    n, m1 = lw.shape
    if n == 0:
        return (np.zeros((0, m1)), 0.0) if return_log_total else np.zeros((0, m1))
    max_nodes = check_int(max_nodes, "max_nodes", minimum=1)
    max_edges = check_int(max_edges, "max_edges", minimum=1)
    beta, log_total, status = _marginals(lw, max_nodes, max_edges)
    if status == _NO_OPTION:
        raise ValueError("every track needs at least one option with finite log weight")
    if status == _TOO_BIG:
        raise MarginalsBudgetError(
            f"cluster of {n} tracks and {m1 - 1} returns is too large for exact JPDA marginals within "
            f"max_nodes={max_nodes:,} and max_edges={max_edges:,}; raise the budget, gate more tightly "
            "or use an approximation"
        )
    if status == _INFEASIBLE:
        raise ValueError("no feasible joint association event (some track can be neither missed nor detected)")
    return (beta, float(log_total)) if return_log_total else beta


def track_order(valid) -> np.ndarray:
    """The processing order used for a cluster: reverse Cuthill–McKee on the conflict graph.

    Parameters
    ----------
    valid : (n, m) bool
        ``valid[t, j]``: return ``j`` lies in track ``t``'s gate.

    Returns
    -------
    order : (n,) int permutation of the tracks.
    """
    return _rcm_order(np.ascontiguousarray(valid, dtype=np.bool_))


_OK, _NO_OPTION, _TOO_BIG, _INFEASIBLE = 0, 1, 2, 3


@njit(cache=True)
def _rcm_order(valid):
    """Reverse Cuthill–McKee: BFS from a minimum-degree track, neighbours by rising degree."""
    n, m = valid.shape
    adj = np.zeros((n, n), np.bool_)
    members = np.empty(n, np.int64)
    for j in range(m):
        c = 0
        for t in range(n):
            if valid[t, j]:
                members[c] = t
                c += 1
        for a in range(c):
            for b in range(c):
                adj[members[a], members[b]] = True
    deg = np.zeros(n, np.int64)
    for t in range(n):
        adj[t, t] = False
        for u in range(n):
            if adj[t, u]:
                deg[t] += 1
    order = np.empty(n, np.int64)
    seen = np.zeros(n, np.bool_)
    pos = 0
    nb = np.empty(n, np.int64)
    while pos < n:
        start = -1
        for t in range(n):
            if not seen[t] and (start < 0 or deg[t] < deg[start]):
                start = t
        seen[start] = True
        order[pos] = start
        head = pos
        pos += 1
        while head < pos:
            u = order[head]
            head += 1
            c = 0
            for v in range(n):
                if adj[u, v] and not seen[v]:
                    nb[c] = v
                    c += 1
                    seen[v] = True
            srt = np.argsort(deg[nb[:c]], kind="mergesort")
            for r in range(c):
                order[pos] = nb[srt[r]]
                pos += 1
    return order[::-1].copy()


@njit(cache=True)
def _marginals(lw, max_nodes, max_edges):
    """Whole computation for one cluster: ordering, frontier bits, EHM sums, unfolding."""
    n, m1 = lw.shape
    m = m1 - 1
    beta = np.zeros((n, m1))
    # A constant per row cancels in β; removing the row maximum keeps exp() in range.
    row_max = np.full(n, -np.inf)
    for t in range(n):
        for c in range(m1):
            if lw[t, c] > row_max[t]:
                row_max[t] = lw[t, c]
        if row_max[t] == -np.inf:
            return beta, 0.0, _NO_OPTION
    valid = np.zeros((n, m), np.bool_)
    for t in range(n):
        for j in range(m):
            valid[t, j] = lw[t, 1 + j] > -np.inf
    order = _rcm_order(valid)

    # Lifetime of each return in processing order: decided tracks first[j]..last[j] gate it.
    first = np.full(m, -1, np.int64)
    last = np.full(m, -1, np.int64)
    for k in range(n):
        t = order[k]
        for j in range(m):
            if valid[t, j]:
                if first[j] < 0:
                    first[j] = k
                last[j] = k
    # Bits for shared returns by greedy interval colouring (optimal for intervals). A bit is
    # free once its return's last track lies strictly before the new return's first track.
    slot = np.full(m, -1, np.int64)
    slot_end = np.full(max(m, 1), -1, np.int64)
    n_slots = 0
    by_first = np.argsort(first, kind="mergesort")
    for r in range(m):
        j = by_first[r]
        if first[j] < 0 or last[j] == first[j]:
            continue
        s = 0
        while slot_end[s] >= first[j]:
            s += 1
        slot[j] = s
        slot_end[s] = last[j]
        n_slots = max(n_slots, s + 1)
    n_words = max(1, (n_slots + 63) // 64)
    keep = np.zeros((n, n_words), np.int64)
    for j in range(m):
        if slot[j] >= 0:
            bit = np.int64(1) << np.int64(slot[j] % 64)
            for k in range(first[j], last[j]):
                keep[k, slot[j] // 64] |= bit

    # Options per level: one "free" option (missed + returns only this track gates: they never
    # conflict) and one per shared return.
    opt_ptr = np.zeros(n + 1, np.int64)
    for k in range(n):
        t = order[k]
        c = 1
        for j in range(m):
            if valid[t, j] and slot[j] >= 0:
                c += 1
        opt_ptr[k + 1] = opt_ptr[k] + c
    n_opt = opt_ptr[n]
    opt_word = np.full(n_opt, -1, np.int64)
    opt_bit = np.zeros(n_opt, np.int64)
    opt_w = np.zeros(n_opt)
    opt_col = np.full(n_opt, -1, np.int64)
    for k in range(n):
        t = order[k]
        o = opt_ptr[k]
        opt_w[o] = np.exp(lw[t, 0] - row_max[t])
        for j in range(m):
            if not valid[t, j]:
                continue
            wj = np.exp(lw[t, 1 + j] - row_max[t])
            if slot[j] < 0:
                opt_w[opt_ptr[k]] += wj
            else:
                o += 1
                opt_word[o] = slot[j] // 64
                opt_bit[o] = np.int64(1) << np.int64(slot[j] % 64)
                opt_w[o] = wj
                opt_col[o] = 1 + j

    marg, log_total, status = _ehm_sums(opt_ptr, opt_word, opt_bit, opt_w, keep, max_nodes, max_edges)
    if status != _OK:
        return beta, log_total, status

    # Unfold: shared options map to their column; the free option's mass is split in
    # proportion to the weights it merged.
    for k in range(n):
        t = order[k]
        o0 = opt_ptr[k]
        for o in range(o0 + 1, opt_ptr[k + 1]):
            beta[t, opt_col[o]] = marg[o]
        if opt_w[o0] > 0.0:
            scale = marg[o0] / opt_w[o0]
            beta[t, 0] = np.exp(lw[t, 0] - row_max[t]) * scale
            for j in range(m):
                if valid[t, j] and slot[j] < 0:
                    beta[t, 1 + j] = np.exp(lw[t, 1 + j] - row_max[t]) * scale
        tot = 0.0
        for c in range(m1):
            tot += beta[t, c]
        for c in range(m1):
            beta[t, c] /= tot
        log_total += row_max[t]
    return beta, log_total, _OK


@njit(cache=True)
def _grow(a, need):
    if need <= a.shape[0]:
        return a
    b = np.empty((max(need, 2 * a.shape[0]),) + a.shape[1:], a.dtype)
    b[: a.shape[0]] = a
    return b


@njit(cache=True)
def _hash(mask, i):
    h = np.int64(-3750763034362895579)  # FNV-1a offset basis; int64 arithmetic wraps
    for w in range(mask.shape[1]):
        h = (h ^ mask[i, w]) * np.int64(1099511628211)
    return h ^ (h >> np.int64(29))


@njit(cache=True)
def _ehm_sums(opt_ptr, opt_word, opt_bit, opt_w, keep, max_nodes, max_edges):
    """Forward–backward sums over the EHM node graph.

    Returns (option marginals normalised per track, log total, status).
    """
    n, n_words = keep.shape
    n_opt = opt_w.shape[0]
    node_mask = np.zeros((256, n_words), np.int64)
    node_f = np.zeros(256)
    node_ptr = np.zeros(n + 2, np.int64)
    node_f[0] = 1.0
    node_ptr[1] = 1
    e_par = np.empty(1024, np.int64)
    e_child = np.empty(1024, np.int64)
    e_opt = np.empty(1024, np.int64)
    edge_ptr = np.zeros(n + 1, np.int64)
    n_edges = 0
    log_scale = 0.0
    child = np.zeros(n_words, np.int64)

    for k in range(n):
        p0, p1 = node_ptr[k], node_ptr[k + 1]
        base = p1
        n_new = 0
        # Open-addressing table of this level's nodes (index into node arrays, -1 = empty).
        cap = 16
        while cap < 4 * (p1 - p0):
            cap *= 2
        table = np.full(cap, -1, np.int64)
        for i in range(p0, p1):
            for o in range(opt_ptr[k], opt_ptr[k + 1]):
                wd = opt_word[o]
                if opt_w[o] == 0.0 or (wd >= 0 and (node_mask[i, wd] & opt_bit[o]) != 0):
                    continue
                for w in range(n_words):
                    child[w] = node_mask[i, w]
                if wd >= 0:
                    child[wd] |= opt_bit[o]
                for w in range(n_words):
                    child[w] &= keep[k, w]
                # Look the child up (linear probing); insert it if new.
                node_mask = _grow(node_mask, base + n_new + 1)
                node_mask[base + n_new] = child
                h = _hash(node_mask, base + n_new) & (cap - 1)
                idx = -1
                while table[h] >= 0:
                    cand = table[h]
                    same = True
                    for w in range(n_words):
                        if node_mask[cand, w] != child[w]:
                            same = False
                            break
                    if same:
                        idx = cand
                        break
                    h = (h + 1) & (cap - 1)
                if idx < 0:
                    idx = base + n_new
                    table[h] = idx
                    node_f = _grow(node_f, idx + 1)
                    node_f[idx] = 0.0
                    n_new += 1
                    if base + n_new > max_nodes:
                        return np.zeros(n_opt), 0.0, _TOO_BIG
                    if 2 * n_new > cap:
                        # Rehash this level into a table twice the size.
                        cap *= 2
                        table = np.full(cap, -1, np.int64)
                        for q in range(base, base + n_new):
                            hq = _hash(node_mask, q) & (cap - 1)
                            while table[hq] >= 0:
                                hq = (hq + 1) & (cap - 1)
                            table[hq] = q
                node_f[idx] += node_f[i] * opt_w[o]
                if n_edges + 1 > max_edges:
                    return np.zeros(n_opt), 0.0, _TOO_BIG
                e_par = _grow(e_par, n_edges + 1)
                e_child = _grow(e_child, n_edges + 1)
                e_opt = _grow(e_opt, n_edges + 1)
                e_par[n_edges] = i
                e_child[n_edges] = idx
                e_opt[n_edges] = o
                n_edges += 1
        if n_new == 0:
            return np.zeros(n_opt), -np.inf, _INFEASIBLE
        node_ptr[k + 2] = base + n_new
        edge_ptr[k + 1] = n_edges
        fmax = 0.0
        for i in range(base, base + n_new):
            fmax = max(fmax, node_f[i])
        for i in range(base, base + n_new):
            node_f[i] /= fmax
        log_scale += np.log(fmax)

    # After the last track no return is in flight: a single end node.
    total_nodes = node_ptr[n + 1]
    node_b = np.zeros(total_nodes)
    for i in range(node_ptr[n], total_nodes):
        node_b[i] = 1.0
    log_total = log_scale + np.log(node_f[node_ptr[n]])
    marg = np.zeros(n_opt)
    for k in range(n - 1, -1, -1):
        for e in range(edge_ptr[k], edge_ptr[k + 1]):
            wb = opt_w[e_opt[e]] * node_b[e_child[e]]
            node_b[e_par[e]] += wb
            marg[e_opt[e]] += node_f[e_par[e]] * wb
        # Normalise this track's option marginals (every scale factor cancels here) and
        # rescale the parents' backward weights for the next level.
        tot = 0.0
        for o in range(opt_ptr[k], opt_ptr[k + 1]):
            tot += marg[o]
        for o in range(opt_ptr[k], opt_ptr[k + 1]):
            marg[o] /= tot
        bmax = 0.0
        for i in range(node_ptr[k], node_ptr[k + 1]):
            bmax = max(bmax, node_b[i])
        for i in range(node_ptr[k], node_ptr[k + 1]):
            node_b[i] /= bmax
    return marg, log_total, _OK

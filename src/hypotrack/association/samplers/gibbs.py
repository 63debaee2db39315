"""Gibbs sampling of association events (Vo, Vo & Hoang 2017, Sec. IV, Algorithm 1).

One Gibbs step redraws one row's column from its exact conditional given all the other rows:
every row option, and every exclusive column not held by another row, with probability
proportional to the event weight it gives (:func:`gibbs_draw`; the change of the count term
``φ[k, b]`` enters the conditional, so any problem of :mod:`.events` can be sampled). Two scans
use it:

* the **systematic scan** of the δ-GLMB filter (:func:`checked_sweep_search`): one sample is a
  sweep over the rows in order, from the published start "every row on option 0" (on the GLMB
  problem, whose rows are the objects: every object missed);
* the **random scan** of R-FISST's chain, variant ``"gibbs"`` (:mod:`.chain`): one step redraws
  a uniformly picked row.

Either way the sampler is a *search* (DESIGN.md §4.3): the distinct samples (:mod:`.visited`)
are returned with their **exact** weights; the sample frequencies are not used.

References
----------
Vo, Vo & Hoang, "An efficient implementation of the generalized labeled multi-Bernoulli
filter", IEEE TSP 65 (2017).
"""

from __future__ import annotations

import numba
import numpy as np

from ..._validation import check_int
from .events import check_problem, checked_event_log_weights, count_delta, owners_and_counts, state_log_weight, to_events
from .visited import Visited, lookup_or_insert

__all__ = ["checked_sweep_search", "gibbs_draw", "move_row", "sweep_search"]


@numba.njit(cache=True, nogil=True)
def gibbs_draw(score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond):
    """Draw row ``i``'s column from its exact conditional given the other rows (``owner``:
    which row holds each exclusive column; ``(k, b)`` the current counts). ``cond[c]`` is left
    holding the log-weight change of moving row ``i`` from ``cur`` to ``c``.

    One uniform of numba's ``np.random`` stream is read (inverse-CDF over the columns)."""
    n_col = score.shape[1]
    best = -np.inf
    for c in range(n_col):
        if c < n_excl and owner[c] != -1 and owner[c] != i:
            cond[c] = -np.inf
            continue
        dk, db = count_delta(cur, c, n_obj, n_excl)
        v = score[i, c] - score[i, cur] + count_term[k + dk, b + db] - count_term[k, b]
        cond[c] = v
        best = max(best, v)
    tot = 0.0
    for c in range(n_col):
        tot += np.exp(cond[c] - best)
    u = np.random.random() * tot
    acc = 0.0
    new = n_col - 1
    for c in range(n_col):
        acc += np.exp(cond[c] - best)
        if u < acc:
            new = c
            break
    while cond[new] == -np.inf:  # guard against rounding at the top end
        new -= 1
    return new


@numba.njit(cache=True, nogil=True)
def move_row(state, owner, zobrist, h, k, b, i, new, n_obj, n_excl):
    """Move row ``i`` to column ``new`` in place (``state``, ``owner``); return the updated Zobrist
    hash and counts ``(h, k, b)``."""
    cur = state[i]
    dk, db = count_delta(cur, new, n_obj, n_excl)
    if cur < n_excl:
        owner[cur] = -1
    if new < n_excl:
        owner[new] = i
    state[i] = new
    return h ^ zobrist[i, cur] ^ zobrist[i, new], k + dk, b + db


@numba.njit(cache=True, nogil=True)
def _sweeps(score, n_obj, n_excl, count_term, state, first, n_sweeps, seed, zobrist, table, hashes, rows, logw,
            n_found):
    """Sweeps ``first .. n_sweeps`` in place, recording distinct states; stops early (returning
    the next sweep to run) when the buffers are full."""
    np.random.seed(seed)
    P, n_col = score.shape
    owner, k, b = owners_and_counts(state, n_obj, n_excl)
    h = np.int64(0)
    for i in range(P):
        h ^= zobrist[i, state[i]]
    lw = state_log_weight(score, state, n_obj, n_excl, count_term)
    cond = np.empty(n_col)
    capacity = rows.shape[0]
    if first == 0:
        n_found = lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
        first = 1
    for s in range(first, n_sweeps + 1):
        if n_found == capacity:
            return n_found, s
        for i in range(P):
            cur = state[i]
            new = gibbs_draw(score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond)
            if new != cur:
                lw += cond[new]
                h, k, b = move_row(state, owner, zobrist, h, k, b, i, new, n_obj, n_excl)
        n_found = lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found, n_sweeps + 1


def sweep_search(score, n_objects, n_exclusive, count_term, *, n_sweeps, seed):
    """The distinct samples of ``n_sweeps`` systematic-scan Gibbs sweeps, weighted exactly.

    Parameters are those of :func:`hypotrack.association.samplers.mcmc_search` (``score``,
    ``n_objects``, ``n_exclusive``, ``count_term``); the chain starts with every row on row
    option 0, which the problem's validation requires finite.

    Returns
    -------
    events : (K, m) int32 array
        The start and the distinct samples of the sweeps, in order of first visit (public codes).
    log_weights : (K,) array
        Their exact log-weights (the gather-sum, not the sweeps' running sums).
    """
    n_sweeps = check_int(n_sweeps, "n_sweeps", minimum=0)
    return checked_sweep_search(*check_problem(score, n_objects, n_exclusive, count_term), n_sweeps=n_sweeps,
                                seed=seed)


def checked_sweep_search(score, n_obj, n_excl, count_term, *, n_sweeps, seed):
    """:func:`sweep_search` of a problem already validated (:func:`.events.check_problem`) and a
    validated ``n_sweeps``: the path of :class:`hypotrack.hypotheses.GibbsGenerator`."""
    P = score.shape[0]
    if P == 0:
        ev = np.zeros((1, 0), dtype=np.int32)
        return ev, checked_event_log_weights(score, n_obj, n_excl, count_term, ev)
    state = np.full(P, n_excl, dtype=np.int64)  # every row on option 0 (GLMB: every object missed)
    ss = np.random.SeedSequence(int(seed))
    _, chain_seed = ss.generate_state(2, dtype=np.uint32)  # the first word once seeded the Zobrist keys
    visited = Visited(P, score.shape[1], min(n_sweeps + 1, 1 << 12))
    s = 0
    while s <= n_sweeps:
        visited.n, s = _sweeps(score, n_obj, n_excl, count_term, state, s, n_sweeps, int(chain_seed) + s,
                               visited.zobrist, visited.table, visited.hashes, visited.rows, visited.logw, visited.n)
        if s <= n_sweeps:
            visited.grow()
    events = to_events(visited.rows[: visited.n], n_excl)
    return events, checked_event_log_weights(score, n_obj, n_excl, count_term, events)

"""The Gibbs child generator of the δ-GLMB filter (Vo, Vo & Hoang 2017, Sec. IV, Algorithm 1).

On an association problem whose rows are the objects (:mod:`.weights_glmb`) the sampler draws
association maps ``γ`` by *systematic-scan* Gibbs: one sample is a sweep over the rows in order,
each row redrawn from its exact conditional given all the others' current values — every row
option (missed, died) and every return not held by another row. The published starting point
is "every object missed" (row option 0); the start is the first sample. Every sweep yields a
sample; the distinct samples (an open-addressing visited set, as in
:mod:`hypotrack.association.mcmc`) are returned with their **exact** weights (the sample
frequencies are not used), so the generator is a search like R-FISST's chain (DESIGN.md §4.3), and its
children are a subset of the exhaustive ones.

The conditional is computed for any count term ``φ`` (its change enters the conditional), so
the sampler runs on any :class:`~.AssociationProblem`; on the GLMB problem ``φ`` is constant and
the conditional is the row's ``η`` over the free columns, as published. The inner loop is
compiled with numba.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from .._validation import check_int
from ..association.mcmc import (
    _lookup_or_insert,
    _owners_and_counts,
    _state_log_weight,
    _to_events,
    _Visited,
    gibbs_draw,
    move_row,
)
from .association_problem import AssociationProblem
from .generators import ChildGenerator, top_k

__all__ = ["GibbsGenerator", "gibbs_search"]


@numba.njit(cache=True, nogil=True)
def _sweeps(score, n_obj, n_excl, count_term, state, first, n_sweeps, seed, zobrist, table, hashes, rows, logw,
            n_found):
    """Sweeps ``first .. n_sweeps`` in place, recording distinct states; stops early (returning
    the next sweep to run) when the buffers are full."""
    np.random.seed(seed)
    P, n_col = score.shape
    owner, k, b = _owners_and_counts(state, n_obj, n_excl)
    h = np.int64(0)
    for i in range(P):
        h ^= zobrist[i, state[i]]
    lw = _state_log_weight(score, state, n_obj, n_excl, count_term)
    cond = np.empty(n_col)
    capacity = rows.shape[0]
    if first == 0:
        n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
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
        n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found, n_sweeps + 1


def gibbs_search(problem: AssociationProblem, n_sweeps: int, seed: int):
    """The distinct samples of ``n_sweeps`` systematic-scan Gibbs sweeps from the all-option-0
    start (the start included), in public event codes, with exact log-weights (first-visit order)."""
    n_sweeps = check_int(n_sweeps, "n_sweeps", minimum=0)
    P = problem.n_returns
    if P == 0:
        ev = np.zeros((1, 0), dtype=np.int32)
        return ev, problem.log_weights(ev)
    score = np.ascontiguousarray(problem.score)
    n_excl = problem.n_exclusive
    if not np.all(np.isfinite(score[:, n_excl])):
        raise ValueError("row option 0 must be finite for every row: it is the sampler's starting point")
    ct = np.ascontiguousarray(problem.count_term)
    state = np.full(P, n_excl, dtype=np.int64)  # every row on option 0 (GLMB: every object missed)
    ss = np.random.SeedSequence(int(seed))
    key_seed, chain_seed = ss.generate_state(2, dtype=np.uint32)
    visited = _Visited(P, score.shape[1], min(n_sweeps + 1, 1 << 12), key_seed)
    s = 0
    while s <= n_sweeps:
        visited.n, s = _sweeps(score, problem.n_objects, n_excl, ct, state, s, n_sweeps, int(chain_seed) + s,
                               visited.zobrist, visited.table, visited.hashes, visited.rows, visited.logw, visited.n)
        if s <= n_sweeps:
            visited.grow()
    events = _to_events(visited.rows[: visited.n], n_excl)
    return events, problem.log_weights(events)  # the gather-sum, not the running sum: exact, bytewise


@dataclass(frozen=True)
class GibbsGenerator(ChildGenerator):
    """The distinct samples of ``n_sweeps`` systematic Gibbs sweeps, weighted exactly.

    Parameters
    ----------
    n_sweeps : int
        Samples per parent (each a sweep over all rows: ``n_sweeps × rows`` conditional draws), at
        least 1: with none, every child is the all-missed start and no measurement is ever used.
    """

    n_sweeps: int = 1000
    name = "gibbs"

    def __post_init__(self):
        check_int(self.n_sweeps, "n_sweeps", minimum=1)

    def generate(self, problem, rng=None, keep=None):
        rng = np.random.default_rng(rng)
        events, lw = gibbs_search(problem, self.n_sweeps, int(rng.integers(2**31 - 1)))
        ok = np.isfinite(lw)
        events, lw = events[ok], lw[ok]
        sel = top_k(lw, keep)
        return events[sel].astype(np.int32), lw[sel]

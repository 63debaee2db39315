"""R-FISST's MCMC search over association events (document 000 Sec. III, Algorithm 1).

The chain walks on the association events of one parent hypothesis (:mod:`.events`: returns on
exclusive columns or row options, log-weight ``Σ_i score[i, a_i] + count_term[k, b]``). Three
proposals are offered:

``"paper"``
    Document 000 Sec. III-B: pick a return uniformly, pick a column uniformly; a return that
    already holds that column is moved to clutter; Metropolis test ``U < w'/w``. The proposal
    is **not** symmetric (the displaced return cannot come back in one step), so visit counts
    are not probabilities.
``"symmetric"``
    The same pick, but the two returns *swap* columns, which makes the proposal symmetric and
    the chain a proper Metropolis sampler of ``w``.
``"gibbs"``
    Random-scan Gibbs (Vo, Vo & Hoang 2017 style): pick a return uniformly and redraw its
    column from its exact conditional given the other returns (:func:`.gibbs.gibbs_draw`).

Whatever the proposal, the chain is used as a *search* (DESIGN.md §4.3): the distinct events it
visits after burn-in (:mod:`.visited`) are returned with their exact log-weights; the caller
normalises those. Visit counts are never returned. :func:`neighbour_completion` then adds the
heavy single-move neighbours of what was found (a deterministic local search). Asked for the ``keep`` heaviest
only (the filter's cap), the search holds only what can be among them in the completion's last round and returns
exactly the ``keep`` heaviest of the search without ``keep`` (:func:`_complete`, :func:`top_k_first`).

The inner loops are compiled with numba (``cache=True``). The paper and symmetric chains read
numba's ``np.random`` stream from a local buffer (:mod:`hypotrack.association.mt19937`) and
reject forbidden pairs (``−inf`` scores) without evaluating the rest of the move: the same
uniforms and decisions as ``np.random.random()`` and the full test, measured 32 → 12 ns per
proposal on ssa50 parents (two shared cores).

References
----------
Faber, Chakravorty & Hussein (document 000), Algorithm 1 and Sec. III-B.
Vo, Vo & Hoang, "An efficient implementation of the generalized labeled multi-Bernoulli
filter", IEEE TSP 65 (2017) — the Gibbs variant.
"""

from __future__ import annotations

import numba
import numpy as np

from ..._validation import check_int, check_positive, check_probability
from ..mt19937 import N_DOUBLES, fill_doubles, seed_state
from .events import check_problem, count_delta, gather_sum, owners_and_counts, state_log_weight, to_events, to_state
from .gibbs import gibbs_draw, move_row
from .selection import heaviest_heap, top_k_first
from .visited import Visited, contains, insert_rows, lookup_or_insert

__all__ = ["MCMC_VARIANTS", "checked_search", "completion_limit", "mcmc_search", "neighbour_completion"]

MCMC_VARIANTS = ("paper", "symmetric", "gibbs")
_VARIANT_CODE = {v: i for i, v in enumerate(MCMC_VARIANTS)}
# Below this log-ratio a Metropolis test ``log(U) < delta`` can only pass for ``U = 0``: the smallest
# positive uniform of the 53-bit generator is 2^-53 (log = -36.74). Testing ``U == 0`` there gives
# the same decisions as the logarithm without computing it (most proposals of a chain that has found
# its mode are far below the threshold).
_LOG_U_FLOOR = -40.0


def completion_limit(m: int, memory_mb: float, returned: bool = False) -> int:
    """The events a visited set of ``m`` returns holds in ``memory_mb`` MiB: ``4 m + 32`` bytes an event (an int32 row,
    its log-weight and hash, two table slots; :mod:`.visited`), at least 2. ``returned``: every event held is also
    returned (no ``keep``), a copy of ``4 m + 8`` bytes more an event (its int32 row in public codes, its
    log-weight: :func:`.events.to_events`), which the budget then holds too."""
    m = check_int(m, "m", minimum=0)
    memory_mb = check_positive(memory_mb, "memory_mb")
    per_event = 4 * m + 32 + (4 * m + 8 if returned else 0)
    return max(2, int(memory_mb * 2**20 // per_event))


@numba.njit(cache=True, nogil=True)
def _chain_start(score, n_obj, n_excl, count_term, state, zobrist, burn_in, table, hashes, rows, logw):
    """Owners, counts, hash and log-weight of the starting event (recorded when ``burn_in == 0``)."""
    owner, k, b = owners_and_counts(state, n_obj, n_excl)
    h = np.int64(0)
    for i in range(state.shape[0]):
        h ^= zobrist[i, state[i]]
    lw = state_log_weight(score, state, n_obj, n_excl, count_term)
    n_found = 0
    if burn_in == 0:
        n_found = lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return owner, k, b, h, lw, n_found


@numba.njit(cache=True, nogil=True)
def _run_gibbs_chain(score, n_obj, n_excl, count_term, state, zobrist, n_steps, burn_in, seed,
                     table, hashes, rows, logw):
    """The Gibbs variant of :func:`_run_chain` (numba's ``np.random`` stream, as :func:`gibbs_draw`)."""
    np.random.seed(seed)
    m = state.shape[0]
    owner, k, b, h, lw, n_found = _chain_start(score, n_obj, n_excl, count_term, state, zobrist, burn_in,
                                               table, hashes, rows, logw)
    cond = np.empty(score.shape[1])
    for step in range(1, n_steps + 1):
        moved = False
        if m > 0:
            i = int(np.random.random() * m)
            cur = state[i]
            new = gibbs_draw(score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond)
            if new != cur:
                lw += cond[new]
                h, k, b = move_row(state, owner, zobrist, h, k, b, i, new, n_obj, n_excl)
                moved = True
        if step == burn_in or (moved and step > burn_in):
            n_found = lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found


@numba.njit(cache=True, nogil=True)
def _run_chain(score, n_obj, n_excl, count_term, state, zobrist, n_steps, burn_in, variant, seed,
               table, hashes, rows, logw):
    """Run the chain in place; return the number of distinct events recorded.

    The uniforms are numba's ``np.random`` stream seeded with ``seed``, read from a local
    buffer (:mod:`hypotrack.association.mt19937`, bit-identical and about twice as fast as
    ``np.random.random()`` per proposal). Column classes are looked up rather than branched on:
    ``owner`` covers every column (−1 on the row options), ``is_obj`` / ``is_birth`` give the
    count changes.
    """
    if variant == 2:
        return _run_gibbs_chain(score, n_obj, n_excl, count_term, state, zobrist, n_steps, burn_in, seed,
                                table, hashes, rows, logw)
    mt = seed_state(seed)
    buf = np.empty(N_DOUBLES)
    pos = N_DOUBLES
    m = state.shape[0]
    n_col = score.shape[1]
    clutter = n_excl  # row option 0
    owner_excl, k, b, h, lw, n_found = _chain_start(score, n_obj, n_excl, count_term, state, zobrist, burn_in,
                                                    table, hashes, rows, logw)
    owner = np.full(n_col, -1, dtype=np.int64)
    owner[:n_excl] = owner_excl
    is_obj = np.zeros(n_col, dtype=np.int64)
    is_obj[:n_obj] = 1
    is_birth = np.zeros(n_col, dtype=np.int64)
    is_birth[n_obj:n_excl] = 1
    for step in range(1, n_steps + 1):
        moved = False
        if m > 0:
            if pos >= N_DOUBLES:
                fill_doubles(mt, buf)
                pos = 0
            i = int(buf[pos] * m)
            cur = state[i]
            if pos + 1 >= N_DOUBLES:
                fill_doubles(mt, buf)
                pos = -1
            c = int(buf[pos + 1] * n_col)
            pos += 2
            if c != cur and score[i, c] == -np.inf:
                # Forbidden pair (out of view, gated out): Δ = −inf whatever the conflict and
                # count terms, so the test consumes its uniform and rejects (most proposals when
                # most of a parent's objects are out of view).
                if pos >= N_DOUBLES:
                    fill_doubles(mt, buf)
                    pos = 0
                pos += 1
            elif c != cur:
                delta = score[i, c] - score[i, cur]
                dk = is_obj[c] - is_obj[cur]
                db = is_birth[c] - is_birth[cur]
                i2 = owner[c]
                dest2 = clutter
                if i2 != -1:
                    # paper: the conflicting return goes to clutter; symmetric: it takes cur.
                    dest2 = clutter if variant == 0 else cur
                    delta += score[i2, dest2] - score[i2, c]
                    dk += is_obj[dest2] - is_obj[c]
                    db += is_birth[dest2] - is_birth[c]
                delta += count_term[k + dk, b + db] - count_term[k, b]
                accept = delta >= 0.0
                if not accept:
                    if pos >= N_DOUBLES:
                        fill_doubles(mt, buf)
                        pos = 0
                    u = buf[pos]
                    pos += 1
                    accept = (u == 0.0 and delta > -np.inf) if delta < _LOG_U_FLOOR else np.log(u) < delta
                if accept:
                    lw += delta
                    owner[cur] = -1
                    state[i] = c
                    h ^= zobrist[i, cur] ^ zobrist[i, c]
                    if i2 != -1:
                        state[i2] = dest2
                        h ^= zobrist[i2, c] ^ zobrist[i2, dest2]
                        if dest2 < n_excl:
                            owner[dest2] = i2
                    if c < n_excl:
                        owner[c] = i
                    k += dk
                    b += db
                    moved = True
        if step == burn_in or (moved and step > burn_in):
            n_found = lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found


@numba.njit(cache=True, nogil=True)
def _completion_round(score, ptr, cols, n_obj, n_excl, count_term, start, stop, threshold, zobrist, table, hashes,
                      rows, logw, n_found, cap, heap, n_heap, slack):
    """Expand visited events ``start .. stop-1``: add every single move of the paper's proposal
    (return ``i`` to column ``c``, a conflicting return to clutter) reaching ``threshold``.

    Only the columns ``cols[ptr[i]:ptr[i+1]]`` of return ``i`` (its finite scores, ascending: :func:`_finite_columns`)
    are tried: a move to a ``−inf`` column weighs ``−inf`` and never reaches the threshold, so the events added and
    their order are those of trying every column. ``heap`` (length ``K``, ``0``: none) is a min-heap of the ``K``
    heaviest weights held (its first ``n_heap`` entries): with ``K > 0`` a move lighter than the ``K``-th heaviest
    held by more than ``slack`` is not added — none of the ``K`` heaviest, in the last round (:func:`_complete`) —
    and each event added enters the heap.

    Returns ``(n_found, overflow, n_heap)``; on overflow (a new event and ``cap`` events already held) the buffers
    must grow (or, at the bound, the lightest events go: :func:`_complete`) and the round be re-run (events already
    added are recognised as visited).
    """
    m = rows.shape[1]
    n_top = heap.shape[0]
    state = np.empty(m, dtype=np.int64)
    for q in range(start, stop):
        lw = logw[q]
        if lw < threshold:
            continue
        for i in range(m):
            state[i] = rows[q, i]
        owner, k, b = owners_and_counts(state, n_obj, n_excl)
        h0 = hashes[q]
        for i in range(m):
            cur = state[i]
            for j in range(ptr[i], ptr[i + 1]):
                c = cols[j]
                if c == cur:
                    continue
                delta = score[i, c] - score[i, cur]
                dk, db = count_delta(cur, c, n_obj, n_excl)
                i2 = -1
                if c < n_excl and owner[c] != -1:
                    i2 = owner[c]
                    delta += score[i2, n_excl] - score[i2, c]
                    dk2, db2 = count_delta(c, n_excl, n_obj, n_excl)
                    dk += dk2
                    db += db2
                new = lw + delta + count_term[k + dk, b + db] - count_term[k, b]
                if not new >= threshold:
                    continue
                if n_top and n_heap == n_top and new < heap[0] - slack:
                    continue  # lighter than the K-th heaviest held: never among the K heaviest
                h = h0 ^ zobrist[i, cur] ^ zobrist[i, c]
                state[i] = c
                if i2 != -1:
                    h ^= zobrist[i2, c] ^ zobrist[i2, n_excl]
                    state[i2] = n_excl
                if n_found >= cap and not contains(h, state, table, hashes, rows):
                    return n_found, True, n_heap  # a new event and no room (an event already held needs none)
                added = lookup_or_insert(h, state, table, hashes, rows, logw, new, n_found)
                if n_top and added > n_found:  # the heap takes the new weight (sift up, or replace the root)
                    if n_heap < n_top:
                        p = n_heap
                        n_heap += 1
                        while p > 0 and heap[(p - 1) // 2] > new:
                            heap[p] = heap[(p - 1) // 2]
                            p = (p - 1) // 2
                        heap[p] = new
                    elif new > heap[0]:
                        p = 0
                        while 2 * p + 1 < n_top:
                            ch = 2 * p + 1
                            if ch + 1 < n_top and heap[ch + 1] < heap[ch]:
                                ch += 1
                            if heap[ch] >= new:
                                break
                            heap[p] = heap[ch]
                            p = ch
                        heap[p] = new
                n_found = added
                state[i] = cur
                if i2 != -1:
                    state[i2] = c
    return n_found, False, n_heap


def _finite_columns(score):
    """``(ptr, cols)``: the columns of each return's finite scores, ascending (CSR: return ``i``'s are
    ``cols[ptr[i]:ptr[i+1]]``), the only moves :func:`_completion_round` can add."""
    finite = np.isfinite(score)
    ptr = np.zeros(score.shape[0] + 1, dtype=np.int64)
    np.cumsum(finite.sum(axis=1), out=ptr[1:])
    return ptr, np.nonzero(finite)[1].astype(np.int64)


def _rounding_slack(score, count_term):
    """How much lighter than the ``K``-th heaviest held a move may be and still be added in the last round.

    A weight is found by sums along a path (the chain's moves, the rounds' single moves: ``lw + Δ``), so the same
    event met from two parents can carry weights a few rounding errors apart. A move skipped at its first meeting
    must stay below the ``K``-th heaviest when met again, or the later (slightly different) weight would stand in
    for the first one the completion without ``keep`` records. Every partial sum is bounded by
    ``S = Σ_i max_c |score[i, c]| + max |φ|`` (finite entries), each move rounds at most 8 times, so two paths of
    fewer than 10⁸ moves differ by less than ``10⁸ · 16 · 2⁻⁵³ S < 2·10⁻⁷ S``: a slack of ``10⁻⁶ (S + 1)`` covers
    them (and adds only the few moves that close to the ``K``-th, never among the ``K`` heaviest)."""
    a = np.abs(np.where(np.isfinite(score), score, 0.0)).max(axis=1).sum() if score.size else 0.0
    phi = count_term[np.isfinite(count_term)]
    return 1e-6 * (float(a) + (float(np.abs(phi).max()) if phi.size else 0.0) + 1.0)


def _complete(visited, score, n_obj, n_excl, count_term, rounds, relative_threshold, max_events=None, keep=None):
    """Run ``rounds`` completion rounds on ``visited`` (growing it on overflow), holding at most ``max_events``
    events (``None``: no bound); with ``keep``, only what can be among the ``keep`` heaviest in the last round.

    **keep.** The last round's events are not expanded, so one lighter than the ``keep``-th heaviest held when it is
    met (a weight that only rises) can never be among the ``keep`` heaviest found: the last round adds none of them
    (:func:`_completion_round`'s heap; lighter by more than :func:`_rounding_slack`, so that an event skipped when
    first met is, when met again, still below the ``keep``-th). Every event at least as heavy as the final
    ``keep``-th is added as without ``keep``, from the same parent at the same point (the rounds before are
    unchanged), so it has the same weight and the same order among the events held: the ``keep`` heaviest
    (:func:`top_k_first`) are those of the completion without ``keep``, exactly (tests: brute-force problems, with
    exact ties and weights one rounding apart at the ``keep``-th). Near the mode of a group of hundreds of returns the last
    round's single moves above the threshold number hundreds of thousands; ``keep`` of them are held.

    **The bound.** A round adds every single move reaching ``τ = max + log(relative_threshold)`` from the events
    above ``τ``; near the mode of a large group these number many times the group's returns per event, and the
    visited set (``4 m + 32`` bytes an event) can outgrow the memory. At ``max_events`` events the completion
    keeps the heaviest: the lightest events go — all those at or below the weight ``w*`` of the
    ``(max_events // 2 + 1)``-th heaviest held, so that at most half the bound is held after it — and ``τ``
    rises above ``w*`` (it only rises: no event that went can come back), and the round goes on from where
    the kept events stand. What is held is then every event found above the final ``τ``, in order of first
    visit: only events of the unbounded completion (its thresholds are never higher, so it expands every event
    this one does, in the same round or earlier), with their weights, and at least those the completion finds
    when run at the final ``τ`` from the start (the tests check both on brute-force problems). While the bound
    is not reached nothing changes (the same events, weights and order). The chain's own visits, when more than
    ``max_events``, are held until the completion's first overflow. Ties at the top beyond the bound (more than
    ``max_events // 2`` events of the very best weight) keep the first visited of them."""
    start = 0
    raised = -np.inf
    limit = visited.rows.shape[0] if max_events is None else int(max_events)
    ptr, cols = _finite_columns(score)
    no_heap = np.empty(0)
    slack = _rounding_slack(score, count_term) if keep is not None else 0.0
    for r in range(rounds):
        stop = visited.n
        if stop == start:
            break
        threshold = max(float(visited.logw[:stop].max()) + np.log(relative_threshold), raised)
        last = keep is not None and r == rounds - 1
        heap, n_heap = heaviest_heap(visited.logw[:visited.n], keep) if last else (no_heap, 0)
        while True:
            cap = visited.rows.shape[0] if max_events is None else min(visited.rows.shape[0], limit)
            n, overflow, n_heap = _completion_round(score, ptr, cols, n_obj, n_excl, count_term, start, stop,
                                                    threshold, visited.zobrist, visited.table, visited.hashes,
                                                    visited.rows, visited.logw, visited.n, cap, heap, n_heap,
                                                    slack)
            visited.n = n
            if not overflow:
                break
            if max_events is None or visited.rows.shape[0] < limit:
                visited.grow(None if max_events is None else limit)
                continue
            # at the bound: the lightest go, the threshold rises past them (the docstring)
            lw = visited.logw[:visited.n]
            half = max(int(max_events) // 2, 1)
            w_star = np.sort(lw)[::-1][min(half, len(lw) - 1)]
            kept = np.flatnonzero(lw > w_star)
            if len(kept) == 0:  # more than half the bound tied at the best: the first visited of them
                kept = np.flatnonzero(lw >= w_star)[:half]
            raised = threshold = max(threshold, float(np.nextafter(w_star, np.inf)))
            start, stop = int(np.searchsorted(kept, start)), int(np.searchsorted(kept, stop))
            visited.keep(kept)
            if last:  # the heap again, of the events still held
                heap, n_heap = heaviest_heap(visited.logw[:visited.n], keep)
        start = stop


def mcmc_search(score, n_objects, n_exclusive, count_term, *, n_steps, seed, burn_in=0, variant="paper",
                init=None, temperature=1.0, completion_rounds=0, completion_threshold=1e-9, completion_max_events=None,
                keep=None):
    """Search the association events of one parent with an MCMC chain.

    Parameters
    ----------
    score : (m, n_exclusive + n_options) array_like
        Log-scores: ``score[i, c]`` for return ``i`` on exclusive column ``c`` (objects first,
        then births; ``-inf`` = forbidden, e.g. gated out) and ``score[i, n_exclusive + t]``
        for row option ``t`` (``t = 0`` clutter, which must be finite).
    n_objects : int
        Columns ``0 .. n_objects-1`` are objects (counted by ``k``).
    n_exclusive : int
        Number of exclusive columns; columns ``n_objects .. n_exclusive-1`` are counted by ``b``.
    count_term : (n_objects + 1, n_exclusive - n_objects + 1) array_like
        ``φ[k, b]`` added to the gather-sum (``-inf`` forbids a count, e.g. two births).
    n_steps : int
        Number of proposals (document 000 Fig 15 uses 100,000).
    seed : int
        Seed of the chain's random numbers (the search is reproducible).
    burn_in : int, optional
        Steps before recording starts (the state at step ``burn_in`` is the first recorded).
    variant : {"paper", "symmetric", "gibbs"}
        Proposal (see the module docstring).
    init : (m,) array_like of int, optional
        Starting event in public codes; default all-clutter. It must have finite weight.
    temperature : float, optional
        The chain targets ``w^(1/T)``; ``T = 1`` is document 000's Metropolis test. ``T > 1``
        flattens the target so the search leaves the heaviest children more often; the
        returned weights are exact whatever ``T``.
    completion_rounds, completion_threshold : optional
        After the chain, :func:`neighbour_completion` (0 rounds: the chain's visits only).
    completion_max_events : int, optional
        The completion's bound: it never holds more events than this, keeping the heaviest (:func:`_complete`;
        e.g. :func:`completion_limit` of a memory budget); ``None`` (default): no bound.
    keep : int, optional
        Return only the ``keep`` heaviest events found, best first (ties: the first visited, :func:`top_k_first`):
        the same events and weights as the ``keep`` heaviest of the search without ``keep``, held without the
        light events of the completion's last round (:func:`_complete`). ``None`` (default): every event.

    Returns
    -------
    events : (K, m) int32 array
        Distinct events visited after burn-in, in order of first visit (public codes), then
        those added by the completion (with ``keep``: the ``keep`` heaviest, best first).
    log_weights : (K,) array
        Their exact log-weights.
    """
    score, n_obj, n_excl, count_term = check_problem(score, n_objects, n_exclusive, count_term)
    n_steps = check_int(n_steps, "n_steps", minimum=0)
    burn_in = check_int(burn_in, "burn_in", minimum=0, maximum=n_steps)
    seed = check_int(seed, "seed", minimum=0)
    if variant not in _VARIANT_CODE:
        raise ValueError(f"variant must be one of {MCMC_VARIANTS}, got {variant!r}")
    temperature = check_positive(temperature, "temperature")
    completion_rounds = check_int(completion_rounds, "completion_rounds", minimum=0)
    completion_threshold = check_probability(completion_threshold, "completion_threshold", low_open=True,
                                             high_open=True)
    if completion_max_events is not None:
        completion_max_events = check_int(completion_max_events, "completion_max_events", minimum=1)
    if keep is not None:
        keep = check_int(keep, "keep", minimum=1)
    m, n_col = score.shape
    if init is None:
        state = np.full(m, n_excl, dtype=np.int64)
    else:
        init = np.asarray(init)
        if init.shape != (m,):
            raise ValueError(f"init must have shape ({m},), got {init.shape}")
        # Codes n_exclusive.. are no column (reading them as row options would be silent nonsense).
        if init.size and (init.min() < n_excl - n_col or init.max() >= n_excl):
            raise ValueError(f"init codes must lie in [{n_excl - n_col}, {n_excl - 1}], "
                             f"got [{init.min()}, {init.max()}]")
        state = to_state(init, n_excl)
        excl = state[state < n_excl]
        if len(np.unique(excl)) != len(excl):
            raise ValueError("init assigns two returns to the same exclusive column")
    return checked_search(score, n_obj, n_excl, count_term, state, n_steps=n_steps, burn_in=burn_in, seed=seed,
                          variant=variant, temperature=temperature, completion_rounds=completion_rounds,
                          completion_threshold=completion_threshold, completion_max_events=completion_max_events,
                          keep=keep)


def checked_search(score, n_obj, n_excl, count_term, state, *, n_steps, burn_in, seed, variant, temperature,
                   completion_rounds, completion_threshold, completion_max_events=None, keep=None):
    """:func:`mcmc_search` from a validated problem (:func:`.events.check_problem`), validated options
    (``keep`` ``None`` or a positive int) and a starting ``state`` in internal column codes
    (:func:`.events.to_state`): the per-parent path of :class:`hypotrack.hypotheses.MCMCGenerator`, which builds
    these once per problem."""
    m, n_col = score.shape
    if not np.isfinite(state_log_weight(score, state, n_obj, n_excl, count_term)):
        raise ValueError("init must have a finite log-weight (a feasible event)")
    ss = np.random.SeedSequence(seed)
    _, chain_seed = ss.generate_state(2, dtype=np.uint32)  # the first word once seeded the Zobrist keys
    visited = Visited(m, n_col, n_steps - burn_in + 1)
    found = _search(visited, score, n_obj, n_excl, count_term, state, n_steps, burn_in, variant, chain_seed,
                    temperature, completion_rounds, completion_threshold, completion_max_events, keep)
    visited.release()
    return found


def _search(visited, score, n_obj, n_excl, count_term, state, n_steps, burn_in, variant, chain_seed, temperature,
            completion_rounds, completion_threshold, completion_max_events=None, keep=None):
    tempered = temperature != 1.0
    visited.n = _run_chain(score / temperature if tempered else score, n_obj, n_excl,
                           count_term / temperature if tempered else count_term, state, visited.zobrist, n_steps,
                           burn_in, _VARIANT_CODE[variant], int(chain_seed), visited.table, visited.hashes,
                           visited.rows, visited.logw)
    if tempered:  # the chain recorded tempered weights: record the exact ones
        gather_sum(score, to_events(visited.rows[: visited.n], n_excl), n_obj, n_excl, count_term,
                   visited.logw[: visited.n])
    if completion_rounds:
        _complete(visited, score, n_obj, n_excl, count_term, completion_rounds, completion_threshold,
                  completion_max_events, keep)
    return _found(visited, n_excl, keep)


def _found(visited, n_excl, keep):
    """The events held (public codes) and their log-weights: all, in order of first visit, or the ``keep``
    heaviest, best first (:func:`top_k_first`); only those rows are converted."""
    if keep is None:
        return to_events(visited.rows[: visited.n], n_excl), visited.logw[: visited.n].copy()
    sel = top_k_first(visited.logw[: visited.n], keep)
    return to_events(visited.rows[sel], n_excl), visited.logw[sel]


def neighbour_completion(score, n_objects, n_exclusive, count_term, events, log_weights, *, rounds=2,
                         relative_threshold=1e-9, max_events=None, keep=None):
    """Add the heavy single-move neighbours of found events (a deterministic local search).

    A Metropolis chain visits a child of relative weight ``r`` next to the mode only about
    ``r / (m (C + T))`` times per step, so children a million times lighter than the mode are
    rarely met in 10⁵ steps although they matter at the 10⁻⁶ level. This completes the chain's
    search: every single move of the paper's proposal (return ``i`` to column ``c``, conflicting
    return to clutter) from each found event whose weight is at least ``relative_threshold``
    times the best is evaluated exactly, and those reaching that threshold are added;
    ``rounds`` repeats this from the newly added events. Compiled; duplicates are recognised
    through the same Zobrist-hashed visited set as the chain's.

    ``max_events`` (optional, default ``None``: none) bounds the events held: at the bound the lightest go and
    the threshold rises past them (:func:`_complete`), so what is returned is every event found above the final
    threshold, the heaviest; below the bound nothing changes. ``keep`` (optional): return only the ``keep``
    heaviest, best first — those of the completion without ``keep``, the last round's lighter events never held
    (:func:`_complete`).

    Returns the augmented ``(events, log_weights)``, the given (distinct) events first (with ``keep``: the ``keep``
    heaviest, best first, ties the first visited).
    """
    score, n_obj, n_excl, count_term = check_problem(score, n_objects, n_exclusive, count_term)
    rounds = check_int(rounds, "rounds", minimum=0)
    tau = check_probability(relative_threshold, "relative_threshold", low_open=True, high_open=True)
    if max_events is not None:
        max_events = check_int(max_events, "max_events", minimum=1)
    if keep is not None:
        keep = check_int(keep, "keep", minimum=1)
    events = np.asarray(events)
    lw = np.asarray(log_weights, dtype=float)
    m, n_col = score.shape
    if rounds == 0 or len(lw) == 0 or m == 0:
        sel = slice(None) if keep is None else top_k_first(lw, keep)
        return events.astype(np.int32)[sel], lw[sel]
    visited = Visited(m, n_col, 4 * len(lw) + 64)
    visited.rows[: len(lw)] = to_state(events, n_excl)
    visited.logw[: len(lw)] = lw
    visited.n = insert_rows(visited.rows, visited.logw, len(lw), visited.zobrist, visited.table, visited.hashes)
    _complete(visited, score, n_obj, n_excl, count_term, rounds, tau, max_events, keep)
    return _found(visited, n_excl, keep)

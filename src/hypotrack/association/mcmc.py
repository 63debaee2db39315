"""R-FISST's MCMC search over association events (document 000 Sec. III, Algorithm 1).

The chain walks on association events of one parent hypothesis. An event assigns each of the
``m`` returns either to an *exclusive* column (an object, or a birth region: at most one return
per column) or to a *row option* that any number of returns may take (option 0 is clutter;
HOMHT's "new target seeded at this return" is option 1). Its log-weight has the form shared by
every weight model of :mod:`hypotrack.hypotheses`::

    log w(a) = Σ_i score[i, a_i] + count_term[k(a), b(a)],

with ``k`` the number of returns on object columns (``0 .. n_objects-1``) and ``b`` the number on
the other exclusive columns (births). Three proposals are offered:

``"paper"``
    Document 000 Sec. III-B: pick a return uniformly, pick a column uniformly; a return that
    already holds that column is moved to clutter; Metropolis test ``U < w'/w``. The proposal
    is **not** symmetric (the displaced return cannot come back in one step), so visit counts
    are not probabilities.
``"symmetric"``
    The same pick, but the two returns *swap* columns, which makes the proposal symmetric and
    the chain a proper Metropolis sampler of ``w``.
``"gibbs"``
    Systematic-scan-free Gibbs (Vo, Vo & Hoang 2017 style): pick a return uniformly and redraw
    its column from its exact conditional given the other returns.

Whatever the proposal, the chain is used as a *search* (DESIGN.md §4.3): the distinct events it
visits after burn-in are returned with their exact log-weights; the caller normalises those.
Visit counts are never returned.

The inner loop is compiled with numba (``cache=True``); a visited-set is kept in an
open-addressing hash table keyed by an incrementally updated Zobrist hash, with an exact row
comparison on every hash hit, so two different events are never merged. The paper and
symmetric chains read numba's ``np.random`` stream from a local buffer (:mod:`.mt19937`) and
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

import threading

import numba
import numpy as np

from .._validation import check_int, check_positive, check_probability
from .mt19937 import N_DOUBLES, fill_doubles, seed_state

__all__ = [
    "MCMC_VARIANTS",
    "check_problem",
    "checked_event_log_weights",
    "checked_search",
    "event_log_weights",
    "mcmc_search",
    "neighbour_completion",
    "to_state",
]

MCMC_VARIANTS = ("paper", "symmetric", "gibbs")
_VARIANT_CODE = {v: i for i, v in enumerate(MCMC_VARIANTS)}
# Below this log-ratio a Metropolis test ``log(U) < delta`` can only pass for ``U = 0``: the smallest
# positive uniform of the 53-bit generator is 2^-53 (log = -36.74). Testing ``U == 0`` there gives
# the same decisions as the logarithm without computing it (most proposals of a chain that has found
# its mode are far below the threshold).
_LOG_U_FLOOR = -40.0


@numba.njit(cache=True, nogil=True)
def _state_log_weight(score, state, n_obj, n_excl, count_term):
    total = 0.0
    k = 0
    b = 0
    for i in range(state.shape[0]):
        c = state[i]
        total += score[i, c]
        if c < n_obj:
            k += 1
        elif c < n_excl:
            b += 1
    return total + count_term[k, b]


@numba.njit(cache=True, nogil=True, inline="always")
def _count_delta(cur, new, n_obj, n_excl):
    """Change of (k, b) when one return moves from column ``cur`` to column ``new``."""
    dk = 0
    db = 0
    if cur < n_obj:
        dk -= 1
    elif cur < n_excl:
        db -= 1
    if new < n_obj:
        dk += 1
    elif new < n_excl:
        db += 1
    return dk, db


@numba.njit(cache=True, nogil=True)
def gibbs_draw(score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond):
    """Draw row ``i``'s column from its exact conditional given the other rows (``owner``:
    which row holds each exclusive column; ``(k, b)`` the current counts). ``cond[c]`` is left
    holding the log-weight change of moving row ``i`` from ``cur`` to ``c``."""
    n_col = score.shape[1]
    best = -np.inf
    for c in range(n_col):
        if c < n_excl and owner[c] != -1 and owner[c] != i:
            cond[c] = -np.inf
            continue
        dk, db = _count_delta(cur, c, n_obj, n_excl)
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
    """Move row ``i`` to column ``new`` in place; return the updated hash and counts."""
    cur = state[i]
    dk, db = _count_delta(cur, new, n_obj, n_excl)
    if cur < n_excl:
        owner[cur] = -1
    if new < n_excl:
        owner[new] = i
    state[i] = new
    return h ^ zobrist[i, cur] ^ zobrist[i, new], k + dk, b + db


@numba.njit(cache=True, nogil=True)
def _owners_and_counts(state, n_obj, n_excl):
    """Which return holds each exclusive column, and the counts ``(k, b)`` of an event."""
    owner = np.full(n_excl, -1, dtype=np.int64)
    k = 0
    b = 0
    for i in range(state.shape[0]):
        c = state[i]
        if c < n_excl:
            owner[c] = i
        if c < n_obj:
            k += 1
        elif c < n_excl:
            b += 1
    return owner, k, b


@numba.njit(cache=True, nogil=True)
def _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found):
    """Insert ``state`` in the visited set unless present; return the new ``n_found``."""
    mask = table.shape[0] - 1
    pos = h & mask
    m = state.shape[0]
    while table[pos] != -1:
        idx = table[pos]
        if hashes[idx] == h:
            same = True
            for i in range(m):
                if rows[idx, i] != state[i]:
                    same = False
                    break
            if same:
                return n_found
        pos = (pos + 1) & mask
    table[pos] = n_found
    hashes[n_found] = h
    for i in range(m):
        rows[n_found, i] = state[i]
    logw[n_found] = lw
    return n_found + 1


@numba.njit(cache=True, nogil=True)
def _chain_start(score, n_obj, n_excl, count_term, state, zobrist, burn_in, table, hashes, rows, logw):
    """Owners, counts, hash and log-weight of the starting event (recorded when ``burn_in == 0``)."""
    owner, k, b = _owners_and_counts(state, n_obj, n_excl)
    h = np.int64(0)
    for i in range(state.shape[0]):
        h ^= zobrist[i, state[i]]
    lw = _state_log_weight(score, state, n_obj, n_excl, count_term)
    n_found = 0
    if burn_in == 0:
        n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
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
            n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found


@numba.njit(cache=True, nogil=True)
def _run_chain(score, n_obj, n_excl, count_term, state, zobrist, n_steps, burn_in, variant, seed,
               table, hashes, rows, logw):
    """Run the chain in place; return the number of distinct events recorded.

    The uniforms are numba's ``np.random`` stream seeded with ``seed``, read from a local
    buffer (:mod:`.mt19937`, bit-identical and about twice as fast as ``np.random.random()``
    per proposal). Column classes are looked up rather than branched on: ``owner`` covers every
    column (−1 on the row options), ``is_obj`` / ``is_birth`` give the count changes.
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
            n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found)
    return n_found


@numba.njit(cache=True, nogil=True)
def _completion_round(score, n_obj, n_excl, count_term, start, stop, threshold, zobrist, table, hashes, rows, logw,
                      n_found):
    """Expand visited events ``start .. stop-1``: add every single move of the paper's proposal
    (return ``i`` to column ``c``, a conflicting return to clutter) reaching ``threshold``.

    Returns ``(n_found, overflow)``; on overflow the buffers must grow and the round be re-run
    (events already added are recognised as visited).
    """
    m = rows.shape[1]
    n_col = score.shape[1]
    cap = rows.shape[0]
    state = np.empty(m, dtype=np.int64)
    for q in range(start, stop):
        lw = logw[q]
        if lw < threshold:
            continue
        for i in range(m):
            state[i] = rows[q, i]
        owner, k, b = _owners_and_counts(state, n_obj, n_excl)
        h0 = hashes[q]
        for i in range(m):
            cur = state[i]
            for c in range(n_col):
                if c == cur:
                    continue
                delta = score[i, c] - score[i, cur]
                dk, db = _count_delta(cur, c, n_obj, n_excl)
                i2 = -1
                if c < n_excl and owner[c] != -1:
                    i2 = owner[c]
                    delta += score[i2, n_excl] - score[i2, c]
                    dk2, db2 = _count_delta(c, n_excl, n_obj, n_excl)
                    dk += dk2
                    db += db2
                new = lw + delta + count_term[k + dk, b + db] - count_term[k, b]
                if not new >= threshold:
                    continue
                if n_found >= cap:
                    return n_found, True
                h = h0 ^ zobrist[i, cur] ^ zobrist[i, c]
                state[i] = c
                if i2 != -1:
                    h ^= zobrist[i2, c] ^ zobrist[i2, n_excl]
                    state[i2] = n_excl
                n_found = _lookup_or_insert(h, state, table, hashes, rows, logw, new, n_found)
                state[i] = cur
                if i2 != -1:
                    state[i2] = c
    return n_found, False


@numba.njit(cache=True, nogil=True)
def _clear_table(table, hashes, n):
    """Reset the slots of the ``n`` recorded events to empty (−1): the table is reusable."""
    mask = table.shape[0] - 1
    for q in range(n):
        pos = hashes[q] & mask
        while table[pos] != q:  # q sits on its probe path; emptied slots are stepped over
            pos = (pos + 1) & mask
        table[pos] = -1


@numba.njit(cache=True, nogil=True)
def _insert_rows(rows, logw, n, zobrist, table, hashes):
    """(Re)build the visited set from ``n`` distinct rows; return ``n``."""
    found = 0
    for q in range(n):
        h = np.int64(0)
        for i in range(rows.shape[1]):
            h ^= zobrist[i, rows[q, i]]
        found = _lookup_or_insert(h, rows[q].copy(), table, hashes, rows, logw, logw[q], found)
    return found


@numba.njit(cache=True, nogil=True)
def _gather_sum(score, events, n_obj, n_excl, count_term, out):
    """Exact log-weights of many events: a gather-sum over ``score`` plus the count term.

    ``events`` uses the public codes (``>= 0`` exclusive column, ``-1 - t`` row option ``t``).
    """
    m = events.shape[1]
    for e in range(events.shape[0]):
        total = 0.0
        k = 0
        b = 0
        for i in range(m):
            c = np.int64(events[e, i])
            if c < 0:
                total += score[i, n_excl - 1 - c]
            else:
                total += score[i, c]
                if c < n_obj:
                    k += 1
                elif c < n_excl:
                    b += 1
        out[e] = total + count_term[k, b]


def check_problem(score, n_objects, n_exclusive, count_term):
    """Validated ``(score, n_objects, n_exclusive, count_term)`` (float, C-contiguous)."""
    score = np.ascontiguousarray(score, dtype=float)
    if score.ndim != 2:
        raise ValueError(f"score must be a 2-D (m, n_exclusive + n_options) array, got shape {score.shape}")
    m, n_col = score.shape
    n_excl = check_int(n_exclusive, "n_exclusive", minimum=0, maximum=max(n_col - 1, 0))
    n_obj = check_int(n_objects, "n_objects", minimum=0, maximum=n_excl)
    if m and n_col - n_excl < 1:
        raise ValueError("score needs at least one row-option column (clutter) after the exclusive columns")
    if not (score < np.inf).all():  # one pass: NaN and +inf both fail the comparison
        raise ValueError("score must not contain NaN or +inf (use -inf for forbidden pairs)")
    if m and not np.all(np.isfinite(score[:, n_excl])):
        raise ValueError("score's clutter column (index n_exclusive) must be finite: clutter must always be possible")
    count_term = np.ascontiguousarray(count_term, dtype=float)
    if count_term.shape != (n_obj + 1, n_excl - n_obj + 1):
        raise ValueError(
            f"count_term must have shape (n_objects + 1, n_exclusive - n_objects + 1) = "
            f"{(n_obj + 1, n_excl - n_obj + 1)}, got {count_term.shape}"
        )
    if not (count_term < np.inf).all():
        raise ValueError("count_term must not contain NaN or +inf")
    return score, n_obj, n_excl, count_term


def to_state(events, n_excl):
    ev = np.asarray(events, dtype=np.int64)
    return np.where(ev < 0, n_excl - 1 - ev, ev)


def _to_events(states, n_excl):
    st = np.asarray(states, dtype=np.int64)
    return np.where(st >= n_excl, n_excl - 1 - st, st).astype(np.int32)


def event_log_weights(score, n_objects, n_exclusive, count_term, events) -> np.ndarray:
    """Exact log-weights ``Σ_i score[i, a_i] + count_term[k, b]`` of events ``(E, m)``.

    Events use the public codes: ``a_i >= 0`` an exclusive column, ``a_i = -1 - t`` row option
    ``t`` (``-1`` clutter). Vectorised (compiled gather-sum), suitable for millions of events.
    """
    score, n_obj, n_excl, count_term = check_problem(score, n_objects, n_exclusive, count_term)
    events = np.asarray(events)
    if events.ndim != 2 or events.shape[1] != score.shape[0]:
        raise ValueError(f"events must have shape (E, {score.shape[0]}), got {events.shape}")
    return checked_event_log_weights(score, n_obj, n_excl, count_term, events)


def checked_event_log_weights(score, n_obj, n_excl, count_term, events) -> np.ndarray:
    """:func:`event_log_weights` of a problem already validated (:func:`check_problem`) and an
    ``(E, m)`` events array; the event codes are still checked."""
    out = np.empty(events.shape[0])
    if events.size:
        lo, hi = int(events.min()), int(events.max())
        if hi >= n_excl or lo < n_excl - score.shape[1]:
            raise ValueError(f"event codes must lie in [{n_excl - score.shape[1]}, {n_excl - 1}], got [{lo}, {hi}]")
    if events.shape[0]:
        _gather_sum(score, np.ascontiguousarray(events), n_obj, n_excl, count_term, out)
    return out


def mcmc_search(score, n_objects, n_exclusive, count_term, *, n_steps, seed, burn_in=0, variant="paper",
                init=None, temperature=1.0, completion_rounds=0, completion_threshold=1e-9):
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

    Returns
    -------
    events : (K, m) int32 array
        Distinct events visited after burn-in, in order of first visit (public codes), then
        those added by the completion.
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
                          completion_threshold=completion_threshold)


def checked_search(score, n_obj, n_excl, count_term, state, *, n_steps, burn_in, seed, variant, temperature,
                   completion_rounds, completion_threshold):
    """:func:`mcmc_search` from a validated problem (:func:`check_problem`), validated options and
    a starting ``state`` in internal column codes (:func:`to_state`): the per-parent path of
    :class:`hypotrack.hypotheses.MCMCGenerator`, which builds these once per problem."""
    m, n_col = score.shape
    if not np.isfinite(_state_log_weight(score, state, n_obj, n_excl, count_term)):
        raise ValueError("init must have a finite log-weight (a feasible event)")
    ss = np.random.SeedSequence(seed)
    _, chain_seed = ss.generate_state(2, dtype=np.uint32)  # the first word once seeded the Zobrist keys
    visited = _Visited(m, n_col, n_steps - burn_in + 1)
    found = _search(visited, score, n_obj, n_excl, count_term, state, n_steps, burn_in, variant, chain_seed,
                    temperature, completion_rounds, completion_threshold)
    visited.release()
    return found


def _search(visited, score, n_obj, n_excl, count_term, state, n_steps, burn_in, variant, chain_seed, temperature,
            completion_rounds, completion_threshold):
    tempered = temperature != 1.0
    visited.n = _run_chain(score / temperature if tempered else score, n_obj, n_excl,
                           count_term / temperature if tempered else count_term, state, visited.zobrist, n_steps,
                           burn_in, _VARIANT_CODE[variant], int(chain_seed), visited.table, visited.hashes,
                           visited.rows, visited.logw)
    if tempered:  # the chain recorded tempered weights: record the exact ones
        _gather_sum(score, _to_events(visited.rows[: visited.n], n_excl), n_obj, n_excl, count_term,
                    visited.logw[: visited.n])
    if completion_rounds:
        visited.complete(score, n_obj, n_excl, count_term, completion_rounds, completion_threshold)
    return _to_events(visited.rows[: visited.n], n_excl), visited.logw[: visited.n].copy()


_BUFFERS = threading.local()
_ZOBRIST_CACHE_SIZE = 256


def _zobrist(m, n_col):
    """Zobrist keys of an (m, n_col) problem. The visited set compares rows exactly on every hash hit,
    so the keys change only where events sit in the table, never which events are found or their
    order: they are drawn once per shape and reused (a chain per parent per scan would
    otherwise draw them tens of thousands of times)."""
    cache = getattr(_BUFFERS, "zobrist", None)
    if cache is None:
        cache = _BUFFERS.zobrist = {}
    key = (m, n_col)
    z = cache.get(key)
    if z is None:
        if len(cache) >= _ZOBRIST_CACHE_SIZE:
            cache.clear()
        z = cache[key] = np.random.default_rng(0).integers(
            np.iinfo(np.int64).min, np.iinfo(np.int64).max, size=(m, n_col), dtype=np.int64)
    return z


class _Visited:
    """Growable buffers of the visited set: rows (states), exact log-weights, hashes, table.

    The buffers of the last search of the same capacity are reused (per thread): :meth:`release`
    empties the table slots it used, so a search costs what it visits, not a fresh 2·capacity-slot
    table and row store (one per parent per scan).
    """

    def __init__(self, m, n_col, capacity, key_seed=None):  # key_seed: unused, see _zobrist
        self.zobrist = _zobrist(m, max(n_col, 1))
        self.n = 0
        self._alloc(m, max(int(capacity), 1))

    def _alloc(self, m, capacity):
        pool = getattr(_BUFFERS, "pool", None)
        if pool is not None and pool[0] == capacity and pool[1].size >= capacity * m:
            _, flat, self.logw, self.hashes, self.table = pool
            _BUFFERS.pool = None
        else:
            flat = np.empty(capacity * max(m, 1), dtype=np.int64)
            self.logw = np.empty(capacity)
            self.hashes = np.empty(capacity, dtype=np.int64)
            self.table = np.full(1 << int(2 * capacity - 1).bit_length(), -1, dtype=np.int64)
        self._flat = flat
        self.rows = flat[: capacity * m].reshape(capacity, m)

    def release(self):
        """Empty the table and hand the buffers to the next search of this thread."""
        _clear_table(self.table, self.hashes, self.n)
        _BUFFERS.pool = (self.rows.shape[0], self._flat, self.logw, self.hashes, self.table)
        self.n = 0

    def grow(self):
        rows, logw, n = self.rows[: self.n].copy(), self.logw[: self.n].copy(), self.n
        self._alloc(rows.shape[1], 2 * self.rows.shape[0])
        self.rows[:n], self.logw[:n] = rows, logw
        self.n = _insert_rows(self.rows, self.logw, n, self.zobrist, self.table, self.hashes)

    def complete(self, score, n_obj, n_excl, count_term, rounds, relative_threshold):
        start = 0
        for _ in range(rounds):
            stop = self.n
            if stop == start:
                break
            threshold = float(self.logw[:stop].max()) + np.log(relative_threshold)
            while True:
                n, overflow = _completion_round(score, n_obj, n_excl, count_term, start, stop, threshold,
                                                self.zobrist, self.table, self.hashes, self.rows, self.logw, self.n)
                self.n = n
                if not overflow:
                    break
                self.grow()
            start = stop


def neighbour_completion(score, n_objects, n_exclusive, count_term, events, log_weights, *, rounds=2,
                         relative_threshold=1e-9):
    """Add the heavy single-move neighbours of found events (a deterministic local search).

    A Metropolis chain visits a child of relative weight ``r`` next to the mode only about
    ``r / (m (C + T))`` times per step, so children a million times lighter than the mode are
    rarely met in 10⁵ steps although they matter at the 10⁻⁶ level. This completes the chain's
    search: every single move of the paper's proposal (return ``i`` to column ``c``, conflicting
    return to clutter) from each found event whose weight is at least ``relative_threshold``
    times the best is evaluated exactly, and those reaching that threshold are added;
    ``rounds`` repeats this from the newly added events. Compiled; duplicates are recognised
    through the same Zobrist-hashed visited set as the chain's.

    Returns the augmented ``(events, log_weights)``, the given (distinct) events first.
    """
    score, n_obj, n_excl, count_term = check_problem(score, n_objects, n_exclusive, count_term)
    rounds = check_int(rounds, "rounds", minimum=0)
    tau = check_probability(relative_threshold, "relative_threshold", low_open=True, high_open=True)
    events = np.asarray(events)
    lw = np.asarray(log_weights, dtype=float)
    m, n_col = score.shape
    if rounds == 0 or len(lw) == 0 or m == 0:
        return events.astype(np.int32), lw
    visited = _Visited(m, n_col, 4 * len(lw) + 64)
    visited.rows[: len(lw)] = to_state(events, n_excl)
    visited.logw[: len(lw)] = lw
    visited.n = _insert_rows(visited.rows, visited.logw, len(lw), visited.zobrist, visited.table, visited.hashes)
    visited.complete(score, n_obj, n_excl, count_term, rounds, tau)
    return _to_events(visited.rows[: visited.n], n_excl), visited.logw[: visited.n].copy()

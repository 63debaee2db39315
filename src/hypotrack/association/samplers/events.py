"""Association events of one parent: their two encodings, the problem they live in, their weights.

An event assigns each of the ``m`` returns either to an *exclusive* column (an object, or a
birth region: at most one return per column) or to a *row option* that any number of returns
may take (option 0 is clutter; HOMHT's "new target seeded at this return" is option 1). Its
log-weight has the form shared by every weight model of :mod:`hypotrack.hypotheses`::

    log w(a) = Σ_i score[i, a_i] + count_term[k(a), b(a)],

with ``k`` the number of returns on object columns (``0 .. n_objects-1``) and ``b`` the number on
the other exclusive columns (births).

Two encodings of the same event:

* the **public codes** (every caller's): ``a_i >= 0`` an exclusive column, ``a_i = -1 - t`` row
  option ``t`` (``-1`` clutter);
* the **state** (the samplers' inner loops): the column index of ``score`` itself,
  ``0 .. n_exclusive-1`` exclusive, ``n_exclusive + t`` row option ``t``.

:func:`to_state` and :func:`to_events` convert; the compiled kernels here (weight of a state,
owners and counts, the count change of one move, the gather-sum over many events) are shared
by the MCMC chain (:mod:`.chain`) and the Gibbs sweeps (:mod:`.gibbs`).

Examples
--------
>>> import numpy as np
>>> to_state(np.array([[1, -1, -2]]), n_excl=2)
array([[1, 2, 3]])
>>> to_events(np.array([[1, 2, 3]]), n_excl=2)
array([[ 1, -1, -2]], dtype=int32)
"""

from __future__ import annotations

import numba
import numpy as np

from ..._validation import check_int

__all__ = [
    "check_problem",
    "checked_event_log_weights",
    "count_delta",
    "event_log_weights",
    "gather_sum",
    "owners_and_counts",
    "state_log_weight",
    "to_events",
    "to_state",
]


def to_state(events, n_excl):
    """Public event codes (``>= 0`` exclusive column, ``-1 - t`` row option ``t``) to state codes
    (the column of ``score``: row option ``t`` is column ``n_excl + t``), as int64."""
    ev = np.asarray(events, dtype=np.int64)
    return np.where(ev < 0, n_excl - 1 - ev, ev)


def to_events(states, n_excl):
    """State codes (columns of ``score``) back to the public event codes, as int32: the inverse
    of :func:`to_state`."""
    # One int32 copy, rewritten in place: the visited set's rows of a large group are gigabytes, and an int64
    # intermediate (np.where over int64) would double, then triple, them.
    out = np.array(states, dtype=np.int32)  # column indices, far below 2³¹
    np.subtract(np.int32(n_excl - 1), out, out=out, where=out >= n_excl)
    return out


@numba.njit(cache=True, nogil=True)
def state_log_weight(score, state, n_obj, n_excl, count_term):
    """Log-weight ``Σ_i score[i, state[i]] + count_term[k, b]`` of one event in state codes
    (``k`` returns on columns below ``n_obj``, ``b`` on the other exclusive columns)."""
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
def count_delta(cur, new, n_obj, n_excl):
    """Change ``(dk, db)`` of the counts when one return moves from column ``cur`` to column ``new``
    (``k``: object columns below ``n_obj``; ``b``: the other exclusive columns below ``n_excl``)."""
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
def owners_and_counts(state, n_obj, n_excl):
    """Which return holds each exclusive column (``-1``: none), and the counts ``(k, b)`` of an
    event in state codes."""
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
def gather_sum(score, events, n_obj, n_excl, count_term, out):
    """Exact log-weights of many events, written to ``out``: a gather-sum over ``score`` plus the
    count term.

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
        gather_sum(score, np.ascontiguousarray(events), n_obj, n_excl, count_term, out)
    return out

"""Exhaustive enumeration of data-association events.

An event for ``n`` objects and ``m`` returns is an int vector ``a`` of length ``m`` with
``a[i] = j`` (return ``i`` from object ``j``) or ``a[i] = -1`` (clutter); the non-negative entries
are distinct. Events are produced in lexicographic order of ``(a[0], a[1], ...)`` with ``-1``
smallest, so the all-clutter event comes first and the order is the same on every run.

The generator is an odometer: from one event, the next one is found by releasing the last
return's object and moving it to the next free, gated object, carrying to the previous return
when none is left; returns after the carry position restart at clutter, which is always
feasible. Each step is amortised O(1) for dense gating, so a compiled (numba) loop writes events
at memory speed; the count is known exactly beforehand (:mod:`.counting`), so the output is
allocated once and a budget is enforced before any allocation.

References
----------
Paper 000 (Faber, Chakravorty & Hussein), Eq. 4 (the number of events) and Sec. II-C;
paper 004 (lecture notes), "Association Hypotheses" (iterating over measurements).
"""

from __future__ import annotations

from collections.abc import Iterator

import numba
import numpy as np

from .._validation import check_int
from .counting import as_validation, count_associations, count_gated_capped

__all__ = ["EnumerationBudgetError", "enumerate_associations", "iter_association_chunks", "event_dtype"]


class EnumerationBudgetError(ValueError):
    """The requested enumeration holds more events than the caller's budget allows.

    Attributes
    ----------
    count : int
        Number of events requested (a lower bound ``> budget`` when counting was capped).
    budget : int
        The ``max_events`` limit that was exceeded.
    """

    def __init__(self, count: int, budget: int, exact: bool = True):
        self.count = count
        self.budget = budget
        what = f"{count:,}" if exact else f"more than {budget:,}"
        super().__init__(
            f"enumeration would produce {what} association events, exceeding max_events={budget:,}; "
            "raise max_events, gate more tightly, or sample instead of enumerating"
        )


def event_dtype(n_tracks: int) -> np.dtype:
    """Smallest signed integer dtype that holds object indices ``-1 .. n_tracks - 1``."""
    n_tracks = check_int(n_tracks, "n_tracks", minimum=0)
    if n_tracks < 127:
        return np.dtype(np.int8)
    if n_tracks < 32767:
        return np.dtype(np.int16)
    return np.dtype(np.int32)


@numba.njit(cache=True)
def _advance(a, used, allowed):
    """Move ``a`` to the next event in lexicographic order; False when ``a`` was the last."""
    m, n = allowed.shape
    for i in range(m - 1, -1, -1):
        cur = a[i]
        if cur >= 0:
            used[cur] = False
        j = cur + 1
        while j < n and not (allowed[i, j] and not used[j]):
            j += 1
        if j < n:
            a[i] = j
            used[j] = True
            return True
        a[i] = -1
    return False


@numba.njit(cache=True)
def _fill(a, used, allowed, out):
    """Write events starting at ``a`` into ``out``; return (rows written, more events remain)."""
    m = a.shape[0]
    for k in range(out.shape[0]):
        for i in range(m):
            out[k, i] = a[i]
        if not _advance(a, used, allowed):
            return k + 1, False
    return out.shape[0], True


def _prepare(n_tracks, n_meas, allowed):
    n = check_int(n_tracks, "n_tracks", minimum=0)
    m = check_int(n_meas, "n_meas", minimum=0)
    if allowed is None:
        return n, m, np.ones((m, n), dtype=np.bool_), None
    gate = np.ascontiguousarray(as_validation(allowed, n, m))
    return n, m, gate, gate


def enumerate_associations(n_tracks: int, n_meas: int, allowed=None, max_events: int = 10**7) -> np.ndarray:
    """Every feasible association event, each exactly once.

    Parameters
    ----------
    n_tracks : int
        Number of objects ``n >= 0``.
    n_meas : int
        Number of returns ``m >= 0``.
    allowed : (m, n) array of bool, optional
        Validation (gating) matrix; return ``i`` may go to object ``j`` only if
        ``allowed[i, j]``. Clutter is always allowed. Default: every pairing allowed.
    max_events : int, optional
        Budget. If the number of events exceeds it, :class:`EnumerationBudgetError` is raised
        before anything is allocated.

    Returns
    -------
    events : (E, m) ndarray of a small signed int dtype (see :func:`event_dtype`)
        ``E = A(n, m)`` (paper 000, Eq. 4) without gating. Row 0 is the all-clutter event;
        rows are in lexicographic order with ``-1`` smallest.

    Raises
    ------
    EnumerationBudgetError
        When the count exceeds ``max_events``.

    See Also
    --------
    iter_association_chunks : the same events in bounded-memory blocks.
    """
    n, m, gate, given = _prepare(n_tracks, n_meas, allowed)
    budget = check_int(max_events, "max_events", minimum=1)
    if given is None:
        count, exact = count_associations(n, m), True
    else:
        count, exact = count_gated_capped(given, budget)
    if count > budget:
        raise EnumerationBudgetError(count, budget, exact=exact)
    out = np.empty((count, m), dtype=event_dtype(n))
    a = np.full(m, -1, dtype=np.int64)
    written, more = _fill(a, np.zeros(n, dtype=np.bool_), gate, out)
    if written != count or more:  # the counter and the generator must agree exactly
        raise RuntimeError(f"enumeration produced {written} events but {count} were counted")
    return out


def iter_association_chunks(
    n_tracks: int, n_meas: int, allowed=None, chunk_size: int = 1 << 16
) -> Iterator[np.ndarray]:
    """Stream the events of :func:`enumerate_associations` in blocks of at most ``chunk_size`` rows.

    Memory stays ``O(chunk_size * m)`` however many events there are, so a caller can scan
    (score, keep the best of) more events than fit in memory. The concatenation of the blocks
    equals ``enumerate_associations(n_tracks, n_meas, allowed)``.

    Parameters
    ----------
    n_tracks, n_meas, allowed
        As for :func:`enumerate_associations`.
    chunk_size : int, optional
        Maximum rows per block, ``>= 1``.

    Yields
    ------
    (k, m) ndarray
        A fresh array per block, ``1 <= k <= chunk_size``.
    """
    n, m, gate, _ = _prepare(n_tracks, n_meas, allowed)
    size = check_int(chunk_size, "chunk_size", minimum=1)
    return _chunks(n, m, gate, size)


def _chunks(n, m, gate, size):
    a = np.full(m, -1, dtype=np.int64)
    used = np.zeros(n, dtype=np.bool_)
    dtype = event_dtype(n)
    more = True
    while more:
        out = np.empty((size, m), dtype=dtype)
        written, more = _fill(a, used, gate, out)
        yield out[:written] if written < size else out

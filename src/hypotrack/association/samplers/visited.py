"""The visited set of a search: the distinct events met, each recorded once with its log-weight.

The samplers (:mod:`.chain`, :mod:`.gibbs`) are used as *searches* (DESIGN.md §4.3): what they
return is the set of distinct events visited, in order of first visit, never visit counts. The
set is an open-addressing hash table keyed by an incrementally updated Zobrist hash (one random
64-bit key per (return, column); an event's hash is the XOR of its rows' keys, so a move of one
return updates it with two XORs), with an exact row comparison on every hash hit, so two
different events are never merged.

:class:`Visited` holds the growable buffers (rows in state codes as int32 — a column index, far below 2³¹ —,
exact log-weights, hashes, the table: ``4 m + 32`` bytes an event, the table's two slots included); the compiled kernels :func:`lookup_or_insert`, :func:`insert_rows` and
:func:`clear_table` work on them inside the samplers' loops.
"""

from __future__ import annotations

import threading

import numba
import numpy as np

__all__ = ["Visited", "clear_table", "contains", "insert_rows", "lookup_or_insert", "zobrist_keys"]


@numba.njit(cache=True, nogil=True)
def _probe(h, state, table, hashes, rows):
    """``(slot, found)``: the open-addressing table's slot of ``state`` (hash ``h``) — its own when ``found``, else
    the empty slot where it would go. ``table`` has a power-of-two length (``-1`` empty, else an index into
    ``rows``/``hashes``) and is probed linearly from ``h & (len - 1)``."""
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
                return pos, True
        pos = (pos + 1) & mask
    return pos, False


@numba.njit(cache=True, nogil=True)
def lookup_or_insert(h, state, table, hashes, rows, logw, lw, n_found):
    """Insert ``state`` (hash ``h``, log-weight ``lw``) in the visited set unless present (:func:`_probe`); return
    the new number of recorded events (``n_found`` unchanged when ``state`` was already there)."""
    pos, found = _probe(h, state, table, hashes, rows)
    if found:
        return n_found
    table[pos] = n_found
    hashes[n_found] = h
    for i in range(state.shape[0]):
        rows[n_found, i] = state[i]
    logw[n_found] = lw
    return n_found + 1


@numba.njit(cache=True, nogil=True)
def contains(h, state, table, hashes, rows):
    """Whether ``state`` (hash ``h``) is in the visited set (:func:`_probe`, no insertion)."""
    return _probe(h, state, table, hashes, rows)[1]


@numba.njit(cache=True, nogil=True)
def clear_table(table, hashes, n):
    """Reset the slots of the ``n`` recorded events to empty (−1): the table is reusable."""
    mask = table.shape[0] - 1
    for q in range(n):
        pos = hashes[q] & mask
        while table[pos] != q:  # q sits on its probe path; emptied slots are stepped over
            pos = (pos + 1) & mask
        table[pos] = -1


@numba.njit(cache=True, nogil=True)
def insert_rows(rows, logw, n, zobrist, table, hashes):
    """(Re)build the visited set from the first ``n`` rows of ``rows`` (distinct events in state
    codes, with their log-weights in ``logw``) into an empty ``table``; return ``n``."""
    found = 0
    for q in range(n):
        h = np.int64(0)
        for i in range(rows.shape[1]):
            h ^= zobrist[i, rows[q, i]]
        found = lookup_or_insert(h, rows[q].copy(), table, hashes, rows, logw, logw[q], found)
    return found


_BUFFERS = threading.local()
_BLOCK_ROWS = 1 << 14  # rows moved at a time by Visited.keep
_ZOBRIST_CACHE_SIZE = 256


def zobrist_keys(m, n_col):
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


class Visited:
    """Growable buffers of the visited set: rows (states), exact log-weights, hashes, table.

    The buffers of the last search of the same capacity are reused (per thread): :meth:`release`
    empties the table slots it used, so a search costs what it visits, not a fresh 2·capacity-slot
    table and row store (one per parent per scan).

    Parameters
    ----------
    m, n_col : int
        Shape of the problem's score matrix (returns × columns).
    capacity : int
        Events the buffers hold before :meth:`grow` is needed.
    """

    def __init__(self, m, n_col, capacity):
        self.zobrist = zobrist_keys(m, max(n_col, 1))
        self.n = 0
        self._alloc(m, max(int(capacity), 1))

    def _alloc(self, m, capacity):
        pool = getattr(_BUFFERS, "pool", None)
        if pool is not None and pool[0] == capacity and pool[1].size >= capacity * m:
            _, flat, self.logw, self.hashes, self.table = pool
            _BUFFERS.pool = None
        else:
            flat = np.empty(capacity * max(m, 1), dtype=np.int32)  # state codes: columns, far below 2³¹
            self.logw = np.empty(capacity)
            self.hashes = np.empty(capacity, dtype=np.int64)
            self.table = np.full(1 << int(2 * capacity - 1).bit_length(), -1, dtype=np.int64)
        self._flat = flat
        self.rows = flat[: capacity * m].reshape(capacity, m)

    def release(self):
        """Empty the table and hand the buffers to the next search of this thread."""
        clear_table(self.table, self.hashes, self.n)
        _BUFFERS.pool = (self.rows.shape[0], self._flat, self.logw, self.hashes, self.table)
        self.n = 0

    def grow(self, limit=None):
        """Double the capacity (at most ``limit`` events), keeping the recorded events in their order."""
        capacity = 2 * self.rows.shape[0] if limit is None else min(2 * self.rows.shape[0], max(int(limit), 1))
        self.keep(np.arange(self.n), capacity)

    def keep(self, idx, capacity=None):
        """Keep only the recorded events ``idx`` (increasing indices: their order is kept), in buffers of
        ``capacity`` events (default the current), the table rebuilt. Growing holds the old buffers and the new ones
        at once (1.5 times the new ones when doubling), no third copy; keeping in the same buffers, no second."""
        idx = np.asarray(idx, dtype=np.int64)
        capacity = self.rows.shape[0] if capacity is None else int(capacity)
        clear_table(self.table, self.hashes, self.n)
        rows, logw = self.rows, self.logw
        if capacity != rows.shape[0]:
            self._alloc(rows.shape[1], capacity)
        # A block at a time, not a copy of every kept row first: near the memory bound that copy was the peak. In
        # place (same buffers) each block's rows come from at or after where it goes (idx increases), and from after
        # every block before it, so nothing is read after it is overwritten.
        n = len(idx)
        for s in range(0, n, _BLOCK_ROWS):
            block = idx[s:s + _BLOCK_ROWS]
            self.rows[s:s + len(block)] = rows[block]
            self.logw[s:s + len(block)] = logw[block]
        self.n = insert_rows(self.rows, self.logw, n, self.zobrist, self.table, self.hashes)

"""The visited set of hypotrack.association.samplers.visited: distinct events once each, in
first-visit order, whatever the hashes; reusable tables; growth keeping the order."""

import numpy as np

from hypotrack.association.samplers.visited import Visited, clear_table, contains, insert_rows, lookup_or_insert


def _buffers(capacity, m, table_size=8):
    return (np.full(table_size, -1, dtype=np.int64), np.empty(capacity, dtype=np.int64),
            np.empty((capacity, m), dtype=np.int64), np.empty(capacity))


def test_lookup_or_insert_records_each_event_once_even_when_hashes_collide():
    table, hashes, rows, logw = _buffers(4, 2)
    a, b = np.array([0, 1]), np.array([1, 0])
    n = lookup_or_insert(5, a, table, hashes, rows, logw, -1.0, 0)
    assert n == 1
    assert lookup_or_insert(5, a.copy(), table, hashes, rows, logw, -9.0, n) == 1  # same event: not again
    n = lookup_or_insert(5, b, table, hashes, rows, logw, -2.0, n)  # same hash, another event: recorded
    assert n == 2
    np.testing.assert_array_equal(rows[:2], [a, b])
    np.testing.assert_array_equal(logw[:2], [-1.0, -2.0])  # the first weight kept
    np.testing.assert_array_equal(table, [-1, -1, -1, -1, -1, 0, 1, -1])  # slot 5, then the next free one


def test_clear_table_empties_exactly_the_used_slots():
    table, hashes, rows, logw = _buffers(4, 1)
    n = 0
    for h, e in ((3, 0), (3, 1), (11, 2)):  # 3, 3 and 11 all start probing at slot 3
        n = lookup_or_insert(h, np.array([e]), table, hashes, rows, logw, 0.0, n)
    np.testing.assert_array_equal(table[3:6], [0, 1, 2])
    clear_table(table, hashes, n)
    assert np.all(table == -1)


def test_insert_rows_rebuilds_the_set_and_recognises_its_events():
    zobrist = np.arange(1, 7, dtype=np.int64).reshape(2, 3)  # keys of (return, column)
    table, hashes, _, _ = _buffers(4, 2)
    rows = np.array([[0, 2], [1, 1], [2, 0], [0, 0]], dtype=np.int64)
    logw = np.array([-1.0, -2.0, -3.0, 0.0])
    assert insert_rows(rows, logw, 3, zobrist, table, hashes) == 3
    np.testing.assert_array_equal(hashes[:3], [1 ^ 6, 2 ^ 5, 3 ^ 4])
    assert lookup_or_insert(2 ^ 5, np.array([1, 1]), table, hashes, rows, logw, 0.0, 3) == 3  # known
    assert lookup_or_insert(1 ^ 4, np.array([0, 0]), table, hashes, rows, logw, 0.0, 3) == 4  # new


def test_visited_grows_keeping_its_events_in_order():
    v = Visited(2, 3, capacity=2)
    for e, lw in (([0, 1], -1.0), ([2, 2], -2.0)):
        state = np.array(e, dtype=np.int64)
        h = v.zobrist[0, e[0]] ^ v.zobrist[1, e[1]]
        v.n = lookup_or_insert(h, state, v.table, v.hashes, v.rows, v.logw, lw, v.n)
    assert v.n == 2 == v.rows.shape[0]
    v.grow()
    assert v.rows.shape == (4, 2) and v.n == 2
    np.testing.assert_array_equal(v.rows[:2], [[0, 1], [2, 2]])
    np.testing.assert_array_equal(v.logw[:2], [-1.0, -2.0])
    h = v.zobrist[0, 2] ^ v.zobrist[1, 2]
    assert lookup_or_insert(h, np.array([2, 2]), v.table, v.hashes, v.rows, v.logw, 0.0, v.n) == 2
    v.release()
    assert v.n == 0


def test_keep_in_place_and_into_new_buffers_moves_every_kept_row_over_several_blocks():
    """Rows kept a block at a time (2¹⁴ rows): in the same buffers (sources at or after their destinations) and into
    doubled ones, the kept rows and weights in order, each still found by its hash, the others not."""
    m, n = 3, 50_000
    rng = np.random.default_rng(0)
    every = np.stack([np.arange(n) % 40, (np.arange(n) // 40) % 40, np.arange(n) // 1600], axis=1)  # distinct
    idx = np.sort(rng.choice(n, 30_000, replace=False))
    idx[:100] = np.arange(100)  # a run kept where it stands
    idx = np.unique(idx)
    for capacity in (None, 2 * n):
        w = Visited(m, 40, capacity=n)
        w.rows[:n], w.logw[:n] = every, -np.arange(n, dtype=float)
        w.n = insert_rows(w.rows, w.logw, n, w.zobrist, w.table, w.hashes)
        w.keep(idx, capacity)
        assert w.n == len(idx) and w.rows.shape[0] == (n if capacity is None else capacity)
        np.testing.assert_array_equal(w.rows[: w.n], every[idx])
        np.testing.assert_array_equal(w.logw[: w.n], -idx.astype(float))
        gone = np.setdiff1d(np.arange(n), idx)[:50]
        for q, held in [(q, True) for q in idx[:50]] + [(q, False) for q in gone]:
            h = np.bitwise_xor.reduce(w.zobrist[np.arange(m), every[q]])
            assert contains(h, every[q].astype(np.int64), w.table, w.hashes, w.rows) is held

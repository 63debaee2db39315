"""Gibbs kernels of hypotrack.association.samplers.gibbs: the exact conditional (against the
brute-force event weights), the draw (against NumPy's legacy stream, which is numba's), the
move, and the systematic sweeps (against exhaustive enumeration)."""

import itertools

import numba
import numpy as np
import pytest

from hypotrack.association.samplers.events import state_log_weight, to_state
from hypotrack.association.samplers.gibbs import gibbs_draw, move_row, sweep_search

# 2 objects, 1 birth column, clutter: 3 returns.
SCORE = np.array([[1.0, 2.0, -0.5, 0.0],
                  [0.5, -np.inf, 1.5, 0.0],
                  [2.5, 0.25, -1.0, 0.0]])
N_OBJ, N_EXCL = 2, 3
PHI = np.array([[0.0, -1.0], [-0.5, -1.25], [-2.0, -3.5]])


@numba.njit
def _seeded_draw(seed, score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond):
    np.random.seed(seed)
    return gibbs_draw(score, count_term, owner, i, cur, k, b, n_obj, n_excl, cond)


def test_gibbs_draw_conditional_and_choice_by_hand():
    state = np.array([0, 2, 3], dtype=np.int64)  # return 0 on object 0, return 1 on the birth, 2 clutter
    owner = np.array([0, -1, 1], dtype=np.int64)
    base = state_log_weight(SCORE, state, N_OBJ, N_EXCL, PHI)
    i = 2
    want = []
    for c in range(SCORE.shape[1]):
        if c < N_EXCL and owner[c] not in (-1, i):
            want.append(-np.inf)  # held by another return
            continue
        moved = state.copy()
        moved[i] = c
        want.append(state_log_weight(SCORE, moved, N_OBJ, N_EXCL, PHI) - base)
    np.testing.assert_allclose(want, [-np.inf, 0.25 + PHI[2, 1] - PHI[1, 1], -np.inf, 0.0], atol=1e-15)
    for seed in range(20):
        cond = np.empty(SCORE.shape[1])
        new = _seeded_draw(seed, SCORE, PHI, owner, i, state[i], 1, 1, N_OBJ, N_EXCL, cond)
        np.testing.assert_allclose(cond, want, atol=1e-15)
        p = np.exp(np.array(want) - max(want))
        u = np.random.RandomState(seed).random_sample() * p.sum()  # numba's stream is the legacy one
        assert new == int(np.searchsorted(np.cumsum(p), u, side="right"))


def test_move_row_updates_state_owner_hash_and_counts():
    zobrist = np.arange(12, dtype=np.int64).reshape(3, 4) * 7 + 1
    state = np.array([0, 2, 3], dtype=np.int64)
    owner = np.array([0, -1, 1], dtype=np.int64)
    h = zobrist[0, 0] ^ zobrist[1, 2] ^ zobrist[2, 3]
    h2, k, b = move_row(state, owner, zobrist, h, 1, 1, 1, 1, N_OBJ, N_EXCL)  # return 1: birth -> object 1
    np.testing.assert_array_equal(state, [0, 1, 3])
    np.testing.assert_array_equal(owner, [0, 1, -1])
    assert (h2, k, b) == (zobrist[0, 0] ^ zobrist[1, 1] ^ zobrist[2, 3], 2, 0)
    h3, k, b = move_row(state, owner, zobrist, h2, k, b, 0, 3, N_OBJ, N_EXCL)  # return 0 to clutter
    np.testing.assert_array_equal(owner, [-1, 1, -1])
    assert (h3, k, b) == (zobrist[0, 3] ^ zobrist[1, 1] ^ zobrist[2, 3], 1, 0)


def _all_events():
    """Every feasible event of SCORE by brute force, with its weight."""
    out = {}
    for st in itertools.product(range(SCORE.shape[1]), repeat=SCORE.shape[0]):
        excl = [c for c in st if c < N_EXCL]
        if len(set(excl)) == len(excl):
            lw = state_log_weight(SCORE, np.array(st, dtype=np.int64), N_OBJ, N_EXCL, PHI)
            if np.isfinite(lw):
                out[st] = lw
    return out


def test_sweep_search_finds_every_event_with_its_exact_weight():
    events, lw = sweep_search(SCORE, N_OBJ, N_EXCL, PHI, n_sweeps=3000, seed=4)
    assert events.dtype == np.int32
    np.testing.assert_array_equal(events[0], [-1, -1, -1])  # the start: every return on option 0
    found = {tuple(s): w for s, w in zip(to_state(events, N_EXCL).tolist(), lw)}
    assert len(found) == len(events)  # distinct
    assert found == pytest.approx(_all_events(), abs=0)  # every feasible event, its exact weight
    again = sweep_search(SCORE, N_OBJ, N_EXCL, PHI, n_sweeps=3000, seed=4)
    np.testing.assert_array_equal(again[0], events)


def test_sweep_search_without_rows_or_sweeps():
    events, lw = sweep_search(np.zeros((0, 3)), 2, 2, PHI[:, :1], n_sweeps=5, seed=0)
    assert events.shape == (1, 0) and events.dtype == np.int32
    np.testing.assert_array_equal(lw, [0.0])
    events, lw = sweep_search(SCORE, N_OBJ, N_EXCL, PHI, n_sweeps=0, seed=0)
    np.testing.assert_array_equal(events, [[-1, -1, -1]])
    np.testing.assert_array_equal(lw, [PHI[0, 0]])
    with pytest.raises(ValueError, match="n_sweeps"):
        sweep_search(SCORE, N_OBJ, N_EXCL, PHI, n_sweeps=-1, seed=0)

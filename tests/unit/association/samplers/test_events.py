"""The event encodings and the compiled event kernels of hypotrack.association.samplers.events,
against hand-computed values."""

import doctest

import numpy as np

from hypotrack.association.samplers import events as events_module
from hypotrack.association.samplers.events import (
    count_delta,
    event_log_weights,
    gather_sum,
    owners_and_counts,
    state_log_weight,
    to_events,
    to_state,
)

# 2 objects (columns 0, 1), 1 birth column (2), row options clutter (3) and seeded birth (4).
SCORE = np.array([[1.0, 2.0, 3.0, 0.5, 0.25],
                  [4.0, -np.inf, 6.0, 0.75, 0.125],
                  [7.0, 8.0, 9.0, 1.5, 0.0625]])
N_OBJ, N_EXCL = 2, 3
PHI = np.array([[0.0, -1.0], [-2.0, -3.0], [-4.0, -5.0]])  # φ[k, b]


def test_codes_round_trip_and_their_dtypes():
    events = np.array([[0, -1, 2], [-2, 1, -1]])
    state = to_state(events, N_EXCL)
    np.testing.assert_array_equal(state, [[0, 3, 2], [4, 1, 3]])  # -1 - t  ->  n_excl + t
    assert state.dtype == np.int64
    back = to_events(state, N_EXCL)
    np.testing.assert_array_equal(back, events)
    assert back.dtype == np.int32


def test_state_log_weight_by_hand():
    # return 0 on object 1, return 1 on the birth column, return 2 on clutter: k = 1, b = 1.
    state = np.array([1, 2, 3], dtype=np.int64)
    assert state_log_weight(SCORE, state, N_OBJ, N_EXCL, PHI) == 2.0 + 6.0 + 1.5 + PHI[1, 1]
    # every return on the seeded-birth option: k = b = 0.
    assert state_log_weight(SCORE, np.array([4, 4, 4]), N_OBJ, N_EXCL, PHI) == 0.25 + 0.125 + 0.0625
    assert state_log_weight(SCORE, np.array([0, 1, 2]), N_OBJ, N_EXCL, PHI) == -np.inf  # return 1 forbidden on 1


def test_count_delta_of_every_kind_of_move():
    # column classes: object (0, 1), birth (2), row option (3, 4)
    assert count_delta(0, 1, N_OBJ, N_EXCL) == (0, 0)
    assert count_delta(0, 2, N_OBJ, N_EXCL) == (-1, 1)
    assert count_delta(0, 3, N_OBJ, N_EXCL) == (-1, 0)
    assert count_delta(2, 4, N_OBJ, N_EXCL) == (0, -1)
    assert count_delta(3, 1, N_OBJ, N_EXCL) == (1, 0)
    assert count_delta(4, 2, N_OBJ, N_EXCL) == (0, 1)
    assert count_delta(3, 4, N_OBJ, N_EXCL) == (0, 0)


def test_owners_and_counts_by_hand():
    owner, k, b = owners_and_counts(np.array([2, 3, 0], dtype=np.int64), N_OBJ, N_EXCL)
    np.testing.assert_array_equal(owner, [2, -1, 0])  # column 0 held by return 2, 1 free, 2 by return 0
    assert (k, b) == (1, 1)
    owner, k, b = owners_and_counts(np.array([3, 4, 3], dtype=np.int64), N_OBJ, N_EXCL)
    np.testing.assert_array_equal(owner, [-1, -1, -1])
    assert (k, b) == (0, 0)


def test_gather_sum_is_the_state_log_weight_of_every_event():
    events = np.array([[1, 2, -1], [-2, -2, -2], [0, -1, 1], [-1, 0, 2]], dtype=np.int32)
    out = np.empty(len(events))
    gather_sum(SCORE, events, N_OBJ, N_EXCL, PHI, out)
    want = [state_log_weight(SCORE, s, N_OBJ, N_EXCL, PHI) for s in to_state(events, N_EXCL)]
    np.testing.assert_array_equal(out, want)
    np.testing.assert_array_equal(out[:2], [2.0 + 6.0 + 1.5 - 3.0, 0.25 + 0.125 + 0.0625])
    np.testing.assert_array_equal(event_log_weights(SCORE, N_OBJ, N_EXCL, PHI, events), out)


def test_the_module_examples_run():
    result = doctest.testmod(events_module)
    assert result.attempted >= 2 and result.failed == 0

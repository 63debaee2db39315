"""The public helpers of hypotrack.association.counting used by enumeration: the validated gating
matrix and the count with its exactness flag, against hand counts and brute force."""

import itertools

import numpy as np
import pytest

from hypotrack.association.counting import as_validation, count_gated_capped


def brute_force_count(allowed):
    m, n = allowed.shape
    options = [[-1, *np.flatnonzero(allowed[i])] for i in range(m)]
    return sum(1 for a in itertools.product(*options) if len({c for c in a if c >= 0}) == sum(c >= 0 for c in a))


def test_exact_counts_by_hand_and_by_brute_force():
    assert count_gated_capped(np.eye(2, dtype=bool), None) == (4, True)  # each return: clutter or its own track
    assert count_gated_capped(np.ones((2, 2), dtype=bool), None) == (7, True)  # A(2, 2) = 1 + 4 + 2
    assert count_gated_capped(np.zeros((3, 2), dtype=bool), None) == (1, True)  # all clutter
    stair = np.triu(np.ones((6, 6), dtype=bool))
    assert count_gated_capped(stair, None) == (brute_force_count(stair), True) == (877, True)


def test_a_wide_component_counted_up_to_the_cap_says_so():
    wide = np.triu(np.ones((25, 25), dtype=bool))  # 24 columns open after the first row: past the exact frontier
    count, exact = count_gated_capped(wide, 10)
    assert count > 10 and not exact
    assert count_gated_capped(wide[:6, :6], 10) == (877, True)  # narrow: exact whatever the cap


def test_as_validation_checks_the_shape():
    allowed = np.eye(2, 3, dtype=bool)
    np.testing.assert_array_equal(as_validation(allowed, 3, 2), allowed)
    with pytest.raises(ValueError, match=r"^allowed must have shape \(n_meas, n_tracks\) = \(3, 2\), got \(2, 3\)$"):
        as_validation(allowed, 2, 3)

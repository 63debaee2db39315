"""The hypothesis filter and its child generators on exact oracles: hand-computed weights with
births and deaths, in-view versus out-of-view objects, brute-force enumeration, exact top-k."""

import numpy as np

from hypotrack.hypotheses.generators import top_k


def test_top_k_is_the_k_largest_best_first_with_stable_ties():
    lw = np.array([0.5, 2.0, -1.0, 2.0, 0.5, 3.0])
    np.testing.assert_array_equal(top_k(lw, 3), [5, 1, 3])
    np.testing.assert_array_equal(top_k(lw, None), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 6), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 1), [5])

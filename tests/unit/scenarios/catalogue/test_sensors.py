"""The ground radar refuses positions that are not (n, 3) rows instead of regrouping their numbers."""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue.sensors import DEFAULT_RADAR


@pytest.mark.parametrize("r_ef", [np.ones((4, 2)), np.ones((2, 6)), np.ones((3, 3, 3)), np.ones(6)])
def test_observe_refuses_positions_that_are_not_rows_of_three(r_ef):
    with pytest.raises(ValueError, match=r"r_ef must have shape \(n, 3\).*got \(" + str(r_ef.shape[0])):
        DEFAULT_RADAR.observe(r_ef, np.random.default_rng(0))


def test_observe_rae_refuses_the_wrong_shape():
    with pytest.raises(ValueError, match=r"rae must have shape \(n, 3\)"):
        DEFAULT_RADAR.observe_rae(np.ones((4, 2)), np.random.default_rng(0))


def test_rows_one_position_and_no_position_still_observe():
    far = np.array([[1e5, 0.0, 0.0], [np.nan, np.nan, np.nan]])
    for r_ef in (far, far[0], np.zeros((0, 3))):
        Z, origin = DEFAULT_RADAR.observe(r_ef, np.random.default_rng(1))
        assert Z.shape[1] == 3 and np.all(origin == -1)

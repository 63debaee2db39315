"""A per-track detection probability is accepted on (0, 1] exactly: 1 (a sure detection) is allowed, anything
above 1 or at 0 is refused with the parameter named; the scores then use the given values."""

import numpy as np
import pytest

from hypotrack.trackers._sht_common import ScanModel, with_track_p_D

MODEL = ScanModel(np.hstack([np.eye(2), np.zeros((2, 2))]), np.eye(2), 0.9, 0.99, 1e-3)


def test_bounds_of_a_per_track_p_D():
    out = with_track_p_D(MODEL, [1.0, 0.25])
    np.testing.assert_array_equal(out.p_D, [1.0, 0.25])
    np.testing.assert_allclose(out.log_missed, np.log1p(-np.array([1.0, 0.25]) * 0.99))
    assert MODEL.p_D == 0.9  # the model itself is unchanged
    for bad in ([1.5, 0.5], [0.0, 0.5], [[0.5]]):
        with pytest.raises(ValueError, match=r"^p_D per track must be a 1-d array of values in \(0, 1\]"):
            with_track_p_D(MODEL, bad)

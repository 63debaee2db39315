"""A track whose innovation covariance passes Cholesky but cannot be inverted in working precision is not scored.

The matrix below is the innovation covariance (range km, azimuth and elevation rad, range-rate km/s) of a HOMHT
seeded birth (8 km/s velocity spread) in the breakup cloud, predicted over an hour out of view with process noise
1e-12 km²/s³ (first order, as :func:`~hypotrack.hypotheses.factored.planner.innovation_covariances` gives it):
Cholesky succeeds by rounding, and the gain's solve stopped the run on an exact zero pivot."""

import numpy as np
import pytest

from hypotrack.hypotheses.factored.planner import MAX_SCALED_CONDITION, scorable

DIVERGED = np.array([  # full precision: rounded to 9 digits its near-unit correlations lose the degeneracy
    [1.527656437728101e+16, 1676930824971.4414, 2935100473476.865, 3214471980897.839],
    [1676930824971.4414, 184079363.73721546, 322190280.706034, 352857124.5257268],
    [2935100473476.865, 322190280.706034, 563923574.7087549, 617599475.640503],
    [3214471980897.8403, 352857124.52572656, 617599475.6405029, 676384551.5668249]])


def test_the_diverged_birth_passes_cholesky_but_is_not_scorable():
    np.linalg.cholesky(DIVERGED)  # the test the scan relied on alone: it passes
    # a tracked object's (range 30 m, angles 0.05 deg, range-rate 10 m/s): condition ~1e9 unscaled, scorable
    tracked = np.diag([9e-4, 7.6e-7, 7.6e-7, 1e-4])
    tracked[0, 3] = tracked[3, 0] = 0.9 * np.sqrt(9e-4 * 1e-4)
    assert scorable(np.stack([DIVERGED, tracked])).tolist() == [False, True]


@pytest.mark.parametrize("one_minus_rho, expected", [(1e-9, True), (1e-11, False)])
def test_the_scaled_condition_number_decides_by_hand(one_minus_rho, expected):
    # unit diagonal with correlation rho: eigenvalues 1 + rho and 1 - rho, condition (1 + rho) / (1 - rho):
    # 2e9 for 1 - rho = 1e-9 (below 1e10), 2e11 for 1e-11 (above); the units (1e6 and 1e-6) do not count
    rho = 1.0 - one_minus_rho
    scale = np.array([1e3, 1e-3])
    S = np.array([[1.0, rho], [rho, 1.0]]) * np.outer(scale, scale)
    assert MAX_SCALED_CONDITION == 1e10
    assert scorable(S[None]).tolist() == [expected]


def test_zero_and_negative_variances_are_not_scorable():
    S = np.stack([np.diag([1.0, 0.0]), np.diag([-1.0, 1.0]), np.eye(2)])
    assert scorable(S).tolist() == [False, False, True]

"""The lazy lane's one prediction over a gap against the scan-by-scan EKF on an orbit (the size the package
docstring states): equal over one scan, far apart over the gaps between an orbit's passes."""

import numpy as np
import pytest

from hypotrack.hypotheses.factored.lane import predict_each
from hypotrack.metrics_scorecard import ric_frame
from hypotrack.models.orbit3d import J2Orbit3D

MOTION = J2Orbit3D(q=1e-9)
_R = 6378.137 + 850.0
_V = np.sqrt(398600.4418 / _R)
X0 = np.array([[_R, 0.0, 0.0, 0.0, _V * np.cos(np.radians(98.7)), _V * np.sin(np.radians(98.7))]])
P0 = np.diag([0.25] * 3 + [2.5e-7] * 3)[None]


def _scan_by_scan(gap, dt=10.0):
    x, P = X0.copy(), P0[0].copy()
    for _ in range(int(round(gap / dt))):
        x, F = MOTION.transition(x, dt)
        P = F[0] @ P @ F[0].T + MOTION.Q(dt)
    return x[0], P


def _ric_sigma(x, P):
    R = ric_frame(x[None])[0]
    return np.sqrt(np.diag(R @ P[:3, :3] @ R.T))


def test_lane_gap_prediction_is_one_ekf_step():
    # what the lane does: Phi(T) P Phi(T)^T + Q(T), one step over the gap
    x, P = predict_each(MOTION, X0, P0, np.array([3880.0]))
    xt, F = MOTION.transition(X0, 3880.0)
    assert x[0] == pytest.approx(xt[0], abs=1e-6)
    assert P[0] == pytest.approx(F[0] @ P0[0] @ F[0].T + MOTION.Q(3880.0), rel=1e-9, abs=1e-12)


def test_one_scan_gap_equals_the_scan_by_scan_prediction():
    x, P = predict_each(MOTION, X0, P0, np.array([10.0]))
    xs, Ps = _scan_by_scan(10.0)
    assert P[0] == pytest.approx(Ps, rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("gap, in_track, cross_track", [(3880.0, (11.0, 17.0), (4.4, 1.4)),
                                                         (5700.0, (15.3, 30.5), (7.9, 1.8))])
def test_pass_gap_covariance_is_far_from_the_scan_by_scan_one(gap, in_track, cross_track):
    # the numbers of the package docstring: in-track sigma too small, cross-track too large
    x, P = predict_each(MOTION, X0, P0, np.array([gap]))
    xs, Ps = _scan_by_scan(gap)
    assert np.linalg.norm(x[0, :3] - xs[:3]) < 0.01  # the means agree (integration error only)
    lazy, exact = _ric_sigma(x[0], P[0]), _ric_sigma(xs, Ps)
    assert (lazy[1], exact[1]) == pytest.approx(in_track, abs=0.1)
    assert (lazy[2], exact[2]) == pytest.approx(cross_track, abs=0.1)

"""M-of-N initiation with a nonlinear (range-bearing) measurement: a new tentative track is the measurement model's
own one-point initiation of the return, with no extra position spread and the initiator's velocity spread
(``one_point(Z, 0, initial_velocity_std)``), here by hand; its next return updates it by the EKF; empty scans
start nothing; the residual of a bearing across the wrap is wrapped; the scan model of a nonlinear sensor."""

from types import SimpleNamespace

import numpy as np
import pytest

from hypotrack.gaussian import predict_with
from hypotrack.models import ConstantVelocity
from scenes import RangeBearing
from hypotrack.trackers import MOfNInitiator, ScanModel

MOTION = ConstantVelocity(0.0)


def test_tentative_tracks_are_the_one_point_initiation_then_the_ekf():
    m = RangeBearing()
    model = ScanModel(None, m.R, 0.9, 0.999, 1e-3, measurement=m)
    init = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=2.0)
    assert init.P0 is None
    x, _ = init.step(0.0, [[10.0, 0.0], [20.0, np.pi / 2]])
    assert len(x) == 0 and len(init) == 2 and init.hits.tolist() == [1, 1]
    # (10, 0°): position (10, 0), J = diag(1, 10): diag(0.04, 100·1e-4); (20, 90°): (0, 20), diag(400·1e-4, 0.04)
    np.testing.assert_allclose(init.x, [[10.0, 0.0, 0.0, 0.0], [0.0, 20.0, 0.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(init.P[0], np.diag([0.04, 0.01, 4.0, 4.0]), atol=1e-12)
    np.testing.assert_allclose(init.P[1], np.diag([0.04, 0.04, 4.0, 4.0]), atol=1e-12)
    x, _ = init.step(1.0, np.zeros((0, 2)))  # an empty scan: both missed, nothing new
    assert len(x) == 0 and len(init) == 2 and init.hits.tolist() == [1, 1] and init.age.tolist() == [2, 2]
    assert init.P.shape == (2, 4, 4)
    # the first track's return two seconds after its start: the EKF update of its prediction confirms it
    z = np.array([[10.5, 0.02]])
    xp, Pp = predict_with(MOTION, np.array([10.0, 0.0, 0.0, 0.0]), np.diag([0.04, 0.01, 4.0, 4.0]), 2.0)
    xe, Pe = m.update(xp[None], Pp[None], z)
    x, P = init.step(2.0, z)
    np.testing.assert_allclose(x, xe, atol=1e-12)
    np.testing.assert_allclose(P, Pe, atol=1e-12)
    assert len(init) == 0  # the second track has 1 hit in 3 scans: dropped


def test_a_return_across_the_bearing_wrap_updates_by_the_wrapped_residual():
    """A tentative track at bearing π − 0.01 takes a return at −π + 0.015: the residual is 0.025 rad, not −2π + 0.025,
    so the confirmed state is the measurement model's own (wrapping) EKF update."""
    m = RangeBearing()
    model = ScanModel(None, m.R, 0.9, 0.999, 1e-3, measurement=m)
    init = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=0.5)
    init.step(0.0, [[10.0, np.pi - 0.01]])
    x0, P0 = init.x.copy(), init.P.copy()
    z = np.array([[10.1, -np.pi + 0.015]])
    x, P = init.step(0.0, z)  # a zero interval: the update alone
    xe, Pe = m.update(x0, P0, z)
    np.testing.assert_allclose(x, xe, atol=1e-12)
    np.testing.assert_allclose(P, Pe, atol=1e-12)
    assert abs(np.arctan2(x[0, 1], x[0, 0])) > np.pi - 0.02  # still beside the wrap, not swung round


def test_scan_model_of_a_nonlinear_sensor():
    """``from_sensor`` of a sensor with a nonlinear measurement: no ``H``, the measurement's ``R``, the sensor's
    ``p_D`` and clutter, the given gate and new-target density; a nonlinear model ignores an ``H``/``R`` given to it
    and checks the measurement's ``R`` under that name."""
    m = RangeBearing()
    sensor = SimpleNamespace(measurement=m, detection=SimpleNamespace(p_D=0.8), clutter=SimpleNamespace(intensity=2e-3))
    model = ScanModel.from_sensor(sensor, p_gate=0.95, new_target_density=1e-4)
    assert model.measurement is m and model.H is None
    np.testing.assert_array_equal(model.R, m.R)
    assert (model.p_D, model.p_gate, model.clutter_density, model.new_target_density) == (0.8, 0.95, 2e-3, 1e-4)
    given = ScanModel(np.eye(2, 4), 5.0 * np.eye(2), 0.9, 0.99, 1e-3, measurement=m)
    assert given.H is None
    np.testing.assert_array_equal(given.R, m.R)
    bad = RangeBearing()
    bad.R = np.array([[1.0, 2.0], [0.0, 1.0]])
    with pytest.raises(ValueError, match=r"^measurement\.R must be symmetric"):
        ScanModel(None, None, 0.9, 0.99, 1e-3, measurement=bad)

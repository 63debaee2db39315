"""The second-order radar model's Hessian (:meth:`ExtendedMeasurement.hessian`: central differences of the Jacobian,
all 2d shifted copies of the means in one Jacobian call) against the differences taken one step at a time, and
against the Hessian of the range, ``∂²ρ/∂r² = (I − u uᵀ)/ρ`` (``u`` the unit line of sight), in closed form."""

import numpy as np

from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, site_teme


def _states():
    rng = np.random.default_rng(3)
    r = rng.normal(size=(5, 3))
    r = 7000.0 * r / np.linalg.norm(r, axis=1)[:, None]
    return np.hstack([r, rng.normal(scale=5.0, size=(5, 3))])


def _one_step_at_a_time(meas, X):
    n, d = X.shape
    out = np.empty((n, meas.dim, d, d))
    for k, h in enumerate(meas.hessian_steps):
        xp, xm = X.copy(), X.copy()
        xp[:, k] += h
        xm[:, k] -= h
        out[:, :, :, k] = (meas.jacobian(xp) - meas.jacobian(xm)) / (2 * h)
    return 0.5 * (out + np.swapaxes(out, 2, 3))


def test_the_batched_hessian_is_the_step_by_step_one_and_the_ranges_closed_form():
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(0.7).measurement
    X = _states()
    H = meas.hessian(X)
    assert H.shape == (5, 4, 6, 6)
    np.testing.assert_allclose(H, _one_step_at_a_time(meas, X), rtol=1e-12, atol=1e-15)
    assert np.array_equal(H, np.swapaxes(H, 2, 3))
    d = X[:, :3] - site_teme(meas.sensor.radar.site, 0.7)[0]
    rho = np.linalg.norm(d, axis=1)
    u = d / rho[:, None]
    exact = (np.eye(3)[None] - u[:, :, None] * u[:, None, :]) / rho[:, None, None]
    np.testing.assert_allclose(H[:, 0, :3, :3], exact, rtol=1e-5, atol=1e-12)
    assert np.all(H[:, 0, 3:, :] == 0.0)  # the range does not depend on the velocity
    assert meas.hessian(np.zeros((0, 6))).shape == (0, 4, 6, 6)

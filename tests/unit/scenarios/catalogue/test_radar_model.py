"""The radar measurement model (range, azimuth, elevation, range-rate of a TEME state) and its Jacobian.

Checked against central finite differences at random states (near the zenith and across the azimuth
wrap included), against the existing Earth-fixed observation code of :class:`GroundRadar` on real
bundled objects propagated by SGP4, and the range-rate against the finite difference of SGP4 ranges.
"""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue import DEFAULT_RADAR, GroundRadar, propagate
from hypotrack.scenarios.catalogue.frames import gmst, rae_to_enu, teme_to_ef, wrap_angle
from hypotrack.scenarios.catalogue.propagation import time_grid_jd
from hypotrack.scenarios.catalogue.radar_model import (
    SIGMA_RANGE_RATE_KM_S,
    RadarTrackerSensor,
    rae_rate,
    rae_rate_jacobian,
    site_teme,
)
from scenes import sgp4_in_view

SITE = DEFAULT_RADAR.site


def _states_at(rae, theta, rng):
    """TEME states at the given (range, az, el) from SITE, with random LEO-like velocities."""
    enu = rae_to_enu(rae)
    ef = enu @ SITE.enu + SITE.ef
    c, s = np.cos(theta), np.sin(theta)
    R3 = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    r = ef @ R3
    v = rng.standard_normal((len(rae), 3))
    v *= rng.uniform(6.5, 8.0, (len(rae), 1)) / np.linalg.norm(v, axis=1, keepdims=True)
    return np.hstack([r, v])


def _random_states(rng, n):
    rae = np.column_stack([rng.uniform(200, 3000, n), rng.uniform(-np.pi, np.pi, n),
                           np.deg2rad(rng.uniform(2, 89.9, n))])
    rae[: n // 5, 2] = np.deg2rad(rng.uniform(89.0, 89.95, n // 5))  # near the zenith
    rae[n // 5: 2 * n // 5, 1] = rng.choice([-1, 1], n // 5) * (np.pi - rng.uniform(0, 1e-6, n // 5))  # at the wrap
    return rae


def _fd_jacobian(x, theta, az_center):
    """Central differences, azimuth differences wrapped: steps 1e-4 km and 1e-6 km/s."""
    J = np.zeros((len(x), 4, 6))
    for k in range(6):
        h = 1e-4 if k < 3 else 1e-6
        xp, xm = x.copy(), x.copy()
        xp[:, k] += h
        xm[:, k] -= h
        d = rae_rate(xp, SITE, theta, az_center=az_center) - rae_rate(xm, SITE, theta, az_center=az_center)
        d[:, 1] = wrap_angle(d[:, 1])
        J[:, :, k] = d / (2 * h)
    return J


@pytest.mark.parametrize("az_center", [0.0, np.pi])
def test_jacobian_against_central_differences(az_center):
    rng = np.random.default_rng(7)
    theta = 1.234
    X = _states_at(_random_states(rng, 400), theta, rng)
    J = rae_rate_jacobian(X, SITE, theta)
    J_fd = _fd_jacobian(X, theta, az_center)
    for row in range(4):
        err = np.linalg.norm(J[:, row] - J_fd[:, row], axis=1) / np.linalg.norm(J[:, row], axis=1)
        assert err.max() < 1e-6, (row, err.max())
    # the wrapped states' azimuths straddle the report window's edge, yet the Jacobian is smooth there
    assert np.all(np.isfinite(J))


def test_site_velocity_and_range_rate_of_a_co_rotating_point_is_zero():
    theta = 0.3
    s, sdot = site_teme(SITE, theta)
    assert np.linalg.norm(sdot) == pytest.approx(7.292115146706979e-5 * np.hypot(*s[:2]))
    # a point fixed to the Earth 500 km above the site: range 500 km, el 90 deg, range-rate 0
    up = SITE.enu[2] * 500.0 + SITE.ef
    c, si = np.cos(theta), np.sin(theta)
    r = np.array([[c, si, 0], [-si, c, 0], [0, 0, 1.0]]).T @ up
    v = 7.292115146706979e-5 * np.array([-r[1], r[0], 0.0])
    z = rae_rate(np.r_[r, v], SITE, theta)[0]
    assert z[0] == pytest.approx(500.0) and np.degrees(z[2]) == pytest.approx(90.0, abs=1e-6)
    assert abs(z[3]) < 1e-12


@pytest.fixture(scope="module")
def sgp4_pairs():
    """(object, time) pairs of 400 bundled active satellites inside the default radar's field of view over
    2 h from the catalogue's epoch, propagated by SGP4 at t and t ± 0.5 s."""
    cat, start, p, theta, vis = sgp4_in_view(400, 7200.0, 30.0)
    obj, k = np.nonzero(vis)
    assert len(obj) >= 30
    return cat, start, p, theta, obj[:60], k[:60]


def test_h_equals_the_radar_observation_code_on_sgp4_states(sgp4_pairs):
    cat, start, p, theta, obj, k = sgp4_pairs
    for i, j in zip(obj, k):
        x = np.r_[p.r[i, j], p.v[i, j]]
        z = rae_rate(x, SITE, theta[j], az_center=DEFAULT_RADAR.fov.az_center)[0]
        r_ef, v_ef = teme_to_ef(p.r[i, j][None, None], p.v[i, j][None, None], theta[[j]])
        rae = DEFAULT_RADAR.rae(r_ef[0, 0])
        assert abs(z[0] - rae[0]) < 1e-6  # 1 mm
        assert abs(np.degrees(wrap_angle(z[1] - rae[1]))) < 1e-6  # 1 micro-degree
        assert abs(np.degrees(z[2] - rae[2])) < 1e-6
        d = r_ef[0, 0] - SITE.ef  # independent range-rate: Earth-fixed relative velocity on the line of sight
        assert z[3] == pytest.approx(d @ v_ef[0, 0] / np.linalg.norm(d), abs=1e-9)
        # the tracker sensor's h is the same
        assert np.allclose(RadarTrackerSensor(DEFAULT_RADAR).at(theta[j]).h(x)[0], z, rtol=0, atol=1e-12)


def test_range_rate_equals_the_finite_difference_of_sgp4_ranges(sgp4_pairs):
    cat, start, p, theta, obj, k = sgp4_pairs
    rows = cat.iloc[obj]
    errs = []
    for n, (i, j) in enumerate(zip(obj, k)):
        t = p.times[j] + np.array([-0.5, 0.5])
        q = propagate(rows.iloc[[n]], t, start)
        r_ef, _ = teme_to_ef(q.r, q.v, gmst(*time_grid_jd(start, t)))
        rng_pm = DEFAULT_RADAR.rae(r_ef[0])[:, 0]
        z = rae_rate(np.r_[p.r[i, j], p.v[i, j]], SITE, theta[j])[0]
        errs.append(abs((rng_pm[1] - rng_pm[0]) / 1.0 - z[3]))
    assert max(errs) < 1e-3  # 1 m/s


def test_sensor_noise_innovation_wrap_and_ekf_update():
    s = RadarTrackerSensor(DEFAULT_RADAR).at(0.7)
    np.testing.assert_allclose(np.sqrt(np.diag(s.R)), [0.03, np.deg2rad(0.05), np.deg2rad(0.05), 0.01])
    assert SIGMA_RANGE_RATE_KM_S == 0.01
    assert s.covariances(np.zeros((3, 4))).shape == (3, 4, 4)
    c = s.az_center
    nu = s.innovation([1000.0, c + np.pi - 1e-3, 0.5, 0.0], [1000.0, c - np.pi + 1e-3, 0.5, 0.0])
    assert nu[1] == pytest.approx(-2e-3)
    # an EKF update with a return of the truth pulls a perturbed state towards it and shrinks P
    rng = np.random.default_rng(3)
    x_true = _states_at(np.array([[1200.0, c + 0.2, np.deg2rad(40.0)]]), 0.7, rng)
    P = np.diag([1.0, 1.0, 1.0, 0.01, 0.01, 0.01])
    x0 = x_true + np.array([[0.5, -0.5, 0.3, 0.0, 0.0, 0.0]])
    x1, P1, ll = s.update(x0, P[None], s.h(x_true)[0])
    assert abs(s.h(x1)[0, 0] - s.h(x_true)[0, 0]) < 0.05 * abs(s.h(x0)[0, 0] - s.h(x_true)[0, 0])  # range fixed
    assert np.linalg.norm(x1[0, :3] - x_true[0, :3]) < 0.5 * np.linalg.norm(x0[0, :3] - x_true[0, :3])
    assert np.trace(P1[0]) < np.trace(P) and np.isfinite(ll).all()
    with pytest.raises(TypeError, match="GroundRadar"):
        RadarTrackerSensor("radar")
    with pytest.raises(ValueError, match="sigma_range_rate_km_s"):
        RadarTrackerSensor(GroundRadar(), sigma_range_rate_km_s=0.0)

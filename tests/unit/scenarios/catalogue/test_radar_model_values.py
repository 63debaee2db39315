"""The radar tracker sensor's parts on values worked out independently: the attributable's state (the inverse of
``h``, its angle rates by differences along the straight line), its complex-step Jacobian against central
differences, the one-point birth's covariance mapped back into the measurement space (``R`` again), the field of
view on states placed in and out of it, the sensor's EKF update and log-likelihood against the measurement
model's update and ``scipy``'s normal density, the defaults a radar hands its sensor, and bad input."""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack.scenarios.catalogue import DEFAULT_RADAR, GroundRadar
from hypotrack.scenarios.catalogue.frames import EARTH_ROTATION, ef_to_rae, teme_to_ef, wrap_angle
from hypotrack.scenarios.catalogue.radar_model import (
    SIGMA_RANGE_RATE_KM_S,
    RadarMeasurement,
    RadarOnePointBirth,
    RadarTrackerSensor,
    attributable_jacobian,
    attributable_to_state,
    rae_rate,
)

SITE = DEFAULT_RADAR.site
THETA = 0.9
C = DEFAULT_RADAR.fov.az_center  # the default radar looks south: azimuths reported in [0, 2π)


def _attributables(rng, n):
    return np.column_stack([rng.uniform(300, 2500, n), C + rng.uniform(-1.0, 1.0, n), np.deg2rad(rng.uniform(6, 80, n)),
                            rng.uniform(-6, 6, n), rng.uniform(-5e-3, 5e-3, n), rng.uniform(-5e-3, 5e-3, n)])


def test_attributable_state_inverts_h_and_carries_its_angle_rates():
    y = _attributables(np.random.default_rng(5), 30)
    x = attributable_to_state(y, SITE, THETA)
    z = rae_rate(x, SITE, THETA, az_center=C)
    np.testing.assert_allclose(z[:, [0, 2, 3]], y[:, [0, 2, 3]], rtol=0, atol=1e-9)
    np.testing.assert_allclose(z[:, 1], y[:, 1], rtol=0, atol=1e-12)  # inside the report window: no wrap
    h = 1e-3  # az, el rates along the straight TEME line, the Earth turning under it
    rae = []
    for s in (-h, h):
        r_ef, _ = teme_to_ef((x[:, :3] + s * x[:, 3:])[None], x[:, 3:][None], np.array([THETA + EARTH_ROTATION * s]))
        rae.append(ef_to_rae(r_ef[0], SITE.ef, SITE.enu))
    rates = np.column_stack([wrap_angle(rae[1][:, 1] - rae[0][:, 1]), rae[1][:, 2] - rae[0][:, 2]]) / (2 * h)
    np.testing.assert_allclose(rates, y[:, 4:], rtol=1e-6, atol=1e-10)


def test_attributable_jacobian_against_central_differences():
    for y in _attributables(np.random.default_rng(6), 4):
        J = attributable_jacobian(y, SITE, THETA)
        J_fd = np.zeros((6, 6))
        for k, step in enumerate([1e-3, 1e-7, 1e-7, 1e-5, 1e-8, 1e-8]):
            yp, ym = y.copy(), y.copy()
            yp[k] += step
            ym[k] -= step
            J_fd[:, k] = (attributable_to_state(yp, SITE, THETA)[0] - attributable_to_state(ym, SITE, THETA)[0]) / (2 * step)
        np.testing.assert_allclose(J, J_fd, rtol=1e-6, atol=1e-6 * np.abs(J).max())


def test_one_point_birth_maps_back_to_the_return_and_its_noise():
    """h(x₀) = z, and the covariance seen through h's Jacobian is R (h∘f is the identity on (ρ, az, el, ρ̇) whatever
    the angle rates); across the line of sight the velocity has the stated spread v_s per direction."""
    s = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    m = s.measurement
    y = _attributables(np.random.default_rng(7), 3)
    Z = y[:, :4]
    x0, P0 = m.one_point(Z, position_std=0.0, velocity_std=5.0)
    np.testing.assert_allclose(s.h(x0), Z, rtol=0, atol=1e-9)
    H = s.jacobian(x0)
    for i in range(3):
        np.testing.assert_allclose(H[i] @ P0[i] @ H[i].T, s.R, rtol=1e-6, atol=1e-12)
        assert np.array_equal(P0[i], P0[i].T)
        # the velocity covariance across the line of sight: 5 km/s in each direction (the angle rates' share;
        # the few-metre position noise adds only Earth-rotation terms, ~1e-6 relative)
        los = H[i, 0, :3]
        across = np.linalg.svd(np.vstack([los, np.zeros((2, 3))]))[2][1:]  # an orthonormal basis ⟂ the line of sight
        np.testing.assert_allclose(across @ P0[i, 3:, 3:] @ across.T, 25.0 * np.eye(2), rtol=1e-4, atol=1e-3)
    x1, P1 = m.one_point(Z, position_std=3.0, velocity_std=5.0)
    np.testing.assert_array_equal(x1, x0)
    np.testing.assert_allclose(P1 - P0, np.broadcast_to(np.diag([9.0] * 3 + [0.0] * 3), P0.shape), atol=1e-9)
    # the defaults: no extra position spread, 8 km/s across the line of sight
    xd, Pd = m.one_point(Z[:1])
    np.testing.assert_allclose(H[0] @ Pd[0] @ H[0].T, s.R, rtol=1e-6, atol=1e-12)
    across0 = np.linalg.svd(np.vstack([H[0, 0, :3], np.zeros((2, 3))]))[2][1:]
    np.testing.assert_allclose(across0 @ Pd[0, 3:, 3:] @ across0.T, 64.0 * np.eye(2), rtol=1e-4, atol=1e-3)
    xb, Pb = RadarOnePointBirth(m, velocity_std=5.0, position_std=3.0).initial_state(Z[1])
    np.testing.assert_array_equal(xb, x1[1])
    np.testing.assert_array_equal(Pb, P1[1])
    xd, Pd = RadarOnePointBirth(m).initial_state(Z[1])  # defaults: 8 km/s across, no extra position spread
    np.testing.assert_array_equal(Pd, m.one_point(Z[1:2], 0.0, 8.0)[1][0])


def test_in_view_on_states_placed_in_and_out_of_the_field_of_view():
    s = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    fov = DEFAULT_RADAR.fov
    mid_el = np.deg2rad((fov.el_min_deg + fov.el_max_deg) / 2)
    y = np.array([[1000.0, C, mid_el, 0, 0, 0],  # inside
                  [fov.r_max_km + 50.0, C, mid_el, 0, 0, 0],  # too far
                  [1000.0, C, np.deg2rad(fov.el_min_deg) - 0.02, 0, 0, 0],  # too low
                  [1000.0, C + np.pi, mid_el, 0, 0, 0],  # behind the site
                  [fov.r_min_km + 10.0, C + 0.9 * np.deg2rad(fov.az_width_deg) / 2, mid_el, 0, 0, 0]])  # near edges
    x = attributable_to_state(y, SITE, THETA)
    assert s.detection.in_view(x).tolist() == [True, False, False, False, True]
    assert s.detection.in_view(x[:, :3]).tolist() == [True, False, False, False, True]  # positions alone
    assert s.detection.in_view(x[:1]).tolist() == [True] and s.detection.in_view(x[0]).tolist() == [True]
    none = s.detection.in_view(np.zeros((0, 6)))
    assert none.shape == (0,) and none.dtype == bool
    assert s.detection.p_D == DEFAULT_RADAR.p_D
    # the same states seen at another GMST have turned away with the Earth
    assert not s.at(THETA + np.pi).detection.in_view(x)[0]


def test_ekf_update_and_loglik_against_the_measurement_model_and_scipy():
    s = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    rng = np.random.default_rng(8)
    x_true = attributable_to_state(_attributables(rng, 3), SITE, THETA)
    X = x_true + rng.normal(0, 1, (3, 6)) * [0.3, 0.3, 0.3, 0.003, 0.003, 0.003]
    G = rng.normal(0, 1, (3, 6, 6)) * np.array([0.5] * 3 + [0.005] * 3)[:, None]
    P = G @ np.swapaxes(G, 1, 2) + np.diag([0.01] * 3 + [1e-6] * 3)
    z = s.h(x_true[1])[0]
    x1, P1, ll = s.update(X, P, z)
    first = RadarMeasurement(s, second_order=False)
    xr, Pr = first.update(X, P, np.broadcast_to(z, (3, 4)))
    np.testing.assert_allclose(x1, xr, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(P1, Pr, rtol=1e-8, atol=1e-14)
    assert np.array_equal(P1, np.swapaxes(P1, 1, 2))
    z_pred, S, _, _ = first.innovation(X, P)
    nu = s.innovation(z, z_pred)
    want = [multivariate_normal(np.zeros(4), S[i]).logpdf(nu[i]) for i in range(3)]
    np.testing.assert_allclose(ll, want, rtol=1e-10)
    one = s.update(X[0], P[0], z)  # one state given as (6,), (6, 6)
    np.testing.assert_allclose(one[0][0], x1[0], rtol=1e-12)
    np.testing.assert_allclose(one[2], ll[:1], rtol=1e-12)


def test_the_measurement_model_of_a_sensor():
    s = RadarTrackerSensor(DEFAULT_RADAR).at(0.4)
    m = s.measurement
    assert isinstance(m, RadarMeasurement) and m.sensor is s and m.R is s.R and m.second_order is True
    assert RadarMeasurement(s).second_order is True and RadarMeasurement(s, second_order=0).second_order is False
    x = attributable_to_state(_attributables(np.random.default_rng(9), 2), SITE, 0.4)
    np.testing.assert_array_equal(m.h(x), rae_rate(x, SITE, 0.4, az_center=C))
    np.testing.assert_array_equal(m.jacobian(x), s.jacobian(x))
    np.testing.assert_array_equal(s.covariances(np.zeros((2, 4))), np.stack([s.R, s.R]))
    # a fresh sensor is at GMST 0
    fresh = RadarTrackerSensor(DEFAULT_RADAR)
    assert fresh.theta == 0.0
    np.testing.assert_array_equal(fresh.h(x), rae_rate(x, SITE, 0.0, az_center=C))


def test_azimuth_report_window():
    y = np.array([[800.0, -2.5, 0.6, 0, 0, 0]])  # 2.5 rad west of north
    x = attributable_to_state(y, SITE, THETA)
    assert rae_rate(x, SITE, THETA)[0, 1] == pytest.approx(-2.5, abs=1e-12)  # default window [-π, π)
    assert rae_rate(x, SITE, THETA, az_center=np.pi)[0, 1] == pytest.approx(2 * np.pi - 2.5, abs=1e-12)


def test_defaults_a_radar_hands_its_sensor():
    fov = DEFAULT_RADAR.fov
    own = GroundRadar(measurement="rae_rate", sigma_range_rate_km_s=0.02, range_rate_span_km_s=5.0, clutter_rate=3.0)
    s = RadarTrackerSensor(own)
    assert s.sigma_range_rate_km_s == 0.02 and s.range_rate_span_km_s == 5.0 and s.R[3, 3] == pytest.approx(4e-4)
    assert s.clutter_volume == pytest.approx(fov.measurement_volume * 10.0)
    assert s.clutter.rate == 3.0 and s.clutter.region.area == s.clutter_volume
    other = RadarTrackerSensor(GroundRadar(measurement="rae"))
    assert other.sigma_range_rate_km_s == SIGMA_RANGE_RATE_KM_S and other.range_rate_span_km_s == 8.0
    assert other.clutter_volume == pytest.approx(fov.measurement_volume * 16.0)
    # a radar of another measurement does not hand over its range-rate settings
    not_own = RadarTrackerSensor(GroundRadar(measurement="rae", sigma_range_rate_km_s=0.02, range_rate_span_km_s=5.0))
    assert not_own.sigma_range_rate_km_s == SIGMA_RANGE_RATE_KM_S and not_own.range_rate_span_km_s == 8.0
    given = RadarTrackerSensor(own, sigma_range_rate_km_s=0.05, range_rate_span_km_s=2.0)
    assert given.sigma_range_rate_km_s == 0.05 and given.range_rate_span_km_s == 2.0


def test_returns_and_sampled_returns():
    s = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    np.testing.assert_array_equal(s.returns([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]), [[1, 2, 3, 4], [5, 6, 7, 8]])
    assert s.returns([]).shape == (0, 4)
    x = attributable_to_state(np.array([[900.0, C + np.pi - 2e-4, 0.5, 1.0, 0, 0]]), SITE, THETA)  # near the window's edge
    Z = s.sample_returns(np.repeat(x, 20000, axis=0), np.random.default_rng(1))
    assert np.all((Z[:, 1] >= C - np.pi) & (Z[:, 1] < C + np.pi))  # re-wrapped into the report window
    nu = s.innovation(Z, s.h(x))
    np.testing.assert_allclose(nu.mean(axis=0) / np.sqrt(np.diag(s.R)), 0.0, atol=0.03)
    np.testing.assert_allclose(nu.std(axis=0) / np.sqrt(np.diag(s.R)), 1.0, atol=0.02)
    assert np.any(Z[:, 1] < C)  # some wrapped to the far side


def test_bad_input_names_the_parameter():
    s = RadarTrackerSensor(DEFAULT_RADAR)
    with pytest.raises(ValueError, match=r"x must have shape \(n, 6\) .*got \(2, 5\)"):
        s.h(np.zeros((2, 5)))
    with pytest.raises(ValueError, match=r"x must have shape \(n, 6\)"):
        s.h(np.zeros((2, 2, 6)))
    with pytest.raises(ValueError, match="theta must be a 0-D array"):
        s.at([0.1, 0.2])
    with pytest.raises(ValueError, match="theta must be finite"):
        s.at(np.nan)
    with pytest.raises(ValueError, match="Z must be finite"):
        s.returns([1.0, 2.0, np.inf, 4.0])
    with pytest.raises(TypeError, match="radar must be a GroundRadar, got str"):
        RadarTrackerSensor("radar")
    with pytest.raises(ValueError, match="^sigma_range_rate_km_s must be"):
        RadarTrackerSensor(DEFAULT_RADAR, sigma_range_rate_km_s=-1.0)
    with pytest.raises(ValueError, match="^range_rate_span_km_s must be"):
        RadarTrackerSensor(DEFAULT_RADAR, range_rate_span_km_s=0.0)


def test_returns_refuse_a_scan_of_the_wrong_width_and_take_an_empty_one():
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    with pytest.raises(ValueError, match=r"^Z must have shape \(n, 4\), got \(3, 8\)$"):
        sensor.returns(np.zeros((3, 8)))  # two returns' width per row: never silently six returns
    with pytest.raises(ValueError, match=r"^Z must have shape \(n, 4\), got \(3, 3\)$"):
        sensor.returns(np.zeros((3, 3)))
    assert sensor.returns([]).shape == (0, 4)
    assert sensor.returns(np.zeros((0, 2))).shape == (0, 4)

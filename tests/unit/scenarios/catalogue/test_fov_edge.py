"""The soft-edged field of view (:mod:`hypotrack.scenarios.catalogue.fov_edge`): ``P_in`` against sampling of the
track's density on each side of the default radar's field of view (elevation, azimuth sector, range), its value on
the edge (one half), the dilated test against the true one, the hook that hands ``p_D P_in`` to the filters, and a
δ-GLMB filter that gives a return to the track whose mean lies just below the horizon only with the soft edge (the
acquisition error it removes)."""

import numpy as np
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.run import make_motion, make_problem, make_radar, make_tracker, tracker_sensor
from hypotrack.hypotheses.detection import state_p_detect
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.fov_edge import SoftEdgeDetection, attach_soft_edge
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, attributable_to_state

THETA = 0.9
F = DEFAULT_RADAR.fov  # az 120-240 deg, el 5-85 deg, range 200-3000 km


def _sensor(margin_deg=1.0, margin_km=50.0):
    s = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    return attach_soft_edge(s, margin_deg, margin_km)


def _state(rho, az_deg, el_deg, site=DEFAULT_RADAR.site):
    y = np.array([[rho, np.deg2rad(az_deg), np.deg2rad(el_deg), 0.5, 1e-3, 2e-3]])
    return attributable_to_state(y, site, THETA)[0]


def _cov(sd_pos_km, sd_vel=1e-4, seed=0):
    A = np.random.default_rng(seed).normal(size=(3, 3))
    Q, _ = np.linalg.qr(A)
    P = np.zeros((6, 6))
    P[:3, :3] = Q @ np.diag(np.square(sd_pos_km)) @ Q.T
    P[3:, 3:] = sd_vel**2 * np.eye(3)
    return P


@pytest.mark.parametrize("where", [(1500.0, 180.0, 5.05), (1500.0, 120.2, 40.0), (2998.0, 180.0, 40.0),
                                   (1500.0, 180.0, 4.9), (203.0, 180.0, 40.0), (1500.0, 180.0, 84.95)])
def test_p_in_view_matches_sampling_of_the_track(where):
    """Each side in turn: a track near it, ~5 km spread; the share of 200,000 draws inside the true field of view
    (the radar's own test) against ``P_in`` (linearised, within 0.01: sampling s.e. ~0.001)."""
    s = _sensor()
    m, P = _state(*where), _cov([5.0, 3.0, 2.0])
    X = np.random.default_rng(1).multivariate_normal(m, P, 200_000)
    share = s.detection.in_fov(X[:, :3]).mean()
    p = s.detection.p_in_view(m[None], P[None])[0]
    assert 0.05 < share < 0.95  # the edge matters here
    assert p == pytest.approx(share, abs=0.01)


def test_p_in_view_is_one_half_on_the_edge_and_one_or_zero_far_from_it():
    s = _sensor()
    P = _cov([2.0, 2.0, 2.0])
    on = _state(1500.0, 180.0, F.el_min_deg)
    assert s.detection.p_in_view(on[None], P[None])[0] == pytest.approx(0.5, abs=1e-6)
    deep, out = _state(1500.0, 180.0, 40.0), _state(1500.0, 180.0, 4.0)  # out: 1 deg = 26 km, ~13 sd below
    p = s.detection.p_D_of_moments(np.stack([deep, out]), np.stack([P, P]))
    assert p[0] == pytest.approx(DEFAULT_RADAR.p_D, abs=1e-12)
    assert p[1] < 1e-20


def test_dilated_view_against_the_true_one():
    """Each side dilated by its margin alone (1° in angle, 50 km in range): below the lowest elevation, beyond the
    longest range, beside the azimuth sector (1° each side, not 1.5°), above the highest elevation, inside the
    shortest range."""
    s = _sensor(margin_deg=1.0, margin_km=50.0)
    X = np.stack([_state(1500.0, 180.0, 4.5), _state(1500.0, 180.0, 3.5), _state(3040.0, 180.0, 40.0),
                  _state(3060.0, 180.0, 40.0), _state(1500.0, 119.5, 40.0), _state(1500.0, 180.0, 40.0),
                  _state(1500.0, 118.7, 40.0), _state(1500.0, 180.0, 85.5), _state(1500.0, 180.0, 86.5),
                  _state(160.0, 180.0, 40.0), _state(140.0, 180.0, 40.0)])
    np.testing.assert_array_equal(s.detection.in_view(X[:, :3]),
                                  [True, False, True, False, True, True, False, True, False, True, False])
    np.testing.assert_array_equal(s.detection.in_fov(X[:, :3]), [False] * 5 + [True] + [False] * 5)
    wide = _sensor(margin_deg=2.0).detection  # the sector widened by the margin on each side: 2°, not 1° or 3°
    Y = np.stack([_state(1500.0, 118.5, 40.0), _state(1500.0, 117.5, 40.0)])
    np.testing.assert_array_equal(wide.in_view(Y[:, :3]), [True, False])


def test_the_dilated_view_stops_at_the_horizon_and_at_the_site():
    """A field of view from 0.5° and 30 km: dilated by 1° and 50 km its lower bounds are 0° and 0 km, not below (a
    point at 0.3° elevation and one 0.5 km from the site are inside it)."""
    from dataclasses import replace

    radar = replace(DEFAULT_RADAR, fov=replace(F, el_min_deg=0.5, r_min_km=30.0))
    s = attach_soft_edge(RadarTrackerSensor(radar).at(THETA), 1.0, 50.0)
    X = np.stack([_state(1500.0, 180.0, 0.3), _state(0.5, 180.0, 40.0)])
    np.testing.assert_array_equal(s.detection.in_view(X[:, :3]), [True, True])
    np.testing.assert_array_equal(s.detection.in_fov(X[:, :3]), [False, False])


def test_no_upper_elevation_bound_at_the_zenith():
    """The breakup radar sees up to 90°: a track 0.05° from the zenith is in view whatever its spread (an elevation
    past 90° is the other side of the zenith), as sampling says; bounding the linearised elevation at 90° would give
    about two thirds."""
    radar = make_radar(_breakup_cfg(False))
    s = attach_soft_edge(tracker_sensor(radar).at(THETA), 1.0, 50.0)
    m, P = _state(1000.0, 180.0, 89.95, radar.site), _cov([2.0, 2.0, 2.0])
    X = np.random.default_rng(2).multivariate_normal(m, P, 100_000)
    assert s.detection.in_fov(X[:, :3]).mean() == 1.0
    assert s.detection.p_in_view(m[None], P[None])[0] == pytest.approx(1.0, abs=1e-6)


def test_empty_tracks_and_the_wrapped_state_dependent_p_D():
    """No track: no probability. Over an SNR detection (p_D of the range) the soft edge scales the wrapped p_D of each
    mean, not the constant."""
    from hypotrack.scenarios.catalogue.snr import SizeModel, SnrModel, attach_snr_detection

    s = _sensor()
    assert s.detection.p_in_view(np.zeros((0, 6)), np.zeros((0, 6, 6))).shape == (0,)
    assert s.detection.p_D_of_moments(np.zeros((0, 6)), np.zeros((0, 6, 6))).shape == (0,)
    snr = attach_snr_detection(RadarTrackerSensor(DEFAULT_RADAR).at(THETA), SnrModel(), SizeModel())
    base = snr.detection
    attach_soft_edge(snr, 1.0, 50.0)
    X = np.stack([_state(1000.0, 180.0, 40.0), _state(2800.0, 180.0, 40.0)])
    P = np.stack([_cov([1.0, 1.0, 1.0])] * 2)
    want = base.p_D_of(X) * snr.detection.p_in_view(X, P)
    assert want[0] != want[1] and abs(want[0] - base.p_D) > 1e-3  # the range matters, the constant is not used
    np.testing.assert_array_equal(snr.detection.p_D_of_moments(X, P), want)


def test_state_p_detect_takes_the_moments_where_in_view_only():
    s = _sensor()
    X = np.stack([_state(1500.0, 180.0, 5.0), _state(1500.0, 180.0, 40.0)])
    P = np.stack([_cov([2.0, 2.0, 2.0])] * 2)
    p = state_p_detect(s.detection, X, np.array([0.9, 0.0]), P)
    assert p[0] == pytest.approx(0.45, abs=1e-6) and p[1] == 0.0  # the second column out of view stays 0
    # without covariances the constant stands (no p_D_of on the radar's own detection)
    np.testing.assert_array_equal(state_p_detect(s.detection, X, np.array([0.9, 0.9])), [0.9, 0.9])


def test_bad_margins_are_refused():
    with pytest.raises(ValueError, match="^margin_deg must"):
        SoftEdgeDetection(RadarTrackerSensor(DEFAULT_RADAR), -1.0, 50.0)
    with pytest.raises(ValueError, match="^margin_km must"):
        SoftEdgeDetection(RadarTrackerSensor(DEFAULT_RADAR), 1.0, float("nan"))


def _breakup_cfg(edge):
    with open("workflows/config/default.yaml") as fh:
        cfg = yaml.safe_load(fh)["ssa_breakup"]
    cfg["model"] = {k: v for k, v in cfg["model"].items() if k != "fov_edge"}
    cfg["model"]["plausibility"] = False  # the test's states are placed by their returns, not on orbits
    if edge:
        cfg["model"]["fov_edge"] = {"margin_deg": 1.0, "margin_km": 50.0}
    return cfg


@pytest.mark.parametrize("edge", [False, True])
def test_a_return_from_a_track_below_the_horizon_goes_to_it_only_with_the_soft_edge(edge):
    """Two catalogued tracks spread 0.2° in elevation (~9 km at 2,500 km): A's mean 0.02° below the lowest
    elevation, B's 0.35° above it, at the same range and azimuth; one return, made by A's object 0.01° above the
    edge. It fits A far better (squared Mahalanobis distances ~0.1 and ~10). Deciding p_D at the mean, A cannot take it (p_D 0)
    and the δ-GLMB's MAP gives it to B; with the soft edge A's p_D is 0.9 P_in ≈ 0.41 and the MAP gives it to A
    (hand count: 0.41 g_A 0.1 against 0.9 g_B 0.59, g_A / g_B ≈ e^5)."""
    cfg = _breakup_cfg(edge)
    radar = make_radar(cfg)
    s = tracker_sensor(radar).at(THETA)
    el_min = radar.fov.el_min_deg
    a, b = _state(2500.0, 180.0, el_min - 0.02, radar.site), _state(2500.0, 180.0, el_min + 0.35, radar.site)
    J = s.jacobian(a[None])[0]
    step = np.linalg.pinv(J[2:3, :3])[:, 0] * np.deg2rad(0.2)  # the position step of 0.2° in elevation
    P = np.diag([0.01] * 3 + [1e-8] * 3)
    P[:3, :3] += np.outer(step, step)
    z = s.h(a[None])[0].copy()
    z[2] = np.deg2rad(el_min + 0.01)
    problem = make_problem(cfg, s, make_motion(cfg), np.stack([a, b]), np.stack([P, P]), np.array([1, 2]))
    p_in = s.detection.p_in_view(a[None], P[None])[0] if edge else None
    tr = make_tracker("glmb_murty", cfg, problem, 0)
    tr.step(z[None], 0.0)
    e = tr.estimates()
    lab, X = np.asarray(e.labels), np.asarray(e.x)
    moved_a = np.linalg.norm(X[lab == 1][0, :3] - a[:3])
    moved_b = np.linalg.norm(X[lab == 2][0, :3] - b[:3])
    if edge:
        assert p_in == pytest.approx(0.46, abs=0.02)  # Φ(−0.1)
        assert moved_a > 1.0 and moved_b == 0.0  # A took the return, B was missed
    else:
        assert moved_a == 0.0 and moved_b > 1.0  # A could not: B took it

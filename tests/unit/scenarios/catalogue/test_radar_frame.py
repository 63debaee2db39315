"""The trackers in the radar's sensor frame: the EKF update against Stone Soup's, the simulated range-rate
returns against the model, and an object born from one return of the admissible region."""

import dataclasses

import numpy as np
import pytest

from hypotrack.gaussian import predict_with
from hypotrack.models.orbit3d import TwoBodyOrbit3D

from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue import GroundRadar, RadarFieldOfView, load_catalogue, select_groups
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth
from hypotrack.scenarios.catalogue.frames import rae_to_enu
from hypotrack.scenarios.catalogue.radar_model import (RadarMeasurement, RadarOnePointBirth, RadarTrackerSensor, rae_rate,
                                                       rae_rate_jacobian, site_teme)
from hypotrack.scenarios.catalogue.scenario import simulate_catalogue

THETA = 1.3
RADAR = GroundRadar(fov=RadarFieldOfView(0.0, 360.0, 5.0, 85.0, 200.0, 3000.0), measurement="rae_rate")


def _state(az, el, rho, rng):
    """A TEME state at (ρ, az, el) from the site, LEO-like velocity."""
    sensor = RadarTrackerSensor(RADAR).at(THETA)
    M = RADAR.site.enu @ np.array([[np.cos(THETA), np.sin(THETA), 0], [-np.sin(THETA), np.cos(THETA), 0], [0, 0, 1]])
    s, _ = site_teme(RADAR.site, THETA)
    r = s + rae_to_enu(np.array([[rho, az, el]]))[0] @ M
    v = np.cross(r, [0.3, 0.2, 1.0])
    v *= 7.4 / np.linalg.norm(v) + rng.normal(0, 0.01)
    return sensor, np.r_[r, v], M


def _stone_soup_update(x, P, z_ours, M, sensor):
    """Stone Soup's EKF on the same problem: the state moved affinely to the site's ENU frame
    (``(M (r − s), M (v − ṡ))``: an EKF commutes with affine maps of the state), measured by
    ``CartesianToElevationBearingRangeRate`` (bearing from east towards north: ``π/2 − az``)."""
    sst = pytest.importorskip("stonesoup")
    del sst
    from stonesoup.models.measurement.nonlinear import CartesianToElevationBearingRangeRate
    from stonesoup.types.angle import Bearing, Elevation
    from stonesoup.types.detection import Detection
    from stonesoup.types.prediction import GaussianStatePrediction
    from stonesoup.types.state import StateVector
    from stonesoup.updater.kalman import ExtendedKalmanUpdater
    from stonesoup.types.hypothesis import SingleHypothesis

    s, sdot = site_teme(RADAR.site, THETA)
    A = np.zeros((6, 6))
    A[:3, :3] = A[3:, 3:] = M
    b = -np.r_[M @ s, M @ sdot]
    perm = [0, 3, 1, 4, 2, 5]  # Stone Soup's (x, vx, y, vy, z, vz)
    xs, Ps = (A @ x + b)[perm], (A @ P @ A.T)[np.ix_(perm, perm)]
    sig2 = np.diag(sensor.R)
    model = CartesianToElevationBearingRangeRate(ndim_state=6, mapping=(0, 2, 4), velocity_mapping=(1, 3, 5),
                                                 noise_covar=np.diag([sig2[2], sig2[1], sig2[0], sig2[3]]))
    rho, az, el, rd = z_ours
    det = Detection(StateVector([Elevation(el), Bearing(np.pi / 2 - az), rho, rd]), measurement_model=model)
    pred = GaussianStatePrediction(StateVector(xs), Ps)
    post = ExtendedKalmanUpdater(model).update(SingleHypothesis(pred, det))
    inv = np.argsort(perm)
    xp = np.asarray(post.state_vector, dtype=float).ravel()[inv]
    Pp = np.asarray(post.covar, dtype=float)[np.ix_(inv, inv)]
    Ai = np.linalg.inv(A)
    return Ai @ (xp - b), Ai @ Pp @ Ai.T


@pytest.mark.parametrize("az, dz", [(np.pi - 2e-4, 5e-4),       # the return across our wrap (az_center 0: ±π)
                                    (-np.pi / 2 + 1e-4, -3e-4)])  # across Stone Soup's (bearing ±π)
def test_sensor_frame_ekf_update_equals_stone_soups(az, dz):
    rng = np.random.default_rng(11)
    sensor, x, M = _state(az, np.deg2rad(35.0), 1400.0, rng)
    A = rng.normal(0, 1, (6, 6))
    D = np.diag(np.sqrt(np.r_[[0.4] * 3, [1e-4] * 3]))
    P = D @ A @ A.T @ D + np.diag(np.r_[[0.2] * 3, [2e-5] * 3])  # correlated, positive definite
    z = sensor.h(x)[0] + np.array([0.05, dz, -2e-4, 0.004])
    z[1] = np.mod(z[1] + np.pi, 2 * np.pi) - np.pi  # reported in [−π, π)
    if az > 3:
        assert z[1] < -3 < 3 < sensor.h(x)[0, 1]  # return and prediction on either side of the wrap
    first = RadarMeasurement(sensor, second_order=False)  # Stone Soup's EKF is first order
    xu, Pu = first.update(x[None], P[None], z[None])
    xs, Ps = _stone_soup_update(x, P, z, M, sensor)
    np.testing.assert_allclose(xu[0], xs, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(Pu[0], Ps, rtol=1e-8, atol=1e-9 * np.abs(P).max())
    assert np.linalg.norm(xu[0, :3] - x[:3]) < 2.0  # a small correction, not a 2π one
    # the sensor's own (older) EKF step agrees
    x2, P2, _ = sensor.update(x[None], P[None], z)
    np.testing.assert_allclose(xu, x2, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(Pu, P2, rtol=1e-10, atol=1e-12)
    # distance of the wrapped residual: what the gates use
    zp, S, _, _ = first.innovation(x[None], P[None])
    d2, _ = first.mahalanobis2(z[None], zp, S)
    nu = z - zp[0]
    nu[1] = np.mod(nu[1] + np.pi, 2 * np.pi) - np.pi
    assert d2[0, 0] == pytest.approx(nu @ np.linalg.solve(S[0], nu), rel=1e-9)
    assert d2[0, 0] < 50


@pytest.fixture(scope="module")
def catalogue_scan():
    cat = select_groups(load_catalogue(), "fengyun-1c-debris")
    radar = GroundRadar(p_D=1.0, clutter_rate=3.0, measurement="rae_rate")
    return simulate_catalogue(cat, radar, n_scans=30, seed=5), radar


def test_simulated_range_rate_returns_are_the_model_plus_its_noise(catalogue_scan):
    sc, radar = catalogue_scan
    assert [c for c in sc.scans.columns if c.startswith("z_")] == ["z_0", "z_1", "z_2", "z_3"]
    sensor = RadarTrackerSensor(radar)
    res, clutter = [], []
    for k, (_t, Z, origin) in enumerate(sc.scan_list(0, with_origin=True)):
        tr = sc.truth[sc.truth["scan"] == k].set_index("target")
        for z, o in zip(Z, origin):
            if o < 0:
                clutter.append(z)
                continue
            x = tr.loc[o, [f"state_{i}" for i in range(6)]].to_numpy(float)
            res.append(sensor.measurement.residual_rows(z[None], rae_rate(x, radar.site, sc.theta[k],
                                                                           az_center=radar.fov.az_center))[0])
    res, clutter = np.array(res), np.array(clutter)
    assert len(res) > 300 and len(clutter) > 60
    w = res / np.sqrt(np.diag(sensor.R))
    assert np.all(np.abs(w.mean(axis=0)) < 4 / np.sqrt(len(w)))  # unbiased (4 standard errors)
    np.testing.assert_allclose(w.std(axis=0), 1.0, atol=0.12)     # σ 30 m, 0.05°, 0.05°, 10 m/s
    assert np.all(np.abs(clutter[:, 3]) <= 8.0) and clutter[:, 3].std() > 3.0  # uniform over ±8 km/s
    assert sensor.clutter.intensity == pytest.approx(3.0 / (radar.fov.measurement_volume * 16.0))
    assert radar.clutter_density == pytest.approx(1 / (radar.fov.measurement_volume * 16.0))


def test_an_object_born_from_one_return_of_its_admissible_region(catalogue_scan):
    """One return of a real object (SGP4) gives the admissible mixture; every component is a plausible orbit; the
    δ-GLMB filter with those births holds the object within a few km after three scans."""
    from hypotrack.experiments.ssa_catalogue.run import make_motion, make_problem, make_tracker

    sc, radar = catalogue_scan
    counts = sc.truth.groupby("target").size()
    norad = int(counts.index[np.argmax(counts.to_numpy())])
    rows = sc.truth[sc.truth["target"] == norad]
    k0 = int(rows["scan"].min())
    cfg = {"model": {"motion": "j2", "process_noise_q": 1e-9, "gate_probability": 0.999, "r_birth": 0.05,
                     "birth_position_std_km": 0.0, "birth_velocity_std_km_s": 8.0, "homht_births_per_scan": 0.5,
                     "birth": "admissible"},
           "radar": {"revisit_s": radar.revisit_s},
           "trackers": {"glmb": {"kind": "glmb", "n_sweeps": 30, "max_hypotheses": 20, "gate_probability": 0.999,
                                 "factored": {"split": "marginal", "min_weight": 0.001}}}}
    sensor = RadarTrackerSensor(dataclasses.replace(radar, p_D=0.9))  # the tracker's p_D below 1 (every return here)
    problem = make_problem(cfg, sensor, make_motion(cfg), np.zeros((0, 6)), np.zeros((0, 6, 6)), np.zeros(0, np.int64))
    tracker = make_tracker("glmb", cfg, problem, 1)
    scans = sc.scan_list(0, with_origin=True)
    errs = []
    for k in range(k0, k0 + 4):
        t, Z, origin = scans[k]
        Z = Z[origin == norad]  # the object's returns alone
        sensor.at(sc.theta[k])
        if k == k0:
            mix = AdmissibleRegionBirth(sensor, n_blocks=3).mixture(Z[0])
            assert 1 <= len(mix) <= 9 and mix.weights.sum() == pytest.approx(1.0)
            assert plausible_orbits(mix.means).all()
            assert plausible_orbits(mix.sample(2000, np.random.default_rng(0))).mean() > 0.95
        tracker.step(Z, float(t))
        if k == k0:
            terms = tracker._engine.population.birth_densities
            assert len(terms) == len(mix) and plausible_orbits(np.array([b.mean for b in terms])).all()
            np.testing.assert_allclose(tracker._engine.population.r_birth, 0.05 * mix.weights, rtol=1e-12)
        e = tracker.estimates()
        truth = rows[rows["scan"] == k][[f"state_{i}" for i in range(6)]].to_numpy(float)[0]
        errs.append(np.linalg.norm(e.x[:, :3] - truth[:3], axis=1).min() if len(e) else np.inf)
        if len(e):
            assert plausible_orbits(e.x).all()
    assert errs[-1] < 3.0 and errs[-2] < 5.0  # km: born at the second return, within a few km by the third


def test_one_point_birth_in_the_sensor_frame_carries_the_range_rate():
    rng = np.random.default_rng(2)
    sensor, x, _ = _state(0.3, np.deg2rad(50.0), 900.0, rng)
    z = sensor.h(x)[0]
    x0, P0 = RadarOnePointBirth(sensor.measurement, 8.0).initial_state(z)
    assert sensor.h(x0)[0] == pytest.approx(z, abs=1e-9)  # its return is the return itself
    H = sensor.jacobian(x0[None])[0]
    S = H @ P0 @ H.T
    np.testing.assert_allclose(np.sqrt(np.diag(S)), np.sqrt(np.diag(sensor.R)), rtol=1e-6)  # measured as well as z
    d = (x0[:3] - site_teme(RADAR.site, THETA)[0]) / z[0]
    Pv = P0[3:, 3:]
    w, V = np.linalg.eigh(Pv)
    assert w[0] == pytest.approx(sensor.R[3, 3], rel=1e-3) and abs(V[:, 0] @ d) == pytest.approx(1.0, abs=1e-3)
    np.testing.assert_allclose(np.sqrt(w[1:]), 8.0, rtol=1e-3)  # across the line of sight: N(0, 8²)


def test_second_order_terms_match_the_geometry_and_sampled_moments():
    """The Hessian of the range is ``(I − d dᵀ/ρ²)/ρ`` (positions) and the range-rate's is bilinear; for a one-point
    birth's prior (80 km across the line of sight after 10 s) the second-order predicted return and covariance
    match 200,000 draws' moments, where the first-order range misses by kilometres."""
    rng = np.random.default_rng(5)
    sensor, x, _ = _state(1.0, np.deg2rad(20.0), 2000.0, rng)
    m2, m1 = sensor.measurement, RadarMeasurement(sensor, second_order=False)
    assert m2.second_order and not m1.second_order
    Hxx = m2.hessian(x[None])[0]
    d = x[:3] - site_teme(RADAR.site, THETA)[0]
    rho = np.linalg.norm(d)
    np.testing.assert_allclose(Hxx[0, :3, :3], (np.eye(3) - np.outer(d, d) / rho**2) / rho, rtol=0, atol=1e-10)
    assert np.abs(Hxx[:3, 3:, 3:]).max() == 0 and np.abs(Hxx[3, 3:, 3:]).max() < 1e-12  # linear in v
    np.testing.assert_allclose(Hxx[3, :3, 3:], (np.eye(3) - np.outer(d, d) / rho**2) / rho, atol=1e-10)
    # ∂²ρ̇/∂v∂r is ∂(d/ρ)/∂r, the range's Hessian; the Hessian is the Jacobian's derivative (its own check)
    x_s = x + np.r_[0.5, -0.3, 0.2, 0.0, 0.0, 0.0]
    np.testing.assert_allclose((rae_rate_jacobian(x_s[None], RADAR.site, THETA)[0] - rae_rate_jacobian(x[None], RADAR.site, THETA)[0])[0, :3],
                               Hxx[0, :3, :3] @ (x_s - x)[:3], rtol=1e-3)
    x0, P0 = RadarOnePointBirth(m2, 8.0).initial_state(sensor.h(x)[0])
    xp, Pp = predict_with(TwoBodyOrbit3D(q=1e-9), x0, P0, 10.0)
    draws = xp + rng.standard_normal((200_000, 6)) @ np.linalg.cholesky(Pp).T
    zs = sensor.h(draws)
    zs[:, 1] = np.mod(zs[:, 1] - sensor.h(xp[None])[0, 1] + np.pi, 2 * np.pi) - np.pi + sensor.h(xp[None])[0, 1]
    mean, cov = zs.mean(axis=0), np.cov(zs.T)
    z2, S2, _, _ = m2.innovation(xp[None], Pp[None])
    z1, S1, _, _ = m1.innovation(xp[None], Pp[None])
    se = np.sqrt(np.diag(cov) / len(zs))
    assert abs(z1[0, 0] - mean[0]) > 1.0                      # first order: the range off by over 1 km
    assert np.all(np.abs(z2[0] - mean) < 5 * se + 1e-3 * np.sqrt(np.diag(cov)))  # second order: the sampled mean
    np.testing.assert_allclose(np.sqrt(np.diag(S2[0])), np.sqrt(np.diag(cov)), rtol=0.05)
    assert np.sqrt(S1[0, 0, 0]) < 0.5 * np.sqrt(cov[0, 0])    # first order: range spread under half the true one


def test_clone_scenario_gives_range_rate_returns_too():
    from hypotrack.scenarios.catalogue.clones import simulate_clones

    radar = GroundRadar(measurement="rae_rate", p_D=1.0, clutter_rate=0.0)
    sc = simulate_clones(load_catalogue(), 3000, radar, n_scans=5, seed=1, clone_seed=2)
    sensor = RadarTrackerSensor(radar)
    w = []
    for k, (_t, Z, origin) in enumerate(sc.scan_list(0, with_origin=True)):
        tr = sc.truth[sc.truth["scan"] == k].set_index("target")
        for z, o in zip(Z, origin):
            x = tr.loc[o, [f"state_{i}" for i in range(6)]].to_numpy(float)
            nu = sensor.measurement.residual_rows(z[None], rae_rate(x, radar.site, sc.theta[k], az_center=radar.fov.az_center))
            w.append(nu[0] / np.sqrt(np.diag(sensor.R)))
    w = np.array(w)
    assert w.shape[1] == 4 and len(w) > 100
    assert np.all(np.abs(w.mean(axis=0)) < 4 / np.sqrt(len(w))) and np.all(np.abs(w.std(axis=0) - 1) < 0.25)

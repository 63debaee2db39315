"""Cluttered 2-D constant-velocity scenarios: geometry, statistics, determinism, bad input."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from hypotrack.scenarios.cluttered import closely_spaced_targets, crossing_targets, simulate_cv_targets
from hypotrack.models.sensors import Box


def test_same_seed_same_tables_different_seed_different():
    a, b, c = crossing_targets(rng=5), crossing_targets(rng=5), crossing_targets(rng=6)
    pd.testing.assert_frame_equal(a.scans, b.scans)
    pd.testing.assert_frame_equal(a.truth, b.truth)
    assert not a.scans.equals(c.scans)


@pytest.mark.parametrize("n", [2, 3, 5])
def test_crossing_geometry(n):
    sc = crossing_targets(n, speed=12.0, crossing_angle_deg=20.0, n_scans=41, q_truth=0.0, rng=1)
    middle = sc.truth[sc.truth["scan"] == 20][["state_0", "state_1"]].to_numpy()
    np.testing.assert_allclose(middle, 0.0, atol=1e-9)  # all paths through the origin at mid-run
    v = sc.initial_states[:, 2:]
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 12.0)
    heading = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    np.testing.assert_allclose(heading, np.linspace(-10, 10, n), atol=1e-12)
    assert sc.truth["in_view"].all()


def test_closely_spaced_formation():
    sc = closely_spaced_targets(6, spacing=15.0, speed=8.0, q_truth=0.0, n_scans=5, rng=2)
    first = sc.truth[sc.truth["scan"] == 0].sort_values("target")
    np.testing.assert_allclose(first["state_1"].to_numpy(), 15.0 * np.arange(6))
    last = sc.truth[sc.truth["scan"] == 4]
    np.testing.assert_allclose(last["state_0"].to_numpy(), 32.0)


def test_clutter_count_and_spread():
    """Poisson(rate) clutter per scan, uniform over the region (one-sample KS on each axis)."""
    sc = simulate_cv_targets(
        np.zeros((0, 4)), n_scans=3000, dt=1.0, q_truth=0.0, R=np.eye(2), p_D=1.0, clutter_rate=4.0,
        region=Box([0.0, 0.0], [100.0, 50.0]), rng=7,
    )
    counts = np.array([len(Z) for _, Z in sc.scan_list()])
    assert counts.mean() == pytest.approx(4.0, abs=4 * np.sqrt(4.0 / 3000))
    assert counts.var() == pytest.approx(4.0, rel=0.1)  # Poisson: variance = mean
    assert (sc.scans["origin"] == -1).all()
    assert stats.kstest(sc.scans["z_0"], stats.uniform(0, 100).cdf).pvalue > 1e-3
    assert stats.kstest(sc.scans["z_1"], stats.uniform(0, 50).cdf).pvalue > 1e-3
    assert sc.clutter_density == pytest.approx(4.0 / 5000)


def test_detection_rate_and_measurement_noise():
    R = np.array([[9.0, 2.0], [2.0, 4.0]])
    X0 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 40.0, 0.0, -1.0]])
    sc = simulate_cv_targets(
        X0, n_scans=2000, dt=1.0, q_truth=0.0, R=R, p_D=0.7, clutter_rate=0.0,
        region=Box([-100.0, -3000.0], [3000.0, 100.0]), rng=9,
    )
    det = sc.scans.merge(sc.truth, left_on=["scan", "origin"], right_on=["scan", "target"])
    rate = len(det) / (2 * 2000)
    assert rate == pytest.approx(0.7, abs=4 * np.sqrt(0.7 * 0.3 / 4000))
    err = det[["z_0", "z_1"]].to_numpy() - det[["state_0", "state_1"]].to_numpy()
    np.testing.assert_allclose(err.mean(axis=0), 0.0, atol=4 * 3 / np.sqrt(len(err)))
    np.testing.assert_allclose(np.cov(err.T), R, atol=0.6)


def test_process_noise_gives_cv_increments():
    """Truth velocity increments have variance q·dt per axis (white-noise acceleration)."""
    q, dt = 2.0, 0.5
    sc = simulate_cv_targets(
        np.zeros((50, 4)), n_scans=200, dt=dt, q_truth=q, R=np.eye(2), p_D=1.0, clutter_rate=0.0,
        region=Box([-1e4, -1e4], [1e4, 1e4]), rng=3,
    )
    v = sc.truth.sort_values(["target", "scan"])[["state_2", "state_3"]].to_numpy().reshape(50, 200, 2)
    dv = np.diff(v, axis=1).reshape(-1, 2)
    np.testing.assert_allclose(dv.var(axis=0), q * dt, rtol=0.05)


def test_zero_targets_and_empty_scans():
    sc = closely_spaced_targets(0, clutter_rate=0.0, n_scans=4, rng=0)
    assert sc.truth.empty and sc.scans.empty
    scans = sc.scan_list()
    assert len(scans) == 4 and all(Z.shape == (0, 2) for _, Z in scans)
    assert [len(ids) for _, ids, _ in sc.truth_list()] == [0, 0, 0, 0]


def test_bad_input():
    with pytest.raises(ValueError, match="n_targets"):
        crossing_targets(0)
    with pytest.raises(ValueError, match="crossing_angle_deg"):
        crossing_targets(2, crossing_angle_deg=180.0)
    with pytest.raises(ValueError, match="sigma"):
        crossing_targets(2, sigma=0.0)
    with pytest.raises(ValueError, match="p_D"):
        closely_spaced_targets(3, p_D=0.0)
    with pytest.raises(ValueError, match="spacing"):
        closely_spaced_targets(3, spacing=-1.0)
    with pytest.raises(ValueError, match="rate"):
        closely_spaced_targets(3, clutter_rate=-1.0)
    with pytest.raises(ValueError, match="initial_states"):
        simulate_cv_targets(np.zeros((2, 3)), n_scans=2, dt=1.0, q_truth=0.0, R=np.eye(2), p_D=1.0,
                            clutter_rate=0.0, region=Box([0, 0], [1, 1]), rng=0)
    with pytest.raises(ValueError, match="n_scans"):
        crossing_targets(2, n_scans=0)

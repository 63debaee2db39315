"""Sensors: measurement noise, FOV geometry, detection, Poisson clutter, sensor arrays."""

import math

import numpy as np
import pytest
from scipy import stats

from hypotrack.models.sensors import (
    Box,
    DetectionModel,
    FieldOfView,
    LinearPositionSensor,
    PoissonClutter,
    Sensor,
    SensorArray,
)

R2 = np.array([[4.0, 1.0], [1.0, 2.0]])


def polar(r, deg):
    th = np.deg2rad(np.asarray(deg, dtype=float))
    return np.column_stack([r * np.cos(th), r * np.sin(th)])


# --- LinearPositionSensor -------------------------------------------------------------


def test_linear_sensor_H_and_exact_noise_draw():
    s = LinearPositionSensor(R2, ndim_state=4, position_indices=(1, 0))
    assert s.dim == 2
    np.testing.assert_array_equal(s.H, [[0, 1, 0, 0], [1, 0, 0, 0]])
    X = np.arange(12.0).reshape(3, 4)
    z = s.measure(X, np.random.default_rng(5))
    # Oracle: the same generator stream coloured by the Cholesky factor of R.
    e = np.random.default_rng(5).standard_normal((3, 2)) @ np.linalg.cholesky(R2).T
    np.testing.assert_allclose(z, X[:, [1, 0]] + e, rtol=0, atol=1e-12)


def test_linear_sensor_noise_covariance_matches_R():
    s = LinearPositionSensor(R2, ndim_state=4)
    n = 200_000
    z = s.measure(np.zeros((n, 4)), np.random.default_rng(1))
    C = np.cov(z.T)
    # Standard error of a sample covariance entry: sqrt((R_ij^2 + R_ii R_jj) / n).
    se = np.sqrt((R2**2 + np.outer(np.diag(R2), np.diag(R2))) / n)
    assert np.all(np.abs(C - R2) < 5 * se)
    assert np.all(np.abs(z.mean(axis=0)) < 5 * np.sqrt(np.diag(R2) / n))


def test_linear_sensor_empty_states():
    s = LinearPositionSensor(np.eye(2), 4)
    assert s.measure(np.zeros((0, 4)), np.random.default_rng(0)).shape == (0, 2)


@pytest.mark.parametrize(
    "R, kwargs, match",
    [
        (np.array([[1.0, 2.0], [2.0, 1.0]]), {}, "R must be positive definite"),
        (np.eye(3), {}, "R must be 2x2"),
        (np.array([[1.0, 0.5], [0.0, 1.0]]), {}, "R must be symmetric"),
        (np.array([[np.nan, 0], [0, 1.0]]), {}, "R must be finite"),
        (np.eye(2), {"position_indices": (0, 4)}, "position_indices"),
        (np.eye(2), {"position_indices": (1, 1)}, "position_indices"),
    ],
)
def test_linear_sensor_bad_input(R, kwargs, match):
    with pytest.raises(ValueError, match=match):
        LinearPositionSensor(R, 4, **kwargs)


def test_linear_sensor_bad_states_shape():
    s = LinearPositionSensor(np.eye(2), 4)
    with pytest.raises(ValueError, match="states"):
        s.measure(np.zeros((3, 5)), np.random.default_rng(0))
    with pytest.raises(ValueError, match="states must be finite"):
        s.measure(np.full((1, 4), np.nan), np.random.default_rng(0))
    with pytest.raises(TypeError, match="rng"):
        s.measure(np.zeros((1, 4)), 3)


# --- FieldOfView ------------------------------------------------------------------------


def test_fov_contains_known_points():
    fov = FieldOfView(15, 30, 6578, 30000)
    pts = polar(
        np.array([10000, 10000, 10000, 10000, 6000, 31000, 6578, 30000]), [0, 30, -0.01, 30.01, 15, 15, 0, 30]
    )
    np.testing.assert_array_equal(fov.contains(pts), [True, True, False, False, False, False, True, True])
    assert fov.contains(np.zeros((0, 2))).shape == (0,)


def test_fov_wraps_around_the_negative_x_axis():
    fov = FieldOfView(180, 20, 1, 10)
    np.testing.assert_array_equal(
        fov.contains(polar(5, [171, 189, -171, 169, 0])), [True, True, True, False, False]
    )
    full = FieldOfView(123, 360, 1, 10)
    assert full.contains(polar(5, np.arange(0, 360, 7))).all()
    assert math.isclose(full.area, math.pi * 99)


def test_fov_area_formula_and_monte_carlo():
    fov = FieldOfView(15, 30, 6578, 30000)
    assert math.isclose(fov.area, math.radians(30) / 2 * (30000**2 - 6578**2), rel_tol=1e-14)
    # Monte Carlo oracle: fraction of a bounding box inside the wedge.
    rng = np.random.default_rng(2)
    box = Box([0, 0], [30000, 15000])
    n = 400_000
    frac = fov.contains(box.sample_uniform(n, rng)).mean()
    se = math.sqrt(frac * (1 - frac) / n) * box.area
    assert abs(frac * box.area - fov.area) < 5 * se


def test_fov_sample_uniform_is_uniform_in_area():
    fov = FieldOfView(15, 30, 6578, 30000)
    pts = fov.sample_uniform(20_000, np.random.default_rng(3))
    assert fov.contains(pts).all()
    r2 = np.sum(pts**2, axis=1)
    th = np.degrees(np.arctan2(pts[:, 1], pts[:, 0]))
    # Uniform over area <=> r^2 uniform on [r_min^2, r_max^2] and angle uniform, independently.
    assert stats.kstest(r2, stats.uniform(6578**2, 30000**2 - 6578**2).cdf).pvalue > 1e-3
    assert stats.kstest(th, stats.uniform(0, 30).cdf).pvalue > 1e-3
    assert abs(stats.spearmanr(r2, th).statistic) < 5 / math.sqrt(len(pts))


def test_fov_split_partitions_the_wedge():
    fov = FieldOfView(15, 30, 6578, 30000)
    parts = fov.split(10)
    assert len(parts) == 10
    assert math.isclose(sum(p.area for p in parts), fov.area, rel_tol=1e-12)
    np.testing.assert_allclose(
        [p.angle_limits_deg for p in parts], [(3 * i, 3 * i + 3) for i in range(10)], atol=1e-12
    )
    pts = fov.sample_uniform(5000, np.random.default_rng(4))
    inside = np.array([p.contains(pts) for p in parts])
    assert (inside.sum(axis=0) == 1).all()  # boundaries have probability zero
    assert fov.split(1)[0] == fov


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"full_angle_deg": 0}, "full_angle_deg"),
        ({"full_angle_deg": 400}, "full_angle_deg"),
        ({"r_min": -1.0}, "r_min"),
        ({"r_min": 10.0, "r_max": 5.0}, "r_max"),
        ({"r_max": np.inf}, "r_max"),
        ({"look_angle_deg": np.nan}, "look_angle_deg"),
    ],
)
def test_fov_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        FieldOfView(**kwargs)


@pytest.mark.parametrize("n", [0, -2])
def test_fov_split_bad_region_count(n):
    with pytest.raises(ValueError, match="n_regions"):
        FieldOfView().split(n)


def test_fov_bad_points():
    with pytest.raises(ValueError, match="points"):
        FieldOfView().contains(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="points must be finite"):
        FieldOfView().contains([[np.nan, 1.0]])


# --- Box ------------------------------------------------------------------------------


def test_box_geometry_and_sampling():
    b = Box([-1, 2], [3, 7])
    assert b.dim == 2 and b.area == 20.0
    np.testing.assert_array_equal(
        b.contains([[0, 2], [3, 7], [3.1, 5], [0, 1.9]]), [True, True, False, False]
    )
    pts = b.sample_uniform(1000, np.random.default_rng(0))
    assert pts.shape == (1000, 2) and b.contains(pts).all()
    seg = Box(-2.0, 2.0)
    assert seg.dim == 1 and seg.area == 4.0
    np.testing.assert_array_equal(seg.contains([-3.0, 0.0, 2.0]), [False, True, True])


@pytest.mark.parametrize("low, high", [([0, 0], [1, 0]), ([0, 0], [1]), ([0, np.nan], [1, 1])])
def test_box_bad_input(low, high):
    with pytest.raises(ValueError, match="high|low"):
        Box(low, high)


# --- PoissonClutter ---------------------------------------------------------------------


def test_clutter_counts_density_and_region():
    fov = FieldOfView()
    c = PoissonClutter(2.5, fov)
    assert math.isclose(c.density, 1 / fov.area) and math.isclose(c.intensity, 2.5 / fov.area)
    rng = np.random.default_rng(6)
    scans = [c.sample(rng) for _ in range(4000)]
    counts = np.array([len(s) for s in scans])
    # Poisson: mean = variance = rate.
    assert abs(counts.mean() - 2.5) < 5 * math.sqrt(2.5 / len(counts))
    assert abs(counts.var() - 2.5) < 0.3
    allpts = np.vstack(scans)
    assert allpts.shape[1] == 2 and fov.contains(allpts).all()


def test_zero_rate_clutter_gives_empty_scans():
    c = PoissonClutter(0.0, Box([0, 0], [1, 1]))
    assert c.sample(np.random.default_rng(0)).shape == (0, 2)


@pytest.mark.parametrize("rate", [-0.1, np.nan, np.inf])
def test_clutter_bad_rate(rate):
    with pytest.raises(ValueError, match="rate"):
        PoissonClutter(rate, FieldOfView())


def test_clutter_bad_region():
    with pytest.raises(TypeError, match="region"):
        PoissonClutter(1.0, (0, 1))


# --- DetectionModel / Sensor / SensorArray ----------------------------------------------


@pytest.mark.parametrize("p_D", [0.0, -0.1, 1.01, np.nan])
def test_detection_bad_p_D(p_D):
    with pytest.raises(ValueError, match=r"p_D must lie in \(0, 1\]"):
        DetectionModel(p_D, FieldOfView())


def make_sensor(p_D=1.0, rate=0.0, R=np.eye(2) * 1e-6):
    fov = FieldOfView()
    return Sensor(LinearPositionSensor(R, 4), DetectionModel(p_D, fov), PoissonClutter(rate, fov))


def test_observe_origin_points_at_the_measured_target_and_order_is_random():
    s = make_sensor(p_D=1.0, rate=0.0)
    rng = np.random.default_rng(7)
    X = np.hstack([polar(np.linspace(8000, 25000, 6), np.linspace(2, 28, 6)), np.zeros((6, 2))])
    X = np.vstack([X, [[-1e4, 0, 0, 0]]])  # out of view: never detected
    orders = []
    for _ in range(20):
        Z, origin = s.observe(X, rng)
        assert sorted(origin.tolist()) == list(range(6))
        np.testing.assert_allclose(Z, X[origin, :2], atol=1e-2)
        orders.append(tuple(origin))
    assert len(set(orders)) > 1


def test_observe_detection_rate_and_clutter():
    s = make_sensor(p_D=0.7, rate=1.5)
    rng = np.random.default_rng(8)
    X = np.hstack([polar(np.full(10, 15000.0), np.linspace(1, 29, 10)), np.zeros((10, 2))])
    det = clut = 0
    n = 2000
    for _ in range(n):
        Z, origin = s.observe(X, rng)
        assert Z.shape == (len(origin), 2)
        det += np.sum(origin >= 0)
        clut += np.sum(origin == -1)
    assert abs(det / (10 * n) - 0.7) < 5 * math.sqrt(0.21 / (10 * n))
    assert abs(clut / n - 1.5) < 5 * math.sqrt(1.5 / n)


def test_observe_zero_targets_and_empty_scan():
    s = make_sensor(p_D=0.9, rate=0.0)
    Z, origin = s.observe(np.zeros((0, 4)), np.random.default_rng(0))
    assert Z.shape == (0, 2) and origin.shape == (0,) and origin.dtype == np.int64
    s2 = make_sensor(p_D=0.9, rate=3.0)
    Z, origin = s2.observe(np.zeros((0, 4)), np.random.default_rng(0))
    assert (origin == -1).all()


def test_sensor_rejects_mismatched_parts():
    fov = FieldOfView()
    with pytest.raises(ValueError, match="clutter region"):
        Sensor(LinearPositionSensor(np.eye(1), 2, (0,)), DetectionModel(0.9), PoissonClutter(1.0, fov))
    with pytest.raises(TypeError, match="detection"):
        Sensor(LinearPositionSensor(np.eye(2), 4), 0.9)


def test_sensor_array_one_scan_per_sensor():
    one_d = [
        Sensor(
            LinearPositionSensor([[0.01 * (i + 1)]], 1, (0,)),
            DetectionModel(1.0),
            PoissonClutter(0.5, Box(-1, 1)),
        )
        for i in range(3)
    ]
    arr = SensorArray(one_d)
    scans = arr.observe(np.array([[0.1], [-0.2]]), np.random.default_rng(9))
    assert len(arr) == 3 and len(scans) == 3
    for Z, origin in scans:
        assert Z.shape[1] == 1 and sorted(origin[origin >= 0].tolist()) == [0, 1]
    with pytest.raises(ValueError, match="sensors"):
        SensorArray([])
    with pytest.raises(TypeError, match=r"sensors\[0\]"):
        SensorArray([1])

"""The measurement-model surface: LinearMeasurement is the old H/R arithmetic bit for bit, and the extended
(EKF) path with a linear h gives the linear path's numbers through the whole hypothesis engine, the factored
engine and GNN/JPDA (births, deaths, clutter, objects leaving the view included)."""

import numpy as np
import pytest

from hypotrack.gaussian import innovation_unchecked, mahalanobis2_unchecked, update_unchecked
from hypotrack.models import ConstantVelocity
from hypotrack.models.measurement import ExtendedMeasurement, LinearMeasurement, as_measurement, wrap_pi
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.registry import TrackerSpec, TrackingProblem, build
from hypotrack.registry.problem import MeasurementBirths
from hypotrack.hypotheses.factored import AdaptiveBirth

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
R = np.diag([0.3, 0.2])


class _LinearAsExtended(ExtendedMeasurement):
    """``h(x) = H x`` through the EKF code path (Jacobian ``H`` per track, nothing wrapped)."""

    ndim_state = 4

    def __init__(self, H, R):
        self.H_, self.R = H, R

    def h(self, means):
        return means @ self.H_.T

    def jacobian(self, means):
        return np.broadcast_to(self.H_, (len(means), *self.H_.shape)).copy()

    def view_points(self, means, z_pred=None):
        return means @ self.H_.T

    def one_point(self, Z, position_std, velocity_std):
        Hp = np.linalg.pinv(self.H_)
        s = np.where(np.any(self.H_ != 0, axis=0), position_std, velocity_std)
        P0 = Hp @ self.R @ Hp.T + np.diag(s**2)
        return np.atleast_2d(Z) @ Hp.T, np.broadcast_to(P0, (len(np.atleast_2d(Z)), 4, 4)).copy()


def _tracks(rng, n):
    x = rng.normal(0, 5, (n, 4))
    A = rng.normal(0, 1, (n, 4, 4))
    return x, A @ np.swapaxes(A, 1, 2) + np.eye(4)


def test_linear_measurement_is_the_old_arithmetic_bit_for_bit():
    rng = np.random.default_rng(0)
    x, P = _tracks(rng, 7)
    Z = rng.normal(0, 5, (5, 2))
    m = LinearMeasurement(H, R)
    z_pred, S, K, Hj = m.innovation(x, P)
    z0, S0, K0 = innovation_unchecked(x, P, H, R)
    assert np.array_equal(z_pred, z0) and np.array_equal(S, S0) and np.array_equal(K, K0)
    assert Hj.shape == (7, 2, 4) and np.array_equal(Hj[3], H)
    d2, ld = m.mahalanobis2(Z, z_pred, S)
    d20, ld0 = mahalanobis2_unchecked(Z, z0, S0)
    assert np.array_equal(d2, d20) and np.array_equal(ld, ld0)
    rows = Z[[0, 1, 2, 3, 4, 0, 1]]
    xu, Pu = m.update(x, P, rows)
    xu0, Pu0 = update_unchecked(x, P, rows, H, R)
    assert np.array_equal(xu, xu0) and np.array_equal(Pu, Pu0)
    assert np.array_equal(m.residual(Z, z_pred)[2, 5], Z[2] - z_pred[5])
    assert as_measurement(m) is m
    assert isinstance(as_measurement(LinearPositionSensor(np.eye(2) * 0.5, ndim_state=4, position_indices=(0, 2))),
                      LinearMeasurement)
    with pytest.raises(TypeError, match="H and R"):
        as_measurement(object())


def test_extended_path_with_a_linear_h_equals_the_kalman_filter():
    rng = np.random.default_rng(1)
    x, P = _tracks(rng, 6)
    Z = rng.normal(0, 5, (4, 2))
    lin, ext = LinearMeasurement(H, R), _LinearAsExtended(H, R)
    a, b = lin.innovation(x, P), ext.innovation(x, P)
    for u, v in zip(a, b):
        np.testing.assert_allclose(u, v, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ext.mahalanobis2(Z, a[0], a[1])[0], lin.mahalanobis2(Z, a[0], a[1])[0], rtol=1e-10)
    rows = Z[[0, 1, 2, 3, 0, 1]]
    for u, v in zip(lin.update(x, P, rows), ext.update(x, P, rows)):
        np.testing.assert_allclose(u, v, rtol=1e-10, atol=1e-12)
    e = ext.innovation(np.zeros((0, 4)), np.zeros((0, 4, 4)))
    assert [t.shape for t in e] == [(0, 2), (0, 2, 2), (0, 4, 2), (0, 2, 4)]
    assert ext.mahalanobis2(np.zeros((0, 2)), a[0], a[1])[0].shape == (0, 6)


def test_wrapped_residual_and_distance():
    class _Angle(_LinearAsExtended):
        wrapped = (1,)

    m = _Angle(H, np.diag([1.0, 0.01]))
    r = m.residual(np.array([[0.0, np.pi - 0.01]]), np.array([[0.0, -np.pi + 0.02]]))
    assert r[0, 0, 1] == pytest.approx(-0.03, abs=1e-12)
    d2, _ = m.mahalanobis2(np.array([[0.0, np.pi - 0.01]]), np.array([[0.0, -np.pi + 0.02]]), np.diag([1.0, 0.01])[None])
    assert d2[0, 0] == pytest.approx(0.03**2 / 0.01, rel=1e-12)
    assert wrap_pi(np.pi) == pytest.approx(-np.pi) and wrap_pi(-np.pi) == pytest.approx(-np.pi)


def _scenario(rng):
    """Three objects crossing a box (one leaves it, one is born at scan 3) with clutter."""
    x = np.array([[0.0, 1.0, 0.0, 0.5], [10.0, -1.0, 5.0, 0.0], [3.0, 0.0, -4.0, 1.0]])
    scans = []
    for k in range(8):
        Z = [x[i, [0, 2]] + rng.normal(0, 0.3, 2) for i in range(3) if (i < 2 or k >= 3) and rng.random() < 0.9
             and abs(x[i, 0]) < 12]
        Z += list(rng.uniform(-15, 15, (rng.poisson(2), 2)))
        scans.append((float(k), np.array(Z).reshape(-1, 2)))
        x = x @ ConstantVelocity(q=0.0).F(1.0).T
    return scans


class _BoxView:
    def __init__(self, det):
        self.det = det
        self.p_D = det.p_D

    def in_view(self, z):
        return np.all(np.abs(np.asarray(z)[:, :2]) <= 12, axis=1)


@pytest.mark.parametrize("kind", ["glmb", "homht_kbest", "gnn", "jpda"])
def test_engine_with_the_extended_path_equals_the_linear_path(kind):
    rng = np.random.default_rng(4)
    scans = _scenario(rng)
    base = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 2)), DetectionModel(0.9),
                  PoissonClutter(2.0, Box([-15, -15], [15, 15])))
    R_ = base.measurement.R

    class _S:
        def __init__(self, measurement):
            self.measurement, self.clutter = measurement, base.clutter
            self.detection = _BoxView(base.detection)

    motion = ConstantVelocity(q=0.01)
    x0 = np.array([[0.0, 1.0, 0.0, 0.5], [10.0, -1.0, 5.0, 0.0]])
    P0 = np.repeat(np.eye(4)[None], 2, axis=0)
    spec = dict(glmb={"kind": "glmb", "n_sweeps": 20, "max_hypotheses": 10, "gate_probability": 0.999,
                      "factored": {"split": "marginal"}},
                homht_kbest={"kind": "homht_kbest", "population": True, "max_hypotheses": 10, "gate_probability": 0.999,
                             "factored": {"split": "marginal"}},
                gnn={"kind": "gnn", "gate_probability": 0.999, "m_of_n": [2, 3], "max_misses": 3,
                     "initial_velocity_std": 2.0},
                jpda={"kind": "jpda", "gate_probability": 0.999, "m_of_n": [2, 3], "max_misses": 3,
                      "initial_velocity_std": 2.0})[kind]
    out = []
    for meas in (base.measurement, _LinearAsExtended(base.measurement.H, R_)):
        sensor = _S(meas)
        births = MeasurementBirths(AdaptiveBirth(velocity_std=2.0, r_birth=0.3), r_birth=0.3, seeded_intensity=0.02,
                                   seeded_density=_OnePoint(meas if not hasattr(meas, "H") else _LinearAsExtended(meas.H, R_)))
        problem = TrackingProblem(motion, sensor, x0, P0, [7, 8], time=0.0, dt=1.0, births=births,
                                  in_view=lambda x: np.all(np.abs(x[:, [0, 2]]) <= 12, axis=1))
        tr = build(TrackerSpec.from_config(spec, kind), problem, seed=3)
        res = []
        for t, Z in scans:
            tr.step(Z, t)
            e = tr.estimates()
            order = np.argsort(e.labels)
            res.append((np.asarray(e.labels)[order], np.asarray(e.x)[order]))
        out.append(res)
    n_tracks = 0
    for (la, xa), (lb, xb) in zip(*out):
        assert np.array_equal(la, lb)
        np.testing.assert_allclose(xa, xb, rtol=1e-9, atol=1e-9)
        n_tracks = max(n_tracks, len(la))
    assert n_tracks >= 3  # the third object was born


class _OnePoint:
    def __init__(self, m):
        self.m = m

    def initial_state(self, z, R=None):
        x, P = self.m.one_point(np.asarray(z)[None], 0.0, 2.0)
        return x[0], P[0]

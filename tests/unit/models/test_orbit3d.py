"""Three-dimensional two-body model: exact propagation, STM, process noise, against DOP853 and invariants."""

import math

import numpy as np
import pytest

from hypotrack.gaussian import predict_with
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.orbit import MU_EARTH, TwoBodyOrbit, elements_to_state
from hypotrack.models.orbit3d import DEFAULT_Q_3D, TwoBodyOrbit3D, integrate_variational_3d

MODEL = TwoBodyOrbit3D()


def kepler_state(a, e, i, raan, argp, nu, mu=MU_EARTH):
    """Inertial state from classical elements (angles in degrees): the perifocal state rotated by
    R3(−Ω) R1(−i) R3(−ω)."""
    p = a * (1 - e**2)
    nu = math.radians(nu)
    r_pf = np.array([math.cos(nu), math.sin(nu), 0.0]) * p / (1 + e * math.cos(nu))
    v_pf = np.array([-math.sin(nu), e + math.cos(nu), 0.0]) * math.sqrt(mu / p)

    def R3(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])

    def R1(t):
        c, s = math.cos(t), math.sin(t)
        return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])

    Q = R3(math.radians(raan)) @ R1(math.radians(i)) @ R3(math.radians(argp))
    return np.concatenate([Q @ r_pf, Q @ v_pf])


ORBITS = {
    "ISS-like LEO": (6795.0, 0.0005, 51.64, 8.0, 35.0, 14.0),
    "sun-synchronous": (7200.0, 0.0012, 98.7, 210.0, 100.0, 250.0),
    "Molniya": (26600.0, 0.72, 63.4, 40.0, 270.0, 10.0),
    "GEO": (42164.0, 0.0002, 0.05, 80.0, 10.0, 300.0),
    "retrograde MEO": (20000.0, 0.1, 150.0, 300.0, 60.0, 170.0),
}
STATES = np.array([kepler_state(*o) for o in ORBITS.values()])


@pytest.mark.parametrize("dt", [10.0, 600.0, 5400.0, -2500.0])
def test_propagation_and_stm_match_dop853(dt):
    x, Phi = MODEL.transition(STATES, dt)
    np.testing.assert_allclose(x, MODEL.propagate(STATES, dt), rtol=1e-13, atol=1e-12)
    for k, x0 in enumerate(STATES):
        x_ref, Phi_ref = integrate_variational_3d(x0, dt)
        np.testing.assert_allclose(x[k, :3], x_ref[:3], rtol=0, atol=1e-6 * np.linalg.norm(x0[:3]))
        np.testing.assert_allclose(x[k, 3:], x_ref[3:], rtol=0, atol=1e-6 * np.linalg.norm(x0[3:]))
        scale = np.abs(Phi_ref).max()
        np.testing.assert_allclose(Phi[k], Phi_ref, rtol=0, atol=1e-7 * scale)


def test_invariants_over_many_periods():
    T = MODEL.period(STATES)
    for k, x0 in enumerate(STATES):
        for t in (0.3 * T[k], 7.25 * T[k]):
            x = MODEL.propagate(x0, t)
            eps = lambda s: 0.5 * s[3:] @ s[3:] - MU_EARTH / np.linalg.norm(s[:3])  # noqa: E731
            assert eps(x) == pytest.approx(eps(x0), rel=1e-11)
            np.testing.assert_allclose(
                np.cross(x[:3], x[3:]), np.cross(x0[:3], x0[3:]), rtol=1e-11, atol=1e-6
            )
        np.testing.assert_allclose(MODEL.propagate(x0, T[k]), x0, rtol=0, atol=1e-6 * np.abs(x0).max())
    a = np.array([o[0] for o in ORBITS.values()])
    np.testing.assert_allclose(T, 2 * np.pi * np.sqrt(a**3 / MU_EARTH), rtol=1e-12)


def test_stm_is_symplectic():
    """Two-body flow is Hamiltonian: Φᵀ J Φ = J with J = [[0, I], [−I, 0]]."""
    J = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.eye(3), np.zeros((3, 3))]])
    _, Phi = MODEL.transition(STATES, 1234.5)
    for P in Phi:
        np.testing.assert_allclose(P.T @ J @ P, J, atol=1e-9 * np.abs(P).max() ** 2)


def test_planar_states_agree_with_the_planar_model():
    X2 = elements_to_state([7000.0, 12000.0], [0.01, 0.08], [0.3, 2.0], [1.0, 4.0])
    X3 = np.zeros((2, 6))
    X3[:, [0, 1, 3, 4]] = X2
    for dt in (60.0, 3000.0):
        x3, Phi3 = MODEL.transition(X3, dt)
        x2, Phi2 = TwoBodyOrbit().transition(X2, dt)
        np.testing.assert_allclose(x3[:, [0, 1, 3, 4]], x2, rtol=1e-13, atol=1e-9)
        np.testing.assert_allclose(x3[:, [2, 5]], 0.0, atol=1e-15)
        np.testing.assert_allclose(Phi3[:, [0, 1, 3, 4]][:, :, [0, 1, 3, 4]], Phi2, rtol=1e-10, atol=1e-12)


def test_process_noise_and_ekf_prediction():
    assert DEFAULT_Q_3D == MODEL.q == 1e-8
    np.testing.assert_array_equal(MODEL.Q(10.0), ConstantVelocity(1e-8, 3).Q(10.0))
    # One-scan standard deviations sqrt(q dt^3 / 3), sqrt(q dt) (orbit3d docstring): 1.8 m, 0.32 m/s at 10 s;
    # 27 m, 0.77 m/s at 60 s.
    assert math.sqrt(MODEL.Q(10.0)[0, 0]) * 1e3 == pytest.approx(1.83, abs=0.01)
    assert math.sqrt(MODEL.Q(10.0)[3, 3]) * 1e3 == pytest.approx(0.316, abs=0.001)
    assert math.sqrt(MODEL.Q(60.0)[0, 0]) * 1e3 == pytest.approx(26.8, abs=0.1)
    assert math.sqrt(MODEL.Q(60.0)[3, 3]) * 1e3 == pytest.approx(0.775, abs=0.001)
    P0 = np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6])
    x, P = predict_with(MODEL, STATES[:2], np.broadcast_to(P0, (2, 6, 6)), 60.0)
    _, Phi = MODEL.transition(STATES[:2], 60.0)
    np.testing.assert_allclose(x, MODEL.propagate(STATES[:2], 60.0))
    np.testing.assert_allclose(P, Phi @ P0 @ np.swapaxes(Phi, 1, 2) + MODEL.Q(60.0), rtol=1e-12)
    x0, Phi0 = MODEL.transition(STATES, 0.0)
    np.testing.assert_array_equal(x0, STATES)
    np.testing.assert_array_equal(Phi0, np.broadcast_to(np.eye(6), (len(STATES), 6, 6)))
    assert MODEL.propagate(np.zeros((0, 6)), 10.0).shape == (0, 6)


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda: TwoBodyOrbit3D(mu=0.0), "mu must be a finite number > 0"),
        (lambda: TwoBodyOrbit3D(q=-1e-9), "q must be a finite number >= 0"),
        (lambda: MODEL.propagate(np.zeros((2, 4)), 10.0), r"x must have shape \(n, 6\)"),
        (lambda: MODEL.propagate(np.full(6, np.nan), 10.0), "x must be finite"),
        (lambda: MODEL.transition(STATES, float("inf")), "dt must be finite"),
        (lambda: MODEL.Q(-1.0), "dt must be a finite number >= 0"),
    ],
)
def test_bad_input(call, fragment):
    with pytest.raises(ValueError, match=fragment):
        call()


def test_per_row_intervals_equal_one_call_per_interval():
    """propagate_each / transition_each / Q_each (one batch with an interval per state) give what
    propagate / transition / Q give state by state, including a zero interval (the identity)."""
    m = TwoBodyOrbit3D(q=1e-7)
    X = np.array([[7000.0, 0.0, 0.0, 0.0, 7.5, 1.0], [0.0, 8000.0, 100.0, -6.9, 0.0, 0.5],
                  [42164.0, 0.0, 0.0, 0.0, 3.07, 0.0]])
    dt = np.array([10.0, 600.0, 0.0])
    x_each, F_each = m.transition_each(X, dt)
    np.testing.assert_array_equal(m.propagate_each(X, dt)[2], X[2])
    np.testing.assert_array_equal(F_each[2], np.eye(6))
    for k in range(3):
        np.testing.assert_allclose(m.propagate_each(X, dt)[k], m.propagate(X[k], dt[k]), rtol=0, atol=1e-9)
        if dt[k]:
            x1, F1 = m.transition(X[k:k + 1], dt[k])
            np.testing.assert_allclose(x_each[k], x1[0], rtol=0, atol=1e-9)
            np.testing.assert_allclose(F_each[k], F1[0], rtol=0, atol=1e-9)
        np.testing.assert_array_equal(m.Q_each(dt)[k], m.Q(dt[k]))
    with pytest.raises(ValueError, match="dt"):
        m.propagate_each(X, dt[:2])
    with pytest.raises(ValueError, match="dt"):
        m.Q_each(np.array([-1.0]))


def test_factored_per_row_prediction_equals_one_ekf_step_per_track():
    """The factored engine's batched prediction with an interval per track (lazy singletons) is the
    EKF prediction of each track over its own interval (Φ P Φᵀ + Q(dt)); a zero interval leaves it."""
    from hypotrack.gaussian import predict_with_unchecked
    from hypotrack.hypotheses.factored import _predict_each

    m = TwoBodyOrbit3D(q=1e-7)
    X = np.array([[7000.0, 0.0, 0.0, 0.0, 7.5, 1.0], [0.0, 8000.0, 100.0, -6.9, 0.0, 0.5],
                  [6900.0, 100.0, 0.0, 0.1, 7.6, 0.0]])
    P = np.stack([np.diag([0.25, 0.25, 0.25, 1e-6, 1e-6, 1e-6]) * (k + 1) for k in range(3)])
    dt = np.array([10.0, 600.0, 0.0])
    x, C = _predict_each(m, X, P, dt)
    for k in range(2):
        xk, Ck = predict_with_unchecked(m, X[k:k + 1], P[k:k + 1], dt[k])
        np.testing.assert_allclose(x[k], xk[0], rtol=0, atol=1e-9)
        np.testing.assert_allclose(C[k], Ck[0], rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(x[2], X[2])
    np.testing.assert_allclose(C[2], P[2], rtol=0, atol=0)

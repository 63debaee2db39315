"""Planar two-body orbit: exact propagation, conservation laws, STM, process noise."""

import math

import numpy as np
import pytest
from scipy import optimize

from hypotrack.gaussian import predict_with
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.orbit import (
    MU_EARTH,
    TwoBodyOrbit,
    angular_momentum,
    circular_velocity,
    elements_to_state,
    integrate_variational,
    orbital_period,
    specific_energy,
)

# (a km, e, argument of periapsis rad, true anomaly rad): LEO to MEO, the DESIGN.md §5 range.
ORBITS = [
    (6778.0, 0.0, 0.0, 0.3),
    (6778.0, 0.0295, 1.0, 2.0),
    (12000.0, 0.07, 4.0, 5.5),
    (26578.0, 0.1, 2.5, 3.1),
]
STATES = np.array([elements_to_state(*o) for o in ORBITS])
MODEL = TwoBodyOrbit()


def kepler_oracle(a, e, w, nu0, t, mu=MU_EARTH):
    """State after time t from the mean anomaly and a root of Kepler's equation."""
    E0 = 2 * math.atan2(math.sqrt(1 - e) * math.sin(nu0 / 2), math.sqrt(1 + e) * math.cos(nu0 / 2))
    M = E0 - e * math.sin(E0) + math.sqrt(mu / a**3) * t
    E = optimize.brentq(lambda E: E - e * math.sin(E) - M, M - 1.0, M + 1.0, xtol=1e-15, rtol=1e-15)
    nu = 2 * math.atan2(math.sqrt(1 + e) * math.sin(E / 2), math.sqrt(1 - e) * math.cos(E / 2))
    return elements_to_state(a, e, w, nu, mu)


def test_elements_to_state_direct_formulas():
    a, e, w = 10000.0, 0.08, 0.7
    x = elements_to_state(a, e, w, 0.0)  # periapsis
    assert math.hypot(x[0], x[1]) == pytest.approx(a * (1 - e), rel=1e-14)
    assert math.atan2(x[1], x[0]) == pytest.approx(w, rel=1e-14)
    assert math.hypot(x[2], x[3]) == pytest.approx(math.sqrt(MU_EARTH * (1 + e) / (a * (1 - e))), rel=1e-14)
    X = elements_to_state(a, e, w, np.linspace(0, 6, 7))
    np.testing.assert_allclose(specific_energy(X), -MU_EARTH / (2 * a), rtol=1e-13)
    np.testing.assert_allclose(angular_momentum(X), math.sqrt(MU_EARTH * a * (1 - e**2)), rtol=1e-13)
    np.testing.assert_allclose(MODEL.period(X), orbital_period(a), rtol=1e-12)


def test_propagation_matches_keplers_equation():
    for orbit, x0 in zip(ORBITS, STATES):
        T = orbital_period(orbit[0])
        for t in (60.0, 0.37 * T, 2.5 * T, -1234.5):
            want = kepler_oracle(*orbit, t)
            got = MODEL.propagate(x0, t)
            # Kepler-equation oracle itself is accurate to ~1e-15 in E (times |r| ~ 3e4 km).
            np.testing.assert_allclose(got[:2], want[:2], rtol=0, atol=1e-7 * max(1.0, abs(t) / T))
            np.testing.assert_allclose(got[2:], want[2:], rtol=0, atol=1e-11 * max(1.0, abs(t) / T))


def test_propagation_matches_numerical_integration():
    for x0 in STATES:
        for dt in (60.0, 4000.0):
            x_ode, _ = integrate_variational(x0, dt)
            np.testing.assert_allclose(MODEL.propagate(x0, dt), x_ode, rtol=1e-10, atol=1e-8)


def test_hyperbolic_arc_matches_numerical_integration():
    x0 = np.array([7000.0, 0.0, 0.5, 12.0])  # v > escape speed (10.7 km/s)
    assert specific_energy(x0)[0] > 0
    for dt in (60.0, 3000.0):
        x_ode, Phi_ode = integrate_variational(x0, dt)
        x, Phi = MODEL.transition(x0, dt)
        np.testing.assert_allclose(x[0], x_ode, rtol=1e-10)
        np.testing.assert_allclose(Phi[0], Phi_ode, rtol=1e-8, atol=1e-8 * np.abs(Phi_ode).max())


def relative_drift(x0, X):
    e0, h0 = specific_energy(x0)[0], angular_momentum(x0)[0]
    return np.max(np.abs(specific_energy(X) / e0 - 1)), np.max(np.abs(angular_momentum(X) / h0 - 1))


def test_energy_and_angular_momentum_conserved_over_ten_periods():
    """Propagated all together in 60-s scans over 10 periods of the longest orbit, and in one step."""
    T_max = orbital_period(ORBITS[-1][0])
    n_steps = int(math.ceil(10 * T_max / 60.0))
    X = STATES.copy()
    worst_e = worst_h = 0.0
    for k in range(n_steps):
        X = MODEL.propagate(X, 60.0)
        if k % 50 == 0 or k == n_steps - 1:
            for x0, x in zip(STATES, X):
                de, dh = relative_drift(x0, x[None])
                worst_e, worst_h = max(worst_e, de), max(worst_h, dh)
    # The brief asks for 1e-9; the exact Kepler solution achieves ~4e-14 over 7,187 steps.
    assert worst_e < 1e-11 and worst_h < 1e-11, (worst_e, worst_h)
    for orbit, x0 in zip(ORBITS, STATES):
        x10 = MODEL.propagate(x0, 10 * orbital_period(orbit[0]))
        de, dh = relative_drift(x0, x10[None])
        assert de < 1e-12 and dh < 1e-12
        np.testing.assert_allclose(x10, x0, rtol=0, atol=1e-7 * np.abs(x0).max())  # back where it started


def test_propagation_is_reversible_and_batched():
    X = MODEL.propagate(STATES, 5000.0)
    np.testing.assert_allclose(MODEL.propagate(X, -5000.0), STATES, rtol=1e-12, atol=1e-9)
    for x0, x in zip(STATES, X):
        np.testing.assert_array_equal(MODEL.propagate(x0, 5000.0), x)
    np.testing.assert_array_equal(MODEL.propagate(STATES, 0.0), STATES)
    assert MODEL.propagate(np.zeros((0, 4)), 60.0).shape == (0, 4)


def central_difference_stm(x0, dt):
    steps = np.array([1e-2, 1e-2, 1e-5, 1e-5])  # km, km/s
    Phi = np.empty((4, 4))
    for j, h in enumerate(steps):
        e = np.zeros(4)
        e[j] = h
        Phi[:, j] = (MODEL.propagate(x0 + e, dt) - MODEL.propagate(x0 - e, dt)) / (2 * h)
    return Phi


@pytest.mark.parametrize("dt", [60.0, 3600.0])
def test_stm_against_central_finite_differences(dt):
    x_pred, Phi = MODEL.transition(STATES, dt)
    # Complex arithmetic rounds differently from real arithmetic: equal to rounding.
    np.testing.assert_allclose(x_pred, MODEL.propagate(STATES, dt), rtol=1e-13)
    for x0, P in zip(STATES, Phi):
        fd = central_difference_stm(x0, dt)
        # Column scales differ by ~dt (∂r/∂v0 ~ dt); compare relative to each column.
        err = np.max(np.abs(P - fd) / np.abs(fd).max(axis=0))
        assert err < 1e-7, err


@pytest.mark.parametrize("dt", [60.0, 20000.0])
def test_stm_against_integrated_variational_equations(dt):
    _, Phi = MODEL.transition(STATES, dt)
    for x0, P in zip(STATES, Phi):
        _, P_ode = integrate_variational(x0, dt)
        err = np.max(np.abs(P - P_ode) / np.abs(P_ode).max(axis=0))
        assert err < 1e-9, err


def test_stm_is_symplectic():
    """Hamiltonian flow: Φᵀ J Φ = J and det Φ = 1 (Liouville)."""
    J = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.eye(2), np.zeros((2, 2))]])
    _, Phi = MODEL.transition(STATES, 1800.0)
    for P in Phi:
        np.testing.assert_allclose(P.T @ J @ P, J, atol=1e-9 * np.abs(P).max() ** 2)
        assert np.linalg.det(P) == pytest.approx(1.0, abs=1e-8)


def test_transition_edge_cases():
    x, Phi = MODEL.transition(STATES, 0.0)
    np.testing.assert_array_equal(Phi, np.broadcast_to(np.eye(4), (4, 4, 4)))
    x, Phi = MODEL.transition(np.zeros((0, 4)), 60.0)
    assert x.shape == (0, 4) and Phi.shape == (0, 4, 4)


def test_Q_is_white_acceleration():
    np.testing.assert_array_equal(MODEL.Q(60.0), ConstantVelocity(1e-10).Q(60.0))
    assert MODEL.Q(60.0)[0, 0] == pytest.approx(1e-10 * 60**3 / 3)
    with pytest.raises(ValueError, match="dt"):
        MODEL.Q(-1.0)


def test_ekf_prediction_through_predict_with():
    P = np.broadcast_to(np.diag([1.0, 1.0, 1e-6, 1e-6]), (4, 4, 4))
    x_pred, P_pred = predict_with(MODEL, STATES, P, 60.0)
    _, Phi = MODEL.transition(STATES, 60.0)
    np.testing.assert_allclose(x_pred, MODEL.propagate(STATES, 60.0))
    np.testing.assert_allclose(P_pred, Phi @ P @ np.swapaxes(Phi, 1, 2) + MODEL.Q(60.0), rtol=1e-12)
    assert np.all(np.linalg.eigvalsh(P_pred) > 0)


def test_circular_velocity():
    p = np.array([[7000.0, 0.0], [0.0, -20000.0]])
    v = circular_velocity(p)
    np.testing.assert_allclose(
        v, [[0, math.sqrt(MU_EARTH / 7000)], [math.sqrt(MU_EARTH / 20000), 0]], atol=1e-15
    )
    X = np.hstack([p, v])
    np.testing.assert_allclose(
        MODEL.propagate(X, 3000.0)[:, :2].__pow__(2).sum(1) ** 0.5, [7000, 20000], rtol=1e-12
    )


@pytest.mark.parametrize(
    "make, exc, match",
    [
        (lambda: TwoBodyOrbit(mu=0.0), ValueError, "mu"),
        (lambda: TwoBodyOrbit(q=-1e-10), ValueError, "q"),
        (lambda: MODEL.propagate(np.zeros((2, 3)), 60.0), ValueError, "x must have shape"),
        (lambda: MODEL.transition([[np.nan, 0, 0, 0]], 60.0), ValueError, "x must be finite"),
        (lambda: MODEL.propagate(STATES, np.nan), ValueError, "dt"),
        (lambda: elements_to_state(-7000.0, 0.0, 0.0, 0.0), ValueError, "semi-major axis"),
        (lambda: elements_to_state(7000.0, 1.0, 0.0, 0.0), ValueError, "eccentricity"),
        (lambda: elements_to_state(7000.0, -0.1, 0.0, 0.0), ValueError, "eccentricity"),
        (lambda: integrate_variational(np.zeros(3), 60.0), ValueError, "x0"),
    ],
)
def test_bad_input(make, exc, match):
    with pytest.raises(exc, match=match):
        make()

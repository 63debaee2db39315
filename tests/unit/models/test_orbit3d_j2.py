"""J2 orbit model: RK4 against an independent DOP853 oracle, the Kepler kernel, the nodal regression,
SGP4, its complex-step STM, and bad input."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from hypotrack.gaussian import predict_with
from hypotrack.models import J2Orbit3D
from hypotrack.models.orbit import elements_to_state
from hypotrack.models.orbit3d import DEFAULT_Q_3D, EARTH_RADIUS_WGS72, J2_WGS72, MU_WGS72, TwoBodyOrbit3D
from hypotrack.scenarios.catalogue import (
    load_catalogue,
    propagate,
    reference_epoch,
    sample_objects,
    select_altitude,
    select_groups,
)
from hypotrack.scenarios.catalogue.tle import groups_in

MU, R_E, J2 = 398600.8, 6378.135, 0.001082616  # WGS-72, written out (Vallado et al. 2006)


def state_from_elements(a, e, i, raan, argp, nu):
    """3-D state from classical elements (km, degrees): the planar state with periapsis at ω, turned by
    Rz(Ω) Rx(i)."""
    s = elements_to_state(a, e, math.radians(argp), math.radians(nu), mu=MU)
    turn = Rotation.from_euler("ZX", [raan, i], degrees=True)
    return np.concatenate([turn.apply([s[0], s[1], 0.0]), turn.apply([s[2], s[3], 0.0])])


MODEL = J2Orbit3D()
# LEO, inclined and eccentric: (a km, e, i, Ω, ω, ν) in degrees
LEO = np.array([
    state_from_elements(7000.0, 0.03, 63.0, 40.0, 80.0, 10.0),
    state_from_elements(6900.0, 0.01, 97.0, 200.0, 10.0, 300.0),
])


def oracle_rhs(_t, y):
    """Two-body + J2 in Vallado's form:
    a = −μ r/r³ − (3/2) J2 μ R²/r⁵ [x(1 − 5z²/r²), y(1 − 5z²/r²), z(3 − 5z²/r²)]."""
    x, y_, z = y[:3]
    r = math.sqrt(x * x + y_ * y_ + z * z)
    w = 5.0 * z * z / (r * r)
    c = 1.5 * J2 * MU * R_E**2 / r**5
    ax = -MU * x / r**3 - c * x * (1.0 - w)
    ay = -MU * y_ / r**3 - c * y_ * (1.0 - w)
    az = -MU * z / r**3 - c * z * (3.0 - w)
    return [y[3], y[4], y[5], ax, ay, az]


def oracle(x0, dt):
    sol = solve_ivp(oracle_rhs, (0.0, dt), x0, method="DOP853", rtol=1e-12, atol=1e-12)
    assert sol.success
    return sol.y[:, -1]


def test_defaults_are_sgp4_wgs72():
    assert (MODEL.mu, MODEL.j2, MODEL.radius, MODEL.max_step, MODEL.q) == (MU, J2, R_E, 30.0, DEFAULT_Q_3D)
    assert (MU_WGS72, J2_WGS72, EARTH_RADIUS_WGS72) == (MU, J2, R_E)
    assert MODEL.ndim == 6


def test_rk4_against_dop853_oracle_over_one_orbit():
    """One orbit (5,400 s): < 1 m at a 20-s step (measured 0.24, 0.26 m), < 2 m at the default 30 s
    (1.25, 1.41 m), < 5 cm at 10 s (1.4, 1.6 cm); the error falls ×16 per halved step (fourth order)."""
    ref = np.array([oracle(x0, 5400.0) for x0 in LEO])
    err = {}
    for step in (10.0, 20.0, 30.0):
        x = J2Orbit3D(max_step=step).propagate(LEO, 5400.0)
        err[step] = np.linalg.norm(x[:, :3] - ref[:, :3], axis=1)
        assert np.all(np.linalg.norm(x[:, 3:] - ref[:, 3:], axis=1) < err[step] * 2e-3)  # km/s vs km
    assert np.all(err[20.0] < 1e-3)
    assert np.all(err[30.0] < 2e-3)
    assert np.all(err[10.0] < 5e-5)
    assert np.all((err[20.0] / err[10.0] > 12) & (err[20.0] / err[10.0] < 20))
    # without J2 the same state would be tens of km off: the oracle really tests the J2 term
    kepler = TwoBodyOrbit3D(mu=MU).propagate(LEO, 5400.0)
    assert np.all(np.linalg.norm(kepler[:, :3] - ref[:, :3], axis=1) > 10.0)


def test_propagate_each_is_rowwise_propagate():
    """Each row takes its own n_i = ceil(|dt_i| / max_step) steps: the 5,400-s row is ``propagate`` exactly
    (180 steps), the −1,800-s row ``propagate`` of itself alone exactly (60 steps, not the 180 of the
    longest row: a 10-s step would end ~1e-5 km elsewhere), the zero row unchanged; a row's result does
    not depend on the rest of the batch."""
    x0 = np.vstack([LEO, LEO[0]])
    dt = np.array([5400.0, 0.0, -1800.0])
    out = MODEL.propagate_each(x0, dt)
    np.testing.assert_array_equal(out[0], MODEL.propagate(x0[0], 5400.0))
    np.testing.assert_array_equal(out[1], x0[1])
    np.testing.assert_array_equal(out[2], MODEL.propagate(x0[2], -1800.0))
    fine = J2Orbit3D(max_step=10.0).propagate(x0[2], -1800.0)
    assert 1e-9 < np.linalg.norm(out[2, :3] - fine[:3]) < 1e-3
    np.testing.assert_array_equal(MODEL.propagate_each(x0[[2, 0]], dt[[2, 0]]), out[[2, 0]])
    np.testing.assert_array_equal(MODEL.propagate_each(x0[[2]], dt[[2]]), out[[2]])
    # backwards is the inverse of forwards (to the integration error)
    back = MODEL.propagate(MODEL.propagate(LEO, 3000.0), -3000.0)
    np.testing.assert_allclose(back[:, :3], LEO[:, :3], rtol=0, atol=1e-3)
    # transition_each: the same means, the identity for a zero interval
    xm, Phi = MODEL.transition_each(x0, dt)
    np.testing.assert_array_equal(xm, out)
    np.testing.assert_array_equal(Phi[1], np.eye(6))
    assert MODEL.propagate_each(np.zeros((0, 6)), np.zeros(0)).shape == (0, 6)
    assert MODEL.transition(np.zeros((0, 6)), 10.0)[1].shape == (0, 6, 6)


def test_without_j2_it_is_the_kepler_solution():
    """j2 = 0 against the exact Kepler kernel over 2 h: < 1e-6 km at a 2-s step (measured 2.6e-8 km);
    1.6 m at 30 s and 8.9 cm at 15 s, a ratio of 17.6 (fourth order: 16)."""
    x0 = LEO[0]
    exact = TwoBodyOrbit3D(mu=MU).propagate(x0, 7200.0)
    err = {s: np.abs(J2Orbit3D(j2=0.0, max_step=s).propagate(x0, 7200.0) - exact) for s in (2.0, 15.0, 30.0)}
    assert err[2.0][:3].max() < 1e-6 and err[2.0][3:].max() < 1e-9
    ratio = np.linalg.norm(err[30.0][:3]) / np.linalg.norm(err[15.0][:3])
    assert 13 < ratio < 22


def _mean_node_rate(model, x0, period, n_orbits=15, per_orbit=180):
    """Secular dΩ/dt: the right ascension of the ascending node from h = r × v, averaged over the
    first and over the last of ``n_orbits + 1`` whole orbits (the short-period terms average out)."""
    t = np.arange(per_orbit) * period / per_orbit
    start = np.repeat(x0[None], per_orbit, axis=0)
    late = np.repeat(model.propagate(x0, n_orbits * period)[None], per_orbit, axis=0)

    def node(X):
        h = np.cross(X[:, :3], X[:, 3:])
        return np.unwrap(np.arctan2(h[:, 0], -h[:, 1]))

    first, last = node(model.propagate_each(start, t)), node(model.propagate_each(late, t))
    turn = np.round((last[0] - first[0]) / (2 * np.pi)) * 2 * np.pi  # the same branch of the angle
    return (last.mean() - first.mean() - turn) / (n_orbits * period)


@pytest.mark.parametrize(
    "elements",
    [
        (7000.0, 0.001, 50.0, 30.0, 0.0, 0.0),
        (7078.0, 0.0005, 98.19, 100.0, 0.0, 0.0),
        (6800.0, 0.002, 28.5, 0.0, 90.0, 0.0),
    ],
    ids=["i=50", "sun-synchronous", "i=28.5"],
)
def test_secular_nodal_regression(elements):
    """dΩ/dt = −(3/2) n J2 (R/p)² cos i within 1 % (measured 0.40 %, 0.44 %, 0.13 %): −4.64°/day at
    i = 50°, +0.99°/day for the sun-synchronous orbit (the Sun's 360°/365.2422 d = 0.9856°/day)."""
    a, e, i = elements[:3]
    x0 = state_from_elements(*elements)
    period = 2 * math.pi * math.sqrt(a**3 / MU)
    rate = _mean_node_rate(MODEL, x0, period)
    n, p = math.sqrt(MU / a**3), a * (1 - e * e)
    expected = -1.5 * n * J2 * (R_E / p) ** 2 * math.cos(math.radians(i))
    assert rate == pytest.approx(expected, rel=0.01)
    if i > 90:
        assert math.degrees(rate) * 86400 == pytest.approx(360 / 365.2422, rel=0.01)
    # two-body motion keeps the node fixed: the regression is the J2 term's
    assert abs(_mean_node_rate(J2Orbit3D(j2=0.0), x0, period, n_orbits=2)) < 1e-3 * abs(expected)


def _sgp4_states(cat, times):
    """SGP4 TEME states (N, K, 6) of the objects valid at every time, each catalogue at its own epoch."""
    out = []
    for g in groups_in(cat):
        c = select_groups(cat, g)
        p = propagate(c, np.asarray(times, dtype=float), reference_epoch(c))
        ok = p.valid.all(axis=1)
        out.append(np.concatenate([p.r, p.v], axis=-1)[ok])
    return np.concatenate(out)


def test_j2_against_sgp4():
    """200 LEO objects (seed 7: 118 active, 82 debris): J2 median position error 0.108 km after 1 h and
    0.191 km after 2 h; two-body 37.3 km and 57.7 km (×345 and ×300)."""
    cat = sample_objects(select_altitude(load_catalogue(), 200.0, 2000.0), 200, seed=7)
    S = _sgp4_states(cat, [0.0, 3600.0, 7200.0])
    assert len(S) >= 190
    x0 = S[:, 0]
    for k, dt in ((1, 3600.0), (2, 7200.0)):
        j2 = np.median(np.linalg.norm(MODEL.propagate(x0, dt)[:, :3] - S[:, k, :3], axis=1))
        kep = np.median(np.linalg.norm(TwoBodyOrbit3D(mu=MU).propagate(x0, dt)[:, :3] - S[:, k, :3], axis=1))
        assert j2 < 1.0
        assert kep > 10 * j2
        assert kep > 20.0  # what J2 removes: tens of km


STEPS = np.r_[np.full(3, 1e-3), np.full(3, 1e-6)]  # central-difference steps: km, km/s


@pytest.mark.parametrize("dt", [10.0, 600.0, -900.0, 5400.0])
def test_stm_against_central_differences(dt):
    """Φ (complex step through the RK4) against central differences of ``propagate``: agreement to
    5e-8 of each column's largest entry (asserted 1e-5); the mean is ``propagate``'s, bit for bit."""
    x, Phi = MODEL.transition(LEO, dt)
    np.testing.assert_array_equal(x, MODEL.propagate(LEO, dt))
    fd = np.empty_like(Phi)
    for j in range(6):
        e = np.zeros(6)
        e[j] = STEPS[j]
        fd[:, :, j] = (MODEL.propagate(LEO + e, dt) - MODEL.propagate(LEO - e, dt)) / (2 * STEPS[j])
    scale = np.abs(fd).max(axis=1, keepdims=True)
    assert np.all(np.abs(Phi - fd) <= 1e-5 * scale)


def test_stm_differs_from_two_body_by_the_j2_term():
    """How far the two-body Φ is from the J2 Φ, relative to ‖Φ‖₂: measured 1.7e-7–2.2e-7 over 10 s,
    2.8e-4–5.8e-4 over 600 s, 1.0e-2–1.4e-2 over 5,400 s."""
    bounds = {10.0: (5e-8, 1e-6), 600.0: (1e-4, 2e-3), 5400.0: (3e-3, 5e-2)}
    for dt, (lo, hi) in bounds.items():
        _, P = MODEL.transition(LEO, dt)
        _, P2 = TwoBodyOrbit3D(mu=MU).transition(LEO, dt)
        rel = np.linalg.norm(P - P2, 2, axis=(1, 2)) / np.linalg.norm(P, 2, axis=(1, 2))
        assert np.all((rel > lo) & (rel < hi)), (dt, rel)


def test_process_noise_and_ekf_prediction():
    np.testing.assert_array_equal(MODEL.Q(10.0), TwoBodyOrbit3D().Q(10.0))
    np.testing.assert_array_equal(MODEL.Q_each(np.array([10.0, 60.0]))[1], MODEL.Q(60.0))
    P0 = np.broadcast_to(np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6]), (2, 6, 6))
    x, P = predict_with(MODEL, LEO, P0, 60.0)
    _, Phi = MODEL.transition(LEO, 60.0)
    np.testing.assert_array_equal(x, MODEL.propagate(LEO, 60.0))
    np.testing.assert_allclose(P, Phi @ P0 @ np.swapaxes(Phi, 1, 2) + MODEL.Q(60.0), rtol=1e-12)


@pytest.mark.parametrize(
    "call, fragment",
    [
        (lambda: J2Orbit3D(q=-1e-9), "q must be a finite number >= 0"),
        (lambda: J2Orbit3D(j2=-1e-3), "j2 must be a finite number >= 0"),
        (lambda: J2Orbit3D(j2=float("nan")), "j2 must be a finite number >= 0"),
        (lambda: J2Orbit3D(max_step=0.0), "max_step must be a finite number > 0"),
        (lambda: J2Orbit3D(max_step=-30.0), "max_step must be a finite number > 0"),
        (lambda: J2Orbit3D(radius=0.0), "radius must be a finite number > 0"),
        (lambda: J2Orbit3D(mu=-1.0), "mu must be a finite number > 0"),
        (lambda: MODEL.propagate(np.full(6, np.nan), 10.0), "x must be finite"),
        (lambda: MODEL.transition(np.zeros((2, 4)), 10.0), r"x must have shape \(n, 6\)"),
        (lambda: MODEL.propagate(LEO, float("nan")), "dt must be finite"),
        (lambda: MODEL.propagate_each(LEO, np.array([1.0])), r"dt must have shape \(2\)"),
        (lambda: MODEL.transition_each(LEO, np.array([1.0, np.inf])), "dt must be finite"),
    ],
)
def test_bad_input(call, fragment):
    with pytest.raises(ValueError, match=fragment):
        call()


@pytest.mark.parametrize("method", ["propagate", "propagate_each", "transition", "transition_each"])
def test_the_singular_centre_is_refused_not_nan_and_a_falling_state_is_propagated(method):
    """The Earth's centre gave NaN: refused, naming the state. A state below the surface (a tracker's
    unresolved newborn hypothesis falling) is propagated as the equations say, finite, so a run goes on;
    trackers prune such hypotheses with a validity test."""
    dt = lambda x: 60.0 if method in ("propagate", "transition") else np.full(len(x), 60.0)  # noqa: E731
    below = np.array([[0, 0, 6300.0, 7.5, 0, 0]])
    out = getattr(MODEL, method)(below, dt(below))
    mean = out[0] if isinstance(out, tuple) else out
    assert np.all(np.isfinite(mean)) and np.linalg.norm(np.atleast_2d(mean)[0, :3]) < 6356.75
    with pytest.raises(ValueError, match=r"x: state 1 .*non-finite state.*Earth's centre"):
        getattr(MODEL, method)(np.vstack([below, np.zeros((1, 6))]), dt(np.zeros((2, 6))))


def test_states_above_the_surface_still_propagate():
    x = np.array([6400.0, 0.0, 0.0, 0.0, 7.9, 0.0])  # 22 km above the equator: allowed
    assert np.all(np.isfinite(MODEL.propagate(x, 10.0)))


def test_the_compiled_real_pass_is_the_array_passes_bit_for_bit():
    """Real rows (the means) take one compiled pass, complex ones (the STM's complex step) the array
    passes: on 2,000 LEO-to-MEO states with per-row intervals of 0, 10, 45, 70 s and −45 s (one to
    three RK4 steps, either sign) the two give the same bits, and a state at the Earth's centre the same
    non-finite row (the refusal's message below is then the same)."""
    from hypotrack.models.orbit3d import _rk4_j2, _rk4_j2_arrays

    rng = np.random.default_rng(7)
    r = rng.normal(size=(2000, 3))
    r *= rng.uniform(6600.0, 26000.0, size=(2000, 1)) / np.linalg.norm(r, axis=1, keepdims=True)
    v = np.cross(r, rng.normal(size=(2000, 3)))
    v *= rng.uniform(3.0, 8.0, size=(2000, 1)) / np.linalg.norm(v, axis=1, keepdims=True)
    X = np.hstack([r, v])
    X[5] = 0.0  # the centre: 1/r² is infinite
    dt = rng.choice([0.0, 10.0, 45.0, 70.0, -45.0], size=2000)
    c_j2 = 1.5 * J2 * MU * R_E**2
    n = np.ceil(np.abs(dt) / 30.0).astype(np.int64)
    with np.errstate(divide="ignore", invalid="ignore"):
        compiled, arrays = _rk4_j2(X, dt, MU, c_j2, 30.0), _rk4_j2_arrays(X, dt, MU, c_j2, n)
    finite = np.all(np.isfinite(arrays), axis=1)
    assert (~finite).sum() == (dt[5] != 0)  # only the centre's row, when it moves
    np.testing.assert_array_equal(compiled[finite], arrays[finite])
    assert np.array_equal(np.isfinite(compiled), np.isfinite(arrays))
    assert not np.array_equal(compiled[dt == 10.0], X[dt == 10.0])  # the rows moved
    np.testing.assert_array_equal(compiled[dt == 0.0], X[dt == 0.0])


def test_rows_of_one_interval_run_side_by_side_bit_for_bit():
    """Rows that all take the same interval (``propagate``: the lane's one-scan advance) run in the columns kernel,
    the rows' loop innermost: on 3,000 LEO-to-MEO states and intervals of 10, 30, 95 and −45 s (one to four steps,
    either sign) the same bits as the row-by-row pass and as the array passes; the centre's row non-finite alike, and
    ``propagate`` refuses it as before."""
    from hypotrack.models.orbit3d import _rk4_j2, _rk4_j2_arrays, _rk4_j2_real

    rng = np.random.default_rng(8)
    r = rng.normal(size=(3000, 3))
    r *= rng.uniform(6600.0, 26000.0, size=(3000, 1)) / np.linalg.norm(r, axis=1, keepdims=True)
    v = np.cross(r, rng.normal(size=(3000, 3)))
    v *= rng.uniform(3.0, 8.0, size=(3000, 1)) / np.linalg.norm(v, axis=1, keepdims=True)
    X = np.hstack([r, v])
    X[7] = 0.0
    c_j2 = 1.5 * J2 * MU * R_E**2
    for dt in (10.0, 30.0, 95.0, -45.0):
        n = int(np.ceil(abs(dt) / 30.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            side = _rk4_j2(X, np.full(3000, dt), MU, c_j2, 30.0)
            rows = _rk4_j2_real(X, np.full(3000, dt / n), np.full(3000, n), MU, c_j2)
            arrays = _rk4_j2_arrays(X, np.full(3000, dt), MU, c_j2, np.full(3000, n))
        np.testing.assert_array_equal(side, rows)
        ok = np.all(np.isfinite(arrays), axis=1)
        assert ok.sum() == 2999 and not np.isfinite(side[7]).all()
        np.testing.assert_array_equal(side[ok], arrays[ok])
        assert side.flags.c_contiguous and not np.array_equal(side[ok], X[ok])
        # propagate (its step count and step computed once for all rows) is the array passes' bits too
        model = J2Orbit3D(mu=MU, j2=J2, radius=R_E)
        out = model.propagate(X[ok], dt)
        np.testing.assert_array_equal(out, arrays[ok])
        assert out.flags.c_contiguous
        np.testing.assert_array_equal(model.propagate(X[8], dt), arrays[8])  # one state (6,)
    model = J2Orbit3D(mu=MU, j2=J2, radius=R_E)
    np.testing.assert_array_equal(model.propagate(X[:6], 0.0), X[:6])  # no step: the states as they are
    tiny = _rk4_j2_arrays(X[:6], np.full(6, 1e-3), MU, c_j2, np.ones(6, dtype=np.int64))
    np.testing.assert_array_equal(model.propagate(X[:6], 1e-3), tiny)
    assert model.propagate(np.zeros((0, 6)), 10.0).shape == (0, 6)
    with pytest.raises(ValueError, match="state 7"):
        J2Orbit3D().propagate(X, 10.0)


def test_rows_of_one_step_size_but_different_step_counts_take_their_own_counts():
    """``propagate_each`` with intervals that share the RK4 step size but not the number of steps (5,730 s and
    5,760 s: 191 and 192 steps of 30 s) is not one interval: each row takes its own steps. (Read as one interval,
    every row took the first row's 191 steps, ~1,000 km off at the others' ends.)"""
    rng = np.random.default_rng(3)
    r = rng.uniform(6900.0, 7300.0, 5)
    u = rng.uniform(0.0, 2 * np.pi, 5)
    X = np.column_stack([r * np.cos(u), r * np.sin(u), np.zeros(5), -np.sqrt(MU / r) * np.sin(u),
                         np.sqrt(MU / r) * np.cos(u), np.zeros(5)])
    m = J2Orbit3D()
    dt = np.array([5730.0, 5760.0, 5790.0, 5790.0, 5880.0])
    each = m.propagate_each(X, dt)
    np.testing.assert_array_equal(each, np.array([m.propagate(X[i], dt[i]) for i in range(5)]))
    assert np.linalg.norm(each[1, :3] - m.propagate(X[1], 5730.0)[:3]) > 100.0  # 30 s of orbit apart

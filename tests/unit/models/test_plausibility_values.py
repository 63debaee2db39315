"""Orbit plausibility on conics worked out by hand with μ = 2 (exact in binary: every number below is exact):
a state at perigee of an ellipse, a parabola and a hyperbola, the energy of a circular orbit, a perigee exactly on
the floor, and the degenerate states (at the Earth's centre, NaN) answered without a warning."""

import warnings

import numpy as np
import pytest

from hypotrack.models.orbit import MU_EARTH
from hypotrack.models.plausibility import (EARTH_RADIUS_PLAUSIBILITY, orbit_energy, perigee_apogee_radius,
                                          plausible_orbits)

MU = 2.0


def test_conics_at_perigee_by_hand():
    # r = 1, v ⟂ r: ε = v²/2 − 2, h² = v², e = sqrt(1 + 2 ε h² / 4), r_p = h² / (2 (1 + e))
    X = np.array([[1.0, 0, 0, 0, 1.5, 0],  # ε = −0.875, e = 0.125: ellipse, a = 2/1.75, r_p = 1, r_a = a (1 + e) = 9/7
                  [1.0, 0, 0, 0, 2.0, 0],  # ε = 0, e = 1: parabola, r_p = 1, unbound
                  [1.0, 0, 0, 0, 3.0, 0]])  # ε = 2.5, e = 3.5: hyperbola, r_p = 1, unbound
    np.testing.assert_array_equal(orbit_energy(X, MU), [-0.875, 0.0, 2.5])
    rp, ra = perigee_apogee_radius(X, MU)
    np.testing.assert_allclose(rp, [1.0, 1.0, 1.0], rtol=1e-15)
    assert ra[0] == pytest.approx(9 / 7, rel=1e-15)
    assert ra[1] == np.inf and ra[2] == np.inf
    assert plausible_orbits(X, mu=MU, earth_radius=0.5, min_perigee_km=0.0).tolist() == [True, False, False]


def test_circular_orbit_energy_and_a_perigee_on_the_floor():
    r = 6778.0
    leo = np.array([r, 0, 0, 0, np.sqrt(398600.4418 / r), 0])
    assert orbit_energy(leo) == pytest.approx(-398600.4418 / (2 * r), rel=1e-14)
    on_floor = np.array([1.0, 0, 0, 0, 1.5, 0])  # perigee radius exactly 1
    assert plausible_orbits(on_floor, mu=MU, earth_radius=0.5, min_perigee_km=0.5)  # the floor is included
    assert not plausible_orbits(on_floor, mu=MU, earth_radius=0.5, min_perigee_km=0.5 + 1e-9)
    assert plausible_orbits(on_floor, mu=MU, earth_radius=1.0, min_perigee_km=0.0)


def test_degenerate_states_are_implausible_without_warnings():
    X = np.array([[0.0] * 6, [np.nan] * 6, [1.0, 0, 0, 0, 0, 0], [1.0, 0, 0, 0, 2.0, 0]])  # ..., a parabola (ε = 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        eps = orbit_energy(X, MU)
        rp, ra = perigee_apogee_radius(X, MU)
        ok = plausible_orbits(X, mu=MU, earth_radius=0.1)
    assert eps[0] == -np.inf and np.isnan(eps[1]) and eps[2] == -2.0
    assert rp[2] == 0.0 and ra[2] == pytest.approx(1.0)  # a radial fall: apogee where it is, perigee at the centre
    assert ok.tolist() == [False, False, False, False] and ra[3] == np.inf
    with pytest.raises(ValueError, match="^min_perigee_km must be"):
        plausible_orbits(X, min_perigee_km=-0.5)


def test_the_one_pass_test_is_orbit_energy_and_perigee_radius_bit_for_bit():
    """``plausible_orbits`` computes ε and r_p in one pass for arrays of states: the same bits as
    :func:`orbit_energy` and :func:`perigee_apogee_radius` (states around LEO of every energy, some NaN, one on the
    floor), for (n, 6) and (m, n, 6) arrays, and the mask is theirs; a single state goes the long way."""
    from hypotrack.models.plausibility import _energy_perigee  # noqa: PLC0415 (the private one-pass form)

    rng = np.random.default_rng(11)
    n = 4000
    r = rng.standard_normal((n, 3))
    r *= (6400.0 + rng.exponential(2000.0, (n, 1))) / np.linalg.norm(r, axis=1, keepdims=True)
    t = np.cross(r, rng.standard_normal((n, 3)))  # near-circular speeds across the line of sight, and noise
    v = (t / np.linalg.norm(t, axis=1, keepdims=True) * np.sqrt(MU_EARTH / np.linalg.norm(r, axis=1, keepdims=True))
         * rng.uniform(0.7, 1.5, (n, 1)) + rng.standard_normal((n, 3)) * rng.uniform(0.0, 3.0, (n, 1)))
    X = np.hstack([r, v])
    X[rng.random(n) < 0.02] = np.nan
    X[0] = [EARTH_RADIUS_PLAUSIBILITY + 100.0, 0, 0, 0, np.sqrt(MU_EARTH / (EARTH_RADIUS_PLAUSIBILITY + 100.0)), 0]
    for states in (X, X.reshape(8, n // 8, 6), X[:3]):
        eps, rp = _energy_perigee(states, MU_EARTH)
        np.testing.assert_array_equal(eps, orbit_energy(states))
        np.testing.assert_array_equal(rp, perigee_apogee_radius(states)[0])
        with np.errstate(invalid="ignore"):
            want = (orbit_energy(states) < 0) & (perigee_apogee_radius(states)[0] >= EARTH_RADIUS_PLAUSIBILITY + 100.0)
        np.testing.assert_array_equal(plausible_orbits(states), want)
    mask = plausible_orbits(X)
    assert 0.2 < mask.mean() < 0.8  # both verdicts are common in the sample
    assert [bool(plausible_orbits(x)) for x in X[:50]] == mask[:50].tolist()

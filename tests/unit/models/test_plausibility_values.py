"""Orbit plausibility on conics worked out by hand with μ = 2 (exact in binary: every number below is exact):
a state at perigee of an ellipse, a parabola and a hyperbola, the energy of a circular orbit, a perigee exactly on
the floor, and the degenerate states (at the Earth's centre, NaN) answered without a warning."""

import warnings

import numpy as np
import pytest

from hypotrack.models.plausibility import orbit_energy, perigee_apogee_radius, plausible_orbits

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

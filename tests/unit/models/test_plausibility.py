"""The one plausibility test of orbits: bound, perigee at least 100 km up (hand-computed orbits)."""

import numpy as np
import pytest

from hypotrack.models.plausibility import (
    EARTH_RADIUS_PLAUSIBILITY as RE,
    orbit_energy,
    perigee_apogee_radius,
    plausible_orbits,
)

MU = 398600.4418


def _at_apogee(rp, ra):
    """State at apogee (on +x, moving +y) of the ellipse with perigee and apogee radii ``rp``, ``ra``."""
    a = (rp + ra) / 2
    return np.array([ra, 0, 0, 0, np.sqrt(MU * (2 / ra - 1 / a)), 0.0])


def test_hand_computed_ellipses_on_both_sides_of_the_floor():
    ok = _at_apogee(RE + 100.5, RE + 800)
    low = _at_apogee(RE + 99.5, RE + 800)
    rp, ra = perigee_apogee_radius(np.stack([ok, low]))
    np.testing.assert_allclose(rp, [RE + 100.5, RE + 99.5], atol=1e-7)
    np.testing.assert_allclose(ra, [RE + 800, RE + 800], atol=1e-7)
    assert plausible_orbits(np.stack([ok, low])).tolist() == [True, False]
    assert plausible_orbits(low, min_perigee_km=99.0)  # the floor is a parameter


def test_unbound_zero_velocity_and_nan_are_implausible():
    r = RE + 500
    v_esc = np.sqrt(2 * MU / r)
    X = np.array([[r, 0, 0, 0, 1.001 * v_esc, 0],  # hyperbolic, perigee 500 km up
                  [r, 0, 0, 0, 0.999 * v_esc, 0],  # bound, perigee 500 km up
                  [r, 0, 0, 0, 0, 0],  # radial fall
                  [np.nan] * 6])
    assert orbit_energy(X[0]) > 0 > orbit_energy(X[1])
    assert plausible_orbits(X).tolist() == [False, True, False, False]
    assert plausible_orbits(X.reshape(2, 2, 6)).shape == (2, 2)


def test_bad_input():
    with pytest.raises(ValueError, match="last axis of 6"):
        plausible_orbits(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="min_perigee_km"):
        plausible_orbits(np.zeros(6), min_perigee_km=-1.0)

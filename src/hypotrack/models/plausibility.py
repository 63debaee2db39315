"""Is an orbit physical? The one plausibility test of the truth side and of the trackers.

A state ``x = [r, v]`` (km, km/s, Earth-centred quasi-inertial frame: TEME) of an object that can be
tracked over more than one revolution has

* **negative specific energy** ``ε = |v|²/2 − μ/|r| < 0`` (a bound, elliptic orbit), and
* **perigee radius** ``r_p = a (1 − e) ≥ R_E + h_min`` with ``h_min`` = 100 km by default: below
  about 100 km (the Kármán line) the atmosphere brings an object down within the revolution.

With ``a = −μ / (2ε)`` and ``e = sqrt(1 + 2 ε h²/μ²)`` (``h = |r × v|``), the osculating two-body
elements (Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., algorithm RV2COE).
The same test marks the states SGP4 returns without an error code but no real object can be in
(:mod:`hypotrack.scenarios.catalogue.propagation`), builds the admissible region of a radar return
(:mod:`hypotrack.scenarios.catalogue.admissible`) and, through the engine's ``validity`` hook
(:class:`hypotrack.hypotheses.HypothesisFilter`), prunes hypotheses holding an unphysical track
(DeMars & Jah 2013 and Tommei, Milani & Rossi 2007 bound the admissible region by exactly these two
conditions).

Examples
--------
>>> import numpy as np
>>> leo = [6778.0, 0, 0, 0, 7.6686, 0]          # circular at 400 km
>>> still = [6778.0, 0, 0, 0, 0, 0]              # zero velocity: falls straight down
>>> plausible_orbits([leo, still]).tolist()
[True, False]
"""

from __future__ import annotations

import numba
import numpy as np

from .._validation import check_nonnegative
from .orbit import MU_EARTH

__all__ = ["plausible_orbits", "orbit_energy", "perigee_apogee_radius", "EARTH_RADIUS_PLAUSIBILITY",
           "MIN_PERIGEE_ALTITUDE"]

EARTH_RADIUS_PLAUSIBILITY = 6378.135
"""Earth radius (km) the perigee altitude is counted from: WGS-72's, SGP4's Earth (2 m below WGS-84's)."""

MIN_PERIGEE_ALTITUDE = 100.0
"""Default lowest perigee altitude (km) of a plausible orbit (the Kármán line)."""


def _rv(states):
    X = np.asarray(states, dtype=float)
    if X.shape[-1] != 6:
        raise ValueError(f"states must have a last axis of 6 (position km, velocity km/s), got shape {X.shape}")
    return X[..., :3], X[..., 3:]


def orbit_energy(states, mu: float = MU_EARTH) -> np.ndarray:
    """Specific orbital energy ``|v|²/2 − μ/|r|`` (km²/s²) of states ``(..., 6)``."""
    r, v = _rv(states)
    with np.errstate(divide="ignore", invalid="ignore"):
        return 0.5 * np.sum(v * v, axis=-1) - mu / np.sqrt(np.sum(r * r, axis=-1))


def perigee_apogee_radius(states, mu: float = MU_EARTH):
    """Osculating perigee and apogee radii ``(a (1 − e), a (1 + e))`` (km) of states ``(..., 6)``;
    ``inf`` apogee for an unbound orbit (the perigee radius ``h²/(μ (1 + e))`` holds for every conic)."""
    r, v = _rv(states)
    eps = orbit_energy(states, mu)
    h2 = np.sum(np.cross(r, v) ** 2, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        e = np.sqrt(np.maximum(0.0, 1.0 + 2.0 * eps * h2 / mu**2))
        rp = h2 / (mu * (1.0 + e))
        ra = np.where(eps < 0, -mu / (2.0 * eps) * (1.0 + e), np.inf)
    return rp, ra


def plausible_orbits(states, *, min_perigee_km: float = MIN_PERIGEE_ALTITUDE, mu: float = MU_EARTH,
                     earth_radius: float = EARTH_RADIUS_PLAUSIBILITY) -> np.ndarray:
    """Mask ``(...)`` of the states ``(..., 6)`` on a bound orbit whose perigee is at least ``min_perigee_km``
    above ``earth_radius`` (module docstring). NaN states are not plausible.

    Parameters
    ----------
    states : (..., 6) array_like
        Position (km) and velocity (km/s), Earth-centred quasi-inertial.
    min_perigee_km : float
        Lowest perigee altitude (km), >= 0; default 100.
    mu : float
        Gravitational parameter (km³/s²); default Earth's (398600.4418).
    earth_radius : float
        Radius (km) the altitude is counted from; default WGS-72's 6378.135.
    """
    h_min = check_nonnegative(min_perigee_km, "min_perigee_km")
    X = np.asarray(states, dtype=float)
    if X.ndim < 2 or X.shape[-1] != 6:  # (a single state, or the shape error of orbit_energy)
        eps = orbit_energy(X, mu)
        rp, _ = perigee_apogee_radius(X, mu)
    else:
        eps, rp = _energy_perigee(X, mu)
    with np.errstate(invalid="ignore"):
        return (eps < 0) & (rp >= earth_radius + h_min)


def _energy_perigee(X, mu):
    """:func:`orbit_energy` and the perigee radius of :func:`perigee_apogee_radius` of states ``(..., 6)`` (at least
    two axes) in one compiled pass over the rows — the same operations in the same order, so the same bits
    (``np.sum`` over a last axis of 3 adds left to right, ``np.cross`` is ``a₁b₂ − a₂b₁``, ``np.maximum`` keeps a NaN,
    no fused multiply-add; the tests compare bit for bit): the engine's validity test calls it on a few states per
    hypothesis, and on every asleep Bernoulli singleton each scan, where array passes' overhead and memory traffic, not
    the arithmetic, would be the cost."""
    Y = np.ascontiguousarray(np.asarray(X, dtype=float).reshape(-1, 6).T)  # columns: the rows side by side
    eps, rp = _energy_perigee_columns(Y, float(mu), float(mu**2))
    return eps.reshape(X.shape[:-1]), rp.reshape(X.shape[:-1])


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _energy_perigee_columns(T, mu, mu2):
    """ε and the perigee radius of the states given as columns ``T`` (6, n), the rows' loop vectorised by the
    compiler (each lane a row's own arithmetic)."""
    n = T.shape[1]
    eps, rp = np.empty(n), np.empty(n)
    rxa, rya, rza, vxa, vya, vza = T[0], T[1], T[2], T[3], T[4], T[5]
    for i in range(n):
        rx, ry, rz, vx, vy, vz = rxa[i], rya[i], rza[i], vxa[i], vya[i], vza[i]
        ep = 0.5 * ((vx * vx + vy * vy) + vz * vz) - mu / np.sqrt((rx * rx + ry * ry) + rz * rz)
        hx, hy, hz = ry * vz - rz * vy, rz * vx - rx * vz, rx * vy - ry * vx
        h2 = (hx * hx + hy * hy) + hz * hz
        t = 1.0 + 2.0 * ep * h2 / mu2
        t = 0.0 if t <= 0.0 else t  # np.maximum(0.0, t): a NaN stays NaN
        eps[i] = ep
        rp[i] = h2 / (mu * (1.0 + np.sqrt(t)))
    return eps, rp

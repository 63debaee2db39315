"""Time and reference frames of the catalogue scenario: UTC → Julian date, TEME → Earth-fixed, sites, RAE.

Frames
------
* **TEME** (true equator, mean equinox of date): SGP4's output frame. Quasi-inertial; the tracker's
  two-body model (:mod:`hypotrack.models.orbit3d`) runs in it.
* **Earth-fixed (PEF)**: TEME rotated about z by the Greenwich mean sidereal time θ (IAU 1982, the
  angle SGP4's own ``gstime`` uses and the one TEME is defined against; Vallado, Crawford, Hujsak &
  Kelso 2006, *Revisiting Spacetrack Report #3*, AIAA 2006-6753, Sec. "TEME"):
  ``r_ef = R3(θ) r_teme``, ``v_ef = R3(θ) v_teme − ω × r_ef`` with ω = 7.292115146706979e-5 rad/s.
  Neglected on the way to the ITRF, and why they do not matter here:

  - **polar motion** (PEF → ITRF, ≲ 0.5″: ≲ 15 m at the Earth's surface);
  - **UT1 − UTC** (|·| < 0.9 s; UTC is used as UT1, an Earth rotation error ≲ 0.9 s × 0.465 km/s
    ≈ 0.42 km at the equator, i.e. the sites sit up to ~0.4 km east or west of where they would
    in the real Earth);
  - **nutation and precession** enter only through TEME's own definition (the equation of the
    equinoxes is what separates TEME from the true-of-date frame; using GMST with TEME is exactly
    right, not an approximation).

  None of this touches the simulation's consistency: truth and sensors live in the same frame.
* **Sites**: geodetic latitude, longitude and height on the WGS-84 ellipsoid (a = 6378.137 km,
  f = 1/298.257223563). SGP4 itself uses WGS-72 constants (its elements are fitted with them); the
  two Earths differ by 2 m in radius, far below the sensor noise.
* **Local ENU / RAE**: east-north-up at the site (up = the ellipsoid normal), range (km),
  azimuth (rad, from north towards east), elevation (rad, above the local horizontal plane).
  Atmospheric refraction, light time (≲ 10 ms, ≲ 75 m along-track at 3,000 km) and the scan's
  own duration are neglected: a return is the object's geometric position at the scan time.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..._validation import check_finite_array

__all__ = [
    "local_to_rae",
    "WGS84_A",
    "WGS84_F",
    "EARTH_ROTATION",
    "utc_timestamp",
    "julian_date",
    "gmst",
    "teme_to_ef",
    "geodetic_to_ef",
    "enu_matrix",
    "ef_to_rae",
    "rae_to_enu",
    "wrap_angle",
]

WGS84_A = 6378.137
"""WGS-84 equatorial radius (km)."""
WGS84_F = 1 / 298.257223563
"""WGS-84 flattening."""
EARTH_ROTATION = 7.292115146706979e-5
"""Earth's rotation rate (rad/s) used with GMST (Vallado et al. 2006)."""

_UNIX_EPOCH_JD = 2440587.5


def utc_timestamp(when, name: str = "start") -> pd.Timestamp:
    """``when`` as a tz-naive UTC :class:`pandas.Timestamp` (a tz-aware value is converted to UTC).

    Accepts anything :class:`pandas.Timestamp` does: ``"2022-11-02T19:40"``, a datetime,
    ``numpy.datetime64``.
    """
    try:
        ts = pd.Timestamp(when)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"{name} must be a UTC date-time (ISO string, datetime, datetime64), got {when!r}"
        ) from exc
    if ts is pd.NaT:
        raise ValueError(f"{name} must be a UTC date-time, got NaT")
    if ts.tzinfo is not None:
        ts = ts.tz_convert("UTC").tz_localize(None)
    return ts


def julian_date(when) -> tuple[float, float]:
    """UTC instant → Julian date in two parts ``(jd, fr)``: ``jd`` ends in .5 (midnight), ``0 <= fr < 1``.

    The split keeps the time of day exact to the nanosecond, as SGP4's ``(jd, fr)`` interface
    intends. ``when``: see :func:`utc_timestamp`.
    """
    ns = utc_timestamp(when).value  # nanoseconds since 1970-01-01T00:00 UTC
    day, ns_of_day = divmod(ns, 86_400 * 10**9)
    return _UNIX_EPOCH_JD + day, ns_of_day / (86_400 * 10**9)


def gmst(jd, fr=0.0) -> np.ndarray:
    """Greenwich mean sidereal time (rad, in [0, 2π)) at UT1 Julian date ``jd + fr`` (IAU 1982).

    ``θ = 67310.54841 s + (876600 h + 8640184.812866 s) T + 0.093104 s T² − 6.2e-6 s T³`` with
    ``T`` Julian centuries of UT1 from J2000 (Vallado, *Fundamentals of Astrodynamics*, 4th ed.,
    Eq. 3-47; the same expression as ``sgp4.propagation.gstime``). Vectorised.
    """
    T = ((np.asarray(jd, dtype=float) - 2451545.0) + np.asarray(fr, dtype=float)) / 36525.0
    sec = ((-6.2e-6 * T + 0.093104) * T + (876600.0 * 3600.0 + 8640184.812866)) * T + 67310.54841
    return np.mod(np.deg2rad(sec / 240.0), 2 * np.pi)


def teme_to_ef(r, v, theta):
    """TEME → Earth-fixed (PEF): rotate by GMST ``theta`` and remove the frame's rotation from v.

    Parameters
    ----------
    r, v : (..., K, 3) arrays (km, km/s); the time axis is the second to last.
    theta : (K,) GMST (rad) at each time.

    Returns
    -------
    r_ef, v_ef : arrays shaped like ``r`` and ``v``.
    """
    r = np.asarray(r, dtype=float)
    v = np.asarray(v, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    x = c * r[..., 0] + s * r[..., 1]
    y = -s * r[..., 0] + c * r[..., 1]
    r_ef = np.stack([x, y, r[..., 2]], axis=-1)
    vx = c * v[..., 0] + s * v[..., 1] + EARTH_ROTATION * y
    vy = -s * v[..., 0] + c * v[..., 1] - EARTH_ROTATION * x
    return r_ef, np.stack([vx, vy, v[..., 2]], axis=-1)


def geodetic_to_ef(lat_deg, lon_deg, alt_km) -> np.ndarray:
    """WGS-84 geodetic latitude, longitude (degrees) and height (km) → Earth-fixed position (km).

    ``N = a / sqrt(1 − e² sin²φ)``; ``x = (N + h) cos φ cos λ``, ``y = (N + h) cos φ sin λ``,
    ``z = (N (1 − e²) + h) sin φ``.
    """
    lat, lon = np.deg2rad(float(lat_deg)), np.deg2rad(float(lon_deg))
    e2 = WGS84_F * (2 - WGS84_F)
    N = WGS84_A / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    return np.array(
        [
            (N + alt_km) * np.cos(lat) * np.cos(lon),
            (N + alt_km) * np.cos(lat) * np.sin(lon),
            (N * (1 - e2) + alt_km) * np.sin(lat),
        ]
    )


def enu_matrix(lat_deg, lon_deg) -> np.ndarray:
    """Rows: the east, north and up unit vectors (Earth-fixed) at a geodetic latitude and longitude."""
    lat, lon = np.deg2rad(float(lat_deg)), np.deg2rad(float(lon_deg))
    sl, cl, so, co = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    return np.array([[-so, co, 0.0], [-sl * co, -sl * so, cl], [cl * co, cl * so, sl]])


def wrap_angle(a, center=0.0):
    """Angles (rad) wrapped into ``[center − π, center + π)``."""
    return np.mod(np.asarray(a, dtype=float) - center + np.pi, 2 * np.pi) - np.pi + center


def ef_to_rae(r_ef, site_ef, enu, az_center=0.0) -> np.ndarray:
    """Earth-fixed positions ``(..., 3)`` → ``(..., 3)`` range (km), azimuth, elevation (rad) from a site.

    Azimuth is wrapped into ``[az_center − π, az_center + π)`` (so a sensor whose field of view is
    centred on ``az_center`` sees no wrap inside it).
    """
    d = np.asarray(r_ef, dtype=float) - site_ef
    return local_to_rae(d @ enu.T, az_center)


def local_to_rae(loc, az_center=0.0) -> np.ndarray:
    """Local east, north, up ``(..., 3)`` (km) → range, azimuth, elevation (:func:`ef_to_rae`'s second half;
    every row on its own)."""
    rng = np.sqrt(np.sum(loc * loc, axis=-1))
    az = wrap_angle(np.arctan2(loc[..., 0], loc[..., 1]), az_center)
    el = np.arcsin(np.clip(loc[..., 2] / np.where(rng > 0, rng, 1.0), -1.0, 1.0))
    return np.stack([rng, az, el], axis=-1)


def rae_to_enu(rae) -> np.ndarray:
    """Range, azimuth, elevation ``(..., 3)`` → local east, north, up ``(..., 3)`` (km)."""
    rae = check_finite_array(rae, "rae")
    r, az, el = rae[..., 0], rae[..., 1], rae[..., 2]
    ce = np.cos(el)
    return np.stack([r * ce * np.sin(az), r * ce * np.cos(az), r * np.sin(el)], axis=-1)

"""The field of view's angle test in one compiled pass, with the array passes' decisions.

:meth:`~.sensors.GroundRadar.in_view_local` decides, for each local east-north-up point ``(e, n, u)`` below the
maximum range, whether its range ``ρ = √(e² + n² + u²)``, azimuth ``az = atan2(e, n)`` (offset from the sector's
centre, wrapped into ``[−π, π)``) and elevation ``el = asin(u / ρ)`` lie in the field of view
(:meth:`~.sensors.RadarFieldOfView.contains`, edges included). The array passes (:func:`~.frames.local_to_rae`, then
``contains``) take ~20 numpy calls whatever the batch; the factored filter asks it of every singleton's advanced mean
every scan.

Why not just the same formulas compiled: numpy's ``arctan2``/``arcsin`` and libm's (which numba calls) may round
differently by an ulp or so, and the wrap is rounded twice in the array passes, once here. So :func:`fov_decide`
decides a point only where its angles and range are more than :data:`MARGIN` from every bound (radians, km):
rounding differences of a few ulps (≤ ~1e-15 rad for angles of at most π, ≤ ~1e-12 km for ranges below 10⁴ km)
cannot move such a point across a bound, so both passes decide it alike. A point within the margin of a bound, or
with a non-finite coordinate, is left **undecided** and the caller tests it by the array passes themselves. The
decisions are therefore the array passes', bit for bit, whatever the libraries' rounding (tests: random points,
points on and one ulp around each bound, NaN rows).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["MARGIN", "fov_decide"]

#: How far (rad for angles, km for ranges) from a bound a point must be to be decided here: ~10³ ulps of π and of
#: 10⁴ km, far above the libraries' rounding differences and far below any point's distance from a bound but ~1e-9
#: of the points (the undecided ones, tested by the array passes).
MARGIN = 1e-9

_IN, _OUT, _UNDECIDED = 1, 0, 2


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _decide(loc, near, r_min, r_max, el_min, el_max, az_center, half_width, all_az, margin):
    n = loc.shape[0]
    out = np.zeros(n, np.uint8)
    two_pi = 2.0 * math.pi
    for i in range(n):
        if not near[i]:
            continue
        e, nn, u = loc[i, 0], loc[i, 1], loc[i, 2]
        if not (math.isfinite(e) and math.isfinite(nn) and math.isfinite(u)):
            out[i] = _UNDECIDED
            continue
        rho = math.sqrt((e * e + nn * nn) + u * u)
        # range: inside by more than the margin, outside by more than it, or undecided
        if rho < r_min - margin or rho > r_max + margin:
            continue
        undecided = rho <= r_min + margin or rho >= r_max - margin
        el = math.asin(min(max(u / rho, -1.0), 1.0)) if rho > 0 else 0.0
        if el < el_min - margin or el > el_max + margin:
            continue
        undecided = undecided or el <= el_min + margin or el >= el_max - margin or rho == 0.0
        if not all_az:
            # |off| is the angular distance from the sector's centre, in [0, π]: continuous, so the wrap's
            # rounding (either side of ±π) moves it by ulps only, as in the array passes
            off = math.atan2(e, nn) - az_center
            a = abs(off - two_pi * math.floor((off + math.pi) / two_pi))
            if a > half_width + margin:
                continue
            undecided = undecided or a >= half_width - margin
        out[i] = _UNDECIDED if undecided else _IN
    return out


def fov_decide(loc, near, r_min_km, r_max_km, el_min_rad, el_max_rad, az_center_rad, half_width_rad, all_az):
    """Per point of ``loc`` ``(n, 3)`` (local ENU, km) with ``near`` ``(n,)`` (bool; the others are out): ``1``
    in the field of view, ``0`` out, ``2`` undecided (within :data:`MARGIN` of a bound, or not finite: the caller
    tests those by the array passes). Bounds as :meth:`~.sensors.RadarFieldOfView.contains` computes them
    (radians from ``np.deg2rad``; ``all_az``: a 360° sector, every azimuth in)."""
    loc = np.asarray(loc, dtype=float).reshape(-1, 3)
    near = np.asarray(near, dtype=np.bool_).reshape(-1)
    return _decide(loc, near, float(r_min_km), float(r_max_km), float(el_min_rad), float(el_max_rad),
                   float(az_center_rad), float(half_width_rad), bool(all_az), MARGIN)

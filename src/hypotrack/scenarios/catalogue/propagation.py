"""SGP4 propagation of a whole catalogue over a time grid (``sgp4.api.SatrecArray``), in TEME.

SGP4 (with SDP4's deep-space terms for periods ≥ 225 min) is the model the element sets are fitted
for: secular and periodic J2–J4 effects, atmospheric drag through B*, and luni-solar terms for deep
space. Its output is the truth of the catalogue scenario. ``SatrecArray.sgp4`` runs the C++ SGP4 over
every (object, epoch) pair in one call.

Absent objects. An object is absent at an epoch (NaN state, nonzero ``error``) when SGP4 returns an
error code (decayed, mean elements out of range; ``sgp4.api.SGP4_ERRORS``) — or, code
:data:`IMPLAUSIBLE` (−1), when SGP4 returns a state without an error code that no real object of that
element set can be in: unbound, an osculating perigee below 100 km altitude (it re-enters within
the revolution), or an osculating semi-major axis more than 10 % above the element set's mean one
(drag only lowers orbits; osculating and mean semi-major axes of every bundled object stay within
−1.5 %/+0.4 % of each other over two days from its epoch). SGP4 extrapolated long past an object's
decay does that: Fengyun-1C and Cosmos 2251 fragments propagated 13 months from their 2021 epochs
come back "raised" from 450 km to 15,000 km, or at 10¹² km, with error code 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..._validation import check_finite_array
from ...models.plausibility import orbit_energy, plausible_orbits
from .frames import julian_date, utc_timestamp
from .tle import UNIX_EPOCH_JD, check_catalogue, satrec_array

__all__ = ["reference_epoch", "Propagation", "propagate", "time_grid_jd", "sgp4_states", "check_epoch_span",
           "IMPLAUSIBLE", "MAX_EPOCH_SPAN_DAYS"]

IMPLAUSIBLE = -1
"""``error`` of a state SGP4 returned without an error code but no real object can be in."""

MAX_EPOCH_SPAN_DAYS = 731.0
"""Longest interval (days, two years) between an element set's epoch and an instant it is propagated to.

An element set is fitted to a few days of observations and is meaningful for days to weeks; the bound
is generous on purpose — the bundled scenario propagates the 2021 debris clouds about 13 months (424 days
at most) past their epochs — and refuses only what no element set can say anything about (a start
mistyped by years or a century). Decayed or implausible states inside it are absent (:data:`IMPLAUSIBLE`)."""

_MU = 398600.4418  # km³/s², for the osculating elements of the plausibility check
_R_EARTH_SGP4 = 6378.135  # km, WGS-72 (SGP4's Earth)
_MIN_PERIGEE_ALT = 100.0  # km
_MAX_A_RATIO = 1.1


def reference_epoch(cat: pd.DataFrame) -> pd.Timestamp:
    """The start the scenario uses by default: a catalogue's epoch, floored to the whole minute.

    The median element epoch of each group present; of those, the latest. For one catalogue this
    is its median epoch (robust to the few element sets published days or weeks off the file's
    date); for the 2022 active catalogue with a 2021 debris cloud it is the active catalogue's,
    so the debris are propagated about 13 months past their epoch (see the data README).
    """
    cat = check_catalogue(cat)
    if len(cat) == 0:
        raise ValueError("catalogue must hold at least one object")
    medians = cat.groupby("group", sort=False)["epoch"].median()
    return medians.max().floor("min")


def check_epoch_span(cat: pd.DataFrame, jd, fr) -> None:
    """Refuse instants ``(jd, fr)`` more than :data:`MAX_EPOCH_SPAN_DAYS` from any object's element epoch
    (``ValueError`` naming the instant, the object and its epoch)."""
    t = np.asarray(jd, dtype=float) + np.asarray(fr, dtype=float)
    if len(t) == 0 or len(cat) == 0:
        return
    ep = cat["epoch_jd"].to_numpy(float) + cat["epoch_fr"].to_numpy(float)
    i_t_hi, i_t_lo, i_e_lo, i_e_hi = int(np.argmax(t)), int(np.argmin(t)), int(np.argmin(ep)), int(np.argmax(ep))
    after, before = t[i_t_hi] - ep[i_e_lo], ep[i_e_hi] - t[i_t_lo]
    k, i, gap = (i_t_hi, i_e_lo, after) if after >= before else (i_t_lo, i_e_hi, -before)
    if abs(gap) > MAX_EPOCH_SPAN_DAYS:
        when = pd.Timestamp(round((t[k] - UNIX_EPOCH_JD) * 86400e6), unit="us")
        row = cat.iloc[i]
        raise ValueError(
            f"propagation time {when} is {abs(gap):.1f} days {'after' if gap > 0 else 'before'} the element "
            f"epoch {row['epoch']} of NORAD {int(row['norad'])} ({row['name']}): SGP4 element sets are meaningful "
            f"for days to weeks, and this library propagates at most {MAX_EPOCH_SPAN_DAYS:g} days (two years) "
            "from an epoch; choose a start near the catalogue's epochs (default: reference_epoch(cat))")


def sgp4_states(sats, jd, fr, a_mean):
    """``SatrecArray.sgp4`` plus the plausibility check (module docstring): the trackers' own test
    (:func:`hypotrack.models.plausibility.plausible_orbits`, bound with perigee >= 100 km) and the
    semi-major-axis bound.

    Returns ``(error (N, K) int64, r (N, K, 3), v (N, K, 3))`` with NaN states where ``error != 0``.
    """
    e, r, v = sats.sgp4(np.asarray(jd, dtype=float), np.asarray(fr, dtype=float))
    e = e.astype(np.int64)
    with np.errstate(invalid="ignore", divide="ignore"):
        X = np.concatenate([r, v], axis=-1)
        ok = plausible_orbits(X, min_perigee_km=_MIN_PERIGEE_ALT, mu=_MU, earth_radius=_R_EARTH_SGP4)
        a = -_MU / (2 * orbit_energy(X, _MU))
        ok &= a <= _MAX_A_RATIO * np.asarray(a_mean, dtype=float)[:, None]
    e[(e == 0) & ~ok] = IMPLAUSIBLE
    bad = e != 0
    if bad.any():
        r[bad] = np.nan
        v[bad] = np.nan
    return e, r, v


def time_grid_jd(start, times) -> tuple[np.ndarray, np.ndarray]:
    """``(jd, fr)`` arrays of the instants ``start + times`` (``times`` in seconds, any sign)."""
    jd0, fr0 = julian_date(start)
    t = check_finite_array(times, "times", ndim=1)
    return np.full(len(t), jd0), fr0 + t / 86400.0


@dataclass(frozen=True, eq=False)
class Propagation:
    """SGP4 states of N objects at K epochs.

    Attributes
    ----------
    norad : (N,) int64 ids, catalogue order.
    times : (K,) seconds since ``start``.
    start : pandas.Timestamp (UTC).
    r, v : (N, K, 3) TEME position (km) and velocity (km/s); NaN where ``error != 0``.
    error : (N, K) SGP4 error codes (0 = fine; 6 = decayed, ``sgp4.api.SGP4_ERRORS``; −1 =
        :data:`IMPLAUSIBLE`).
    """

    norad: np.ndarray
    times: np.ndarray
    start: pd.Timestamp
    r: np.ndarray
    v: np.ndarray
    error: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """(N, K) mask of the propagated (object, epoch) pairs."""
        return self.error == 0


def propagate(cat: pd.DataFrame, times, start=None, *, satrecs=None) -> Propagation:
    """Propagate every object of a catalogue to the instants ``start + times`` with SGP4.

    Parameters
    ----------
    cat : catalogue table (:func:`hypotrack.scenarios.catalogue.parse_tle`).
    times : (K,) seconds from ``start``.
    start : UTC date-time, optional
        Default :func:`reference_epoch` of ``cat``.
    satrecs : sgp4.api.SatrecArray, optional
        Pre-built satellites of ``cat`` (to reuse them across calls).

    Returns
    -------
    Propagation
    """
    cat = check_catalogue(cat)
    start = reference_epoch(cat) if start is None else utc_timestamp(start)
    jd, fr = time_grid_jd(start, times)
    check_epoch_span(cat, jd, fr)
    sats = satrec_array(cat) if satrecs is None else satrecs
    e, r, v = sgp4_states(sats, jd, fr, cat["semi_major_axis_km"].to_numpy(float))
    return Propagation(
        norad=cat["norad"].to_numpy(np.int64),
        times=np.asarray(times, dtype=float).copy(),
        start=start,
        r=r,
        v=v,
        error=e.astype(np.int64),
    )

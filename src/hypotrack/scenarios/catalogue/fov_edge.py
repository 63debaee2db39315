"""The field of view's edge integrated over a track's density: :class:`SoftEdgeDetection`.

A tracker that decides a track's detectability at its predicted mean (``p_D`` inside the field of view, 0 outside)
cannot give a return to a track whose mean lies just outside while the object itself is inside. That is where a pass
begins: an object rising over the radar's lowest elevation, predicted over an hour with an in-track spread of ~10 km
(a quarter of a degree at 2,500 km), is inside the field of view with a probability near one half when its mean is
a hundredth of a degree below the edge. A return there can then only go to a neighbour whose mean is inside, and the
filter is sure of that wrong association, since the right one has weight zero. GNN and JPDA, which gate every track
whatever the field of view, do not make this error.

The track-level detection probability is the expectation of the state's ``p_D(x) = p_D 1_FOV(x)`` under the
predicted density (a state-dependent ``p_D`` integrated against the track's density, as in Mahler, *Statistical
Multisource-Multitarget Information Fusion*, 2007; the Gaussian-mixture PHD filter of Vo and Ma, 2006, evaluates a
slowly varying ``p_D`` at each component's mean instead, which is the approximation that fails at a hard edge):
``p_D P_in`` with ``P_in = P(x ∈ FOV)``. With the linearised
predicted measurement ``N(h(m), H P Hᵀ)`` and the field of view a box in ``(ρ, az, el)`` the box's probability is
the product of its sides' normal probabilities (the cross-covariances of range, azimuth and elevation neglected):

    P_in = [Φ((ρ_max − ρ̂)/σ_ρ) − Φ((ρ_min − ρ̂)/σ_ρ)] [Φ((el_max − êl)/σ_el) − Φ((el_min − êl)/σ_el)] P_az,

``P_az`` the sector's own factor (1 for a full circle). A missed track is weighted ``1 − p_D P_in`` — the exact
probability of no return from it — and a detected one ``p_D N(z; ẑ, S)``: the return itself says the object was
inside (up to its measurement noise, 0.05° against a track's spread of tenths of a degree), so the indicator is 1
under the posterior given the return, and the detected term's mass over the returns in view is ``p_D P_in``. The two
sum to one.

Which tracks are scored: those whose mean lies within ``margin_deg`` in angle and ``margin_km`` in range of the field
of view (:meth:`SoftEdgeDetection.in_view`, the engine's "in view" for waking, gating and ``p_D > 0``); beyond it
``P_in`` is taken as 0. The margin is a stated approximation: a track whose spread in elevation exceeds a quarter of
``margin_deg`` (4σ) loses the tail beyond it. The scorecard and GNN/JPDA's miss rule keep the true field of view
(:meth:`SoftEdgeDetection.in_fov`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.special import ndtr

from ..._validation import check_nonnegative

__all__ = ["SoftEdgeDetection", "attach_soft_edge"]


class _Owner:
    """The wrapped sensor seen through a dilated field of view (its GMST read from the sensor at each call)."""

    def __init__(self, sensor, radar):
        self._sensor, self.radar = sensor, radar

    @property
    def theta(self) -> float:
        return self._sensor.theta


class SoftEdgeDetection:
    """A radar tracker sensor's detection with the field of view's edge integrated (module docstring).

    Parameters
    ----------
    sensor : RadarTrackerSensor
        The sensor whose ``detection`` is wrapped (its ``in_view`` is the true field of view, its ``p_D`` the
        constant, or ``p_D_of`` of the state when it has one).
    margin_deg : float
        Angles (elevation, and azimuth for a sector) within which a track outside the field of view is still
        scored, degrees, ≥ 0.
    margin_km : float
        The same for range, km, ≥ 0.
    """

    _CAP = 1.0 - 1e-9  # log(1 − p_D) of a missed track stays finite

    def __init__(self, sensor, margin_deg: float, margin_km: float):
        from .radar_model import _Detection  # the radar's compiled field-of-view test, on the dilated field

        self._sensor, self._base = sensor, sensor.detection
        self.margin_deg = check_nonnegative(margin_deg, "margin_deg")
        self.margin_km = check_nonnegative(margin_km, "margin_km")
        self.p_D = self._base.p_D
        f = sensor.radar.fov
        self.fov = f
        wide = replace(f, el_min_deg=max(0.0, f.el_min_deg - self.margin_deg),
                       el_max_deg=min(90.0, f.el_max_deg + self.margin_deg),
                       az_width_deg=min(360.0, f.az_width_deg + 2 * self.margin_deg),
                       r_min_km=max(0.0, f.r_min_km - self.margin_km), r_max_km=f.r_max_km + self.margin_km)
        self._wide = _Detection(_Owner(sensor, replace(sensor.radar, fov=wide)))

    def in_view(self, x_teme) -> np.ndarray:
        """Whether TEME positions ``(n, ≥ 3)`` lie in the field of view dilated by the margins (the tracks scored)."""
        return self._wide.in_view(x_teme)

    def in_fov(self, x_teme) -> np.ndarray:
        """Whether TEME positions ``(n, ≥ 3)`` lie in the true field of view."""
        return self._base.in_view(x_teme)

    def p_in_view(self, means, covs) -> np.ndarray:
        """``P_in`` ``(n,)`` of TEME tracks ``(means (n, 6), covs (n, 6, 6))`` (module docstring)."""
        X = np.atleast_2d(np.asarray(means, dtype=float))
        if len(X) == 0:
            return np.zeros(0)
        z = self._sensor.h(X)
        H = self._sensor.jacobian(X)
        var = np.einsum("nij,njk,nik->ni", H[:, :3], np.asarray(covs, dtype=float), H[:, :3])
        sd = np.sqrt(np.maximum(var, 1e-300))
        f = self.fov
        lo, hi = f.low, f.high  # (ρ, az, el), km and rad

        def side(k, lower, upper):
            return ndtr((upper - z[:, k]) / sd[:, k]) - ndtr((lower - z[:, k]) / sd[:, k])

        p = side(0, lo[0], hi[0]) * side(2, lo[2], hi[2] if f.el_max_deg < 90 else np.inf)
        if f.az_width_deg < 360:  # the sector about its centre: azimuths are reported within ±π of it
            p = p * side(1, lo[1], hi[1])
        return p

    def p_D_of_moments(self, means, covs) -> np.ndarray:
        """``p_D P_in`` ``(n,)`` of TEME tracks (the wrapped detection's ``p_D_of`` of the means when it has one)."""
        p_of = getattr(self._base, "p_D_of", None)
        p_D = p_of(means) if p_of is not None else self.p_D
        return np.minimum(p_D * self.p_in_view(means, covs), self._CAP)


def attach_soft_edge(sensor, margin_deg: float, margin_km: float):
    """Give a radar tracker sensor the soft-edged detection (:class:`SoftEdgeDetection`); returns the sensor."""
    sensor.detection = SoftEdgeDetection(sensor, margin_deg, margin_km)
    return sensor

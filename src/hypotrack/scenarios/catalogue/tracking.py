"""The tracker's side of the catalogue scenario: radar returns as linear TEME position measurements.

A ground radar with ``measurement="enu"`` reports the local east-north-up position of an object
with isotropic Gaussian error σ (km) (:class:`.GroundRadar`). The map from ENU at the site to the
quasi-inertial TEME frame at scan time ``t`` is a rotation and a translation,

    r_teme = R3(θ(t))ᵀ (Eᵀ z_enu + r_site,ef),

(``E`` the site's ENU rows, ``R3(θ)`` the Earth rotation by GMST θ), so a return converted to
TEME is ``z = [I 0] x + v`` with ``v ~ N(0, σ² I)`` — an isotropic covariance is unchanged by a
rotation. Every tracker of the project (the hypothesis engine, GNN, JPDA) then runs on a linear
measurement model with a fixed ``H`` and ``R``, and the two-body EKF
(:class:`hypotrack.models.orbit3d.TwoBodyOrbit3D`) carries the nonlinearity. The radar's
range/azimuth/elevation errors (30 m in range, ~1 km across the beam) are not isotropic; the
ENU radar with one σ is a stand-in with a fixed ``H`` and ``R``. The documented radar itself
(``measurement="rae_rate"``: range, azimuth, elevation and range-rate) is tracked **in the sensor
frame** by :class:`.radar_model.RadarTrackerSensor` — an EKF update with ``z = h(x)``, a per-track
Jacobian, a constant ``R`` and the azimuth innovation wrapped (:mod:`hypotrack.models.measurement`):
its noise is Gaussian with a constant covariance there, while a converted Cartesian return would need
a covariance per return and could not carry the range-rate linearly.

:class:`TrackerSensor` is what :class:`~hypotrack.hypotheses.HypothesisFilter` and
:class:`~hypotrack.hypotheses.FactoredFilter` need of a sensor (``measurement.H``/``R``,
``detection.p_D``/``in_view``, ``clutter.rate``/``region.area``): ``in_view`` tests predicted TEME
positions against the radar's field of view at the GMST set with :meth:`TrackerSensor.at`
before each scan; the clutter volume is the field of view's physical volume (clutter is uniform
over it, :meth:`.RadarFieldOfView.sample_enu`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_finite_array
from .sensors import GroundRadar

__all__ = ["enu_to_teme", "teme_to_enu", "TrackerSensor", "OnePointBirth"]


def _r3(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def enu_to_teme(Z_enu, radar: GroundRadar, theta: float) -> np.ndarray:
    """TEME positions ``(m, 3)`` (km) of ENU returns ``(m, 3)`` of ``radar`` at GMST ``theta`` (rad)."""
    Z = check_finite_array(np.asarray(Z_enu, dtype=float).reshape(-1, 3), "Z_enu", shape=(None, 3))
    ef = Z @ radar.site.enu + radar.site.ef
    return ef @ _r3(theta)


def teme_to_enu(r_teme, radar: GroundRadar, theta: float) -> np.ndarray:
    """ENU ``(n, 3)`` at the site of TEME positions ``(n, >= 3)``: the inverse of :func:`enu_to_teme`."""
    r = np.atleast_2d(np.asarray(r_teme, dtype=float))[:, :3]
    return (r @ _r3(theta).T - radar.site.ef) @ radar.site.enu.T


@dataclass(frozen=True, eq=False)
class _Measurement:
    H: np.ndarray
    R: np.ndarray


@dataclass(frozen=True, eq=False)
class _Region:
    area: float


@dataclass(frozen=True, eq=False)
class _Clutter:
    rate: float
    region: _Region

    @property
    def intensity(self) -> float:
        return self.rate / self.region.area


class _Detection:
    def __init__(self, radar: GroundRadar, owner: "TrackerSensor"):
        self.p_D = radar.p_D
        self._radar, self._owner = radar, owner

    def in_view(self, z_teme) -> np.ndarray:
        """Mask of predicted TEME positions inside the radar's field of view at the current GMST."""
        z = np.atleast_2d(np.asarray(z_teme, dtype=float))
        if len(z) == 0:
            return np.zeros(0, dtype=bool)
        r_ef = z[:, :3] @ _r3(self._owner.theta).T
        return self._radar.in_view(r_ef)


class TrackerSensor:
    """A 6-state TEME tracker's view of an ENU ground radar (module docstring).

    Parameters
    ----------
    radar : GroundRadar with ``measurement="enu"``.

    Attributes
    ----------
    measurement : ``H = [I₃ 0]`` (3, 6), ``R = σ² I₃``.
    detection : ``p_D`` and ``in_view`` at the current GMST :attr:`theta`.
    clutter : ``rate`` = the radar's clutter rate, ``region.area`` = the physical volume of the
        field of view (km³).
    theta : GMST (rad) of the scan being processed; set with :meth:`at`.
    """

    def __init__(self, radar: GroundRadar):
        if not isinstance(radar, GroundRadar):
            raise TypeError(f"radar must be a GroundRadar, got {type(radar).__name__}")
        if radar.measurement != "enu":
            raise ValueError(f"radar.measurement must be 'enu' (a linear TEME position after rotation), "
                             f"got {radar.measurement!r}")
        self.radar = radar
        H = np.hstack([np.eye(3), np.zeros((3, 3))])
        self.measurement = _Measurement(H, np.eye(3) * radar.sigma_enu_km**2)
        self.detection = _Detection(radar, self)
        self.clutter = _Clutter(radar.clutter_rate, _Region(radar.fov.physical_volume))
        self.theta = 0.0

    def at(self, theta: float) -> "TrackerSensor":
        """Set the GMST (rad) of the next scan; returns ``self``."""
        self.theta = float(check_finite_array(theta, "theta", ndim=0))
        return self

    def returns(self, Z_enu) -> np.ndarray:
        """The scan's ENU returns as TEME positions at the current GMST."""
        return enu_to_teme(Z_enu, self.radar, self.theta)


class OnePointBirth:
    """Birth density of HOMHT's births seeded at a return (``initial_state(z, R)``): the return's
    position with its noise ``R`` plus ``position_std`` (km), zero velocity with ``velocity_std``
    (km/s) per component — one-point initiation of an orbit whose direction is unknown."""

    def __init__(self, velocity_std: float, position_std: float = 0.0):
        if not (np.isfinite(velocity_std) and velocity_std > 0):
            raise ValueError(f"velocity_std must be finite and > 0, got {velocity_std!r}")
        if not (np.isfinite(position_std) and position_std >= 0):
            raise ValueError(f"position_std must be finite and >= 0, got {position_std!r}")
        self.velocity_std, self.position_std = float(velocity_std), float(position_std)

    def initial_state(self, z, R):
        z = np.asarray(z, dtype=float).reshape(3)
        P = np.zeros((6, 6))
        P[:3, :3] = np.asarray(R, dtype=float) + np.eye(3) * self.position_std**2
        P[3:, 3:] = np.eye(3) * self.velocity_std**2
        return np.concatenate([z, np.zeros(3)]), P

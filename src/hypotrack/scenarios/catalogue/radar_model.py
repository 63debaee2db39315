"""The documented radar measurement model: range, azimuth, elevation and range-rate of a TEME state.

A ground radar (:class:`.GroundRadar`, :data:`.DEFAULT_RADAR`) measures, of an object at TEME position
``r`` with velocity ``v`` (km, km/s), seen from a site at GMST ``θ`` (:mod:`.frames`):

* the site in TEME: ``s = R3(θ)ᵀ s_ef`` and ``ṡ = ω ẑ × s`` (the Earth-fixed site carried round by the
  Earth's rotation ω, :data:`.frames.EARTH_ROTATION`);
* the line of sight ``d = r − s`` and its local east-north-up coordinates ``l = (e, n, u) = E R3(θ) d``
  (``E``: the site's ENU rows);
* ``z = h(x) = (ρ, az, el, ρ̇)`` with ``ρ = |d|``, ``az = atan2(e, n)`` (from north towards east),
  ``el = asin(u / ρ)`` and ``ρ̇ = d · (v − ṡ) / ρ``

(Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Sec. 4.4, algorithm RAZEL:
the same range-rate, written there with the Earth-fixed velocity ``R3(θ)(v − ω × r)``; the two agree
because ``d · (ω × d) = 0``). Its Jacobian ``∂h/∂x`` (4 × 6) is analytic:

* ``∂ρ/∂r = dᵀ/ρ``; ``∂az/∂r = (n, −e, 0) M / (e² + n²)``;
  ``∂el/∂r = (−e u, −n u, e² + n²) M / (ρ² sqrt(e² + n²))`` with ``M = E R3(θ)``;
* ``∂ρ̇/∂r = (w − ρ̇ d/ρ)ᵀ / ρ`` with ``w = v − ṡ``; ``∂ρ̇/∂v = dᵀ/ρ``; the angles and the range do not
  depend on ``v``.

Azimuth is singular at the zenith (``e² + n² → 0``), where the radar's field of view stops (85°).
It is reported in ``[c − π, c + π)`` around a centre ``c`` (the face's boresight); innovations are
wrapped into ``[−π, π)`` (:meth:`RadarTrackerSensor.innovation`), so a return just across the wrap is
a small innovation, not a 2π one.

Noise (:class:`RadarTrackerSensor`): independent Gaussian errors σ_ρ = 30 m, σ_az = σ_el = 0.05° (the
:data:`.DEFAULT_RADAR`'s documented numbers) and σ_ρ̇ = :data:`SIGMA_RANGE_RATE_KM_S` = 10 m/s. The
range-rate σ is derived here, not quoted from a radar's specification: the precision of a Doppler
measurement is ``σ_ρ̇ ≈ (λ/2) / (T_d sqrt(2 SNR))`` (Blair, Richards & Long, "Radar measurements", Ch. 18
of *Principles of Modern Radar*, SciTech 2010, Sec. 18.7: a frequency estimate's precision is its
resolution ``1/T_d`` over ``sqrt(2 SNR)``); for a UHF space-surveillance array (435 MHz, λ = 0.69 m,
the band of PAVE PAWS and of the AMISR/PFISR radar used for debris tracking, Nicolls, "Space debris
measurements using the Advanced Modular Incoherent Scatter Radar", AMOS conference) with a 10-ms coherent
dwell, ``λ/(2 T_d)`` = 34.5 m/s and at the 8-dB detection threshold (SNR 6.3) σ_ρ̇ = 9.7 m/s; stronger
returns are measured better (13 dB: 5.5 m/s), so 10 m/s is the conservative end.
"""

from __future__ import annotations

import numpy as np

from dataclasses import dataclass

from ..._validation import check_finite_array, check_positive
from ...models.measurement import ExtendedMeasurement
from .frames import EARTH_ROTATION, wrap_angle
from .radar_kernels import INNOVATION, MOMENTS, UPDATE, radar_jacobian, radar_moments, teme_near
from .sensors import GroundRadar, GroundSite
from .tracking import _Clutter, _Region  # the clutter record the engine reads of either tracker sensor

__all__ = ["site_teme", "rae_rate", "rae_rate_jacobian", "attributable_to_state", "attributable_jacobian", "RadarTrackerSensor", "RadarMeasurement", "RadarOnePointBirth",
           "SIGMA_RANGE_RATE_KM_S"]

SIGMA_RANGE_RATE_KM_S = 0.01
"""Range-rate standard deviation (km/s) of the radar model: 10 m/s (module docstring for its derivation)."""


def _r3(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def _states(x):
    X = np.atleast_2d(np.asarray(x, dtype=float))
    if X.ndim != 2 or X.shape[1] != 6:
        raise ValueError(f"x must have shape (n, 6) (TEME position km, velocity km/s), got {np.shape(x)}")
    return X


def site_teme(site: GroundSite, theta: float):
    """The site's TEME position (km) and velocity (km/s) at GMST ``theta`` (rad): ``R3(θ)ᵀ s_ef`` and
    ``ω ẑ × s``."""
    s = _r3(theta).T @ site.ef
    return s, EARTH_ROTATION * np.array([-s[1], s[0], 0.0])


def _geometry(X, site, theta):
    s, sdot = site_teme(site, theta)
    M = site.enu @ _r3(theta)
    d = X[:, :3] - s
    w = X[:, 3:] - sdot
    return d, w, d @ M.T, M


def rae_rate(x, site: GroundSite, theta: float, *, az_center: float = 0.0) -> np.ndarray:
    """``(n, 4)`` range (km), azimuth (rad, in ``[az_center − π, az_center + π)``), elevation (rad) and
    range-rate (km/s) of TEME states ``x`` ``(n, 6)`` (or one ``(6,)``) from ``site`` at GMST ``theta``
    (module docstring)."""
    X = _states(x)
    d, w, loc, _ = _geometry(X, site, theta)
    rho = np.sqrt(np.sum(d * d, axis=1))
    az = wrap_angle(np.arctan2(loc[:, 0], loc[:, 1]), az_center)
    el = np.arctan2(loc[:, 2], np.hypot(loc[:, 0], loc[:, 1]))  # = asin(u/ρ), well conditioned at the zenith
    return np.column_stack([rho, az, el, np.sum(d * w, axis=1) / rho])


def rae_rate_jacobian(x, site: GroundSite, theta: float) -> np.ndarray:
    """``∂h/∂x`` ``(n, 4, 6)`` of :func:`rae_rate` at TEME states ``x`` ``(n, 6)`` (module docstring)."""
    X = _states(x)
    d, w, loc, M = _geometry(X, site, theta)
    n = len(X)
    e, nn, u = loc.T
    rho2 = np.sum(d * d, axis=1)
    rho = np.sqrt(rho2)
    hz2 = e * e + nn * nn
    hz = np.sqrt(hz2)
    rdot = np.sum(d * w, axis=1) / rho
    J = np.zeros((n, 4, 6))
    J[:, 0, :3] = d / rho[:, None]
    J[:, 1, :3] = np.column_stack([nn / hz2, -e / hz2, np.zeros(n)]) @ M
    J[:, 2, :3] = (np.column_stack([-e * u, -nn * u, hz2]) / (rho2 * hz)[:, None]) @ M
    J[:, 3, :3] = (w - rdot[:, None] * d / rho[:, None]) / rho[:, None]
    J[:, 3, 3:] = d / rho[:, None]
    return J


_H_STEP = 1e-20


def attributable_to_state(y, site: GroundSite, theta: float) -> np.ndarray:
    """TEME states ``(n, 6)`` of attributables ``y`` ``(n, 6)`` = (ρ km, az rad, el rad, ρ̇ km/s, α̇ rad/s,
    ε̇ rad/s) seen from ``site`` at GMST ``theta`` (module docstring, step 1). Accepts complex input (for the
    complex-step Jacobian)."""
    Y = np.atleast_2d(y)
    rho, az, el, rd, azd, eld = (Y[:, k][:, None] for k in range(6))
    ce, se, ca, sa = np.cos(el), np.sin(el), np.cos(az), np.sin(az)
    zero = np.zeros_like(ce)
    u = np.hstack([ce * sa, ce * ca, se])
    du_az = np.hstack([ce * ca, -ce * sa, zero])
    du_el = np.hstack([-se * sa, -se * ca, ce])
    l = rho * u
    ldot = rd * u + rho * (azd * du_az + eld * du_el)
    M = site.enu @ _r3(theta)
    s, _ = site_teme(site, theta)
    r = s + l @ M
    w_x_r = EARTH_ROTATION * np.stack([-r[:, 1], r[:, 0], np.zeros_like(r[:, 0])], axis=1)
    return np.hstack([r, ldot @ M + w_x_r])


def attributable_jacobian(y, site, theta):
    """``∂x/∂y`` (6, 6) of :func:`attributable_to_state` at one ``y`` by complex step."""
    Yc = np.repeat(np.asarray(y, dtype=float)[None], 6, axis=0).astype(complex)
    Yc[np.arange(6), np.arange(6)] += 1j * _H_STEP
    return (attributable_to_state(Yc, site, theta).imag / _H_STEP).T


class _Detection:
    def __init__(self, owner: "RadarTrackerSensor"):
        self.p_D = owner.radar.p_D
        self._owner = owner

    def in_view(self, x_teme) -> np.ndarray:
        """Mask of TEME positions ``(n, >= 3)`` inside the field of view at the current GMST."""
        r = np.atleast_2d(np.asarray(x_teme, dtype=float))
        if len(r) == 0:
            return np.zeros(0, dtype=bool)
        # GroundRadar.in_view of r R3(θ)ᵀ, its range and horizon test in one compiled pass (the same decisions)
        radar = self._owner.radar
        loc, near = teme_near(r, _r3(self._owner.theta), radar.site.ef, radar.site.enu, radar.fov.r_max_km,
                              radar.fov.el_min_deg > 0)
        return radar.in_view_local(loc, near)


class RadarMeasurement(ExtendedMeasurement):
    """The radar's ``z = h(x) = (ρ, az, el, ρ̇)`` as the trackers' measurement model (:mod:`hypotrack.models.measurement`):
    the EKF in the sensor frame at the GMST its sensor is set to (:meth:`RadarTrackerSensor.at`), constant
    ``R = diag(σ_ρ², σ_az², σ_el², σ_ρ̇²)``, the azimuth residual (index 1) wrapped into ``[−π, π)``.

    Why the sensor frame: the radar's noise is Gaussian with a constant covariance in ``(ρ, az, el, ρ̇)``; a
    return converted to a Cartesian position would need a covariance per return (it grows with range across
    the beam) and cannot carry the range-rate, a nonlinear function of position and velocity, linearly."""

    wrapped = (1,)
    ndim_state = 6
    hessian_steps = (1e-2,) * 3 + (1e-3,) * 3  # km, km/s: the Jacobian is linear in v, smooth over 10 m in r

    def __init__(self, sensor: "RadarTrackerSensor", second_order: bool = True, compiled: bool = True):
        self.sensor = sensor
        self.R = sensor.R
        self.second_order = bool(second_order)
        #: the moments, innovation and update by the compiled kernel (:mod:`.radar_kernels`, one pass for the batch),
        #: else by the array passes of :class:`~...models.measurement.ExtendedMeasurement` (the same formulas)
        self.compiled = bool(compiled)

    def _geometry(self):
        """``(s, ṡ, M)`` of the sensor's current GMST (:func:`site_teme`, ``M = E R3(θ)``), kept for the scan."""
        site, theta = self.sensor.radar.site, self.sensor.theta
        key = (theta, id(site))
        if getattr(self, "_geo_key", None) != key:
            s, sdot = site_teme(site, theta)
            self._geo = (s, sdot, np.ascontiguousarray(site.enu @ _r3(theta)), np.asarray(self.hessian_steps, dtype=float))
            self._geo_key = key
        return self._geo

    def _kernel(self, means, covs, Z, mode):
        s, sdot, M, steps = self._geometry()
        return radar_moments(means, covs, Z, s, sdot, M, steps, self.R, self.sensor.az_center, self.second_order, mode)

    def _moments(self, means, covs):
        if not self.compiled:
            return super()._moments(means, covs)
        z_pred, H, R = self._kernel(means, covs, None, MOMENTS)
        return z_pred, H, (R if self.second_order else self.R)  # first order: the one R, as the array passes

    def innovation(self, means, covs):
        if not self.compiled or len(means) == 0:
            return super().innovation(means, covs)
        return self._kernel(means, covs, None, INNOVATION)

    def update(self, means, covs, Z_rows):
        if not self.compiled or len(means) == 0:
            return super().update(means, covs, Z_rows)
        return self._kernel(means, covs, Z_rows, UPDATE)

    def h(self, means) -> np.ndarray:
        return self.sensor.h(means)

    def jacobian(self, means) -> np.ndarray:
        if not self.compiled:
            return self.sensor.jacobian(means)
        s, sdot, M, _ = self._geometry()
        return radar_jacobian(means, s, sdot, M)

    def one_point(self, Z, position_std: float = 0.0, velocity_std: float = 8.0):
        """One-point initiation ``(x₀ (m, 6), P₀ (m, 6, 6))`` of returns ``Z`` ``(m, 4)`` in the sensor frame: the
        state of the attributable ``(ρ, az, el, ρ̇, 0, 0)`` (:func:`attributable_to_state`) — the
        return's position, its range-rate along the line of sight — with the covariance ``J C Jᵀ`` of
        ``C = diag(R, (v_s/(ρ cos el))², (v_s/ρ)²)`` (``v_s`` = ``velocity_std``: the velocity across the line of
        sight is ``N(0, v_s²)`` per direction) plus ``position_std²`` on each position component."""
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        site, theta = self.sensor.radar.site, self.sensor.theta
        x0, P0 = np.zeros((len(Z), 6)), np.zeros((len(Z), 6, 6))
        C = np.zeros((6, 6))
        C[:4, :4] = self.R
        for i, z in enumerate(Z):
            y = np.r_[z, 0.0, 0.0]
            C[4, 4] = (velocity_std / (z[0] * max(np.cos(z[2]), 1e-6))) ** 2
            C[5, 5] = (velocity_std / z[0]) ** 2
            J = attributable_jacobian(y, site, theta)
            x0[i] = attributable_to_state(y, site, theta)[0].real
            P = J @ C @ J.T
            P[:3, :3] += np.eye(3) * position_std**2
            P0[i] = 0.5 * (P + P.T)
        return x0, P0


@dataclass(frozen=True, eq=False)
class RadarOnePointBirth:
    """The birth density of births seeded at a radar return (HOMHT's ``initial_state(z, R)``): the
    sensor-frame one-point initiation :meth:`RadarMeasurement.one_point` (``R`` is the sensor's own)."""

    measurement: RadarMeasurement
    velocity_std: float = 8.0
    position_std: float = 0.0

    def initial_state(self, z, R=None):
        x, P = self.measurement.one_point(np.asarray(z, dtype=float).reshape(1, 4), self.position_std, self.velocity_std)
        return x[0], P[0]


class RadarTrackerSensor:
    """A 6-state TEME tracker's view of a ground radar measuring ``(ρ, az, el, ρ̇)`` (module docstring).

    The nonlinear counterpart of :class:`.TrackerSensor` (which needs ENU returns and a fixed ``H``): an
    extended Kalman filter linearises :meth:`h` with :meth:`jacobian` at each predicted state
    (:meth:`update`), and every return has the covariance :attr:`R` (:meth:`covariances`). The trackers
    work **in the sensor frame**: :attr:`measurement` (:class:`RadarMeasurement`) is what
    :class:`~hypotrack.hypotheses.HypothesisFilter`, the factored engine, the birth terms and GNN/JPDA use
    (``innovation``/``residual``/``update``), :attr:`clutter` its clutter rate over the measurement-space
    volume ``Δρ Δaz Δel 2 span_ρ̇``.

    Parameters
    ----------
    radar : GroundRadar
        Site, field of view, σ_ρ (km), σ_az and σ_el (degrees), ``p_D`` and clutter rate.
    sigma_range_rate_km_s : float
        σ_ρ̇ (km/s), > 0; default :data:`SIGMA_RANGE_RATE_KM_S`.
    range_rate_span_km_s : float
        Clutter range-rates are uniform over ``[−span, span]`` (km/s), > 0; default 8 (LEO speeds).

    Attributes
    ----------
    R : (4, 4) diagonal measurement covariance (km², rad², rad², km²/s²).
    detection : ``p_D`` and ``in_view`` at the current GMST :attr:`theta`.
    clutter_volume : measurement-space volume of the field of view ``Δρ Δaz Δel Δρ̇`` (km·rad²·km/s).
    measurement : RadarMeasurement (the EKF in the sensor frame).
    clutter : ``rate`` (the radar's) and ``region.area`` = :attr:`clutter_volume`.
    theta : GMST (rad) of the scan being processed; set with :meth:`at`.

    A radar with ``measurement="rae_rate"`` gives the defaults of ``sigma_range_rate_km_s`` and
    ``range_rate_span_km_s`` (its own); otherwise :data:`SIGMA_RANGE_RATE_KM_S` and 8 km/s.
    """

    def __init__(self, radar: GroundRadar, sigma_range_rate_km_s: float | None = None,
                 range_rate_span_km_s: float | None = None):
        if not isinstance(radar, GroundRadar):
            raise TypeError(f"radar must be a GroundRadar, got {type(radar).__name__}")
        own = radar.measurement == "rae_rate"
        if sigma_range_rate_km_s is None:
            sigma_range_rate_km_s = radar.sigma_range_rate_km_s if own else SIGMA_RANGE_RATE_KM_S
        if range_rate_span_km_s is None:
            range_rate_span_km_s = radar.range_rate_span_km_s if own else 8.0
        self.radar = radar
        self.sigma_range_rate_km_s = check_positive(sigma_range_rate_km_s, "sigma_range_rate_km_s")
        self.range_rate_span_km_s = check_positive(range_rate_span_km_s, "range_rate_span_km_s")
        sig = np.array([radar.sigma_range_km, np.deg2rad(radar.sigma_az_deg), np.deg2rad(radar.sigma_el_deg),
                        self.sigma_range_rate_km_s])
        self.R = np.diag(sig**2)
        self.detection = _Detection(self)
        self.clutter_volume = radar.fov.measurement_volume * 2 * self.range_rate_span_km_s
        self.clutter = _Clutter(radar.clutter_rate, _Region(self.clutter_volume))
        self.measurement = RadarMeasurement(self)
        self.theta = 0.0

    @property
    def az_center(self) -> float:
        return self.radar.fov.az_center

    def at(self, theta: float) -> "RadarTrackerSensor":
        """Set the GMST (rad) of the next scan; returns ``self``."""
        self.theta = float(check_finite_array(theta, "theta", ndim=0))
        return self

    def returns(self, Z) -> np.ndarray:
        """The scan's returns as the trackers take them: ``(m, 4)`` as measured (the sensor frame); a flat
        sequence of ``4m`` numbers is read as ``m`` returns, any other shape is refused."""
        Z = np.asarray(Z, dtype=float)
        if Z.size == 0:  # an empty scan, however it is shaped
            Z = Z.reshape(0, 4)
        elif Z.ndim == 1 and Z.size % 4 == 0:  # a flat list: four numbers per return
            Z = Z.reshape(-1, 4)
        return check_finite_array(Z, "Z", shape=(None, 4))

    def h(self, x) -> np.ndarray:
        """Noise-free returns ``(n, 4)`` of TEME states ``(n, 6)`` at the current GMST."""
        return rae_rate(x, self.radar.site, self.theta, az_center=self.az_center)

    def jacobian(self, x) -> np.ndarray:
        """``∂h/∂x`` ``(n, 4, 6)`` at TEME states ``(n, 6)``."""
        return rae_rate_jacobian(x, self.radar.site, self.theta)

    def covariances(self, Z) -> np.ndarray:
        """Measurement covariance ``(m, 4, 4)`` of each return of ``Z`` ``(m, 4)``."""
        m = len(np.atleast_2d(Z))
        return np.broadcast_to(self.R, (m, 4, 4)).copy()

    @staticmethod
    def innovation(z, z_pred) -> np.ndarray:
        """``z − z_pred`` (broadcast) with the azimuth difference wrapped into ``[−π, π)``."""
        nu = np.asarray(z, dtype=float) - np.asarray(z_pred, dtype=float)
        nu[..., 1] = wrap_angle(nu[..., 1])
        return nu

    def sample_returns(self, x, rng) -> np.ndarray:
        """Noisy returns ``(n, 4)`` of TEME states ``(n, 6)`` (every state detected; azimuth re-wrapped)."""
        z = self.h(x) + rng.standard_normal((len(np.atleast_2d(x)), 4)) * np.sqrt(np.diag(self.R))
        z[:, 1] = wrap_angle(z[:, 1], self.az_center)
        return z

    def update(self, x, P, z):
        """Extended-Kalman update of states ``x`` ``(n, 6)``, covariances ``P`` ``(n, 6, 6)`` with one return
        ``z`` ``(4,)`` each (``(n, 4)``): Joseph form, the innovation's azimuth wrapped.

        Returns ``(x⁺ (n, 6), P⁺ (n, 6, 6), loglik (n,))`` with ``loglik = log N(ν; 0, S)``."""
        X = _states(x)
        P = np.asarray(P, dtype=float).reshape(len(X), 6, 6)
        Z = np.broadcast_to(np.asarray(z, dtype=float), (len(X), 4))
        Hj = self.jacobian(X)
        nu = self.innovation(Z, self.h(X))
        S = Hj @ P @ np.swapaxes(Hj, 1, 2) + self.R
        K = np.swapaxes(np.linalg.solve(S, Hj @ P), 1, 2)
        IKH = np.eye(6) - K @ Hj
        P_new = IKH @ P @ np.swapaxes(IKH, 1, 2) + K @ self.R @ np.swapaxes(K, 1, 2)
        x_new = X + np.einsum("nij,nj->ni", K, nu)
        L = np.linalg.cholesky(S)
        y = np.linalg.solve(L, nu[..., None])[..., 0]
        ll = -0.5 * np.sum(y * y, axis=1) - np.sum(np.log(np.diagonal(L, axis1=1, axis2=2)), axis=1) \
            - 2.0 * np.log(2 * np.pi)
        return x_new, 0.5 * (P_new + np.swapaxes(P_new, 1, 2)), ll

"""Ground-based surveillance radars: site, field of view, detection, noise and clutter.

The default sensor (:data:`DEFAULT_RADAR`) is one face of a UHF phased-array surveillance radar, the
class of the PAVE PAWS / BMEWS radars and of the commercial space-surveillance arrays (the numbers
below are typical of that class, not any one radar's specification):

* **site**: geodetic 45° N, 0° E, 0.1 km (WGS-84) — a mid-latitude site, face towards the equator;
* **field of view**: azimuth 180° ± 60° (a planar array scans ±60° off its boresight), elevation
  5°–85° (5° horizon mask; near the zenith azimuth is ill-conditioned), range 200–3,000 km (200 km:
  transmit blanking; 3,000 km: detection limit for ~10-cm debris at UHF, so LEO only);
* **revisit**: the face's surveillance frame is revisited every 10 s; the scan is treated as
  instantaneous (all returns at the scan time);
* **measurement**: ``z = (range, azimuth, elevation)`` in km, rad, rad with independent Gaussian
  errors σ_r = 0.03 km (30 m), σ_az = σ_el = 0.05° (0.87 mrad, ≈ 1.3 km across the beam at 1,500 km);
  azimuth is reported in ``[c − 180°, c + 180°)`` around the face's centre c, so it never wraps
  inside the field of view. Alternatively (``measurement="enu"``) the local east-north-up position
  with isotropic Gaussian error σ_enu (km);
* **detection**: every object inside the field of view is detected with p_D = 0.9, independently;
  nothing outside it is (a detected object's noisy return may fall just outside the field of view);
  optionally (``snr``, :mod:`.snr`) each object's p_D is instead the Swerling I p_D of its size at its
  range (radar equation, SNR ∝ RCS/r⁴), given object sizes (:func:`.simulate_catalogue`'s ``sizes``);
* **clutter**: Poisson, 2 false returns per scan on average, uniform over the field of view in
  measurement space — over the box ``[r_min, r_max] × [az sector] × [el band]`` (density
  ``1/V``, V in km·rad²) for RAE, over the physical volume (V in km³) for ENU.

Line of sight: an object above the site's horizon (elevation > 0) is never behind the Earth, so
the field of view's elevation floor (≥ 0) is the whole visibility test besides range.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..._validation import check_finite_array, check_nonnegative, check_positive, check_probability
from .fov_kernels import fov_decide
from .frames import ef_to_rae, enu_matrix, geodetic_to_ef, local_to_rae, rae_to_enu, wrap_angle
from .snr import SnrModel

__all__ = ["GroundSite", "RadarFieldOfView", "GroundRadar", "DEFAULT_SITE", "DEFAULT_RADAR", "MEASUREMENTS"]

MEASUREMENTS = ("rae", "enu", "rae_rate")


def _in_range(value, name, lo, hi, *, lo_open=False, hi_open=False):
    v = float(check_finite_array(value, name, ndim=0))
    ok = (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        b = ("(" if lo_open else "[") + f"{lo:g}, {hi:g}" + (")" if hi_open else "]")
        raise ValueError(f"{name} must lie in {b}, got {value!r}")
    return v


def _rows3(a, name):
    """``a`` as ``(n, 3)`` rows: an ``(n, 3)`` array or one ``(3,)`` position; any other shape is refused
    (a reshape would silently regroup the numbers of ``(n, 2)`` rows into other rows). NaN rows stay."""
    arr = np.asarray(a, dtype=float)
    if arr.ndim == 1 and arr.shape == (3,):
        return arr[None]
    if arr.ndim == 2 and arr.shape[1] == 3 or arr.size == 0:
        return arr.reshape(-1, 3)
    raise ValueError(f"{name} must have shape (n, 3) (one row of three coordinates per object), got {arr.shape}")


@dataclass(frozen=True)
class GroundSite:
    """A sensor site: geodetic latitude and longitude (degrees, WGS-84) and height (km)."""

    lat_deg: float
    lon_deg: float
    alt_km: float = 0.0
    name: str = ""

    def __post_init__(self):
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731 (frozen dataclass)
        set_("lat_deg", _in_range(self.lat_deg, "lat_deg", -90.0, 90.0))
        set_("lon_deg", _in_range(self.lon_deg, "lon_deg", -180.0, 360.0, hi_open=True))
        set_("alt_km", _in_range(self.alt_km, "alt_km", -0.5, 10.0))
        set_("_ef", geodetic_to_ef(self.lat_deg, self.lon_deg, self.alt_km))
        set_("_enu", enu_matrix(self.lat_deg, self.lon_deg))

    @property
    def ef(self) -> np.ndarray:
        """Earth-fixed position (km)."""
        return self._ef

    @property
    def enu(self) -> np.ndarray:
        """(3, 3): rows east, north, up (Earth-fixed unit vectors)."""
        return self._enu


@dataclass(frozen=True)
class RadarFieldOfView:
    """Azimuth sector × elevation band × range interval, as seen from the site.

    Parameters
    ----------
    az_center_deg : float
        Centre of the azimuth sector (degrees from north towards east), in [−180, 360).
    az_width_deg : float
        Width of the sector, in (0, 360].
    el_min_deg, el_max_deg : float
        Elevation band, ``0 <= el_min < el_max <= 90`` (a narrow band makes a fence).
    r_min_km, r_max_km : float
        Range interval, ``0 <= r_min < r_max``.
    """

    az_center_deg: float = 180.0
    az_width_deg: float = 120.0
    el_min_deg: float = 5.0
    el_max_deg: float = 85.0
    r_min_km: float = 200.0
    r_max_km: float = 3000.0

    def __post_init__(self):
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        set_("az_center_deg", _in_range(self.az_center_deg, "az_center_deg", -180.0, 360.0, hi_open=True))
        set_("az_width_deg", _in_range(self.az_width_deg, "az_width_deg", 0.0, 360.0, lo_open=True))
        set_("el_min_deg", _in_range(self.el_min_deg, "el_min_deg", 0.0, 90.0, hi_open=True))
        set_("el_max_deg", _in_range(self.el_max_deg, "el_max_deg", self.el_min_deg, 90.0, lo_open=True))
        set_("r_min_km", check_nonnegative(self.r_min_km, "r_min_km"))
        r_max = check_positive(self.r_max_km, "r_max_km")
        if not r_max > self.r_min_km:
            raise ValueError(f"r_max_km must be > r_min_km = {self.r_min_km} km, got {self.r_max_km!r}")
        set_("r_max_km", r_max)

    @property
    def az_center(self) -> float:
        """Sector centre (rad); azimuths are reported in ``[az_center − π, az_center + π)``."""
        return np.deg2rad(self.az_center_deg)

    @property
    def low(self) -> np.ndarray:
        """Lower corner of the field of view in measurement space ``(r, az, el)`` (km, rad, rad)."""
        h = np.deg2rad(self.az_width_deg) / 2
        return np.array([self.r_min_km, self.az_center - h, np.deg2rad(self.el_min_deg)])

    @property
    def high(self) -> np.ndarray:
        h = np.deg2rad(self.az_width_deg) / 2
        return np.array([self.r_max_km, self.az_center + h, np.deg2rad(self.el_max_deg)])

    @property
    def measurement_volume(self) -> float:
        """``Δr Δaz Δel`` (km·rad²): the clutter density of RAE measurements is its inverse."""
        return float(np.prod(self.high - self.low))

    @property
    def physical_volume(self) -> float:
        """``Δaz (sin el_max − sin el_min) (r_max³ − r_min³) / 3`` (km³)."""
        lo, hi = self.low, self.high
        return float((hi[1] - lo[1]) * (np.sin(hi[2]) - np.sin(lo[2])) * (hi[0] ** 3 - lo[0] ** 3) / 3)

    def contains(self, rae) -> np.ndarray:
        """Mask of the ``(n, 3)`` (range, az, el) points inside (edges included; NaN rows are not).

        Azimuths may be given in any 2π window.
        """
        p = np.asarray(rae, dtype=float).reshape(-1, 3)
        off = wrap_angle(p[:, 1] - self.az_center)
        in_az = np.abs(off) <= np.deg2rad(self.az_width_deg) / 2 if self.az_width_deg < 360 else True
        with np.errstate(invalid="ignore"):
            return (
                (p[:, 0] >= self.r_min_km)
                & (p[:, 0] <= self.r_max_km)
                & (p[:, 2] >= np.deg2rad(self.el_min_deg))
                & (p[:, 2] <= np.deg2rad(self.el_max_deg))
                & in_az
            )

    def sample_rae(self, n: int, rng) -> np.ndarray:
        """``n`` points uniform over the measurement-space box, ``(n, 3)`` (r, az, el)."""
        return rng.uniform(self.low, self.high, size=(n, 3))

    def sample_enu(self, n: int, rng) -> np.ndarray:
        """``n`` points uniform over the physical volume, as local ENU ``(n, 3)`` (km).

        ``r = cbrt(U(r_min³, r_max³))``, ``az ~ U``, ``sin el ~ U(sin el_min, sin el_max)``.
        """
        lo, hi = self.low, self.high
        r = np.cbrt(rng.uniform(lo[0] ** 3, hi[0] ** 3, n))
        az = rng.uniform(lo[1], hi[1], n)
        el = np.arcsin(rng.uniform(np.sin(lo[2]), np.sin(hi[2]), n))
        return rae_to_enu(np.column_stack([r, az, el]))


DEFAULT_SITE = GroundSite(45.0, 0.0, 0.1, "mid-latitude site")


@dataclass(frozen=True, eq=False)
class GroundRadar:
    """A ground surveillance radar (module docstring for the model and its default numbers).

    Parameters
    ----------
    site : GroundSite
    fov : RadarFieldOfView
    revisit_s : float
        Scan (revisit) interval (s), > 0.
    sigma_range_km, sigma_az_deg, sigma_el_deg : float
        Standard deviations of the RAE errors, > 0.
    p_D : float
        Detection probability inside the field of view, in (0, 1].
    clutter_rate : float
        Expected false returns per scan, >= 0.
    measurement : {"rae", "enu", "rae_rate"}
        What a return is: (range km, azimuth rad, elevation rad), local (east, north, up) km, or
        (range, azimuth, elevation, range-rate km/s) — the documented radar of
        :mod:`.radar_model` (range-rate from the Doppler shift; its σ derived there).
    sigma_enu_km : float
        Standard deviation of each ENU component (``measurement="enu"`` only), > 0.
    name : str
    snr : hypotrack.scenarios.catalogue.snr.SnrModel, optional
        SNR detection model: with it (and object sizes, :func:`.simulate_catalogue`'s ``sizes``) each
        object's p_D is the Swerling I ``p_D`` of its size at its range (:mod:`.snr`) in place of ``p_D``.
    sigma_range_rate_km_s : float
        Standard deviation of the range-rate (``measurement="rae_rate"`` only), > 0; default 0.01 (10 m/s,
        :data:`.radar_model.SIGMA_RANGE_RATE_KM_S`).
    range_rate_span_km_s : float
        Clutter range-rates are uniform over ``[−span, span]`` (``"rae_rate"`` only), > 0; default 8.
    """

    site: GroundSite = DEFAULT_SITE
    fov: RadarFieldOfView = field(default_factory=RadarFieldOfView)
    revisit_s: float = 10.0
    sigma_range_km: float = 0.03
    sigma_az_deg: float = 0.05
    sigma_el_deg: float = 0.05
    p_D: float = 0.9
    clutter_rate: float = 2.0
    measurement: str = "rae"
    sigma_enu_km: float = 1.0
    name: str = "UHF phased-array face"
    snr: object = None
    sigma_range_rate_km_s: float = 0.01
    range_rate_span_km_s: float = 8.0

    def __post_init__(self):
        if not isinstance(self.site, GroundSite):
            raise TypeError(f"site must be a GroundSite, got {type(self.site).__name__}")
        if not isinstance(self.fov, RadarFieldOfView):
            raise TypeError(f"fov must be a RadarFieldOfView, got {type(self.fov).__name__}")
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731
        for name in ("revisit_s", "sigma_range_km", "sigma_az_deg", "sigma_el_deg", "sigma_enu_km",
                     "sigma_range_rate_km_s", "range_rate_span_km_s"):
            set_(name, check_positive(getattr(self, name), name))
        set_("p_D", check_probability(self.p_D, "p_D", low_open=True))
        set_("clutter_rate", check_nonnegative(self.clutter_rate, "clutter_rate"))
        if self.measurement not in MEASUREMENTS:
            raise ValueError(f"measurement must be one of {MEASUREMENTS}, got {self.measurement!r}")
        if self.snr is not None and not isinstance(self.snr, SnrModel):
            raise TypeError(f"snr must be an SnrModel or None, got {type(self.snr).__name__}")

    @property
    def R(self) -> np.ndarray:
        """Measurement-noise covariance (3, 3) in the measurement's units."""
        if self.measurement == "enu":
            return np.eye(3) * self.sigma_enu_km**2
        s = np.array([self.sigma_range_km, np.deg2rad(self.sigma_az_deg), np.deg2rad(self.sigma_el_deg)])
        if self.measurement == "rae_rate":
            s = np.r_[s, self.sigma_range_rate_km_s]
        return np.diag(s**2)

    @property
    def clutter_density(self) -> float:
        """``g(z) = 1/V`` of one clutter return (per km·rad² for RAE, per km³ for ENU)."""
        v = self.fov.physical_volume if self.measurement == "enu" else self.fov.measurement_volume
        if self.measurement == "rae_rate":
            v *= 2 * self.range_rate_span_km_s
        return 1.0 / v

    def rae(self, r_ef) -> np.ndarray:
        """Range, azimuth, elevation ``(..., 3)`` of Earth-fixed positions ``(..., 3)``."""
        return ef_to_rae(r_ef, self.site.ef, self.site.enu, self.fov.az_center)

    def in_view(self, r_ef) -> np.ndarray:
        """Mask ``(...)`` of the Earth-fixed positions ``(..., 3)`` inside the field of view (NaN: no)."""
        r_ef = np.asarray(r_ef, dtype=float)
        loc = (r_ef - self.site.ef) @ self.site.enu.T  # as ef_to_rae
        f = self.fov
        # Only points below the maximum range (and above the horizon when the field of view is) can be
        # inside: their angles alone are computed, each row as ef_to_rae would (the same decisions).
        near = np.sum(loc * loc, axis=-1) <= (f.r_max_km * (1 + 1e-9)) ** 2
        if f.el_min_deg > 0:
            near &= loc[..., 2] > 0
        return self.in_view_local(loc, near)

    def in_view_local(self, loc, near) -> np.ndarray:
        """:meth:`in_view` of local east-north-up points ``loc`` ``(..., 3)`` of which only ``near`` (bool) may be
        inside (below the maximum range, and above the horizon when the field of view is): their angles alone tested."""
        f = self.fov
        if np.ndim(loc) == 2:  # one compiled pass decides all but the points at a bound (:mod:`.fov_kernels`)
            code = fov_decide(loc, near, f.r_min_km, f.r_max_km, np.deg2rad(f.el_min_deg), np.deg2rad(f.el_max_deg),
                              f.az_center, np.deg2rad(f.az_width_deg) / 2, f.az_width_deg >= 360)
            out = code == 1
            hard = np.flatnonzero(code == 2)
            if len(hard):  # those the array passes decide themselves
                out[hard] = f.contains(local_to_rae(np.asarray(loc, dtype=float)[hard], f.az_center))
            return out
        out = np.zeros(loc.shape[:-1], dtype=bool)
        out[near] = f.contains(local_to_rae(loc[near], f.az_center))
        return out

    def observe_rae(self, rae, rng, p_detect=None):
        """One scan, given the true (range, az, el) ``(n, 3)`` of the objects inside the field of view
        (``p_detect`` ``(n,)``: each object's p_D, default :attr:`p_D` for all).

        Random draws, in order: detections (n uniforms), measurement noise of the detected,
        the clutter count and positions, the shuffle of the returns.

        Returns
        -------
        Z : (m, 3) returns; origin : (m,) row of ``rae`` that produced each, or −1 (clutter).
        """
        if self.measurement == "rae_rate":  # (range, az, el, range-rate) rows
            rae = np.asarray(rae, dtype=float)
            if not (rae.ndim == 2 and rae.shape[1] == 4 or rae.size == 0):
                raise ValueError(f"rae must have shape (n, 4) (range, azimuth, elevation, range-rate) for a "
                                 f"'rae_rate' radar, got {rae.shape}")
            rae = rae.reshape(-1, 4)
        else:
            rae = _rows3(rae, "rae")
        det = rng.uniform(size=len(rae)) < (self.p_D if p_detect is None else np.asarray(p_detect, dtype=float))
        true = rae[det]
        if self.measurement == "enu":
            Z_t = rae_to_enu(true) + rng.standard_normal(true.shape) * self.sigma_enu_km
        else:
            Z_t = true + rng.standard_normal(true.shape) * np.sqrt(np.diag(self.R))
            Z_t[:, 1] = wrap_angle(Z_t[:, 1], self.fov.az_center)
        k = int(rng.poisson(self.clutter_rate))
        Z_c = self.fov.sample_enu(k, rng) if self.measurement == "enu" else self.fov.sample_rae(k, rng)
        if self.measurement == "rae_rate":
            Z_c = np.column_stack([Z_c, rng.uniform(-self.range_rate_span_km_s, self.range_rate_span_km_s, k)])
        Z = np.vstack([Z_t, Z_c])
        origin = np.concatenate([np.flatnonzero(det), np.full(k, -1)]).astype(np.int64)
        order = rng.permutation(len(Z))
        return Z[order], origin[order]

    def observe(self, r_ef, rng):
        """One scan of Earth-fixed positions ``(n, 3)`` (NaN rows: absent objects).

        Returns ``(Z (m, 3), origin (m,))`` with ``origin`` the row index into ``r_ef`` or −1.
        """
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
        r_ef = _rows3(r_ef, "r_ef")
        rae = self.rae(r_ef)
        rows = np.flatnonzero(self.fov.contains(rae))
        Z, origin = self.observe_rae(rae[rows], rng)
        origin[origin >= 0] = rows[origin[origin >= 0]]
        return Z, origin

    # --- the tracker's side: measurement function of a TEME state ----------------------------

    def _no_rate(self, what):
        if self.measurement == "rae_rate":
            raise ValueError(f"{what} is the position-only model: a 'rae_rate' radar's is radar_model.rae_rate "
                             "(RadarTrackerSensor.h / .jacobian)")

    def _local(self, x_teme, theta):
        """ENU of TEME positions at GMST θ and the (3, 3) matrix d(ENU)/d(r_teme)."""
        c, s = np.cos(theta), np.sin(theta)
        R3 = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        M = self.site.enu @ R3
        r = np.atleast_2d(np.asarray(x_teme, dtype=float))[:, :3]
        return (r @ R3.T - self.site.ef) @ self.site.enu.T, M

    def h(self, x_teme, theta) -> np.ndarray:
        """Noise-free measurement ``(n, 3)`` of TEME states ``(n, >= 3)`` at GMST ``theta`` (rad)."""
        self._no_rate("h")
        loc, _ = self._local(x_teme, theta)
        if self.measurement == "enu":
            return loc
        rng = np.linalg.norm(loc, axis=1)
        az = wrap_angle(np.arctan2(loc[:, 0], loc[:, 1]), self.fov.az_center)
        return np.column_stack([rng, az, np.arcsin(loc[:, 2] / rng)])

    def h_jacobian(self, x_teme, theta) -> np.ndarray:
        """``∂h/∂x`` ``(n, 3, d)`` of TEME states ``(n, d)`` (d = 3 or 6; zero for velocities).

        RAE: ``∂ρ/∂l = l/ρ``, ``∂az/∂l = (n, −e, 0)/(e² + n²)``,
        ``∂el/∂l = (−e u, −n u, e² + n²) / (ρ² sqrt(e² + n²))`` with ``l = (e, n, u)``, chained with
        ``∂l/∂r_teme = E R3(θ)``.
        """
        self._no_rate("h_jacobian")
        X = np.atleast_2d(np.asarray(x_teme, dtype=float))
        loc, M = self._local(X, theta)
        n = len(X)
        if self.measurement == "enu":
            D = np.broadcast_to(np.eye(3), (n, 3, 3))
        else:
            e, nn, u = loc.T
            rho2 = np.sum(loc * loc, axis=1)
            rho = np.sqrt(rho2)
            hz2 = e * e + nn * nn
            hz = np.sqrt(hz2)
            D = np.empty((n, 3, 3))
            D[:, 0] = loc / rho[:, None]
            D[:, 1] = np.column_stack([nn / hz2, -e / hz2, np.zeros(n)])
            D[:, 2] = np.column_stack([-e * u, -nn * u, hz2]) / (rho2 * hz)[:, None]
        H = np.zeros((n, 3, X.shape[1]))
        H[:, :, :3] = D @ M
        return H


DEFAULT_RADAR = GroundRadar()
"""The default sensor (module docstring)."""

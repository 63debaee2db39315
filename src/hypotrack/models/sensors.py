"""Sensors: linear position measurements, fields of view, detection and Poisson clutter.

The pieces compose like Stone Soup's components, one responsibility each:

* :class:`LinearPositionSensor` — ``z = H x + v``, ``v ~ N(0, R)``;
* :class:`FieldOfView` (a polar wedge at the sensor, the origin) and :class:`Box` (an
  axis-aligned box) — regions with ``contains``, ``area`` and ``sample_uniform``;
* :class:`PoissonClutter` — a Poisson number of false returns per scan, uniform over a
  region, density ``g(z) = 1/V`` (document 000 Sec. II-B; document 001 Eq. 6–7);
* :class:`DetectionModel` — detection with probability ``p_D`` inside a region;
* :class:`Sensor` — all of the above: ``observe(states, rng) -> (Z, origin)``;
* :class:`SensorArray` — several sensors observing synchronously, one scan each.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validation import (
    check_covariance,
    check_finite_array,
    check_int,
    check_nonnegative,
    check_probability,
)

__all__ = [
    "LinearPositionSensor",
    "FieldOfView",
    "Box",
    "PoissonClutter",
    "DetectionModel",
    "Sensor",
    "SensorArray",
]


def _check_rng(rng) -> np.random.Generator:
    if not isinstance(rng, np.random.Generator):
        raise TypeError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    return rng


def _points(points, dim: int, name: str = "points") -> np.ndarray:
    arr = np.asarray(points, dtype=float)
    if arr.size == 0:
        return np.zeros((0, dim))
    if dim == 1 and arr.ndim == 1:
        arr = arr[:, None]
    return check_finite_array(arr, name, shape=(None, dim))


@dataclass(frozen=True, eq=False)
class LinearPositionSensor:
    """Linear Gaussian measurement of position components: ``z = H x + v``, ``v ~ N(0, R)``.

    Parameters
    ----------
    R : (p, p) array_like
        Measurement-noise covariance, symmetric positive definite.
    ndim_state : int
        State dimension ``d``.
    position_indices : sequence of int
        State components measured, in measurement order (default ``(0, 1)``: x, y).
    """

    R: np.ndarray
    ndim_state: int
    position_indices: tuple = (0, 1)

    def __post_init__(self):
        d = check_int(self.ndim_state, "ndim_state", minimum=1)
        idx = tuple(
            int(check_int(i, "position_indices", minimum=0, maximum=d - 1)) for i in self.position_indices
        )
        if not idx or len(set(idx)) != len(idx):
            raise ValueError(
                f"position_indices must be distinct indices in [0, {d - 1}], got {self.position_indices!r}"
            )
        R = np.atleast_2d(np.asarray(self.R, dtype=float))
        object.__setattr__(self, "ndim_state", d)
        object.__setattr__(self, "position_indices", idx)
        object.__setattr__(self, "R", check_covariance(R, "R", dim=len(idx)))
        H = np.zeros((len(idx), d))
        H[np.arange(len(idx)), idx] = 1.0
        object.__setattr__(self, "H", H)
        object.__setattr__(self, "_chol_R", np.linalg.cholesky(self.R))

    @property
    def dim(self) -> int:
        """Measurement dimension ``p``."""
        return len(self.position_indices)

    def positions(self, states) -> np.ndarray:
        """Noise-free measured components ``H x`` of states ``(n, d)`` -> ``(n, p)``."""
        return _points(states, self.ndim_state, "states") @ self.H.T

    def measure(self, states, rng) -> np.ndarray:
        """Noisy measurements ``H x + v`` of states ``(n, d)`` -> ``(n, p)``."""
        mean = self.positions(states)
        noise = _check_rng(rng).standard_normal(mean.shape) @ self._chol_R.T
        return mean + noise


def _wrap_deg(a):
    """Angles wrapped to [-180, 180)."""
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


@dataclass(frozen=True)
class FieldOfView:
    """A planar polar wedge with its apex at the sensor (the origin).

    Points with range ``r_min <= r <= r_max`` and polar angle within ``full_angle_deg / 2``
    of ``look_angle_deg`` (both measured from the +x axis, counter-clockwise) are inside.
    The defaults are document 000's sensor (look direction 15°, field of view 30°, Sec. IV-A)
    with the range limits of DESIGN.md §5 (km).

    Parameters
    ----------
    look_angle_deg : float
        Direction of the wedge's axis (degrees).
    full_angle_deg : float
        Opening angle, in (0, 360] degrees.
    r_min, r_max : float
        Range limits, ``0 <= r_min < r_max < inf``.
    """

    look_angle_deg: float = 15.0
    full_angle_deg: float = 30.0
    r_min: float = 6578.0
    r_max: float = 30000.0

    def __post_init__(self):
        look = check_finite_array(self.look_angle_deg, "look_angle_deg", ndim=0)
        full = check_nonnegative(self.full_angle_deg, "full_angle_deg")
        if not 0.0 < full <= 360.0:
            raise ValueError(f"full_angle_deg must lie in (0, 360], got {self.full_angle_deg!r}")
        r_min = check_nonnegative(self.r_min, "r_min")
        r_max = check_nonnegative(self.r_max, "r_max")
        if not r_max > r_min:
            raise ValueError(f"r_max must be > r_min = {r_min}, got {self.r_max!r}")
        object.__setattr__(self, "look_angle_deg", float(look))
        object.__setattr__(self, "full_angle_deg", full)
        object.__setattr__(self, "r_min", r_min)
        object.__setattr__(self, "r_max", r_max)

    dim = 2

    @property
    def angle_limits_deg(self) -> tuple[float, float]:
        """The wedge's bounding polar angles (degrees), ``look ∓ full/2``."""
        h = self.full_angle_deg / 2
        return self.look_angle_deg - h, self.look_angle_deg + h

    @property
    def area(self) -> float:
        """Area ``(θ_full / 2) (r_max² − r_min²)`` with ``θ_full`` in radians."""
        return np.deg2rad(self.full_angle_deg) / 2 * (self.r_max**2 - self.r_min**2)

    def contains(self, points) -> np.ndarray:
        """Boolean mask ``(n,)``: which of ``points (n, 2)`` lie in the wedge (edges included)."""
        p = _points(points, 2)
        r = np.hypot(p[:, 0], p[:, 1])
        off = _wrap_deg(np.rad2deg(np.arctan2(p[:, 1], p[:, 0])) - self.look_angle_deg)
        in_angle = (
            np.abs(off) <= self.full_angle_deg / 2 if self.full_angle_deg < 360 else np.ones(len(p), bool)
        )
        return (r >= self.r_min) & (r <= self.r_max) & in_angle

    def sample_uniform(self, n: int, rng) -> np.ndarray:
        """``n`` points uniform over the wedge's area, shape ``(n, 2)``.

        The range is drawn as ``sqrt(U(r_min², r_max²))`` (area grows with r²) and the
        angle uniformly.
        """
        n = check_int(n, "n", minimum=0)
        rng = _check_rng(rng)
        r = np.sqrt(rng.uniform(self.r_min**2, self.r_max**2, n))
        lo, hi = self.angle_limits_deg
        th = np.deg2rad(rng.uniform(lo, hi, n))
        return np.column_stack([r * np.cos(th), r * np.sin(th)])

    def split(self, n_regions: int) -> list["FieldOfView"]:
        """Split the wedge into ``n_regions`` sub-wedges of equal angle (same range limits).

        These are document 000's birth regions: the FOV divided into ``M_b`` parts (Sec. II-C).
        """
        k = check_int(n_regions, "n_regions", minimum=1)
        lo, _ = self.angle_limits_deg
        w = self.full_angle_deg / k
        return [FieldOfView(lo + (i + 0.5) * w, w, self.r_min, self.r_max) for i in range(k)]


@dataclass(frozen=True, eq=False)
class Box:
    """An axis-aligned box ``low <= z <= high`` in any dimension (a segment in 1-D).

    Parameters
    ----------
    low, high : array_like, shape (p,)
        Corners, with ``low < high`` componentwise.
    """

    low: np.ndarray
    high: np.ndarray

    def __post_init__(self):
        low = check_finite_array(np.atleast_1d(self.low), "low", ndim=1)
        high = check_finite_array(np.atleast_1d(self.high), "high", shape=low.shape)
        if not np.all(high > low):
            raise ValueError(f"high must exceed low in every component, got low={low}, high={high}")
        object.__setattr__(self, "low", low)
        object.__setattr__(self, "high", high)

    @property
    def dim(self) -> int:
        return self.low.shape[0]

    @property
    def area(self) -> float:
        """Volume (length, area, ...) of the box."""
        return float(np.prod(self.high - self.low))

    def contains(self, points) -> np.ndarray:
        p = _points(points, self.dim)
        return np.all((p >= self.low) & (p <= self.high), axis=1)

    def sample_uniform(self, n: int, rng) -> np.ndarray:
        n = check_int(n, "n", minimum=0)
        return _check_rng(rng).uniform(self.low, self.high, size=(n, self.dim))


def _check_region(region, name="region"):
    if not all(hasattr(region, a) for a in ("contains", "area", "sample_uniform", "dim")):
        raise TypeError(
            f"{name} must be a FieldOfView or Box (contains/area/sample_uniform), got {type(region).__name__}"
        )
    return region


@dataclass(frozen=True)
class PoissonClutter:
    """Poisson clutter: ``Poisson(rate)`` false returns per scan, uniform over ``region``.

    Parameters
    ----------
    rate : float
        Expected number of clutter returns per scan, λ ≥ 0 (document 001's ``λV``).
    region : FieldOfView or Box
        Where clutter appears.

    Attributes
    ----------
    density : float
        Spatial density of one clutter return, ``g(z) = 1 / V`` (document 000 Sec. II-B).
    intensity : float
        Clutter intensity ``λ / V`` (returns per unit area per scan).
    """

    rate: float
    region: object

    def __post_init__(self):
        object.__setattr__(self, "rate", check_nonnegative(self.rate, "rate"))
        _check_region(self.region)

    @property
    def dim(self) -> int:
        return self.region.dim

    @property
    def density(self) -> float:
        return 1.0 / self.region.area

    @property
    def intensity(self) -> float:
        return self.rate / self.region.area

    def sample(self, rng) -> np.ndarray:
        """One scan of clutter, shape ``(k, p)`` with ``k ~ Poisson(rate)``."""
        rng = _check_rng(rng)
        return self.region.sample_uniform(int(rng.poisson(self.rate)), rng)


@dataclass(frozen=True)
class DetectionModel:
    """Detection with probability ``p_D`` for targets inside ``fov`` (never outside it).

    Parameters
    ----------
    p_D : float
        Detection probability in (0, 1].
    fov : FieldOfView or Box, optional
        Region of the measured components in which targets can be detected; ``None``
        means everywhere.
    """

    p_D: float
    fov: object = None

    def __post_init__(self):
        object.__setattr__(self, "p_D", check_probability(self.p_D, "p_D", low_open=True))
        if self.fov is not None:
            _check_region(self.fov, "fov")

    def in_view(self, positions) -> np.ndarray:
        """Boolean mask of which noise-free measured positions ``(n, p)`` are in view."""
        p = np.asarray(positions, dtype=float)
        n = 0 if p.size == 0 else len(p)
        return np.ones(n, bool) if self.fov is None else self.fov.contains(p)

    def detect(self, positions, rng) -> np.ndarray:
        """Boolean mask of detected targets: in view and a Bernoulli(p_D) success."""
        inside = self.in_view(positions)
        return inside & (_check_rng(rng).uniform(size=inside.shape) < self.p_D)


@dataclass(frozen=True)
class Sensor:
    """A sensor: measurement model, detection model and (optional) clutter together.

    Parameters
    ----------
    measurement : LinearPositionSensor
    detection : DetectionModel
    clutter : PoissonClutter, optional
    """

    measurement: LinearPositionSensor
    detection: DetectionModel
    clutter: PoissonClutter | None = None

    def __post_init__(self):
        if not isinstance(self.measurement, LinearPositionSensor):
            raise TypeError("measurement must be a LinearPositionSensor")
        if not isinstance(self.detection, DetectionModel):
            raise TypeError("detection must be a DetectionModel")
        if self.clutter is not None:
            if not isinstance(self.clutter, PoissonClutter):
                raise TypeError("clutter must be a PoissonClutter or None")
            if self.clutter.dim != self.measurement.dim:
                raise ValueError(
                    f"clutter region is {self.clutter.dim}-D but measurements are {self.measurement.dim}-D"
                )

    @property
    def dim(self) -> int:
        return self.measurement.dim

    def in_view(self, states) -> np.ndarray:
        """Which states ``(n, d)`` lie in the field of view."""
        return self.detection.in_view(self.measurement.positions(states))

    def observe(self, states, rng):
        """One scan of the targets ``states (n, d)``.

        Each target inside the FOV is detected with probability ``p_D`` and measured with
        noise; clutter returns are added; the returns are shuffled so their order carries
        no information. Random draws, in order: detections, measurement noise, clutter
        count and positions, the shuffle.

        Returns
        -------
        Z : (m, p) array of returns.
        origin : (m,) int array — row index into ``states`` of each return's target, or
            −1 for clutter.
        """
        rng = _check_rng(rng)
        X = _points(states, self.measurement.ndim_state, "states")
        detected = self.detection.detect(self.measurement.positions(X), rng)
        Z_t = self.measurement.measure(X[detected], rng)
        Z_c = self.clutter.sample(rng) if self.clutter is not None else np.zeros((0, self.dim))
        Z = np.vstack([Z_t, Z_c])
        origin = np.concatenate([np.flatnonzero(detected), np.full(len(Z_c), -1)]).astype(np.int64)
        order = rng.permutation(len(Z))
        return Z[order], origin[order]


@dataclass(frozen=True)
class SensorArray:
    """Synchronous sensors: at each scan time every sensor produces one scan."""

    sensors: tuple = field(default_factory=tuple)

    def __post_init__(self):
        sensors = tuple(self.sensors)
        if not sensors:
            raise ValueError("sensors must hold at least one Sensor")
        for i, s in enumerate(sensors):
            if not isinstance(s, Sensor):
                raise TypeError(f"sensors[{i}] must be a Sensor, got {type(s).__name__}")
        object.__setattr__(self, "sensors", sensors)

    def __len__(self) -> int:
        return len(self.sensors)

    def observe(self, states, rng) -> list:
        """One scan per sensor, in sensor order: a list of ``(Z, origin)`` pairs."""
        rng = _check_rng(rng)
        return [s.observe(states, rng) for s in self.sensors]

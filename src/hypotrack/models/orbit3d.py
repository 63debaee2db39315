"""Three-dimensional two-body orbit model for tracking real catalogue objects, EKF-ready.

State ``x = [x, y, z, vx, vy, vz]`` in km and km/s, in a quasi-inertial Earth-centred frame (TEME,
the frame of SGP4's output, :mod:`hypotrack.scenarios.catalogue`).

Propagation is the exact Keplerian solution — Kepler's equation in the universal variable and the
Lagrange coefficients, the same kernel as the planar :class:`hypotrack.models.orbit.TwoBodyOrbit`
(which is dimension-free: f and g multiply the position and velocity vectors) — and the
state-transition matrix ``Φ = ∂x(t + Δt)/∂x(t)`` is its complex-step derivative, exact to rounding.
:func:`integrate_variational_3d` (DOP853 on the equations of motion and the variational equations)
is the independent reference the tests check both against.

What it neglects relative to the SGP4 truth
-------------------------------------------
Everything but the central term of the Earth's gravity: the zonal harmonics J2 (dominant: a
perturbing acceleration ≈ (3/2) J2 μ R_E²/r⁴ ≈ 1.2e-5 km/s² ≈ 0.012 m/s² in LEO), J3, J4, atmospheric
drag (B*; ~1e-6 m/s² at 400 km, 10⁻⁴ of J2) and, for deep-space objects, the Moon and Sun. A two-body
prediction started from the SGP4 state therefore drifts from SGP4 as ``½ a_pert Δt²`` at first.
Measured over one scan interval of the default radar (Δt = 10 s), from the SGP4 TEME state of
every LEO object (perigee ≥ 200 km, apogee ≤ 2,000 km) of the bundled catalogues at its own
catalogue's epoch — 10,088 objects: 6,035 active satellites and 4,053 debris fragments
(:func:`hypotrack.scenarios.catalogue.benchmark.two_body_mismatch`):

* Δt = 10 s — position error median 0.66 m, 99th percentile 2.5 m, max 5.8 m; velocity error
  median 0.11 m/s, max 0.25 m/s (the active satellites alone: median 0.62 m, max 5.8 m);
* Δt = 60 s — position error median 21 m, 99th percentile 41 m, max 46 m; velocity error median
  0.69 m/s, max 1.5 m/s. The ratio of the 20-s to the 10-s error is 3.95 (median): the Δt² law of a
  missing acceleration (½ · 0.0115 m/s² · Δt² = 0.58 m at 10 s, 21 m at 60 s). The largest errors
  are on eccentric orbits (e ≈ 0.04–0.06), where SGP4's periodic terms are largest.

These are far below the default radar's noise (30 m in range, ~1 km across the beam), so the
process noise need only cover them. White acceleration of intensity ``q`` gives one-scan standard
deviations ``sqrt(q Δt³/3)`` in position and ``sqrt(q Δt)`` in velocity; the default
``q = 1e-8 km²/s³`` gives 1.8 m and 0.32 m/s at Δt = 10 s (the 99th-percentile position mismatch is
1.4 σ, the worst 3.2 σ; every velocity mismatch is below 1 σ) and 27 m and 0.77 m/s at Δt = 60 s
(the median mismatch is 0.8 σ, the worst 1.7 σ in position and 2 σ in velocity).
The test ``test_two_body_one_scan_mismatch_against_sgp4`` holds these numbers (median in 0.4–0.9 m,
max < 8 m at 10 s, Δt² ratio in 3.6–4.4).

Over longer gaps the missing J2 dominates: after 1 h two-body drifts from SGP4 by a median 35 km
(2 h: 54 km). :class:`J2Orbit3D` is the remedy — the same protocol with the J2 acceleration, integrated
by RK4 (median 0.12 km after 1 h, 0.19 km after 2 h; its docstring) — for a tracker that must
re-acquire objects after an orbit out of view.
"""

from __future__ import annotations

import math

from dataclasses import dataclass

import numba
import numpy as np

from .._validation import check_finite_array, check_nonnegative, check_positive
from .orbit import _H_STEP, MU_EARTH, TwoBodyOrbit, _check_dt, _states, integrate_variational

__all__ = [
    "TwoBodyOrbit3D",
    "J2Orbit3D",
    "integrate_variational_3d",
    "DEFAULT_Q_3D",
    "MU_WGS72",
    "EARTH_RADIUS_WGS72",
    "FLATTENING_WGS72",
    "J2_WGS72",
]

DEFAULT_Q_3D = 1e-8
"""Default white-acceleration intensity (km²/s³): covers the 10-s mismatch against SGP4 (module docstring)."""


@dataclass(frozen=True)
class TwoBodyOrbit3D(TwoBodyOrbit):
    """Two-body motion ``r̈ = −μ r / |r|³`` in 3-D plus white acceleration noise (module docstring).

    The planar :class:`~hypotrack.models.orbit.TwoBodyOrbit` with a 3-D state ``[x, y, z, vx, vy, vz]``:
    its Kepler kernel, complex-step STM and white-acceleration ``Q`` are dimension-free. Follows the
    motion-model protocol of :mod:`hypotrack.models.motion` (``ndim``, ``propagate``, ``transition``,
    ``Q``); ``dt`` may be negative for :meth:`propagate` and :meth:`transition`, :meth:`Q` needs ``dt >= 0``.

    Parameters
    ----------
    mu : float
        Gravitational parameter (km³/s²), default Earth's (398600.4418).
    q : float
        Acceleration-noise intensity (km²/s³) ≥ 0; default :data:`DEFAULT_Q_3D`.
    """

    q: float = DEFAULT_Q_3D

    ndim = 6


def integrate_variational_3d(x0, dt, mu=MU_EARTH, *, rtol=1e-13, atol=1e-13):
    """DOP853 integration of the 3-D two-body equations and their variational equations: the slow,
    independent reference for :class:`TwoBodyOrbit3D` (:func:`~hypotrack.models.orbit.integrate_variational`
    with ``ndim=6``).

    Returns
    -------
    x : (6,) state at ``dt``; Phi : (6, 6).
    """
    return integrate_variational(x0, dt, mu, rtol=rtol, atol=atol, ndim=6)


MU_WGS72 = 398600.8
"""Earth's gravitational parameter μ (km³/s²) of WGS-72, the constant SGP4 uses (Vallado et al. 2006)."""

EARTH_RADIUS_WGS72 = 6378.135
"""Earth's equatorial radius (km) of WGS-72, SGP4's."""

J2_WGS72 = 0.001082616
"""Second zonal harmonic J2 of WGS-72, SGP4's."""

FLATTENING_WGS72 = 1.0 / 298.26
"""Earth's flattening f of WGS-72: the polar radius is ``R (1 − f)`` (6356.75 km)."""


def _j2_acceleration(r, mu, c_j2):
    """Two-body plus J2 acceleration of positions ``r`` ``(3, N)`` (real or complex);
    ``c_j2 = (3/2) J2 μ R²``.

    Only analytic operations (no ``abs``, no conjugation), so the complex step through it is exact.
    """
    x, y, z = r
    ir2 = 1.0 / (x * x + y * y + z * z)
    ir3 = ir2 * np.sqrt(ir2)  # 1/r³
    kj = c_j2 * ir2  # (3/2) J2 μ R²/r² : times x/r³ etc. gives the 1/r⁵ law
    s = 5.0 * z * z * ir2
    f = ir3 * (kj * (s - 1.0) - mu)
    a = r * f
    a[2] = z * (ir3 * (kj * (s - 3.0) - mu))
    return a


def _rk4_j2(X, dt, mu, c_j2, max_step):
    """Classical RK4 of ``r̈ = −μ r/r³ + a_J2(r)`` for rows ``X`` ``(N, 6)`` (real or complex), each by its
    own interval ``dt`` ``(N,)`` in ``n_i = ceil(|dt_i| / max_step)`` steps of ``dt_i / n_i``.

    A row's result does not depend on the other rows of the batch. The rows run together, longest
    first: step ``k`` advances only the rows with ``n_i > k`` (a prefix once sorted), so a batch costs
    ``Σ n_i`` row-steps in ``max n_i`` array passes — one row with a gap of hours does not make every
    other row take its many short steps."""
    n = np.ceil(np.abs(dt) / max_step).astype(np.int64)
    if not len(n) or n.max() == 0:
        return X.copy()
    if not np.iscomplexobj(X):  # the means alone (no complex step): one compiled pass, the same arithmetic
        h = np.asarray(dt, dtype=float) / np.maximum(n, 1)
        if np.all(n == n[0]) and np.all(h == h[0]):  # one interval for all (propagate): the rows side by side
            out = _rk4_j2_columns(np.ascontiguousarray(np.asarray(X, dtype=float).T), float(h[0]), int(n[0]), float(mu),
                                  float(c_j2))
            return np.ascontiguousarray(out.T)
        return _rk4_j2_real(np.ascontiguousarray(X, dtype=float), h, n, float(mu), float(c_j2))
    return _rk4_j2_arrays(X, dt, mu, c_j2, n)


def _rk4_j2_arrays(X, dt, mu, c_j2, n):
    """:func:`_rk4_j2` in array passes (real or complex rows; ``n`` the steps of each row)."""
    if not len(n) or n.max() == 0:
        return X.copy()
    order = np.argsort(-n, kind="stable")
    ns = n[order]
    h = np.asarray(dt, dtype=float)[order] / np.maximum(ns, 1)
    hh, h6 = h / 2, h / 6
    r = np.ascontiguousarray(X[order, :3].T)
    v = np.ascontiguousarray(X[order, 3:].T)
    active = np.searchsorted(-ns, -np.arange(ns[0]), side="left")  # rows with n_i > k, per step k
    for a in active:
        ri, vi, hk, hk2, hk6 = r[:, :a], v[:, :a], h[:a], hh[:a], h6[:a]
        a1 = _j2_acceleration(ri, mu, c_j2)
        v2 = vi + hk2 * a1
        a2 = _j2_acceleration(ri + hk2 * vi, mu, c_j2)
        v3 = vi + hk2 * a2
        a3 = _j2_acceleration(ri + hk2 * v2, mu, c_j2)
        v4 = vi + hk * a3
        a4 = _j2_acceleration(ri + hk * v3, mu, c_j2)
        r[:, :a] = ri + hk6 * (vi + 2 * (v2 + v3) + v4)
        v[:, :a] = vi + hk6 * (a1 + 2 * (a2 + a3) + a4)
    out = np.empty_like(X)
    out[order] = np.vstack([r, v]).T
    return out


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _j2_acceleration_xyz(x, y, z, mu, c_j2):
    """:func:`_j2_acceleration` of one real position, operation for operation (the same rounding)."""
    ir2 = 1.0 / (x * x + y * y + z * z)
    ir3 = ir2 * np.sqrt(ir2)
    kj = c_j2 * ir2
    s = 5.0 * z * z * ir2
    f = ir3 * (kj * (s - 1.0) - mu)
    return x * f, y * f, z * (ir3 * (kj * (s - 3.0) - mu))


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rk4_step(rx, ry, rz, vx, vy, vz, hk, hk2, hk6, mu, c_j2):
    """One RK4 step of ``hk`` (``hk2 = hk / 2``, ``hk6 = hk / 6``) of two-body motion plus J2 from one real state:
    the array passes' operations in their order (no reassociation, no fused multiply-add), written once for the
    kernels below; inlined, so a loop over rows still runs several rows in one vector instruction."""
    a1x, a1y, a1z = _j2_acceleration_xyz(rx, ry, rz, mu, c_j2)
    v2x, v2y, v2z = vx + hk2 * a1x, vy + hk2 * a1y, vz + hk2 * a1z
    a2x, a2y, a2z = _j2_acceleration_xyz(rx + hk2 * vx, ry + hk2 * vy, rz + hk2 * vz, mu, c_j2)
    v3x, v3y, v3z = vx + hk2 * a2x, vy + hk2 * a2y, vz + hk2 * a2z
    a3x, a3y, a3z = _j2_acceleration_xyz(rx + hk2 * v2x, ry + hk2 * v2y, rz + hk2 * v2z, mu, c_j2)
    v4x, v4y, v4z = vx + hk * a3x, vy + hk * a3y, vz + hk * a3z
    a4x, a4y, a4z = _j2_acceleration_xyz(rx + hk * v3x, ry + hk * v3y, rz + hk * v3z, mu, c_j2)
    return (rx + hk6 * (vx + 2 * (v2x + v3x) + v4x), ry + hk6 * (vy + 2 * (v2y + v3y) + v4y),
            rz + hk6 * (vz + 2 * (v2z + v3z) + v4z), vx + hk6 * (a1x + 2 * (a2x + a3x) + a4x),
            vy + hk6 * (a1y + 2 * (a2y + a3y) + a4y), vz + hk6 * (a1z + 2 * (a2z + a3z) + a4z))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _rk4_j2_real(X, h, n, mu, c_j2):
    """:func:`_rk4_j2` of real rows ``X`` (N, 6), row ``i`` in ``n[i]`` steps of ``h[i]``: the array passes'
    operations row by row in the same order, so bit for bit their result (no fast-math: no reassociation,
    no fused multiply-add), in one pass over the rows instead of ~30 array passes."""
    out = np.empty_like(X)
    for i in range(X.shape[0]):
        rx, ry, rz, vx, vy, vz = X[i, 0], X[i, 1], X[i, 2], X[i, 3], X[i, 4], X[i, 5]
        hk = h[i]
        hk2, hk6 = hk / 2, hk / 6
        for _ in range(n[i]):
            rx, ry, rz, vx, vy, vz = _rk4_step(rx, ry, rz, vx, vy, vz, hk, hk2, hk6, mu, c_j2)
        out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4], out[i, 5] = rx, ry, rz, vx, vy, vz
    return out


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _rk4_j2_columns(T, hk, n_steps, mu, c_j2):
    """:func:`_rk4_j2_real` of rows that all take ``n_steps`` steps of ``hk``, given as columns ``T`` (6, N): the same
    operations on each row, the rows' loop innermost, so that the compiler runs several rows in one vector
    instruction (each lane the row's own arithmetic, rounded alike: bit for bit :func:`_rk4_j2_real`; the one-step
    advance of a lane of 10⁴ means, every scan, ~3x faster)."""
    O = T.copy()
    hk2, hk6 = hk / 2, hk / 6
    rxa, rya, rza, vxa, vya, vza = O[0], O[1], O[2], O[3], O[4], O[5]
    for _ in range(n_steps):
        for i in range(O.shape[1]):
            rx, ry, rz, vx, vy, vz = rxa[i], rya[i], rza[i], vxa[i], vya[i], vza[i]
            rxa[i], rya[i], rza[i], vxa[i], vya[i], vza[i] = _rk4_step(rx, ry, rz, vx, vy, vz, hk, hk2, hk6, mu, c_j2)
    return O


_BLOCK = 64  # rows per block of :func:`_rk4_j2_rows`: six columns of it stay in the first-level cache


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _rk4_j2_rows(X, hk, n_steps, mu, c_j2):
    """:func:`_rk4_j2_columns` of rows ``X`` (N, 6) given as rows: each block of :data:`_BLOCK` rows copied into
    columns, stepped there by the same operations (bit for bit), written back as rows — no transposed copies of the
    whole batch — and whether every input and output value is finite (``(out, finite_in, finite_out)``)."""
    N = X.shape[0]
    out = np.empty((N, 6))
    T = np.empty((6, _BLOCK))
    finite_in = finite_out = True
    hk2, hk6 = hk / 2, hk / 6
    for b0 in range(0, N, _BLOCK):
        nb = min(_BLOCK, N - b0)
        for i in range(nb):
            for c in range(6):
                v = X[b0 + i, c]
                T[c, i] = v
                finite_in = finite_in and np.isfinite(v)
        rxa, rya, rza, vxa, vya, vza = T[0], T[1], T[2], T[3], T[4], T[5]
        for _ in range(n_steps):
            for i in range(nb):
                rx, ry, rz, vx, vy, vz = rxa[i], rya[i], rza[i], vxa[i], vya[i], vza[i]
                rxa[i], rya[i], rza[i], vxa[i], vya[i], vza[i] = _rk4_step(rx, ry, rz, vx, vy, vz, hk, hk2, hk6, mu,
                                                                           c_j2)
        for i in range(nb):
            for c in range(6):
                v = T[c, i]
                out[b0 + i, c] = v
                finite_out = finite_out and np.isfinite(v)
    return out, finite_in, finite_out


@dataclass(frozen=True)
class J2Orbit3D(TwoBodyOrbit3D):
    """Two-body motion plus the Earth's oblateness J2 by fixed-step RK4, plus white acceleration noise.

    Equations of motion (TEME, km, km/s; ``r = |r|``)::

        r̈ = −μ r / r³ + a_J2(r),
        a_J2 = (3/2) J2 μ R² / r⁵ · [x (5 z²/r² − 1), y (5 z²/r² − 1), z (5 z²/r² − 3)]

    (``a_J2 = −∇ V_J2`` with the J2 term of the geopotential ``V_J2 = μ J2 R² P₂(z/r) / r³``,
    ``P₂(s) = (3 s² − 1)/2``; Vallado, *Fundamentals of Astrodynamics*). Integrated by the classical
    fourth-order Runge–Kutta method with a fixed step: an interval ``Δt`` is cut into
    ``n = ceil(|Δt| / max_step)`` equal steps (:meth:`propagate_each`: each row ``i`` by its own
    ``n_i = ceil(|Δt_i| / max_step)`` steps, so a row's result does not depend on the rest of the batch;
    a zero interval leaves its row unchanged, a negative one integrates backwards).

    Constants. The defaults are those SGP4 uses — WGS-72: μ = 398600.8 km³/s², R = 6378.135 km,
    J2 = 0.001082616 (Vallado, Crawford, Hujsak & Kelso 2006, "Revisiting Spacetrack Report #3",
    AIAA 2006-6753; ``sgp4.earth_gravity.wgs72``), since the truth the model predicts is SGP4 (the
    bundled element sets are fitted with them). WGS-84/EGM-96 values (μ = 398600.4418, R = 6378.137,
    J2 = 1.08262668e-3) may be passed instead: they move the prediction by a median 59 m after 1 h
    and 86 m after 2 h, and leave it slightly further from SGP4 (below).

    State-transition matrix. ``Φ = ∂x(t + Δt)/∂x(t)`` is the complex-step derivative of the RK4 map itself
    (six perturbed copies of each state through the same integration, as the parent class does
    through the Kepler solution): the exact Jacobian of the discrete propagation, J2 included, and
    consistent with the mean to rounding (the mean is the real part of the same run, bit-identical to
    :meth:`propagate`). Measured for 100 LEO states (``time.perf_counter``, best of 200): over Δt = 10 s
    (one RK4 step) it costs 0.18 ms against 0.38 ms for the two-body complex-step Φ of
    :class:`TwoBodyOrbit3D` (0.33 against 0.39 ms over 60 s); its cost grows with the number of steps
    (10,000 states over intervals uniform in [0, 2 h]: 2.2 s against 0.10 s). The two-body Φ would differ from it
    by 2e-7 of ``‖Φ‖`` over 10 s, 6e-4 over 600 s and 1e-2 over one orbit (``tests/unit/models/test_orbit3d_j2.py``).

    Integration error. Against a DOP853 solution of the same equations (tolerances 1e-12), one orbit of
    a LEO state (a = 6,900–7,500 km, e = 0.01–0.05) ends 0.8–1.4 m off at the default step of 30 s,
    0.15–0.26 m at 20 s and 1–2 cm at 10 s (fourth order: ×16 per halving) — far below the distance
    to SGP4. Cost: 10,000 LEO states each propagated by its own interval, uniform in [0, 2 h], take 0.12 s at
    ``max_step = 30`` and 0.06 s at 60 (:meth:`propagate_each`; two-body: 6 ms).

    Against SGP4. Measured from the SGP4 TEME states of 1,000 LEO objects (a seeded sample, seed 1, of
    the bundled catalogue's objects with perigee ≥ 200 km and apogee ≤ 2,000 km: 607 active satellites,
    393 debris; each catalogue at its own epoch), propagated 1 h and 2 h and compared with SGP4 there —
    position error median 0.12 km, 90th percentile 0.90 km, max 6.1 km after 1 h; median 0.19 km, 90 %
    1.3 km, max 10 km after 2 h (the step hardly matters: the same to 0.01 km at 20 and 60 s). Two-body
    (:class:`TwoBodyOrbit3D`) from the same states: median 35 km, 90 % 94 km, max 122 km after 1 h;
    median 54 km, 90 % 136 km, max 172 km after 2 h. With the WGS-84 constants the J2 medians are
    0.13 and 0.19 km. The test ``test_j2_against_sgp4`` holds a 200-object sample to a 1-h median
    below 1 km and at least 10× below two-body's.

    What it still neglects: the zonal harmonics J3, J4 and higher (SGP4 carries J3 and J4), tesseral
    harmonics (SGP4 has none except deep-space resonances), atmospheric drag (SGP4's B*), the Moon and
    the Sun (SDP4's deep-space terms), and SGP4's own approximations (an analytic mean-element theory
    with truncated periodic terms), which the residual against SGP4 above also contains.

    Parameters
    ----------
    mu : float
        Gravitational parameter (km³/s²) > 0; default :data:`MU_WGS72`.
    q : float
        Acceleration-noise intensity (km²/s³) ≥ 0; default :data:`DEFAULT_Q_3D`.
    j2 : float
        Second zonal harmonic ≥ 0 (0 gives two-body motion, by RK4); default :data:`J2_WGS72`.
    radius : float
        Equatorial radius R (km) > 0 of the J2 term; default :data:`EARTH_RADIUS_WGS72`. A state that
        propagates to a non-finite one (at or through the Earth's centre, where the acceleration is
        singular) is refused (``ValueError``) instead of returning NaN. A state below the surface is
        propagated as the equations say: the trackers predict their own hypotheses with this model every
        scan, and an unresolved newborn hypothesis may fall below the surface before the data prune it; a
        tracker removes such hypotheses with a validity test (:mod:`hypotrack.models.plausibility`), the
        model does not stop the run.
    max_step : float
        Longest RK4 step (s) > 0; default 30.
    """

    mu: float = MU_WGS72
    j2: float = J2_WGS72
    radius: float = EARTH_RADIUS_WGS72
    max_step: float = 30.0

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "j2", check_nonnegative(self.j2, "j2"))
        object.__setattr__(self, "radius", check_positive(self.radius, "radius"))
        object.__setattr__(self, "max_step", check_positive(self.max_step, "max_step"))

    def _integrate(self, X, dt):
        return _rk4_j2(X, dt, self.mu, 1.5 * self.j2 * self.mu * self.radius**2, self.max_step)

    @staticmethod
    def _finite(X, out):
        """``out`` if every propagated row is finite; a row that is not came through the Earth's centre."""
        if np.isfinite(out).all():  # (one pass; the row is looked for only when there is one)
            return out
        bad = np.flatnonzero(~np.all(np.isfinite(out.reshape(len(X), -1)), axis=1)) if len(X) else []
        if len(bad):
            i = int(bad[0])
            r = float(np.linalg.norm(X[i, :3].real))
            raise ValueError(f"x: state {i} (position radius {r:.6g} km) propagates to a non-finite state: it is "
                             "at or falls through the Earth's centre, where the two-body + J2 acceleration is "
                             "singular")
        return out

    def _transition_rows(self, X, dt):
        """Means and Φ of rows ``X`` ``(n, 6)``, intervals ``dt`` ``(n,)``: complex step through the RK4."""
        d, n = self.ndim, len(X)
        if n == 0:
            return X.copy(), np.zeros((0, d, d))
        # row (k, j): object k with its component j perturbed by i·h
        Xc = np.repeat(X[:, None, :], d, axis=1).astype(complex)
        Xc[:, np.arange(d), np.arange(d)] += 1j * _H_STEP
        out = self._integrate(Xc.reshape(d * n, d), np.repeat(dt, d)).reshape(n, d, d)
        return out[:, 0, :].real.copy(), np.swapaxes(out.imag, 1, 2) / _H_STEP

    def propagate(self, x, dt) -> np.ndarray:
        """Propagate states ``(n, 6)`` (or one ``(6,)``) by ``dt`` seconds (any sign), RK4 with J2."""
        single = np.ndim(x) == 1
        try:
            dt = _check_dt(dt)
        except (TypeError, ValueError):
            _states(x, ndim=self.ndim)  # a bad x is reported first, as below
            raise
        n = int(math.ceil(abs(dt) / self.max_step))
        if (not single and n and isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == 2
                and x.shape[1] == self.ndim and len(x)):
            # a batch of rows (the lane's means each scan): one pass, no transposed copies nor separate checks of
            # the whole batch; a non-finite value goes the checked way below, which raises as it does
            out, finite_in, finite_out = _rk4_j2_rows(x, dt / n, n, float(self.mu),
                                                      float(1.5 * self.j2 * self.mu * self.radius**2))
            if finite_in and finite_out:
                return out
        X = _states(x, ndim=self.ndim)
        # one interval for every row: _rk4_j2's side-by-side pass, its step count and step (the same IEEE operations
        # on the one dt) computed once, not per row (the lane's means each scan: ~40% of the call at 10⁴ rows)
        with np.errstate(divide="ignore", invalid="ignore"):  # the centre is refused below, not warned about
            if n == 0 or len(X) == 0:
                out = X.copy()
            else:
                out = np.ascontiguousarray(_rk4_j2_columns(np.ascontiguousarray(X.T), dt / max(n, 1), n, float(self.mu),
                                                           float(1.5 * self.j2 * self.mu * self.radius**2)).T)
            out = self._finite(X, out)
        return out[0] if single else out

    def propagate_each(self, x, dt) -> np.ndarray:
        """States ``(n, 6)`` propagated by their own intervals ``dt`` ``(n,)`` (s) in one batch (see the
        class docstring)."""
        X = _states(x, ndim=self.ndim)
        dt = check_finite_array(np.asarray(dt, dtype=float), "dt", shape=(len(X),))
        with np.errstate(divide="ignore", invalid="ignore"):
            return self._finite(X, self._integrate(X, dt))

    def transition(self, x, dt):
        """Propagated states ``(n, 6)`` and their state-transition matrices ``(n, 6, 6)`` (class
        docstring)."""
        X = _states(x, ndim=self.ndim)
        dt = _check_dt(dt)
        with np.errstate(divide="ignore", invalid="ignore"):  # the centre is refused below, not warned about
            mean, phi = self._transition_rows(X, np.full(len(X), dt))
        return self._finite(X, mean), self._finite(X, phi)

    def replay_each(self, x, P, h, k):
        """EKF predictions of states ``(n, 6)`` and covariances ``(n, 6, 6)``, row ``i`` in ``k[i]`` steps of ``h[i]``
        s (each :meth:`transition`, ``P ← sym(Φ P Φᵀ + Q(h))``), all rows in one compiled pass
        (:func:`~.orbit3d_replay.replay_j2`: bit for bit the array passes where
        :func:`~.orbit3d_replay.rounds_as_numpy`, else the means bit for bit and the covariances to rounding)."""
        from .orbit3d_replay import replay_j2

        return replay_j2(self, x, P, h, k)

    def transition_each(self, x, dt):
        """:meth:`transition` with an interval per state, ``dt`` ``(n,)``, in one batch."""
        X = _states(x, ndim=self.ndim)
        dt = check_finite_array(np.asarray(dt, dtype=float), "dt", shape=(len(X),))
        with np.errstate(divide="ignore", invalid="ignore"):
            mean, phi = self._transition_rows(X, dt)
        return self._finite(X, mean), self._finite(X, phi)

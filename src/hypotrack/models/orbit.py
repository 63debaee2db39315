"""Planar two-body (Keplerian) orbit model for the SSA experiments, EKF-ready.

State ``x = [x, y, vx, vy]`` in km and km/s, inertial frame centred on the Earth.

Propagation solves the two-body problem *exactly*: Kepler's equation in the universal
variable χ (valid for every conic) by Newton's method, then the Lagrange coefficients
f, g, ḟ, ġ (Vallado, *Fundamentals of Astrodynamics*, 4th ed., Alg. 8; Curtis, *Orbital
Mechanics for Engineering Students*, §3.7). This is exact up to rounding, vectorised over
objects, and far cheaper than numerical integration — the hypothesis filters propagate
~100 tracks every scan for hundreds of scans.

The state-transition matrix ``Φ = ∂x(t)/∂x(0)`` is the exact derivative of that solution,
computed by complex-step differentiation (Squire & Trapp 1998; Martins, Sturdza & Alonso
2003): the four perturbed initial states ``x0 + i h e_j`` are propagated with complex
arithmetic and ``Φ[:, j] = Im x(t) / h``. With ``h = 1e-30`` there is no subtractive
cancellation, so Φ is accurate to machine precision — unlike finite differences. The
numerical solution of the variational equations ``Φ̇ = A(x) Φ`` (DESIGN.md §3) is kept as
:func:`integrate_variational` (scipy DOP853 at tight tolerances): the independent
reference the tests check both the propagation and Φ against.

Process noise is white acceleration of intensity ``q`` (km²/s³), discretised as for the
nearly-constant-velocity model (DESIGN.md §5); over a 60-s scan the gravity-gradient
coupling it ignores changes Q by a relative amount of order ``(n Δt)²`` ≲ 1e-2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .._validation import check_finite_array, check_nonnegative, check_positive
from .motion import ConstantVelocity

__all__ = [
    "MU_EARTH",
    "EARTH_RADIUS",
    "TwoBodyOrbit",
    "integrate_variational",
    "specific_energy",
    "angular_momentum",
    "orbital_period",
    "elements_to_state",
    "circular_velocity",
]

MU_EARTH = 398600.4418
"""Earth's gravitational parameter μ (km³/s²)."""

EARTH_RADIUS = 6378.137
"""Earth's equatorial radius (km), WGS-84."""

_H_STEP = 1e-30  # complex step; any tiny value works since nothing is subtracted
_NEWTON_MAX_ITER = 60


def _states(x, name="x", ndim=4) -> np.ndarray:
    """States as an ``(n, ndim)`` array (positions then velocities), checked finite."""
    arr = np.asarray(x, dtype=float)
    if arr.ndim == 1:
        arr = arr[None]
    if arr.size == 0:
        return np.zeros((0, ndim))
    return check_finite_array(arr, name, shape=(None, ndim))


# Taylor series C(z) = Σ (−z)^k/(2k+2)!, S(z) = Σ (−z)^k/(2k+3)!, used for |z| < 0.1 where
# the closed forms cancel; 8 terms leave a truncation error below 1e-20.
_C_COEF = tuple((-1) ** k / math.factorial(2 * k + 2) for k in range(8))
_S_COEF = tuple((-1) ** k / math.factorial(2 * k + 3) for k in range(8))


def _horner(coef, z):
    """``Σ coef[k] z^k`` by Horner's rule — the operations of ``numpy.polynomial.polyval`` (the
    same bits) without its per-call overhead, which dominated short Kepler steps."""
    y = coef[-1] + z * 0
    for c in coef[-2::-1]:
        y = c + y * z
    return y


def _C_SERIES(z):
    return _horner(_C_COEF, z)


def _S_SERIES(z):
    return _horner(_S_COEF, z)


def _stumpff(z):
    """Stumpff functions C(z) = (1 − cos √z)/z and S(z) = (√z − sin √z)/√z³.

    Both are entire functions of z (even in √z, so the branch of the square root does
    not matter), which is what makes the complex step exact. Near z = 0 the closed forms
    cancel, so the Taylor series is used there.
    """
    if not np.iscomplexobj(z) and np.any(z < 0):
        # Hyperbolic arcs: √z is imaginary; evaluate on the complex plane, result is real.
        C, S = _stumpff(z.astype(complex))
        return C.real, S.real
    small = np.abs(z) < 0.1
    if np.all(small):  # the common case of a short scan interval: series only
        return _C_SERIES(z), _S_SERIES(z)
    zb = np.where(small, 1.0, z)
    sq = np.sqrt(zb)
    c = (1 - np.cos(sq)) / zb
    s = (sq - np.sin(sq)) / (zb * sq)
    if np.any(small):
        zs = np.where(small, z, 0)
        c = np.where(small, _C_SERIES(zs), c)
        s = np.where(small, _S_SERIES(zs), s)
    return c, s


def _rowdot(a, b):
    """Row-wise ``a · b`` of (N, d) arrays without conjugation (analytic, so the complex step is exact).

    Written out component by component: for d = 2 it is ``a0 b0 + a1 b1`` exactly as before the
    3-D model shared this kernel, so the planar results are bit-identical.
    """
    out = a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]
    for j in range(2, a.shape[1]):
        out = out + a[:, j] * b[:, j]
    return out


def _kepler_universal(r0v, v0v, dt, mu):
    """Propagate position/velocity rows (real or complex) by ``dt`` on Keplerian orbits.

    Parameters
    ----------
    r0v, v0v : (N, d) arrays, d = 2 (planar) or 3 (complex for the complex step).
    dt : (N,) float array.

    Returns
    -------
    r, v : (N, d) arrays.
    """
    sqmu = np.sqrt(mu)
    r0 = np.sqrt(_rowdot(r0v, r0v))  # analytic in the state, unlike np.abs
    v0sq = _rowdot(v0v, v0v)
    rdotv = _rowdot(r0v, v0v)
    alpha = 2.0 / r0 - v0sq / mu  # reciprocal semi-major axis
    sigma0 = rdotv / sqmu
    # Initial guess: exact for circular orbits (elliptic), and a safe start otherwise.
    ar = np.real(alpha)
    chi = np.where(ar > 1e-12, sqmu * dt * alpha, sqmu * dt / r0)
    converged_once = np.zeros(len(dt), bool)
    for _ in range(_NEWTON_MAX_ITER):
        z = alpha * chi**2
        C, S = _stumpff(z)
        chi2 = chi**2
        F = sigma0 * chi2 * C + (1 - alpha * r0) * chi**3 * S + r0 * chi - sqmu * dt
        r = sigma0 * chi * (1 - z * S) + (1 - alpha * r0) * chi2 * C + r0  # dF/dχ = |r(t)|
        step = F / r
        chi = chi - step
        # Newton converges quadratically: at 1e-13 the next step is at rounding level.
        done = np.abs(np.real(step)) <= 1e-13 * np.maximum(np.abs(np.real(chi)), 1.0)
        # One Newton step after the real part has converged makes the derivative part
        # (the complex step's imaginary part) converge too.
        if np.all(converged_once):
            break
        converged_once |= done
    else:
        raise RuntimeError("Kepler's equation (universal variable) did not converge")
    z = alpha * chi**2
    C, S = _stumpff(z)
    chi2 = chi**2
    f = 1 - chi2 / r0 * C
    g = dt - chi**3 / sqmu * S
    rv = f[:, None] * r0v + g[:, None] * v0v
    rn = np.sqrt(_rowdot(rv, rv))
    fdot = sqmu / (rn * r0) * (alpha * chi**3 * S - chi)
    gdot = 1 - chi2 / rn * C
    vv = fdot[:, None] * r0v + gdot[:, None] * v0v
    return rv, vv


def _check_dt(dt) -> float:
    dt = check_finite_array(dt, "dt", ndim=0)
    return float(dt)


@dataclass(frozen=True)
class TwoBodyOrbit:
    """Planar two-body motion ``r̈ = −μ r / |r|³`` plus white acceleration noise.

    Follows the motion-model protocol of :mod:`hypotrack.models.motion`. ``dt`` may be
    negative for :meth:`propagate` and :meth:`transition` (the dynamics are reversible);
    :meth:`Q` needs ``dt >= 0``.

    Parameters
    ----------
    mu : float
        Gravitational parameter (km³/s²), default Earth's.
    q : float
        Acceleration-noise intensity (km²/s³) ≥ 0; DESIGN.md §5 uses 1e-10.
    """

    mu: float = MU_EARTH
    q: float = 1e-10

    def __post_init__(self):
        object.__setattr__(self, "mu", check_positive(self.mu, "mu"))
        object.__setattr__(self, "q", check_nonnegative(self.q, "q"))

    ndim = 4

    def propagate(self, x, dt) -> np.ndarray:
        """Propagate states ``(n, ndim)`` (or one ``(ndim,)``) by ``dt`` seconds, exactly."""
        single = np.ndim(x) == 1
        X = _states(x, ndim=self.ndim)
        dt = _check_dt(dt)
        p = self.ndim // 2  # the Lagrange coefficients f, g act on position and velocity vectors of any size
        if len(X) == 0 or dt == 0:
            out = X.copy()
        else:
            r, v = _kepler_universal(X[:, :p], X[:, p:], np.full(len(X), dt), self.mu)
            out = np.hstack([r, v])
        return out[0] if single else out

    def transition(self, x, dt):
        """Propagated states ``(n, ndim)`` and their state-transition matrices ``(n, ndim, ndim)``.

        ``Φ[k] = ∂x_k(t + dt) / ∂x_k(t)``, by complex-step differentiation of the exact
        Kepler solution (module docstring): the EKF's Jacobian.
        """
        d, p = self.ndim, self.ndim // 2
        X = _states(x, ndim=d)
        dt = _check_dt(dt)
        n = len(X)
        if n == 0:
            return X.copy(), np.zeros((0, d, d))
        if dt == 0:
            return X.copy(), np.broadcast_to(np.eye(d), (n, d, d)).copy()
        # Row (k, j) is object k with its component j perturbed by i·h.
        Xc = np.repeat(X[:, None, :], d, axis=1).astype(complex)
        Xc[:, np.arange(d), np.arange(d)] += 1j * _H_STEP
        Xc = Xc.reshape(d * n, d)
        r, v = _kepler_universal(Xc[:, :p], Xc[:, p:], np.full(d * n, dt), self.mu)
        out = np.hstack([r, v]).reshape(n, d, d)  # [object, perturbed column j, component i]
        x_pred = out[:, 0, :].real.copy()
        Phi = np.swapaxes(out.imag, 1, 2) / _H_STEP
        return x_pred, Phi

    def Q(self, dt) -> np.ndarray:
        """White-acceleration process noise ``q [[dt³/3 I, dt²/2 I], [dt²/2 I, dt I]]``."""
        return ConstantVelocity(self.q, self.ndim // 2).Q(dt)

    def propagate_each(self, x, dt) -> np.ndarray:
        """States ``(n, ndim)`` propagated by their own intervals ``dt`` ``(n,)`` (s), exactly, in
        one batch (the Kepler kernel takes an interval per row); a zero interval returns the state."""
        X = _states(x, ndim=self.ndim)
        dt = check_finite_array(np.asarray(dt, dtype=float), "dt", shape=(len(X),))
        p = self.ndim // 2
        if len(X) == 0:
            return X.copy()
        r, v = _kepler_universal(X[:, :p], X[:, p:], dt, self.mu)
        return np.hstack([r, v])

    def transition_each(self, x, dt):
        """:meth:`transition` with an interval per state, ``dt`` ``(n,)``, in one batch."""
        d, p = self.ndim, self.ndim // 2
        X = _states(x, ndim=d)
        dt = check_finite_array(np.asarray(dt, dtype=float), "dt", shape=(len(X),))
        n = len(X)
        if n == 0:
            return X.copy(), np.zeros((0, d, d))
        Xc = np.repeat(X[:, None, :], d, axis=1).astype(complex)
        Xc[:, np.arange(d), np.arange(d)] += 1j * _H_STEP
        Xc = Xc.reshape(d * n, d)
        r, v = _kepler_universal(Xc[:, :p], Xc[:, p:], np.repeat(dt, d), self.mu)
        out = np.hstack([r, v]).reshape(n, d, d)
        return out[:, 0, :].real.copy(), np.swapaxes(out.imag, 1, 2) / _H_STEP

    def Q_each(self, dt) -> np.ndarray:
        """:meth:`Q` of every interval ``dt`` ``(n,)`` (each ``>= 0``): ``(n, ndim, ndim)``."""
        dt = check_finite_array(np.asarray(dt, dtype=float), "dt", ndim=1)
        if np.any(dt < 0):
            raise ValueError("dt must be >= 0 for the process noise")
        k = self.ndim // 2
        i = np.arange(k)
        Q = np.zeros((len(dt), 2 * k, 2 * k))
        Q[:, i, i] = (dt**3 / 3)[:, None]
        Q[:, i, i + k] = Q[:, i + k, i] = (dt**2 / 2)[:, None]
        Q[:, i + k, i + k] = dt[:, None]
        return self.q * Q

    def period(self, x) -> np.ndarray:
        """Orbital period(s) ``2π sqrt(a³/μ)`` (s) of states; ``inf`` if unbound."""
        return orbital_period(_semi_major_axis(_states(x, ndim=self.ndim), self.mu), self.mu)


def integrate_variational(x0, dt, mu=MU_EARTH, *, rtol=1e-13, atol=1e-13, ndim=4):
    """Numerically integrate the two-body equations and their variational equations.

    ``ẋ = [v, −μ r/|r|³]``, ``Φ̇ = A(x) Φ`` with
    ``A = [[0, I], [μ(3 r rᵀ/|r|² − I)/|r|³, 0]]``,
    ``Φ(0) = I``, by scipy's DOP853. Slow (one object at a time); it is the independent
    reference for :class:`TwoBodyOrbit`, not the production path.

    Parameters
    ----------
    x0 : (ndim,) initial state (km, km/s): positions, then velocities.
    dt : float, time span (s), any sign.
    ndim : 4 (planar) or 6 (3-D).

    Returns
    -------
    x : (ndim,) state at ``dt``; Phi : (ndim, ndim) state-transition matrix.
    """
    if ndim not in (4, 6):
        raise ValueError(f"ndim must be 4 (planar) or 6 (3-D), got {ndim!r}")
    d, p = ndim, ndim // 2
    x0 = check_finite_array(x0, "x0", shape=(d,))
    mu = check_positive(mu, "mu")
    dt = _check_dt(dt)

    def rhs(_t, y):
        r, v = y[:p], y[p:d]
        Phi = y[d:].reshape(d, d)
        rn = np.sqrt(r @ r)
        G = mu * (3 * np.outer(r, r) / rn**2 - np.eye(p)) / rn**3
        A = np.zeros((d, d))
        A[:p, p:] = np.eye(p)
        A[p:, :p] = G
        return np.concatenate([v, -mu * r / rn**3, (A @ Phi).ravel()])

    y0 = np.concatenate([x0, np.eye(d).ravel()])
    if dt == 0:
        return x0.copy(), np.eye(d)
    sol = solve_ivp(rhs, (0.0, dt), y0, method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"variational integration failed: {sol.message}")
    y = sol.y[:, -1]
    return y[:d], y[d:].reshape(d, d)


def specific_energy(x, mu=MU_EARTH) -> np.ndarray:
    """Specific orbital energy ``|v|²/2 − μ/|r|`` (km²/s²) of states ``(n, 4)``."""
    X = _states(x)
    return 0.5 * np.sum(X[:, 2:] ** 2, axis=1) - mu / np.hypot(X[:, 0], X[:, 1])


def angular_momentum(x) -> np.ndarray:
    """Specific angular momentum ``x vy − y vx`` (km²/s) of states ``(n, 4)``; > 0 prograde."""
    X = _states(x)
    return X[:, 0] * X[:, 3] - X[:, 1] * X[:, 2]


def _semi_major_axis(X, mu):
    p = X.shape[1] // 2
    eps = specific_energy(X, mu) if p == 2 else \
        0.5 * np.sum(X[:, p:] ** 2, axis=1) - mu / np.linalg.norm(X[:, :p], axis=1)
    with np.errstate(divide="ignore"):
        return np.where(eps < 0, -mu / (2 * eps), np.inf)


def orbital_period(a, mu=MU_EARTH):
    """Period ``2π sqrt(a³/μ)`` (s) of semi-major axis ``a`` (km)."""
    return 2 * np.pi * np.sqrt(np.asarray(a, dtype=float) ** 3 / mu)


def elements_to_state(a, e, arg_periapsis, true_anomaly, mu=MU_EARTH) -> np.ndarray:
    """Prograde (counter-clockwise) planar state(s) from orbital elements.

    Parameters
    ----------
    a : semi-major axis (km), > 0.
    e : eccentricity in [0, 1).
    arg_periapsis : angle of periapsis from the +x axis (rad).
    true_anomaly : angle from periapsis (rad); the polar angle is their sum.

    Returns
    -------
    (n, 4) states ``[x, y, vx, vy]`` (``(4,)`` for scalar inputs).
    """
    a_, e_, w_, nu_ = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (a, e, arg_periapsis, true_anomaly))
    )
    scalar = a_.ndim == 0
    a_, e_, w_, nu_ = (np.atleast_1d(v) for v in (a_, e_, w_, nu_))
    for v, name in ((a_, "a"), (e_, "e"), (w_, "arg_periapsis"), (nu_, "true_anomaly")):
        check_finite_array(v, name)
    if np.any(a_ <= 0):
        raise ValueError(f"a (semi-major axis) must be > 0 km, got {a_[a_ <= 0][0]!r}")
    if np.any((e_ < 0) | (e_ >= 1)):
        raise ValueError(f"e (eccentricity) must lie in [0, 1), got {e_[(e_ < 0) | (e_ >= 1)][0]!r}")
    p = a_ * (1 - e_**2)
    r = p / (1 + e_ * np.cos(nu_))
    th = w_ + nu_
    k = np.sqrt(mu / p)
    v_r = k * e_ * np.sin(nu_)
    v_t = k * (1 + e_ * np.cos(nu_))
    c, s = np.cos(th), np.sin(th)
    out = np.column_stack([r * c, r * s, v_r * c - v_t * s, v_r * s + v_t * c])
    return out[0] if scalar else out


def circular_velocity(positions, mu=MU_EARTH) -> np.ndarray:
    """Prograde circular-orbit velocity ``sqrt(μ/|r|)`` perpendicular to ``r``, ``(n, 2)``.

    The velocity prior mean of an SSA birth (:class:`hypotrack.models.population.UniformBirthDensity`).
    """
    p = np.atleast_2d(np.asarray(positions, dtype=float))
    rn = np.hypot(p[:, 0], p[:, 1])
    k = np.sqrt(mu / rn) / rn
    return np.column_stack([-p[:, 1] * k, p[:, 0] * k])

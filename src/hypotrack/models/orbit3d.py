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
"""

from __future__ import annotations

from dataclasses import dataclass

from .orbit import MU_EARTH, TwoBodyOrbit, integrate_variational

__all__ = ["TwoBodyOrbit3D", "integrate_variational_3d", "DEFAULT_Q_3D"]

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

"""The NASA standard breakup model (Johnson, Krisko, Liou & Anz-Meador 2001, "NASA's new breakup
model of EVOLVE 4.0", *Adv. Space Res.* 28(9), 1377–1384): fragment sizes, area-to-mass ratios and
ejection speeds of an explosion or a collision.

Laws (``L_c`` characteristic length in metres, ``λ = log10 L_c``, ``χ = log10(A/M)`` with A/M in m²/kg):

* **size** — cumulative number of fragments larger than ``L_c``:
  explosion ``N(>L_c) = 6 S L_c^−1.6`` (S a dimensionless scaling factor, 1 for a typical explosion),
  collision ``N(>L_c) = 0.1 M^0.75 L_c^−1.71`` (M in kg). The count above ``L_min`` is
  ``floor(N(>L_min))`` and the sizes are drawn by inverting the conditional distribution
  ``P(L > l | L > L_min) = (l / L_min)^−β`` (β = 1.6 or 1.71): ``L = L_min U^(−1/β)``, U ~ U(0, 1].
* **area-to-mass** — below 8 cm one normal ``χ ~ N(μ_s(λ), σ_s(λ))`` (Eq. 6 of the paper's small-fragment
  law); above 11 cm the spacecraft's (or upper stage's) two-normal mixture
  ``α N(μ₁, σ₁) + (1 − α) N(μ₂, σ₂)`` with the piecewise-linear parameters of the paper; between 8 and
  11 cm the model bridges the two — here (a stated simplification) each fragment takes the large-fragment
  law with probability ``(λ − log10 0.08) / (log10 0.11 − log10 0.08)``, the small one otherwise.
* **ejection speed** (m/s) — ``ν = log10 Δv ~ N(0.2 χ + 1.85, 0.4)`` for explosions,
  ``N(0.9 χ + 2.9, 0.4)`` for collisions; the direction is isotropic (uniform on the sphere), as the
  model states. The model does not conserve momentum fragment by fragment: the mean Δv vector is zero
  in expectation only (its sampling error is ``E|Δv| / sqrt(3 n)`` per axis).

Every random draw comes from the ``numpy.random.Generator`` passed in; :func:`sample_breakup` draws in a
fixed order (sizes, A/M, speeds, directions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_positive

__all__ = ["BREAKUP_KINDS", "PARENT_KINDS", "sbm_count", "size_exponent", "sample_sizes", "am_parameters",
           "sample_area_to_mass", "delta_v_mean_log10", "DELTA_V_SIGMA_LOG10", "sample_delta_v",
           "isotropic_directions", "Fragments", "sample_breakup"]

BREAKUP_KINDS = ("explosion", "collision")
PARENT_KINDS = ("spacecraft", "rocket_body")
DELTA_V_SIGMA_LOG10 = 0.4
"""Standard deviation of ``log10 Δv`` (Δv in m/s), both kinds."""

_SMALL, _LARGE = 0.08, 0.11  # m: the small- and large-fragment A/M laws' limits


def _check_kind(kind):
    if kind not in BREAKUP_KINDS:
        raise ValueError(f"kind must be one of {BREAKUP_KINDS}, got {kind!r}")


def size_exponent(kind: str) -> float:
    """β of ``N(>L_c) ∝ L_c^−β``: 1.6 (explosion), 1.71 (collision)."""
    _check_kind(kind)
    return 1.6 if kind == "explosion" else 1.71


def sbm_count(kind: str, lc_min_m: float, *, scaling: float = 1.0, mass_kg: float | None = None) -> int:
    """``floor(N(>L_min))``: fragments larger than ``lc_min_m`` (explosion: ``6 S L^−1.6``; collision:
    ``0.1 M^0.75 L^−1.71``, ``mass_kg`` required)."""
    _check_kind(kind)
    lc = check_positive(lc_min_m, "lc_min_m")
    if kind == "explosion":
        return int(np.floor(6.0 * check_positive(scaling, "scaling") * lc ** -1.6))
    if mass_kg is None:
        raise ValueError("mass_kg (> 0) is required for a collision")
    return int(np.floor(0.1 * check_positive(mass_kg, "mass_kg") ** 0.75 * lc ** -1.71))


def sample_sizes(n: int, lc_min_m: float, kind: str, rng) -> np.ndarray:
    """``n`` characteristic lengths (m) above ``lc_min_m`` from the size law (module docstring)."""
    u = 1.0 - rng.random(n)  # (0, 1]
    return check_positive(lc_min_m, "lc_min_m") * u ** (-1.0 / size_exponent(kind))


def _ramp(lam, x0, x1, y0, y1):
    """``y0`` below ``x0``, ``y1`` above ``x1``, linear between."""
    return np.interp(lam, [x0, x1], [y0, y1])


def am_parameters(lc_m, parent: str = "spacecraft"):
    """Parameters of the A/M law at sizes ``lc_m``: ``(mu_small, sigma_small, alpha, mu1, sigma1, mu2, sigma2)``
    (each an array like ``lc_m``), Johnson et al. 2001, Eqs. 6–8 (spacecraft) and 5 (upper stages)."""
    if parent not in PARENT_KINDS:
        raise ValueError(f"parent must be one of {PARENT_KINDS}, got {parent!r}")
    lam = np.log10(np.asarray(lc_m, dtype=float))
    mu_s = _ramp(lam, -1.75, -1.25, -0.3, -1.0)
    sd_s = np.where(lam <= -3.5, 0.2, 0.2 + 0.1333 * (lam + 3.5))
    if parent == "spacecraft":
        alpha = _ramp(lam, -1.95, 0.55, 0.0, 1.0)
        mu1 = _ramp(lam, -1.1, 0.0, -0.6, -0.95)
        sd1 = _ramp(lam, -1.3, -0.3, 0.1, 0.3)
        mu2 = _ramp(lam, -0.7, -0.1, -1.2, -2.0)
        sd2 = _ramp(lam, -0.5, -0.3, 0.5, 0.3)
    else:
        alpha = _ramp(lam, -1.4, 0.0, 1.0, 0.5)
        mu1 = _ramp(lam, -0.5, 0.0, -0.45, -0.9)
        sd1 = np.full_like(lam, 0.55)
        mu2 = np.full_like(lam, -0.9)
        sd2 = _ramp(lam, -1.0, 0.1, 0.28, 0.1)
    return mu_s, sd_s, alpha, mu1, sd1, mu2, sd2


def sample_area_to_mass(lc_m, rng, parent: str = "spacecraft") -> np.ndarray:
    """``χ = log10(A/M)`` of fragments of sizes ``lc_m`` (module docstring). Draws, in order: the bridge
    uniforms, the mixture uniforms, the standard normals (one of each per fragment)."""
    lc = np.asarray(lc_m, dtype=float)
    mu_s, sd_s, alpha, mu1, sd1, mu2, sd2 = am_parameters(lc, parent)
    lam = np.log10(lc)
    p_large = _ramp(lam, np.log10(_SMALL), np.log10(_LARGE), 0.0, 1.0)
    large = rng.random(len(lc)) < p_large
    first = rng.random(len(lc)) < alpha
    z = rng.standard_normal(len(lc))
    mu = np.where(large, np.where(first, mu1, mu2), mu_s)
    sd = np.where(large, np.where(first, sd1, sd2), sd_s)
    return mu + sd * z


def delta_v_mean_log10(chi, kind: str) -> np.ndarray:
    """Mean of ``log10 Δv`` (m/s) given ``χ``: ``0.2 χ + 1.85`` (explosion), ``0.9 χ + 2.9`` (collision)."""
    _check_kind(kind)
    chi = np.asarray(chi, dtype=float)
    return 0.2 * chi + 1.85 if kind == "explosion" else 0.9 * chi + 2.9


def sample_delta_v(chi, kind: str, rng) -> np.ndarray:
    """Ejection speeds (m/s) given ``χ`` (one standard normal per fragment)."""
    return 10.0 ** (delta_v_mean_log10(chi, kind) + DELTA_V_SIGMA_LOG10 * rng.standard_normal(np.shape(chi)))


def isotropic_directions(n: int, rng) -> np.ndarray:
    """``n`` unit vectors uniform on the sphere (normalised standard normals)."""
    g = rng.standard_normal((n, 3))
    return g / np.linalg.norm(g, axis=1, keepdims=True)


@dataclass(frozen=True)
class Fragments:
    """The fragments of one breakup: sizes ``lc_m`` (m), ``chi = log10 A/M`` (m²/kg), speeds ``dv_m_s``
    (m/s) and ejection velocities ``dv_km_s`` (n, 3) (km/s, in the frame of the parent's velocity)."""

    lc_m: np.ndarray
    chi: np.ndarray
    dv_m_s: np.ndarray
    dv_km_s: np.ndarray

    def __len__(self):
        return len(self.lc_m)


def sample_breakup(kind: str, lc_min_m: float, rng, *, parent: str = "spacecraft", scaling: float = 1.0,
                   mass_kg: float | None = None) -> Fragments:
    """All fragments above ``lc_min_m`` of one breakup (count :func:`sbm_count`; sizes, A/M, speeds,
    isotropic directions drawn in that order)."""
    n = sbm_count(kind, lc_min_m, scaling=scaling, mass_kg=mass_kg)
    lc = sample_sizes(n, lc_min_m, kind, rng)
    chi = sample_area_to_mass(lc, rng, parent)
    dv = sample_delta_v(chi, kind, rng)
    return Fragments(lc, chi, dv, 1e-3 * dv[:, None] * isotropic_directions(n, rng))

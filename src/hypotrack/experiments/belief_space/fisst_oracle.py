"""An independent oracle for one scan of the hypothesis recursion: the seeds' densities, evaluated directly.

This module shares no code with the engine (:mod:`hypotrack.hypotheses`): it imports numpy and
scipy only, predicts the prior tracks itself and enumerates every child hypothesis by brute force.
For each child it evaluates

* **FISST (document 001 Eqs. 5–7, 31–33, 59; document 000 Eq. 20)** — the predicted multi-object density
  (each prior object survives with ``p_s``; one birth pixel, binomial birth in the Poisson limit
  ``e^{−α} α^b``; a born object's position uniform on the pixel) times the multi-object likelihood
  with Poisson clutter (``e^{−λV} Π_clutter λV c(z)``, ``c = 1/V``; ``p_D`` per object), integrated
  over the states of the child's objects: a detected object contributes
  ``p_D ∫ N(z; Hx, R) p(x) dx`` (the Gaussian convolution for a prior track, the exact integral of
  the Gaussian over the uniform pixel for a birth), a missed one ``1 − p_D``;
* **Reid (1979; document 001 Eqs. 30, 35)** — ``p_D^{N_DT} (1 − p_D)^{N_TGT − N_DT} β_FT^{N_FT}
  β_NT^{N_NT} Π N(z; H x̄, H P H' + R)`` for a fixed set of prior targets, false targets of
  density ``β_FT = λV / V`` and new targets of density ``β_NT``.

A child is keyed as the engine keys it — ``(events, kind, arg)``: ``events[i]`` is the object a
return is assigned to (``0..M−1``), the birth pixel (``M``), clutter (``−1``) or a Reid new target
(``−2``); ``kind`` 0 is an association child, 1 adds an undetected birth (``arg`` = pixel 0), 2 a
death (``arg`` = the dead object); as in the engine, a child holds at most one undetected birth or
one death, and only an undetected object may die. Normalising over the children gives the posterior
the engine must reproduce.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy import stats
from scipy.special import logsumexp

__all__ = ["OracleScene", "fisst_children", "reid_children", "normalise", "undetected_birth_ratios"]

ASSOCIATION, UNDETECTED_BIRTH, DEATH = 0, 1, 2
CLUTTER, NEW_TARGET = -1, -2


@dataclass(frozen=True)
class OracleScene:
    """One scan: prior tracks, motion, sensor, clutter, one birth pixel and the returns.

    Attributes
    ----------
    means, covs : (M, d), (M, d, d) prior (posterior at the last scan) of each object.
    F, Q : (d, d) motion over one scan.  H, R : (p, d), (p, p) position measurement; R diagonal.
    p_D : detection probability.  clutter_rate : λV, expected clutter returns per scan.
    clutter_volume : V.  Z : (m, p) returns.
    pixel_low, pixel_high : (p,) corners of the birth pixel (position space); ``alpha`` its birth
    probability per scan.  p_survive : p_s.  new_target_density : Reid's β_NT (0: no new targets).
    """

    means: np.ndarray
    covs: np.ndarray
    F: np.ndarray
    Q: np.ndarray
    H: np.ndarray
    R: np.ndarray
    p_D: float
    clutter_rate: float
    clutter_volume: float
    Z: np.ndarray
    pixel_low: np.ndarray | None = None
    pixel_high: np.ndarray | None = None
    alpha: float = 0.0
    p_survive: float = 1.0
    new_target_density: float = 0.0

    def __post_init__(self):
        if not 0 < self.p_D < 1:
            raise ValueError(f"p_D must lie in (0, 1), got {self.p_D}")
        if not 0 < self.p_survive <= 1:
            raise ValueError(f"p_survive must lie in (0, 1], got {self.p_survive}")
        if not 0 <= self.alpha < 1:
            raise ValueError(f"alpha must lie in [0, 1), got {self.alpha}")
        R = np.asarray(self.R, dtype=float)
        if np.any(R != np.diag(np.diag(R))):
            raise ValueError("R must be diagonal (the birth integral factorises over axes)")

    @property
    def has_birth(self) -> bool:
        return self.pixel_low is not None and self.alpha > 0


def _log_target_likelihoods(s: OracleScene) -> np.ndarray:
    """(m, M) ``log ∫ N(z_i; Hx, R) N(x; F μ_j, F P_j F' + Q) dx = log N(z_i; H F μ_j, H P⁻ H' + R)``."""
    Z = np.atleast_2d(np.asarray(s.Z, dtype=float))
    out = np.empty((len(Z), len(s.means)))
    for j, (mu, P) in enumerate(zip(s.means, s.covs)):
        mean = s.H @ s.F @ mu
        cov = s.H @ (s.F @ P @ s.F.T + s.Q) @ s.H.T + s.R
        out[:, j] = stats.multivariate_normal(mean, cov).logpdf(Z) if len(Z) else []
    return out


def _log_birth_likelihood(s: OracleScene) -> np.ndarray:
    """(m,) ``log ∫ N(z; x, R) U(x; pixel) dx`` — exact, a product of normal CDF differences."""
    Z = np.atleast_2d(np.asarray(s.Z, dtype=float))
    lo, hi = np.asarray(s.pixel_low, float), np.asarray(s.pixel_high, float)
    sd = np.sqrt(np.diag(s.R))
    mass = stats.norm.cdf((hi - Z) / sd) - stats.norm.cdf((lo - Z) / sd)
    return np.log(mass).sum(axis=1) - np.log(np.prod(hi - lo))


def _associations(m: int, options: list, unique: set):
    """Every assignment of ``m`` returns to ``options``; an option in ``unique`` at most once."""
    for a in itertools.product(options, repeat=m):
        used = [x for x in a if x in unique]
        if len(used) == len(set(used)):
            yield a


DEFECTS = (None, "no_missed_detection")


def _check_defect(defect):
    if defect not in DEFECTS:
        raise ValueError(f"defect must be one of {DEFECTS}, got {defect!r}")
    return defect


def fisst_children(s: OracleScene, defect: str | None = None) -> dict:
    """Log-weight of every child under document 001's multi-object densities (module docstring).

    ``defect="no_missed_detection"`` drops every missed-detection factor ``1 − p_D`` (undetected
    objects and the undetected birth, Eqs. 6 and 37): a density with a known defect, run as the
    negative control of the oracle rows."""
    _check_defect(defect)
    M, m = len(s.means), len(np.atleast_2d(s.Z)) if np.size(s.Z) else 0
    g = _log_target_likelihoods(s)
    gb = _log_birth_likelihood(s) if s.has_birth else None
    log_pd, log_md = math.log(s.p_D), (0.0 if defect else math.log1p(-s.p_D))
    log_kappa = math.log(s.clutter_rate / s.clutter_volume)  # Poisson clutter intensity λV c(z)
    out = {}
    twins = [(ASSOCIATION, -1)] + ([(UNDETECTED_BIRTH, 0)] if s.has_birth else [])
    twins += [(DEATH, j) for j in range(M)] if s.p_survive < 1 else []
    for kind, arg in twins:
        alive = [j for j in range(M) if not (kind == DEATH and j == arg)]
        birth_column = s.has_birth and kind != UNDETECTED_BIRTH
        options = [CLUTTER, *alive] + ([M] if birth_column else [])
        for a in _associations(m, options, set(alive) | {M}):
            detected = {x for x in a if x >= 0}
            lw = sum(log_pd + g[i, x] for i, x in enumerate(a) if 0 <= x < M)
            lw += log_md * sum(j not in detected for j in alive)
            births = 0
            if M in detected:  # a detected birth: p_D ∫ N(z; Hx, R) p_b(x) dx
                lw += sum(log_pd + gb[i] for i, x in enumerate(a) if x == M)
                births += 1
            if kind == UNDETECTED_BIRTH:  # (1 − p_D) ∫ p_b(x) dx
                lw += log_md
                births += 1
            if s.has_birth:  # binomial birth, Poisson limit (document 001 Eq. 33): e^{−α} α^b
                lw += -s.alpha + births * math.log(s.alpha)
            if s.p_survive < 1:  # survival (document 001 Eq. 59)
                lw += len(alive) * math.log(s.p_survive) + (M - len(alive)) * math.log1p(-s.p_survive)
            k_clutter = sum(x == CLUTTER for x in a)
            lw += -s.clutter_rate + k_clutter * log_kappa  # Poisson clutter set density
            out[(a, kind, arg)] = lw
    return out


def reid_children(s: OracleScene, defect: str | None = None) -> dict:
    """Log-weight of every hypothesis by Reid's formula (fixed prior targets, new targets seeded).

    ``defect="no_missed_detection"`` drops the factor ``(1 − p_D)`` of each undetected target (001
    Eq. 30 with a known defect: the negative control)."""
    _check_defect(defect)
    M, m = len(s.means), len(np.atleast_2d(s.Z)) if np.size(s.Z) else 0
    g = _log_target_likelihoods(s)
    beta_ft = s.clutter_rate / s.clutter_volume
    options = [CLUTTER, *range(M)] + ([NEW_TARGET] if s.new_target_density > 0 else [])
    out = {}
    for a in _associations(m, options, set(range(M))):
        n_dt = sum(0 <= x < M for x in a)
        lw = n_dt * math.log(s.p_D) + (0.0 if defect else (M - n_dt) * math.log1p(-s.p_D))
        lw += sum(g[i, x] for i, x in enumerate(a) if x >= 0)
        lw += sum(x == CLUTTER for x in a) * math.log(beta_ft)
        if s.new_target_density > 0:
            lw += sum(x == NEW_TARGET for x in a) * math.log(s.new_target_density)
        out[(a, ASSOCIATION, -1)] = lw
    return out


def normalise(children: dict) -> dict:
    """Log posterior probabilities: log-weights minus their log-sum-exp."""
    total = logsumexp(list(children.values()))
    return {k: v - total for k, v in children.items()}


def undetected_birth_ratios(children: dict) -> np.ndarray:
    """``w(child + undetected birth) / w(child)`` for every association child that has such a twin."""
    return np.array([math.exp(v - children[(a, ASSOCIATION, -1)])
                     for (a, kind, _), v in children.items() if kind == UNDETECTED_BIRTH])

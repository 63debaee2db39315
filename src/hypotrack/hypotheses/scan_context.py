"""Per-scan quantities every weight model reads, computed once for all hypotheses."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

__all__ = ["ScanContext"]


@dataclass(frozen=True, eq=False)
class ScanContext:
    """What one scan contributes to the weights of every child.

    Attributes
    ----------
    Z : (m, p) returns.
    loglik : (m, N) ``log N(z_i; H x̂_j, S_j)`` for every return and predicted track of the
        store (the predictive density, not the point likelihood at the mean: DESIGN.md §4.2).
    allowed : (m, N) bool gate (True = return i may be assigned to track j).
    p_detect : (N,) detection probability of each predicted track (0 outside the field of view).
    birth_loglik : (m, B) ``log ∫ p(z_i|x) p_b,r(x) dx`` for each birth region ``r``.
    p_detect_birth : float, detection probability of a newly born object.
    clutter_rate : float, expected clutter returns per scan ``λV``.
    clutter_volume : float, ``V`` (clutter density ``g(z) = 1/V``).
    p_survive : (N,) survival probability of each predicted track, or ``None`` (the population's one
        ``p_S`` for every track): set when the population's survival depends on the track
        (:meth:`~.population_lmb.LabeledMultiBernoulliPopulation.track_survival`).
    memo : dict, what a weight model computes from the scan once for every parent (e.g. Reid's option scores).
    """

    Z: np.ndarray
    loglik: np.ndarray
    allowed: np.ndarray
    p_detect: np.ndarray
    birth_loglik: np.ndarray
    p_detect_birth: float
    clutter_rate: float
    clutter_volume: float
    p_survive: np.ndarray | None = None
    #: what a weight model derives from the scan once for all the parents (its own keys; a new context, a new memo)
    memo: dict = field(default_factory=dict, init=False, repr=False)

    @property
    def n_returns(self) -> int:
        return self.Z.shape[0]

    @property
    def n_birth_regions(self) -> int:
        return self.birth_loglik.shape[1]

    @cached_property
    def detection_scores(self) -> tuple[np.ndarray, np.ndarray]:
        """``(log_miss, obj)``: ``log(1 − p_D,j)`` (N,) of every predicted track and its column
        of the association matrix ``log N(z_i; ·) + log p_D,j − log(1 − p_D,j)`` (m, N), ``−inf``
        where gated out or out of view (document 000 Eq. 8, 18). Elementwise, so a parent's columns
        are a gather of these: computed once per scan instead of once per parent."""
        p = self.p_detect
        log_miss = np.log1p(-p)
        with np.errstate(divide="ignore"):
            obj = self.loglik + (np.log(p) - log_miss)[None, :]
        return log_miss, np.where(self.allowed, obj, -np.inf)

    @cached_property
    def birth_scores(self) -> np.ndarray:
        """(m, B) birth columns ``log ∫ p(z_i|x) p_b,r(x) dx + log p_D`` (document 000 Eq. 30)."""
        return self.birth_loglik + np.log(self.p_detect_birth)

    @property
    def log_clutter_density(self) -> float:
        """``log g(z) = −log V`` (document 000 Eq. 18)."""
        return -float(np.log(self.clutter_volume))

    @property
    def clutter_intensity(self) -> float:
        """``λ_C = λV / V`` (returns per unit volume; Reid's β_FT)."""
        return self.clutter_rate / self.clutter_volume

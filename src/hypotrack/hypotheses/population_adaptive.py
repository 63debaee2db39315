"""Measurement-driven birth (the labeled multi-Bernoulli filter's adaptive birth): :class:`AdaptiveBirth`.

Beside the population models (:mod:`.population_events`, :mod:`.population_lmb`): it makes, from
the returns a scan leaves unexplained, the birth terms a population uses at the next scan. The
factored filter (:mod:`.factored`) sets them each scan (:meth:`~._Population.with_birth_terms`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_positive
from ..gaussian import predict_with_unchecked
from .population_lmb import GaussianBirthTerm

__all__ = ["AdaptiveBirth"]


@dataclass(frozen=True)
class AdaptiveBirth:
    """Measurement-driven birth: every return no group explained starts a birth term at the next scan.

    Reuter, Vo, Vo & Dietmayer ("The labeled multi-Bernoulli filter", IEEE TSP 62(12), 2014,
    Sec. IV-C) let the birth at scan ``k + 1`` depend on the returns of scan ``k``: a return
    ``z`` gives a labeled-Bernoulli birth term placed at ``z`` with existence ``r_B(z)``
    proportional to ``1 − r_U(z)``, ``r_U(z)`` the probability that ``z`` was associated with
    an existing object. Here ``r_U`` is taken as 0 or 1 from the gates: a return in no group's
    gate and in no birth term's gate (the engine's *unexplained* returns) gives a term of
    existence ``r_birth``; a return in a gate gives none.

    The term of a return ``z`` at scan ``k`` is the one-point initiation ``x₀ = H⁺ z``,
    ``P₀ = H⁺ R H⁺ᵀ + diag(s²)`` (``s`` = ``position_std`` on the measured state components,
    ``velocity_std`` on the others, e.g. zero velocity with a spread covering every orbit's
    speed) predicted by the motion model over the scan interval (EKF, so the position spread at
    ``k + 1`` is ``√(σ_z² + s_p² + Δt² s_v²)`` with the position–velocity correlation that lets
    the second return fix the velocity). Each term is gated with ``gate_probability`` (a
    :class:`~.population_lmb.GaussianBirthTerm`), so it couples only the returns near it and the
    groups gating them: a new object is born inside its own group.

    An object first detected at scan ``k`` is born at the first scan after ``k`` at which it is
    detected again right after a detection — when the hypothesis "born undetected" (weight
    ``r_B (1 − p_D)`` relative to not born) is pruned at once (``min_weight`` above it); kept, it
    can pick the object up later — so with independent detections of probability ``p_D`` the number of scans from its first chance of detection to its birth is
    ``1/p_D + 1/p_D² − 1`` on average (the waiting time for two successes in a row, less one).

    Parameters
    ----------
    position_std : float
        Extra position spread of a term (state units, ≥ 0), added to the return's own noise.
    velocity_std : float
        Spread of each unmeasured component (state units per second), > 0.
    r_birth : float
        Existence probability of each term (labeled multi-Bernoulli ``r_B``) in (0, 1); a
        binomial population uses its own ``alpha``.
    gate_probability : float
        Gate of each term, in (0, 1).
    mixture : object, optional
        A birth mixture per return in place of the one-point initiation: ``mixture.components(z)
        -> (weights (K,), means (K, d), covs (K, d, d))`` (``K = 0``: no state can give ``z``), e.g. the
        admissible region of a radar return (:class:`hypotrack.scenarios.catalogue.admissible.AdmissibleRegionBirth`).
        Each component is a term of weight ``weights[k]`` (existence ``r_birth × weights[k]``), predicted
        over the scan interval like a one-point term. A mixture with ``components_batch(Z) -> (weights, means,
        covs, owner)`` (every return's components in one pass, in the order of the returns) is asked once per scan.

    With a nonlinear measurement model (``measurement`` of :meth:`terms`, e.g. a radar's range, angles and
    range-rate in the sensor frame) the one-point initiation is the model's own ``one_point(Z, position_std,
    velocity_std)`` and each term is observed through the model (:class:`~.population_lmb.GaussianBirthTerm`).
    """

    position_std: float = 0.0
    velocity_std: float = 1.0
    r_birth: float = 0.01
    gate_probability: float = 0.999
    mixture: object = None

    def __post_init__(self):
        if not (np.isfinite(self.position_std) and self.position_std >= 0):
            raise ValueError(f"position_std must be finite and >= 0, got {self.position_std!r}")
        check_positive(self.velocity_std, "velocity_std")
        if not 0.0 < float(self.r_birth) < 1.0:
            raise ValueError(f"r_birth must lie in (0, 1), got {self.r_birth!r}")
        if not 0.0 < float(self.gate_probability) < 1.0:
            raise ValueError(f"gate_probability must lie in (0, 1), got {self.gate_probability!r}")

    def initial(self, Z, H, R):
        """One-point initiation ``(x₀ (m, d), P₀ (m, d, d))`` of returns ``Z`` (m, p)."""
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        Hp = np.linalg.pinv(H)
        measured = np.any(H != 0, axis=0)
        s = np.where(measured, self.position_std, self.velocity_std)
        P0 = Hp @ R @ Hp.T + np.diag(s**2)
        return Z @ Hp.T, np.broadcast_to(P0, (len(Z), *P0.shape)).copy()

    def terms(self, Z, H, R, motion, dt, measurement=None) -> list:
        """The birth terms of the next scan: the one-point initiations of ``Z`` (or their mixtures'
        components) predicted by ``dt``. ``measurement``: the sensor's measurement model; a nonlinear one
        (``measurement.linear`` false) replaces ``H``. :meth:`components` then :meth:`observed`."""
        if len(Z) == 0:
            return []
        x0, P0, weights = self.components(Z, H, R, measurement)
        if len(x0) == 0:
            return []
        x, P = predict_with_unchecked(motion, x0, P0, dt)
        return self.observed(x, P, weights, H, R, measurement)

    def components(self, Z, H, R, measurement=None):
        """``(x₀ (K, d), P₀ (K, d, d), weights (K,) or None)``: the states of returns ``Z`` at their own scan —
        the one-point initiation of each (the nonlinear ``measurement``'s own, else through ``H``, ``R``) or the
        components of its mixture (``K = 0``: none); ``weights`` is ``None`` for one-point terms."""
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        nonlinear = measurement is not None and not measurement.linear
        if self.mixture is not None and hasattr(self.mixture, "components_batch"):
            # all returns' mixtures in one vectorised pass, in the order of the per-return list below
            w, x0, P0, _ = self.mixture.components_batch(Z)
            return x0, P0, w
        if self.mixture is not None:
            parts = [p for p in (self.mixture.components(z) for z in Z) if len(p[0])]
            if not parts:
                d = measurement.ndim_state if nonlinear else np.shape(H)[1]
                return np.zeros((0, d)), np.zeros((0, d, d)), np.zeros(0)
            return (np.concatenate([p[1] for p in parts]), np.concatenate([p[2] for p in parts]),
                    np.concatenate([p[0] for p in parts]))
        if nonlinear:
            return (*measurement.one_point(Z, self.position_std, self.velocity_std), None)
        return (*self.initial(Z, H, R), None)

    def observed(self, x, P, weights, H, R, measurement=None) -> list:
        """Birth terms (:class:`~.population_lmb.GaussianBirthTerm`, this model's gate) of states ``x``, ``P`` (already
        predicted to the scan they are for), ``weights`` as :meth:`components` gives them, observed by that scan's
        sensor: ``H``, ``R`` or a nonlinear ``measurement`` (its own ``R``). Another sensor than the one whose
        returns made the states may observe them (:mod:`.factored.multisensor`)."""
        if measurement is not None and not measurement.linear:
            return GaussianBirthTerm.many(x, P, None, measurement.R, self.gate_probability, measurement, weights)
        return GaussianBirthTerm.many(x, P, H, R, self.gate_probability, None, weights)

"""The δ-GLMB joint prediction–update weight (Vo, Vo & Hoang 2017, Eq. 8–12), in log space.

For a parent with tracks ``ℓ_1 .. ℓ_M`` and birth terms ``b_1 .. b_B`` the child indexed by the
association map ``γ`` (one value per object: died / missed / return ``j``) weighs

    log w = log w_parent − λ + Σ_j log κ(z_j) + Σ_i log η_i(γ_i),

``η`` as tabulated in :mod:`.population_lmb` (``κ(z) = λ_C``, uniform Poisson clutter). This is
the form ``Σ_rows L[i, a_i] + φ`` of DESIGN.md §4.2 with the **objects as rows**: exclusive
columns are the returns (one object each), row option 0 is "missed" (code −1, always
possible) and row option 1 "died / not born" (code −2); ``φ`` is constant. Hence the exhaustive enumerator, Murty's ranked assignment (on the
``P × (m + 2P)`` matrix of Vo & Vo's GLMB update), the R-FISST chain and the Gibbs sampler
(:mod:`.gibbs`) all serve it unchanged.

The common factor ``e^{−λ} Π_j κ(z_j)`` is kept so that a GLMB child weighs exactly what the
same child weighs under document 001's FISST weights with Poisson clutter and the binomial
population (:class:`~.FISSTPoissonWeights`): the identity tested in
``tests/crosscheck/test_equivalence_glmb.py``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_positive
from .association_problem import AssociationProblem
from .weights import WeightModel

__all__ = ["GLMBWeights"]


@dataclass(frozen=True)
class GLMBWeights(WeightModel):
    """Joint prediction–update weights of the δ-GLMB filter (object-indexed; see module docstring).

    Parameters
    ----------
    clutter_intensity : float, optional
        Overrides the scan's ``κ = λ_C = λV / V`` (returns per unit volume, > 0).
    """

    clutter_intensity: float | None = None
    name = "glmb"

    @property
    def sensor_parameters(self) -> tuple:
        """``H``, ``R``, ``p_D`` and (unless overridden here) ``κ``: the clutter rate over the region's volume."""
        return super().sensor_parameters + (() if self.clutter_intensity is not None else
                                            ("clutter.rate", "clutter.region"))

    def __post_init__(self):
        if self.clutter_intensity is not None:
            check_positive(self.clutter_intensity, "clutter_intensity")

    def problem(self, ctx, tracks, constant=0.0, population_log_prob=None):
        raise ValueError("GLMB weights index children by object: use a LabeledMultiBernoulliPopulation, "
                         "whose children() calls labeled_problem")

    def labeled_problem(self, ctx, tracks, log_exist, log_not_exist, constant=0.0) -> AssociationProblem:
        """The object-indexed association problem of one parent.

        Parameters
        ----------
        ctx : ScanContext
        tracks : (M,) int array of track indices into the predicted store.
        log_exist, log_not_exist : (M + B,) arrays
            ``log r`` and ``log(1 − r)`` per object: ``r = p_S`` for the tracks, ``r_B`` for the
            birth terms (:meth:`LabeledMultiBernoulliPopulation.log_existence`).
        constant : float
            The parent's log-weight.
        """
        tracks = np.asarray(tracks, dtype=np.int64)
        M, B, m = len(tracks), ctx.n_birth_regions, ctx.n_returns
        log_exist = np.asarray(log_exist, dtype=float)
        log_not_exist = np.asarray(log_not_exist, dtype=float)
        if log_exist.shape != (M + B,) or log_not_exist.shape != (M + B,):
            raise ValueError(f"log_exist and log_not_exist must have shape ({M + B},), "
                             f"got {log_exist.shape} and {log_not_exist.shape}")
        kappa = check_positive(ctx.clutter_intensity if self.clutter_intensity is None else self.clutter_intensity,
                               "clutter intensity")
        log_kappa = np.log(kappa)
        p = np.concatenate([ctx.p_detect[tracks], np.full(B, ctx.p_detect_birth)])
        with np.errstate(divide="ignore"):
            log_pd = np.log(p)
        loglik = np.vstack([np.where(ctx.allowed[:, tracks], ctx.loglik[:, tracks], -np.inf).T,
                            ctx.birth_loglik.T]).reshape(M + B, m)
        detect = log_exist[:, None] + log_pd[:, None] + loglik - log_kappa
        options = np.stack([log_exist + np.log1p(-p), log_not_exist], axis=1)
        return AssociationProblem(
            target_scores=detect, option_scores=options, n_objects=m, count_term=np.zeros((m + 1, 1)),
            constant=constant - ctx.clutter_rate + m * log_kappa,
        )

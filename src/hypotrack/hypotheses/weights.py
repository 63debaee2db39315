"""Weight models: the one place H-FISST, FISST with Poisson clutter and HOMHT differ.

Each model turns a parent hypothesis and a scan into an :class:`AssociationProblem`, i.e. it
says how the extra columns of the data association matrix and the count term ``φ`` are filled
(DESIGN.md §4.2). Common to all three:

* object column ``j``: ``log N(z_i; H x̂_j, S_j) + log p_D,j − log(1 − p_D,j)`` and the constant
  ``Σ_j log(1 − p_D,j)`` — together ``Π_detected p_D Π_missed (1 − p_D)``;
* birth column ``r`` (H-FISST / FISST births, and HOMHT with a population model): ``log ∫ p(z|x) p_b,r(x) dx + log p_D``;
* the population-event probability (Eq. 30 or document 001 Eq. 59) added to ``φ`` by the caller.

Detection probabilities must lie in [0, 1): a missed detection must be possible for
``log(1 − p_D)`` to be finite (a track outside the field of view has ``p_D = 0``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.special import gammaln

from .._validation import check_nonnegative, check_positive
from .association_problem import AssociationProblem
from .seeded import is_mixture, prime_scan, seeded_moments, seeded_option_scores, seeded_state  # noqa: F401 (filter's imports)

__all__ = ["WeightModel", "HFISSTWeights", "FISSTPoissonWeights", "ReidWeights", "make_weight_model"]


class WeightModel:
    """Base class: builds the association problem of a parent; subclasses fill the extras.

    :attr:`sensor_parameters` names the sensor's parameters the model's weights use (``Sensor``
    attribute paths); a parameter not listed — H-FISST's ``clutter.rate`` — does not change them.
    """

    name = "base"
    seeded_births = False

    @property
    def sensor_parameters(self) -> tuple:
        """The sensor parameters the weights use (every model: ``H``, ``R``, ``p_D``)."""
        return ("measurement.H", "measurement.R", "detection.p_D")

    def option_scores(self, ctx) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def count_term(self, ctx, n_objects: int, n_births: int) -> np.ndarray:  # pragma: no cover - abstract
        """``φ[k, b]`` of the weight model (without the population-event probability)."""
        raise NotImplementedError

    def uses_birth_columns(self) -> bool:
        return True

    def problem(self, ctx, tracks, constant: float = 0.0, population_log_prob=None) -> AssociationProblem:
        """The association problem of a parent holding store tracks ``tracks``.

        Parameters
        ----------
        ctx : ScanContext
        tracks : (M,) int array of track indices into the predicted store.
        constant : float
            Added to every child (the parent's log-weight).
        population_log_prob : (B + 1,) array, optional
            Log-probability of the population event "``b`` detected births, nothing else"
            (document 000 Eq. 30 / document 001 Eq. 59); default: no births, probability 1.
        """
        return AssociationProblem(**self.problem_fields(ctx, tracks, constant, population_log_prob))

    def problem_fields(self, ctx, tracks, constant: float = 0.0, population_log_prob=None) -> dict:
        """The arrays of :meth:`problem` (``target_scores``, ``option_scores``, ``n_objects``, ``count_term``,
        ``constant``) before :class:`~.association_problem.AssociationProblem` wraps and validates them."""
        tracks = np.asarray(tracks, dtype=np.int64)
        log_miss_all, obj_all = ctx.detection_scores  # per scan; the same numbers as per parent
        log_miss = log_miss_all[tracks]
        obj = obj_all[:, tracks]
        n_births = ctx.n_birth_regions if self.uses_birth_columns() else 0
        if n_births:
            target = np.hstack([obj, ctx.birth_scores])
        else:
            target = obj
        pop = np.zeros(1) if population_log_prob is None else np.asarray(population_log_prob, dtype=float)
        if pop.shape != (n_births + 1,):
            raise ValueError(f"population_log_prob must have shape ({n_births + 1},), got {pop.shape}")
        phi = self.count_term(ctx, len(tracks), n_births) + pop[None, :]
        return dict(target_scores=target, option_scores=self.option_scores(ctx), n_objects=len(tracks), count_term=phi,
                    constant=constant + float(log_miss.sum()))


def _detected_counts(m, n_objects, n_births):
    k = np.arange(n_objects + 1)[:, None]
    b = np.arange(n_births + 1)[None, :]
    return k, b, k + b <= m


@dataclass(frozen=True)
class HFISSTWeights(WeightModel):
    """H-FISST / R-FISST weights (document 000 Eq. 8, 17–19, 30–31).

    ``w_ij ∝ w_i p_pop p_D^k (1 − p_D)^{N−k} / (C(m, k) k!) Π_assoc N(z; H x̂⁻, S) Π_clutter g(z)``
    with ``k`` the detected objects (births included) among the ``N`` of the child and
    ``g(z) = 1/V`` the clutter density. H-FISST uses no clutter *rate*: the number of clutter
    returns enters only through ``C(m, k) k!``. A sensor's ``PoissonClutter(rate=...)`` therefore
    changes nothing in H-FISST/R-FISST posteriors (rates 0, 2 and 50 give identical ones); only its
    ``region`` (``V``) counts (:attr:`sensor_parameters`). :class:`FISSTPoissonWeights` and
    :class:`ReidWeights` use the rate.

    Notes
    -----
    **Eq. 9 is wrong for M > m.** Document 000 states that ``Σ_j p_ij = 1`` (Eq. 9), assuming
    ``M < m``. Summing Eq. 8 over all ``A(M, m)`` associations actually gives
    ``Σ_{k=0}^{min(M, m)} C(M, k) p_D^k (1 − p_D)^{M−k} = P[Binomial(M, p_D) ≤ m]``, which is 1
    only when ``M ≤ m``: with more objects than returns the prior over associations loses the
    mass of "more detections than returns". The engine implements Eq. 8 as published (the
    lost mass is common to all children of a parent with the same ``M``, but it does change
    the relative weights of parents with different numbers of objects);
    ``tests/unit/hypotheses/test_weights.py`` checks the binomial-CDF sum.
    """

    name = "hfisst"

    @property
    def sensor_parameters(self) -> tuple:
        """``H``, ``R``, ``p_D`` and the clutter region (``g(z) = 1/V``); not the clutter rate."""
        return (*super().sensor_parameters, "clutter.region")

    def option_scores(self, ctx) -> np.ndarray:
        return np.full((ctx.n_returns, 1), ctx.log_clutter_density)

    def count_term(self, ctx, n_objects, n_births):
        return _hfisst_count_term(ctx.n_returns, int(n_objects), int(n_births))


@lru_cache(maxsize=4096)
def _hfisst_count_term(m, n_objects, n_births):
    # A function of three counts, asked for by every parent of every scan: computed once each
    # (read-only, so no caller can change the shared array).
    k, b, ok = _detected_counts(m, n_objects, n_births)
    n = np.minimum(k + b, m)
    # −log(C(m, n) n!) = −log(m! / (m − n)!), Eq. 8 / 31.
    out = np.where(ok, gammaln(m - n + 1) - gammaln(m + 1), -np.inf)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class FISSTPoissonWeights(WeightModel):
    """FISST with Poisson clutter (document 001 Eq. 6–7, 18, 29).

    ``p(σ|n) = p_D^{m−k'} (1 − p_D)^{n−(m−k')} e^{−λV} (λV)^{k'} / k'!`` (Eq. 6) and
    ``l = (k'! / V^{k'}) Π N(z; H x̂⁻, S)`` (Eq. 7) with ``k'`` clutter returns; both factors
    are evaluated as written (the ``k'!`` cancel numerically), so that the equality with
    Reid's weights (document 001 Sec. V-A) is a test, not an identity of the code. Births enter
    through birth columns ``∫ p(z|x) 1_pixel(x)/V̄ dx`` (document 001 Eq. 31, 34).

    Parameters
    ----------
    clutter_rate : float, optional
        Overrides the scan's expected clutter count λV (> 0).
    """

    clutter_rate: float | None = None
    name = "fisst_poisson"

    @property
    def sensor_parameters(self) -> tuple:
        """``H``, ``R``, ``p_D``, the clutter region and (unless overridden here) the clutter rate."""
        return (*super().sensor_parameters, "clutter.region") + (("clutter.rate",) if self.clutter_rate is None else ())

    def option_scores(self, ctx) -> np.ndarray:
        return np.zeros((ctx.n_returns, 1))

    def count_term(self, ctx, n_objects, n_births):
        m = ctx.n_returns
        k, b, ok = _detected_counts(m, n_objects, n_births)
        kc = np.maximum(m - k - b, 0)
        lam_v = check_positive(ctx.clutter_rate if self.clutter_rate is None else self.clutter_rate, "clutter_rate")
        V = ctx.clutter_volume
        log_assoc_prior = -lam_v + kc * np.log(lam_v) - gammaln(kc + 1)  # Eq. 6 (p_D factors in columns)
        log_clutter_lik = gammaln(kc + 1) - kc * np.log(V)  # Eq. 7
        return np.where(ok, log_assoc_prior + log_clutter_lik, -np.inf)


@dataclass(frozen=True)
class ReidWeights(WeightModel):
    """Reid's HOMHT weights (Reid 1979 Eq. 16; document 001 Eq. 30 and 35).

    ``w ∝ w_i p_D^d (1 − p_D)^{n−d} λ_C^{k'} λ_B^{b} Π_assoc N(z; H x̂⁻, S)`` — document 001 writes the
    birth factor as ``(λ_B / p_D)^b`` next to ``p_D^{m−k}``, whose exponent counts the ``b``
    births' returns; the ``p_D`` cancel. The association likelihood is the predictive density
    ``N(z; H x̂⁻, S)``, not the point likelihood at the mean (document 000 Eq. 21 misstates Reid).

    Births come from one of two models, never both:

    * **Reid's own** (``birth_intensity > 0``): births *seeded at their return* (every birth is
      detected; any number per scan) through the row option "new target" with score
      ``log λ_B``; their tracks start from the return (``birth_density.initial_state``).
    * **a population model of the filter** (``birth_intensity = 0`` and the filter's
      ``population``, e.g. document 000's single-event births and deaths, Eq. 30, or document
      001's binomial births and survival, Eq. 31–33 and 59). This is *this project's
      construction*, not Reid's: the objects' factors above are Reid's, unchanged, and the
      population enters exactly as in the FISST weight models — a detected birth in region ``r``
      is an exclusive birth column scored ``log ∫ p(z|x) p_b,r(x) dx + log p_D`` (the pdf of the
      newborn's return, ``1/V̄_r`` for a uniform region, in place of Reid's ``λ_B``), the
      population-event probability (``1 − M_b α − M_d β``, ``α`` or ``β`` for Eq. 30) is added
      to the count term by the filter (:meth:`WeightModel.problem`), and the undetected-birth and
      death *twins* get the population's ratios times ``1 − p_D`` (:mod:`.population_events`).
      Reid's count term is zero, so a child's weight is Reid's product × the population
      event's probability × ``p_D/V̄_r`` per detected birth; with ``α = β = 0`` every birth
      and death child has weight 0 and the association children's weights are the
      fixed-number HOMHT's exactly. It matches document 001 Sec. V's equivalence of FISST and
      Reid (``λ_B ↔ α p_D / V̄``; :mod:`hypotrack.experiments.belief_space`).

    Parameters
    ----------
    birth_intensity : float, optional
        ``λ_B`` ≥ 0, new targets per unit volume per scan; 0 disables Reid's seeded births.
    birth_density : object, optional
        Anything with ``initial_state(z, R) -> (mean, cov)`` (e.g.
        :class:`hypotrack.models.population.UniformBirthDensity`), or a mixture with ``components(z)``
        (one seeded option per component, :mod:`.seeded`); required when ``birth_intensity > 0``.
    clutter_intensity : float, optional
        Overrides the scan's ``λ_C = λV / V``.
    """

    birth_intensity: float = 0.0
    birth_density: object = None
    clutter_intensity: float | None = None
    name = "reid"

    def __post_init__(self):
        object.__setattr__(self, "birth_intensity", check_nonnegative(self.birth_intensity, "birth_intensity"))
        if self.birth_intensity > 0 and not (hasattr(self.birth_density, "initial_state") or
                                             is_mixture(self.birth_density)):
            raise ValueError("birth_density with initial_state(z, R) (or a mixture's components(z)) is required "
                             "when birth_intensity > 0")
        if self.clutter_intensity is not None:
            check_positive(self.clutter_intensity, "clutter_intensity")

    @property
    def seeded_births(self) -> bool:
        return self.birth_intensity > 0

    @property
    def sensor_parameters(self) -> tuple:
        """``H``, ``R``, ``p_D`` and (unless overridden here) ``λ_C``: the clutter rate over the region's volume."""
        return super().sensor_parameters + (() if self.clutter_intensity is not None else
                                            ("clutter.rate", "clutter.region"))

    def uses_birth_columns(self) -> bool:
        """Birth columns of a population model, unless births are Reid's seeded ones."""
        return not self.seeded_births

    def problem(self, ctx, tracks, constant: float = 0.0, population_log_prob=None) -> AssociationProblem:
        if self.seeded_births and ctx.n_birth_regions:
            raise ValueError(
                f"birth_intensity = {self.birth_intensity:g} > 0 (Reid's births seeded at returns) cannot be used "
                f"with a population that has {ctx.n_birth_regions} birth regions: two birth models; "
                "set birth_intensity = 0 to use the population's births"
            )
        return super().problem(ctx, tracks, constant, population_log_prob)

    def option_scores(self, ctx) -> np.ndarray:
        """``(m, T)``: ``log λ_C``, then the seeded births' ``log λ_B`` (+ ``log w_c``), read-only. Every parent of a
        step asks for the same scan's; computed once per context and model (a mixture's weights return by return),
        kept in the context's ``memo``."""
        memo = getattr(ctx, "memo", {})
        mine = memo.get("reid_option_scores")
        if mine is not None and mine[0] is self:
            return mine[1]
        lam_c = check_positive(ctx.clutter_intensity if self.clutter_intensity is None else self.clutter_intensity,
                               "clutter intensity")
        cols = [np.full(ctx.n_returns, np.log(lam_c))]
        if self.seeded_births:  # one column, or one per mixture component (:mod:`.seeded`)
            out = np.hstack([np.stack(cols, axis=1),
                             seeded_option_scores(self.birth_density, ctx.Z, np.log(self.birth_intensity))])
        else:
            out = np.stack(cols, axis=1)
        out.setflags(write=False)  # shared by the parents' problems
        memo["reid_option_scores"] = (self, out)
        return out

    def count_term(self, ctx, n_objects, n_births):
        return np.zeros((n_objects + 1, n_births + 1))


_MODELS = {"hfisst": HFISSTWeights, "fisst_poisson": FISSTPoissonWeights, "reid": ReidWeights}


def make_weight_model(name: str, **kwargs) -> WeightModel:
    """``"hfisst"``, ``"fisst_poisson"`` or ``"reid"`` with its keyword parameters."""
    if name not in _MODELS:
        raise ValueError(f"weight model must be one of {sorted(_MODELS)}, got {name!r}")
    return _MODELS[name](**kwargs)

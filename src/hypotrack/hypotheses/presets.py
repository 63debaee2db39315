"""The papers' trackers as short configurations of :class:`HypothesisFilter`.

=============== ================================= =================================
preset          weight model                       child generator
=============== ================================= =================================
``hfisst``      H-FISST (document 000 Eq. 8, 30–31)     exhaustive (with optional gating)
``rfisst``      H-FISST                             MCMC search (document 000 Sec. III)
``homht``       Reid (document 001 Eq. 30, 35)          exhaustive
``homht_kbest`` Reid                                Murty k-best
``glmb``        δ-GLMB joint prediction–update      Gibbs sampler (Vo, Vo & Hoang 2017)
``glmb_murty``  δ-GLMB joint prediction–update      Murty ranked assignment (Vo & Vo 2014)
=============== ================================= =================================

The HOMHT presets take Reid's births seeded at returns (``birth_intensity``) or a population model
(``population``: document 000 Eq. 30 or document 001's binomial), never both (:class:`~.weights.ReidWeights`).

The ``glmb`` presets need a :class:`~.population_lmb.LabeledMultiBernoulliPopulation` (per-object
survival, labeled-Bernoulli births): with it a hypothesis is a δ-GLMB component (label set and
association history) and the filter is the δ-GLMB filter (DESIGN.md §4.7).

Every preset takes the motion model, the sensor and keyword options of
:class:`HypothesisFilter` (``population``, ``dt``, ``max_hypotheses``, ``cap``,
``gate_probability``, ``seed``, ``means``, ``covs``, ``labels``).
"""

from __future__ import annotations

from ..models.population import SingleEventBirthDeath
from .filter import HypothesisFilter
from .generators import ExhaustiveGenerator, MCMCGenerator, MurtyGenerator
from .gibbs import GibbsGenerator
from .population_events import SingleEventPopulation
from .population_lmb import LabeledMultiBernoulliPopulation
from .weights import HFISSTWeights, ReidWeights
from .weights_glmb import GLMBWeights

__all__ = ["hfisst", "rfisst", "homht", "homht_kbest", "glmb", "glmb_murty"]


def _population(population):
    if isinstance(population, SingleEventBirthDeath):
        return SingleEventPopulation(population)
    return population


def _filter(motion, sensor, weights, generator, population=None, **options):
    return HypothesisFilter(motion, sensor, weights, generator, population=_population(population), **options)


def hfisst(motion, sensor, *, max_events=10**7, population=None, **options) -> HypothesisFilter:
    """H-FISST: every child of every parent, weighted by document 000 Eq. 8/30–31.

    ``population`` may be a :class:`~hypotrack.models.population.SingleEventBirthDeath`
    (document 000 Eq. 30) or a :class:`~.population_events.BinomialPopulation` (document 001).
    The sensor's clutter *rate* is not used: the weights take the clutter density ``1/V`` (the
    clutter region) only (:class:`~.weights.HFISSTWeights`, ``filter.sensor_parameters``).
    """
    return _filter(motion, sensor, HFISSTWeights(), ExhaustiveGenerator(max_events=max_events), population, **options)


def rfisst(motion, sensor, *, n_steps=10_000, burn_in=None, variant="paper", init="random", completion_rounds=2,
           population=None, **options) -> HypothesisFilter:
    """R-FISST: H-FISST weights on the children found by the MCMC search (document 000 Sec. III).

    ``n_steps`` proposals per parent per scan (document 000 Fig. 15 uses 100,000);
    ``completion_rounds`` rounds of this project's neighbour search after the chain
    (:class:`MCMCGenerator`; ``0`` is the paper's chain alone). As for :func:`hfisst`, the
    sensor's clutter *rate* is not used, only the clutter density ``1/V``.
    """
    gen = MCMCGenerator(n_steps=n_steps, burn_in=burn_in, variant=variant, init=init,
                        completion_rounds=completion_rounds)
    return _filter(motion, sensor, HFISSTWeights(), gen, population, **options)


def _reid(birth_intensity, birth_density, population):
    """Reid's weights, refusing two birth models at once (seeded births and population birth regions)."""
    pop = _population(population)
    if birth_intensity and pop is not None and getattr(pop, "n_birth_regions", 0):
        raise ValueError(
            f"birth_intensity must be 0 when population has birth regions (got birth_intensity = {birth_intensity!r} "
            f"and {pop.n_birth_regions} birth regions): Reid's births seeded at returns and the population's "
            "births are two birth models; use one"
        )
    return ReidWeights(birth_intensity=birth_intensity, birth_density=birth_density), pop


def homht(motion, sensor, *, birth_intensity=0.0, birth_density=None, max_events=10**7, population=None,
          **options) -> HypothesisFilter:
    """Reid's HOMHT with exhaustive hypothesis generation (document 001 Eq. 30, 35).

    Births either seeded at returns (``birth_intensity`` ``λ_B`` > 0, Reid's own), or from
    ``population`` — a :class:`~hypotrack.models.population.SingleEventBirthDeath` (document 000
    Eq. 30: the population R-FISST runs with) or a :class:`~.population_events.BinomialPopulation`
    (document 001 Eq. 31–33, 59) — scored as in :class:`~.weights.ReidWeights` (this project's
    construction: Reid's factors for the objects, the population's event probabilities for births
    and deaths). ``None`` and ``birth_intensity = 0``: a fixed number of objects.
    """
    weights, pop = _reid(birth_intensity, birth_density, population)
    return _filter(motion, sensor, weights, ExhaustiveGenerator(max_events=max_events), pop, **options)


def homht_kbest(motion, sensor, *, k=None, birth_intensity=0.0, birth_density=None, population=None,
                **options) -> HypothesisFilter:
    """HOMHT with Murty's k best children per parent (``k`` defaults to ``max_hypotheses``).

    Births and ``population`` as in :func:`homht`. With a population the count term (the event
    probability) differs between "no birth" and "one detected birth", so the k best are found per
    count block and merged (:class:`~.generators.MurtyGenerator`): still the exact k best.
    """
    weights, pop = _reid(birth_intensity, birth_density, population)
    k = options.get("max_hypotheses", 100) if k is None else k
    return _filter(motion, sensor, weights, MurtyGenerator(k=k), pop, **options)


def _labeled(population):
    if not isinstance(population, LabeledMultiBernoulliPopulation):
        raise ValueError("population must be a LabeledMultiBernoulliPopulation for the GLMB presets, "
                         f"got {type(population).__name__}")
    return population


def glmb(motion, sensor, *, population, n_sweeps=1000, **options) -> HypothesisFilter:
    """δ-GLMB filter with the joint prediction–update and Gibbs sampling (Vo, Vo & Hoang 2017):
    ``n_sweeps`` Gibbs samples per parent per scan, distinct ones kept with exact weights."""
    return _filter(motion, sensor, GLMBWeights(), GibbsGenerator(n_sweeps=n_sweeps), _labeled(population), **options)


def glmb_murty(motion, sensor, *, population, k=None, **options) -> HypothesisFilter:
    """δ-GLMB filter truncated by ranked assignment: the ``k`` best children of each parent
    (Murty on the ``P × (m + 2P)`` matrix; ``k`` defaults to ``max_hypotheses``)."""
    k = options.get("max_hypotheses", 100) if k is None else k
    return _filter(motion, sensor, GLMBWeights(), MurtyGenerator(k=k), _labeled(population), **options)

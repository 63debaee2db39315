"""The papers' trackers as short configurations of :class:`HypothesisFilter`.

=============== ================================= =================================
preset          weight model                       child generator
=============== ================================= =================================
``hfisst``      H-FISST (document 000 Eq. 8, 30–31)     exhaustive (with optional gating)
``rfisst``      H-FISST                             MCMC search (document 000 Sec. III)
``homht``       Reid (document 001 Eq. 30, 35)          exhaustive
``homht_kbest`` Reid                                Murty k-best
``fisst_kbest`` FISST, Poisson clutter (001 Eq. 18)   Murty k-best
``glmb``        δ-GLMB joint prediction–update      Gibbs sampler (Vo, Vo & Hoang 2017)
``glmb_murty``  δ-GLMB joint prediction–update      Murty ranked assignment (Vo & Vo 2014)
``pmbm_murty``  PMBM (García-Fernández et al. 2018) Murty k-best per global hypothesis
``pmbm_gibbs``  PMBM                                Gibbs sampler
``pmb_lbp``     PMB (Williams 2015)                 none: LBP association marginals
=============== ================================= =================================

The PMBM presets run :class:`~.pmbm.PMBMFilter` (:mod:`.pmbm`): its hypotheses are Bernoullis with an
existence probability, which the engine's track store does not hold, so it has its own state and step; the
association problem of a global hypothesis is the δ-GLMB preset's object-indexed
:class:`~.AssociationProblem`, and the child generators are the engine's.

The HOMHT presets take Reid's births seeded at returns (``birth_intensity``) or a population model
(``population``: document 000 Eq. 30 or document 001's binomial), never two birth models
(:class:`~.weights.ReidWeights`); seeded births with a population of no birth term give the population's deaths
only (e.g. a binomial population with per-track ``survival``).

The ``glmb`` presets need a :class:`~.population_lmb.LabeledMultiBernoulliPopulation` (per-object
survival, labeled-Bernoulli births): with it a hypothesis is a δ-GLMB component (label set and
association history) and the filter is the δ-GLMB filter (DESIGN.md §4.7).

Every preset takes the motion model, the sensor and keyword options of
:class:`HypothesisFilter` (``population``, ``dt``, ``max_hypotheses``, ``cap``,
``gate_probability``, ``seed``, ``means``, ``covs``, ``labels``).
"""

from __future__ import annotations

import numpy as np

from ..models.population import SingleEventBirthDeath
from .filter import HypothesisFilter
from .generators import ExhaustiveGenerator, MCMCGenerator, MurtyGenerator
from .gibbs import GibbsGenerator
from .pmbm import PMBMFilter
from .population_events import SingleEventPopulation
from .population_lmb import LabeledMultiBernoulliPopulation
from .weights import FISSTPoissonWeights, HFISSTWeights, ReidWeights
from .weights_glmb import GLMBWeights

__all__ = ["hfisst", "rfisst", "homht", "homht_kbest", "fisst_kbest", "glmb", "glmb_murty", "pmbm_murty",
           "pmbm_gibbs", "pmb_lbp", "pmbm_births"]


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


def rfisst(motion, sensor, *, n_steps=10_000, burn_in=None, mcmc_variant="paper", init="random", completion_rounds=2,
           population=None, **options) -> HypothesisFilter:
    """R-FISST: H-FISST weights on the children found by the MCMC search (document 000 Sec. III).

    ``n_steps`` proposals per parent per scan (document 000 Fig. 15 uses 100,000) with the proposal
    ``mcmc_variant`` (``"paper"``: document 000 Sec. III-B) from the start ``init``;
    ``completion_rounds`` rounds of this project's neighbour search after the chain
    (:class:`MCMCGenerator`; ``0`` is the paper's chain alone). As for :func:`hfisst`, the
    sensor's clutter *rate* is not used, only the clutter density ``1/V``.

    Examples
    --------
    Two objects (state ``(x, y, vx, vy)``), a 100 × 100 view with one clutter return expected per
    scan, one scan with a return near each object and one far from both:

    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> view = Box([-50.0, -50.0], [50.0, 50.0])
    >>> sensor = Sensor(LinearPositionSensor(0.5 * np.eye(2), 4), DetectionModel(0.9, view),
    ...                 PoissonClutter(1.0, view))
    >>> means = np.array([[0.0, 0.0, 1.0, 0.0], [20.0, 0.0, 0.0, 1.0]])
    >>> covs = np.repeat(np.eye(4)[None], 2, axis=0)
    >>> Z = np.array([[1.1, 0.2], [19.8, 1.1], [-30.0, 25.0]])
    >>> f = rfisst(ConstantVelocity(0.1), sensor, n_steps=500, means=means, covs=covs, seed=0)
    >>> post = f.step(Z)

    The chain visits a few of the 13 possible associations (``count_associations(2, 3)``), among
    them the maximum-a-posteriori one: both objects detected, the far return clutter.

    >>> len(post.log_weights) <= 13, int(post.n_objects[0]), post.top[0].labels.tolist()
    (True, 2, [0, 1])
    >>> round(post.top[0].weight, 4)
    0.9993
    """
    gen = MCMCGenerator(n_steps=n_steps, burn_in=burn_in, variant=mcmc_variant, init=init,
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

    Examples
    --------
    Two objects (state ``(x, y, vx, vy)``), a 100 × 100 view with one clutter return expected per
    scan, one scan with a return near each object and one far from both:

    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> view = Box([-50.0, -50.0], [50.0, 50.0])
    >>> sensor = Sensor(LinearPositionSensor(0.5 * np.eye(2), 4), DetectionModel(0.9, view),
    ...                 PoissonClutter(1.0, view))
    >>> means = np.array([[0.0, 0.0, 1.0, 0.0], [20.0, 0.0, 0.0, 1.0]])
    >>> covs = np.repeat(np.eye(4)[None], 2, axis=0)
    >>> Z = np.array([[1.1, 0.2], [19.8, 1.1], [-30.0, 25.0]])
    >>> f = homht(ConstantVelocity(0.1), sensor, means=means, covs=covs)
    >>> post = f.step(Z)

    Every association of 2 objects with 3 returns is a hypothesis (``count_associations(2, 3)``):

    >>> len(post.log_weights), int(np.argmax(post.cardinality)), post.top[0].labels.tolist()
    (13, 2, [0, 1])

    The runner-up misses one object (its return clutter; both residuals have length √0.05), at
    ``(1 − p_D) κ / (p_D N(z; ẑ, S))`` times the MAP's weight, ``κ = 10⁻⁴``, ``S = 2.5333 I`` (the
    predicted position variance ``1 + 1 + q/3`` plus ``R``):

    >>> w = np.exp(post.log_weights)
    >>> S = 2 + 0.1 / 3 + 0.5
    >>> N = np.exp(-0.5 * (0.1**2 + 0.2**2) / S) / (2 * np.pi * S)
    >>> bool(np.isclose(w[1] / w[0], 0.1 * 1e-4 / (0.9 * N))), round(post.top[0].weight, 4)
    (True, 0.9996)
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


def fisst_kbest(motion, sensor, *, k=None, population=None, **options) -> HypothesisFilter:
    """FISST weights with Poisson clutter (document 001 Eq. 6–7, 18) on Murty's ``k`` best children per
    parent (``k`` defaults to ``max_hypotheses``); ``population`` as in :func:`hfisst`.

    The GLMB benchmark's "HOMHT k-best" column: with document 001's binomial population it is the
    FISST side of document 001's FISST = HOMHT equivalence, ranked by Murty.
    """
    k = options.get("max_hypotheses", 100) if k is None else k
    return _filter(motion, sensor, FISSTPoissonWeights(), MurtyGenerator(k=k), population, **options)


def _labeled(population):
    if not isinstance(population, LabeledMultiBernoulliPopulation):
        raise ValueError("population must be a LabeledMultiBernoulliPopulation for the GLMB presets, "
                         f"got {type(population).__name__}")
    return population


def glmb(motion, sensor, *, population, n_sweeps=1000, **options) -> HypothesisFilter:
    """δ-GLMB filter with the joint prediction–update and Gibbs sampling (Vo, Vo & Hoang 2017):
    ``n_sweeps`` Gibbs samples per parent per scan, distinct ones kept with exact weights.

    Examples
    --------
    Two objects (state ``(x, y, vx, vy)``), a 100 × 100 view with one clutter return expected per
    scan, one scan with a return near each object and one far from both:

    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> view = Box([-50.0, -50.0], [50.0, 50.0])
    >>> sensor = Sensor(LinearPositionSensor(0.5 * np.eye(2), 4), DetectionModel(0.9, view),
    ...                 PoissonClutter(1.0, view))
    >>> means = np.array([[0.0, 0.0, 1.0, 0.0], [20.0, 0.0, 0.0, 1.0]])
    >>> covs = np.repeat(np.eye(4)[None], 2, axis=0)
    >>> Z = np.array([[1.1, 0.2], [19.8, 1.1], [-30.0, 25.0]])
    >>> from hypotrack.hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation
    >>> birth = GaussianBirthTerm([-30.0, 25.0, 0.0, 0.0], np.diag([4.0, 4.0, 1.0, 1.0]),
    ...                           sensor.measurement.H, sensor.measurement.R)
    >>> population = LabeledMultiBernoulliPopulation([birth], r_birth=0.1, p_survive=0.95)
    >>> f = glmb(ConstantVelocity(0.1), sensor, population=population, n_sweeps=100, means=means, covs=covs,
    ...          seed=0)
    >>> post = f.step(Z)

    The far return is a birth: the MAP cardinality is 3, and two objects (the return clutter, no
    birth) have probability ``0.9 κ / (0.9 κ + 0.1 (0.9 N(z; m_b, 4.5 I) + 0.1 κ)) = 0.027``:

    >>> int(np.argmax(post.cardinality)), post.top[0].labels.tolist(), round(float(post.cardinality[2]), 3)
    (3, [0, 1, 2], 0.027)
    """
    return _filter(motion, sensor, GLMBWeights(), GibbsGenerator(n_sweeps=n_sweeps), _labeled(population), **options)


def glmb_murty(motion, sensor, *, population, k=None, **options) -> HypothesisFilter:
    """δ-GLMB filter truncated by ranked assignment: the ``k`` best children of each parent
    (Murty on the ``P × (m + 2P)`` matrix; ``k`` defaults to ``max_hypotheses``)."""
    k = options.get("max_hypotheses", 100) if k is None else k
    return _filter(motion, sensor, GLMBWeights(), MurtyGenerator(k=k), _labeled(population), **options)


def pmbm_births(population, birth="poisson") -> dict:
    """The :class:`~.pmbm.PMBMFilter` keywords of a labeled multi-Bernoulli birth model: ``p_survive`` and
    the Gaussian birth terms, each term's ``r_B`` the weight of a Poisson birth component (``birth="poisson"``,
    the Poisson process with the same expected number of births per term) or the existence of a Bernoulli
    birth (``birth="bernoulli"``, the δ-GLMB's births). ``None``: no births, ``p_S = 1``."""
    if population is None:
        return {"birth": birth}
    if not isinstance(population, LabeledMultiBernoulliPopulation):
        raise ValueError(f"population must be a LabeledMultiBernoulliPopulation, got {type(population).__name__}")
    if population.survival is not None:
        raise ValueError("population.survival: the PMBM presets take one p_S for every object (p_survive)")
    terms = population.birth_densities
    if not all(hasattr(t, "prior") for t in terms):
        raise ValueError("the PMBM presets need Gaussian birth terms (a prior() -> (mean, cov) each)")
    priors = [t.prior() for t in terms]
    d = len(priors[0][0]) if priors else None
    return {"birth": birth, "p_survive": population.p_survive, "birth_weights": np.asarray(population.r_birth),
            "birth_means": np.array([p[0] for p in priors]).reshape(len(priors), -1) if priors else None,
            "birth_covs": np.array([p[1] for p in priors]).reshape(len(priors), d, d) if priors else None}


def pmbm_murty(motion, sensor, *, population=None, birth="poisson", k=None, **options) -> PMBMFilter:
    """PMBM filter (García-Fernández et al. 2018) with Murty's ``k`` best children of each global hypothesis
    (``k`` defaults to ``max_hypotheses``: then the kept hypotheses are the exact best ``max_hypotheses``).
    ``population``: births and survival (:func:`pmbm_births`); ``options``: :class:`~.pmbm.PMBMFilter`'s.

    Examples
    --------
    Two known objects (state ``(x, y, vx, vy)``), a 100 × 100 view with one clutter return expected per
    scan, a Poisson birth of weight 0.1 at ``(−30, 25)``; one scan with a return near each object and one at
    the birth's mean:

    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> from hypotrack.hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation
    >>> view = Box([-50.0, -50.0], [50.0, 50.0])
    >>> sensor = Sensor(LinearPositionSensor(0.5 * np.eye(2), 4), DetectionModel(0.9, view),
    ...                 PoissonClutter(1.0, view))
    >>> birth = GaussianBirthTerm([-30.0, 25.0, 0.0, 0.0], np.diag([4.0, 4.0, 1.0, 1.0]),
    ...                           sensor.measurement.H, sensor.measurement.R)
    >>> population = LabeledMultiBernoulliPopulation([birth], r_birth=0.1, p_survive=0.95)
    >>> f = pmbm_murty(ConstantVelocity(0.1), sensor, population=population)
    >>> f.initialise([[0.0, 0.0, 1.0, 0.0], [20.0, 0.0, 0.0, 1.0]], np.stack([np.eye(4)] * 2))
    >>> post = f.step(np.array([[1.1, 0.2], [19.8, 1.1], [-30.0, 25.0]]))

    The best global hypothesis holds both objects (detected, ``r = 1``) and the track the third return starts
    (label 4: each return of the scan is given one), a Bernoulli of existence ``e / (κ + e)`` with
    ``e = 0.1 · 0.9 · N(z; H m_b, 4.5 I) = 0.09 / (2π 4.5)`` and ``κ = 10⁻⁴``:

    >>> post.top[0].labels.tolist(), np.round(post.top[0].existence, 4).tolist()
    ([0, 1, 4], [1.0, 1.0, 0.9695])
    >>> e = 0.09 / (2 * np.pi * 4.5)
    >>> round(e / (1e-4 + e), 4), f.estimates().labels.tolist()
    (0.9695, [0, 1, 4])
    """
    k = options.get("max_hypotheses", 100) if k is None else k
    return PMBMFilter(motion, sensor, MurtyGenerator(k=k), **pmbm_births(population, birth), **options)


def pmbm_gibbs(motion, sensor, *, population=None, birth="poisson", n_sweeps=1000, **options) -> PMBMFilter:
    """PMBM filter with the children of each global hypothesis found by ``n_sweeps`` Gibbs sweeps
    (:class:`~.gibbs.GibbsGenerator`: distinct samples, exact weights)."""
    return PMBMFilter(motion, sensor, GibbsGenerator(n_sweeps=n_sweeps), **pmbm_births(population, birth), **options)


def pmb_lbp(motion, sensor, *, population=None, birth="poisson", marginals="lbp", **options) -> PMBMFilter:
    """PMB filter (Williams 2015): the PMBM update collapsed to one multi-Bernoulli by the association
    marginals — loopy belief propagation (``marginals="lbp"``) or ``"exact"`` (every association)."""
    if marginals not in ("lbp", "exact"):
        raise ValueError(f"marginals must be 'lbp' or 'exact', got {marginals!r}")
    return PMBMFilter(motion, sensor, ExhaustiveGenerator(), collapse=marginals, **pmbm_births(population, birth),
                      **options)

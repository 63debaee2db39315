"""SSA experiments, step 2a: the hypothesis filters, built from a named tracker of a config section.

A config section (``ssa50``, ``ssa15``, ``ssa_seeds``) names its trackers under ``trackers``;
each entry's ``kind`` selects the preset (:data:`TRACKER_KINDS`) and the other keys its options.
Each tracker draws from its own random stream (:func:`tracker_seed`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..._validation import check_int, check_positive, check_probability
from ...hypotheses import LabeledMultiBernoulliPopulation, glmb, hfisst, homht, homht_kbest, rfisst
from ...scenarios.ssa import SSAScenario
from ..seeds import experiment_seeds

__all__ = ["TRACKER_KINDS", "TRACKER_NAMES", "TrackerSettings", "make_tracker", "tracker_seed"]

TRACKER_KINDS = ("rfisst", "hfisst", "homht", "glmb")
TRACKER_NAMES = {"rfisst": "R-FISST", "hfisst": "H-FISST", "homht": "HOMHT", "glmb": "GLMB (Gibbs)"}


@dataclass(frozen=True)
class TrackerSettings:
    """How one hypothesis filter of the SSA experiments is configured.

    Parameters
    ----------
    kind : {"rfisst", "hfisst", "homht"}
        R-FISST (H-FISST weights, MCMC search; document 000 Sec. III), H-FISST (exhaustive), or
        Reid's HOMHT (exhaustive or Murty's k best; by default a fixed number of objects: the
        scenario's objects are all in the initial hypothesis).
    max_hypotheses : int
        ``H∞``, hypotheses kept after every scan (document 000 Sec. III-A).
    gate_probability : float or None
        Validation gate ``P_G`` in (0, 1) applied to every track; ``None``: no gating.
    n_steps : int
        MCMC proposals per parent per scan (R-FISST).
    mcmc_variant : {"paper", "symmetric", "gibbs"}
        The MCMC proposal (``"paper"``: document 000 Sec. III-B).
    completion_rounds : int
        Rounds of this project's deterministic neighbour search after the chain
        (:class:`hypotrack.hypotheses.MCMCGenerator`); ``0`` is the paper's chain alone (R-FISST).
    alpha, beta, n_birth_regions, birth_velocity_std :
        Document 000's single-event birth/death model (Eq. 30) of the FISST trackers: birth
        probability per region per scan, death probability per in-view object per scan,
        number of birth regions (the FOV split in equal angles), and the birth velocity
        prior's standard deviation (km/s) around the circular-orbit velocity.
    population : bool
        Use the birth/death model; ``False`` fixes the number of objects. Default ``True`` for
        the FISST trackers and ``False`` for HOMHT, which with ``True`` runs with the same Eq. 30
        births and deaths as R-FISST (:class:`hypotrack.hypotheses.ReidWeights`: Reid's factors for
        the objects, the population's event probabilities; this project's construction).
    max_events : int
        Budget of the exhaustive generators (children per parent).
    k_best : int or None
        HOMHT only: Murty's ``k_best`` best children per parent (:func:`hypotrack.hypotheses.homht_kbest`);
        ``None``: exhaustive. With ``k_best >= max_hypotheses`` the kept hypotheses are the exhaustive
        HOMHT's (the filter keeps the best ``H∞`` children of each parent either way) up to the
        order in which children of equal weight meet the cap.
    n_sweeps : int
        Gibbs samples per parent per scan (``glmb``: the δ-GLMB filter with the labeled
        multi-Bernoulli population built from the same α and birth regions, ``r_B = α`` per
        region, and ``p_S = 1 − β`` for every object at every scan, in view or not).
    """

    kind: str = "rfisst"
    max_hypotheses: int = 100
    gate_probability: float | None = None
    n_steps: int = 10_000
    mcmc_variant: str = "paper"
    completion_rounds: int = 2
    alpha: float = 1e-3
    beta: float = 1e-4
    n_birth_regions: int = 10
    birth_velocity_std: float = 0.5
    population: bool = True
    max_events: int = 10**7
    n_sweeps: int = 1000
    k_best: int | None = None

    def __post_init__(self):
        if self.kind not in TRACKER_KINDS:
            raise ValueError(f"kind must be one of {TRACKER_KINDS}, got {self.kind!r}")
        check_int(self.max_hypotheses, "max_hypotheses", minimum=1)
        if self.gate_probability is not None:
            check_probability(self.gate_probability, "gate_probability", low_open=True, high_open=True)
        check_int(self.n_steps, "n_steps", minimum=1)
        check_int(self.max_events, "max_events", minimum=1)
        check_int(self.completion_rounds, "completion_rounds", minimum=0)
        check_positive(self.birth_velocity_std, "birth_velocity_std")
        if self.k_best is not None:
            check_int(self.k_best, "k_best", minimum=1)
            if self.kind != "homht":
                raise ValueError(f"k_best is a HOMHT option (Murty's k best children), got kind {self.kind!r}")

    @property
    def label(self) -> str:
        """Name for legends and claims, e.g. ``"R-FISST, paper chain"``,
        ``"R-FISST + completion, fixed number"`` or ``"HOMHT with births and deaths"`` (HOMHT's
        default is a fixed number: plain ``"HOMHT"``)."""
        name = TRACKER_NAMES[self.kind]
        if self.kind == "rfisst":
            name += " + completion" if self.completion_rounds else ", paper chain"
        if self.kind == "homht":
            return f"{name} with births and deaths" if self.population else name
        return name if self.population else f"{name}, fixed number"

    @classmethod
    def from_config(cls, section: Mapping, name: str) -> TrackerSettings:
        """Settings of the tracker called ``name`` in an ``ssa50`` / ``ssa15`` config section.

        ``section["trackers"][name]`` gives the ``kind`` and the tracker's own options
        (``n_steps``, ``mcmc_variant``, ``max_events``, ``population``); the section's
        ``max_hypotheses`` and ``gate_probability`` apply to every tracker, and its
        ``population`` block (α, β, regions, birth velocity) to the trackers with births and deaths.
        """
        trackers = section.get("trackers", {})
        if name not in trackers:
            raise ValueError(f"unknown tracker {name!r}; the config section defines {sorted(trackers)}")
        own = dict(trackers[name])
        kind = own.pop("kind")
        population = own.pop("population", kind != "homht")
        pop = dict(section.get("population", {})) if population else {}
        return cls(kind=kind, max_hypotheses=section["max_hypotheses"],
                   gate_probability=section.get("gate_probability"), population=population, **pop, **own)


def tracker_seed(master_seed: int, experiment: str, name: str) -> np.random.Generator:
    """The random generator of tracker ``name`` of ``experiment``, from the master seed.

    :func:`hypotrack.experiments.seeds.experiment_seeds` with the key ``"<experiment>/<name>"``:
    each tracker has its own stream, unchanged when other trackers are added or removed.
    """
    for label, value in (("experiment", experiment), ("name", name)):
        if not isinstance(value, str) or not value:
            raise ValueError(f"{label} must be a non-empty str, got {value!r}")
    return np.random.default_rng(experiment_seeds(master_seed, f"{experiment}/{name}", 1)[0])


def make_tracker(scenario: SSAScenario, settings: TrackerSettings, seed):
    """A :class:`hypotrack.hypotheses.HypothesisFilter` started from the initial hypothesis.

    The objects of the initial hypothesis are labelled with their true ids, so their tracks
    can be checked object by object (:func:`evaluate_map`).
    """
    s = settings
    common = dict(dt=scenario.params.dt, max_hypotheses=s.max_hypotheses, gate_probability=s.gate_probability,
                  seed=seed, means=scenario.prior_means, covs=scenario.prior_covs, labels=scenario.prior_ids)
    population = (scenario.birth_model(s.alpha, s.beta, s.n_birth_regions, s.birth_velocity_std)
                  if s.population else None)
    if s.kind == "homht":
        if s.k_best is not None:
            return homht_kbest(scenario.motion, scenario.sensor, k=s.k_best, population=population, **common)
        return homht(scenario.motion, scenario.sensor, max_events=s.max_events, population=population, **common)
    if s.kind == "glmb":
        if population is None:
            raise ValueError("population must be true for glmb (its births and deaths are the labeled multi-Bernoulli)")
        births = [population.birth_density(r) for r in range(population.n_birth_regions)]
        lmb = LabeledMultiBernoulliPopulation(births, r_birth=s.alpha, p_survive=1.0 - s.beta)
        return glmb(scenario.motion, scenario.sensor, population=lmb, n_sweeps=s.n_sweeps, **common)
    if s.kind == "rfisst":
        return rfisst(scenario.motion, scenario.sensor, n_steps=s.n_steps, variant=s.mcmc_variant,
                      completion_rounds=s.completion_rounds, population=population, **common)
    return hfisst(scenario.motion, scenario.sensor, max_events=s.max_events, population=population, **common)

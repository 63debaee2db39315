"""SSA experiments, step 2a: the hypothesis filters, built from a named tracker of a config section.

A config section (``ssa50``, ``ssa15``, ``ssa_seeds``) names its trackers under ``trackers``;
each entry is a tracker specification of :mod:`hypotrack.registry` (``kind`` plus options, one
vocabulary for every experiment). The section's ``max_hypotheses`` and ``gate_probability`` apply to
every tracker and its ``population`` block (document 000's Eq. 30) is the birth model of the
problem every tracker is built on. Each tracker draws from its own random stream (:func:`tracker_seed`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ...registry import TrackerSpec, TrackingProblem, build, preset
from ...scenarios.ssa import SSAScenario
from ..seeds import experiment_seeds

__all__ = ["TRACKER_KINDS", "TRACKER_NAMES", "TrackerSettings", "make_tracker", "make_problem", "tracker_seed"]

#: The kinds the SSA configs use (any registered kind of the engine family is accepted).
TRACKER_KINDS = ("rfisst", "hfisst", "homht", "homht_kbest", "glmb")
TRACKER_NAMES = {"rfisst": "R-FISST", "hfisst": "H-FISST", "homht": "HOMHT", "homht_kbest": "HOMHT", "glmb": "GLMB (Gibbs)"}
_BIRTH_KEYS = ("alpha", "beta", "n_birth_regions", "birth_velocity_std")


class TrackerSettings:
    """One hypothesis filter of the SSA experiments: a tracker specification and the birth model.

    Parameters
    ----------
    kind : str
        A registered kind of the hypothesis engine (:func:`hypotrack.registry.kinds`), e.g.
        ``"rfisst"`` (document 000 Sec. III), ``"hfisst"``, ``"homht"`` (Reid's; by default a
        fixed number of objects: the scenario's objects are all in the initial hypothesis), ``"glmb"``.
    alpha, beta, n_birth_regions, birth_velocity_std :
        Document 000's single-event birth/death model (Eq. 30) of the trackers with births and
        deaths: birth probability per region per scan, death probability per in-view object per
        scan, number of birth regions (the FOV split in equal angles), and the birth velocity
        prior's standard deviation (km/s) around the circular-orbit velocity. The δ-GLMB filter
        takes it as one labeled-Bernoulli term per region, ``r_B = α``, ``p_S = 1 − β``
        (:meth:`hypotrack.registry.TrackingProblem.labeled_population`).
    **options :
        The kind's options (``presets.yaml`` of :mod:`hypotrack.registry`: ``max_hypotheses``,
        ``gate_probability``, ``population``, ``n_steps``, ``completion_rounds``, ``k``, …),
        validated; a misspelled option is an error naming it.
    """

    def __init__(self, kind: str = "rfisst", *, alpha: float = 1e-3, beta: float = 1e-4, n_birth_regions: int = 10,
                 birth_velocity_std: float = 0.5, **options):
        spec = TrackerSpec.from_config({"kind": kind, **options})
        if preset(kind).family != "engine":
            raise ValueError(f"kind must be a preset of the hypothesis engine for the SSA experiments (their "
                             f"metrics read the posterior), got {kind!r}")
        if not birth_velocity_std > 0:
            raise ValueError(f"birth_velocity_std must be > 0, got {birth_velocity_std!r}")
        self.spec = spec
        self.births = dict(alpha=alpha, beta=beta, n_birth_regions=n_birth_regions,
                           birth_velocity_std=birth_velocity_std)

    def __repr__(self) -> str:
        return f"TrackerSettings({self.spec.to_config()!r}, births={self.births!r})"

    def __getattr__(self, name):
        """The specification's options as attributes (``settings.n_steps``, ``settings.population``)."""
        if name.startswith("__") or name in ("spec", "births"):
            raise AttributeError(name)
        if name == "kind":
            return self.spec.kind
        if name in self.spec.options:
            return self.spec.options[name]
        if name in self.births:
            return self.births[name]
        raise AttributeError(f"{type(self).__name__} has no option {name!r}")

    def with_options(self, **options) -> TrackerSettings:
        """The same settings with some options changed (validated again)."""
        births = {k: options.pop(k, v) for k, v in self.births.items()}
        return TrackerSettings(self.spec.kind, **births, **{**self.spec.options, **options})

    @property
    def label(self) -> str:
        """Name for legends and claims, e.g. ``"R-FISST, paper chain"``,
        ``"R-FISST + completion, fixed number"`` or ``"HOMHT with births and deaths"`` (HOMHT's
        default is a fixed number: plain ``"HOMHT"``)."""
        kind = self.spec.kind
        name = TRACKER_NAMES.get(kind, kind)
        if kind == "rfisst":
            name += " + completion" if self.completion_rounds else ", paper chain"
        if kind in ("homht", "homht_kbest"):  # Reid's filter: a fixed number unless said otherwise
            return f"{name} with births and deaths" if self.population else name
        return name if self.population else f"{name}, fixed number"

    @classmethod
    def from_config(cls, section: Mapping, name: str) -> TrackerSettings:
        """Settings of the tracker called ``name`` in an ``ssa50`` / ``ssa15`` config section.

        ``section["trackers"][name]`` is the tracker's specification; the section's
        ``max_hypotheses`` and ``gate_probability`` apply to every tracker, and its ``population``
        block (α, β, regions, birth velocity) is the birth model.
        """
        trackers = section.get("trackers", {})
        if name not in trackers:
            raise ValueError(f"unknown tracker {name!r}; the config section defines {sorted(trackers)}")
        pop = {k: v for k, v in dict(section.get("population", {})).items() if k in _BIRTH_KEYS}
        own = dict(trackers[name])
        return cls(own.pop("kind"), **pop, **{"max_hypotheses": section["max_hypotheses"],
                                              "gate_probability": section.get("gate_probability"), **own})


def tracker_seed(master_seed: int, experiment: str, name: str) -> np.random.Generator:
    """The random generator of tracker ``name`` of ``experiment``, from the master seed.

    :func:`hypotrack.experiments.seeds.experiment_seeds` with the key ``"<experiment>/<name>"``:
    each tracker has its own stream, unchanged when other trackers are added or removed.
    """
    for label, value in (("experiment", experiment), ("name", name)):
        if not isinstance(value, str) or not value:
            raise ValueError(f"{label} must be a non-empty str, got {value!r}")
    return np.random.default_rng(experiment_seeds(master_seed, f"{experiment}/{name}", 1)[0])


def make_problem(scenario: SSAScenario, settings: TrackerSettings) -> TrackingProblem:
    """The scenario as a :class:`~hypotrack.registry.TrackingProblem`: its EKF and sensor, the objects of
    its initial hypothesis labelled with their true ids (so their tracks can be checked object by
    object, :func:`evaluate_map`), the scan interval and document 000's Eq. 30 birth model."""
    b = settings.births
    births = scenario.birth_model(b["alpha"], b["beta"], b["n_birth_regions"], b["birth_velocity_std"])
    return TrackingProblem(scenario.motion, scenario.sensor, scenario.prior_means, scenario.prior_covs,
                           scenario.prior_ids, time=float(scenario.times[0]), dt=scenario.params.dt, births=births)


def make_tracker(scenario: SSAScenario, settings: TrackerSettings, seed):
    """The tracker of ``settings`` on the scenario (:func:`make_problem`), started from its initial hypothesis."""
    return build(settings.spec, make_problem(scenario, settings), seed=seed)

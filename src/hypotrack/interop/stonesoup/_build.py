"""The hypotrack tracker behind the adapter: construction, GLMB births from Stone Soup states, per-scan settings."""

from __future__ import annotations

import dataclasses

import numpy as np

from ...models.measurement import LinearMeasurement

from ...hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation
from ...models.sensors import DetectionModel, PoissonClutter, Sensor
from ...registry import TrackingProblem, build
from ...trackers import MOfNInitiator, SingleHypothesisTracker
from ._common import LABELED_BIRTHS

__all__ = ["_build", "glmb_population", "scan_settings"]

BIRTH_OPTIONS = ("birth_states", "birth_probability", "survival_probability")


def _build(algorithm, motion, measurement, p_D, clutter_rate, region, means, covs, options):
    """The hypotrack tracker of kind ``algorithm`` (any kind of :mod:`hypotrack.registry`), built there.

    ``options`` are the kind's options (the registry's vocabulary, validated there) plus ``seed`` and,
    for the hypothesis filters, ``population``: a hypotrack population object, the problem's birth
    model (:class:`~hypotrack.registry.TrackingProblem`). The known objects start at time 0 (seconds
    since the adapter's epoch).
    """
    options = dict(options)
    seed = options.pop("seed", None)
    population = options.pop("population", None)
    sensor = Sensor(measurement, DetectionModel(p_D=p_D), PoissonClutter(rate=clutter_rate, region=region))
    problem = TrackingProblem(motion, sensor, means, covs, time=0.0, births=population)
    return build({"kind": algorithm, **options}, problem, seed=seed, where="options")


def glmb_population(algorithm, options, perm, H, R):
    """``options`` with the Stone Soup birth options replaced by a labeled multi-Bernoulli population.

    For the δ-GLMB and Poisson multi-Bernoulli kinds (:data:`LABELED_BIRTHS`) a Stone Soup user describes
    births in Stone Soup's terms:
    ``birth_states`` (``GaussianState``\\s in Stone Soup's state order, one labeled-Bernoulli birth
    term each, observed through the tracker's measurement model), ``birth_probability`` (``r_B``
    per scan, one value or one per term, in (0, 1)) and ``survival_probability`` (``p_S`` per scan,
    in (0, 1], default 1: objects never die). A hypotrack ``population``
    (:class:`~hypotrack.hypotheses.LabeledMultiBernoulliPopulation`, hypotrack's state order) may
    be given instead. Without either, the population has no birth term and ``p_S = 1``. The PMBM kinds take
    each term's ``r_B`` as a Poisson birth weight (their default ``birth: poisson``) or as a Bernoulli birth
    (``birth: bernoulli``), as their registry options say.
    """
    options = dict(options)
    given = [k for k in BIRTH_OPTIONS if k in options]
    if algorithm not in LABELED_BIRTHS:
        if given:
            raise ValueError(f"options {given} describe the labeled population of {LABELED_BIRTHS}; algorithm "
                             f"{algorithm!r} does not take them")
        return options
    if "population" in options:
        if given:
            raise ValueError(f"options: give either population (hypotrack's) or {list(BIRTH_OPTIONS)}, not both")
        return options
    states = list(options.pop("birth_states", None) or [])
    r_birth = options.pop("birth_probability", None if states else 0.5)
    p_survive = options.get("survival_probability", 1.0)
    d = len(perm)
    terms = []
    for k, s in enumerate(states):
        mean, cov = np.asarray(s.state_vector, dtype=float), np.asarray(getattr(s, "covar", None), dtype=float)
        if mean.shape not in ((d,), (d, 1)) or cov.shape != (d, d):
            raise ValueError(f"options['birth_states'][{k}] must be a GaussianState with a {d}-component state "
                             f"vector and a ({d}, {d}) covariance, got shapes {mean.shape} and {cov.shape}")
        try:
            terms.append(GaussianBirthTerm(mean.ravel()[perm], cov[np.ix_(perm, perm)], H, R))
        except ValueError as err:
            raise ValueError(f"options['birth_states'][{k}]: {err}") from None
    if states and r_birth is None:
        raise ValueError("options['birth_probability'] (r_B, the probability that a birth term's object "
                         "appears at a scan, in (0, 1)) is required with birth_states")
    r = np.asarray(r_birth, dtype=float)
    if r.ndim > 1 or (r.ndim == 1 and len(r) != len(terms)) or not np.all((r > 0) & (r < 1)):
        raise ValueError(f"options['birth_probability'] must lie in (0, 1), one value or one per birth state "
                         f"({len(terms)}), got {r_birth!r}")
    try:
        p_survive = float(p_survive)
    except (TypeError, ValueError):
        p_survive = np.nan
    if not 0.0 < p_survive <= 1.0:
        raise ValueError(f"options['survival_probability'] (p_S per scan) must lie in (0, 1], got "
                         f"{options.get('survival_probability', p_survive)!r}")
    population = LabeledMultiBernoulliPopulation(birth_densities=terms, r_birth=r if terms else 0.5,
                                                 p_survive=p_survive)
    options.pop("survival_probability", None)
    options["population"] = population
    return options


def scan_settings(tracker, R=None):
    """``[(object, attribute, value)]`` that run one scan of ``tracker`` with noise covariance ``R``
    (a detection model's, see :class:`DetectionFrame`).

    The hypotrack trackers take one ``H`` and ``R`` at construction; a scan with another ``R`` sets
    it on the tracker (and on the parts that derive quantities from it: the initiator's initial
    covariance, the GLMB birth terms' likelihoods) for that scan only.
    """
    settings = []
    if isinstance(tracker, SingleHypothesisTracker):
        if R is not None:
            model = dataclasses.replace(tracker.model, R=R)
            settings.append((tracker, "model", model))
            ini = tracker.initiator
            if ini is not None:
                template = MOfNInitiator(ini.motion, dataclasses.replace(ini.model, R=R), m=ini.m, n=ini.n,
                                         initial_velocity_std=ini.initial_velocity_std)
                settings += [(ini, "model", template.model), (ini, "P0", template.P0)]
        return settings
    if R is not None:
        settings.append((tracker, "R", np.asarray(R, dtype=float)))
        if isinstance(getattr(tracker, "measurement", None), LinearMeasurement):  # the engine's update reads it
            settings.append((tracker, "measurement", LinearMeasurement(tracker.H, np.asarray(R, dtype=float))))
        pop = getattr(tracker, "population", None)  # the PMBM filters keep their birth intensity as a prior
        if pop is not None and any(isinstance(b, GaussianBirthTerm) for b in pop.birth_densities):
            terms = tuple(dataclasses.replace(b, R=R) if isinstance(b, GaussianBirthTerm) else b
                          for b in pop.birth_densities)
            settings.append((pop, "birth_densities", terms))
    return settings

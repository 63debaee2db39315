"""What the trackers of one experiment share: the models, the known objects, the birth model.

A :class:`TrackingProblem` is handed with a tracker specification to :func:`hypotrack.registry.build`;
each preset takes from it what it needs and expresses the problem's birth model in its own terms
(:meth:`TrackingProblem.event_population`, :meth:`~TrackingProblem.labeled_population`,
:meth:`~TrackingProblem.reid_births`), so one problem serves every preset — the documents'
comparisons on identical terms.

Birth models a problem may carry (``births``):

* ``None`` — a fixed number of objects;
* :class:`~hypotrack.models.population.SingleEventBirthDeath` — document 000's Eq. 30 (at most one
  birth in one of ``M_b`` regions, or one death, per scan);
* :class:`~hypotrack.hypotheses.LabeledMultiBernoulliPopulation` — labeled-Bernoulli birth terms
  with existence ``r_B`` and survival ``p_S`` (the GLMB papers' model);
* :class:`MeasurementBirths` — births started at the returns no track explains (adaptive birth
  terms for the factored δ-GLMB and FISST presets, Reid's births seeded at the returns for HOMHT,
  β_NT for GNN/JPDA).

Several sensors fused: a :class:`MultiSensorProblem` (the shared motion model and known objects, one
:class:`SensorEntry` per sensor: its model, field of view, births), whose
:meth:`~MultiSensorProblem.problem` ``(s)`` is sensor ``s``'s :class:`TrackingProblem`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validation import (check_covariance, check_finite_array, check_int, check_labels, check_positive,
                           check_probability)
from ..hypotheses import BinomialPopulation, LabeledMultiBernoulliPopulation
from ..hypotheses.factored import AdaptiveBirth
from ..models.population import SingleEventBirthDeath

__all__ = ["MeasurementBirths", "MultiSensorProblem", "SensorEntry", "TrackingProblem"]


@dataclass(frozen=True)
class MeasurementBirths:
    """Births started at the returns no track explains.

    Parameters
    ----------
    adaptive : AdaptiveBirth
        The factored engine's measurement-driven birth terms (δ-GLMB and the FISST presets).
    r_birth : float
        Existence of each adaptive birth term, in (0, 1) (the FISST presets' binomial ``α``).
    seeded_intensity : float
        Reid's birth intensity ``λ_B`` per unit measurement volume (HOMHT's births seeded at the
        returns; GNN/JPDA's ``β_NT``), ≥ 0.
    seeded_density : object, optional
        Reid's birth density at a return (e.g. :class:`hypotrack.scenarios.catalogue.tracking.OnePointBirth`).
    survival : callable, optional
        ``survival(means, covs) -> p_S (n,)`` of each predicted track (e.g.
        :class:`hypotrack.hypotheses.UnconfirmedDecay`: a track never confirmed loses existence each scan),
        the death model of every preset: the δ-GLMB presets' labeled multi-Bernoulli survival
        (:meth:`TrackingProblem.labeled_population`), the FISST presets' and HOMHT's binomial survival of
        document 001 (Eq. 59 with each track's own ``p_S``; at most one death per child:
        :meth:`~TrackingProblem.event_population`, :meth:`~TrackingProblem.reid_births`). ``None``: ``p_S = 1``.
    """

    adaptive: AdaptiveBirth
    r_birth: float
    seeded_intensity: float = 0.0
    seeded_density: object = None
    survival: object = None

    def __post_init__(self):
        if not isinstance(self.adaptive, AdaptiveBirth):
            raise TypeError(f"adaptive must be an AdaptiveBirth, got {type(self.adaptive).__name__}")
        check_probability(self.r_birth, "r_birth", low_open=True, high_open=True)
        if not (np.isfinite(self.seeded_intensity) and self.seeded_intensity >= 0):
            raise ValueError(f"seeded_intensity must be a finite number >= 0, got {self.seeded_intensity!r}")
        if self.survival is not None and not callable(self.survival):
            raise TypeError(f"survival must be callable (means, covs -> p_S per track) or None, "
                            f"got {type(self.survival).__name__}")


_BIRTHS = (SingleEventBirthDeath, LabeledMultiBernoulliPopulation, MeasurementBirths)


def _state_dim(m) -> int:
    """The state dimension of measurement model ``m`` (a nonlinear one, with no ``H``, states it)."""
    return m.ndim_state if getattr(m, "linear", True) is False else np.asarray(m.H).shape[1]


@dataclass(frozen=True, eq=False)
class TrackingProblem:
    """The models and known objects every tracker of an experiment shares.

    Parameters
    ----------
    motion : motion model
        ``transition(x, dt)`` and ``Q(dt)``.
    sensor : hypotrack.models.sensors.Sensor or a sensor of the same shape
        ``measurement`` (``H``, ``R``), ``detection`` (``p_D``) and ``clutter`` (rate, region).
    means, covs : array_like, optional
        The objects known at ``time``: ``(n, d)`` means and ``(n, d, d)`` covariances.
    labels : array_like, optional
        Their integer labels (default ``0 .. n − 1``).
    time : float
        Time of the known objects (the first scan may be at this time: an update without prediction).
    dt : float
        The hypothesis filters' default scan interval (> 0).
    births : None, SingleEventBirthDeath, LabeledMultiBernoulliPopulation or MeasurementBirths
        The birth model (module docstring).
    in_view : callable, optional
        ``in_view(x) -> (n,) bool`` for states ``x``: where the sensor sees (single-hypothesis
        trackers count misses there only).
    validity : callable, optional
        ``validity(means) -> (n,) bool``: the physics every hypothesis must satisfy (e.g.
        :func:`hypotrack.models.plausibility.plausible_orbits`: bound, perigee above 100 km); the
        engine's presets give a child holding a track that fails it weight 0 before the cap.
    """

    motion: object
    sensor: object
    means: np.ndarray | None = None
    covs: np.ndarray | None = None
    labels: np.ndarray | None = None
    time: float = 0.0
    dt: float = 1.0
    births: object = None
    in_view: object = field(default=None, repr=False)
    validity: object = field(default=None, repr=False)

    def __post_init__(self):
        d = _state_dim(self.sensor.measurement)
        means = np.zeros((0, d)) if self.means is None else np.asarray(self.means, dtype=float)
        means = check_finite_array(means.reshape(-1, d) if means.size == 0 else means, "means", shape=(None, d))
        n = len(means)
        if self.covs is None:
            if n:
                raise ValueError("covs are required with means")
            covs = np.zeros((0, d, d))
        else:
            covs = np.asarray(self.covs, dtype=float).reshape(-1, d, d)
            if len(covs) != n:
                raise ValueError(f"covs must hold one covariance per mean: {n} means, {len(covs)} covariances")
            if n:
                covs = check_covariance(covs, "covs", dim=d, batched=True)
        labels = np.arange(n, dtype=np.int64) if self.labels is None else check_labels(self.labels, n)
        object.__setattr__(self, "means", means)
        object.__setattr__(self, "covs", covs)
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "time", float(self.time))
        object.__setattr__(self, "dt", check_positive(self.dt, "dt"))
        if self.births is not None and not isinstance(self.births, _BIRTHS):
            raise TypeError("births must be None, a SingleEventBirthDeath, a LabeledMultiBernoulliPopulation or "
                            f"MeasurementBirths, got {type(self.births).__name__}")
        for name in ("in_view", "validity"):
            if getattr(self, name) is not None and not callable(getattr(self, name)):
                raise TypeError(f"{name} must be callable or None, got {type(getattr(self, name)).__name__}")

    @property
    def ndim(self) -> int:
        return self.means.shape[1]

    # ---------------------------------------------------------------- births, per family of presets
    def event_population(self):
        """The birth model as the FISST presets take it (``population`` of :func:`~hypotrack.hypotheses.hfisst`).

        Document 000's Eq. 30 as it is; labeled-Bernoulli terms as document 001's binomial
        population with ``α = r_B`` and the same survival (at most one death or undetected birth
        per child: :mod:`hypotrack.hypotheses.population_lmb`); measurement births as a binomial
        population with no terms of its own (the factored engine's adaptive terms fill it) and the
        births' per-track ``survival`` (``None``: ``p_S = 1``).
        """
        b = self.births
        if b is None or isinstance(b, SingleEventBirthDeath):
            return b
        if isinstance(b, LabeledMultiBernoulliPopulation):
            return BinomialPopulation(list(b.birth_densities), alpha=_scalar(b.r_birth, "r_birth"),
                                      p_survive=b.p_survive)
        return BinomialPopulation([], alpha=b.r_birth, p_survive=1.0, survival=b.survival)

    def labeled_population(self) -> LabeledMultiBernoulliPopulation:
        """The birth model as the δ-GLMB presets take it (a labeled multi-Bernoulli population).

        Document 000's Eq. 30 becomes one labeled-Bernoulli term per birth region with ``r_B = α``
        and ``p_S = 1 − β`` for every object at every scan; measurement births, a population with
        no terms of its own (the factored engine's adaptive terms fill it).
        """
        b = self.births
        if b is None:
            raise ValueError("births: the δ-GLMB presets need a birth model (their births and deaths are the "
                             "labeled multi-Bernoulli's); the problem has none")
        if isinstance(b, LabeledMultiBernoulliPopulation):
            return b
        if isinstance(b, SingleEventBirthDeath):
            terms = [b.birth_density(r) for r in range(b.n_birth_regions)]
            return LabeledMultiBernoulliPopulation(terms, r_birth=b.alpha, p_survive=1.0 - b.beta)
        return LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0, survival=b.survival)

    def reid_births(self) -> dict:
        """The birth model as Reid's HOMHT presets take it: ``population``, or ``birth_intensity`` and
        ``birth_density`` for births seeded at the returns (measurement births) — with the births' per-track
        ``survival``, also a binomial population with no birth term of its own that holds it (deaths only:
        document 001's Eq. 59, each track with its own ``p_S``; the seeded births stay the only births)."""
        b = self.births
        if isinstance(b, MeasurementBirths):
            out = {"birth_intensity": b.seeded_intensity, "birth_density": b.seeded_density}
            if b.survival is not None:
                out["population"] = BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=b.survival)
            return out
        return {"population": self.event_population()}

    def adaptive_birth(self):
        """The factored engine's measurement-driven birth terms (or ``None``)."""
        return self.births.adaptive if isinstance(self.births, MeasurementBirths) else None

    def seeded_intensity(self) -> float:
        """``λ_B`` (``β_NT``) of births seeded at the returns; 0 without measurement births."""
        return self.births.seeded_intensity if isinstance(self.births, MeasurementBirths) else 0.0


def _scalar(value, name):
    a = np.asarray(value, dtype=float)
    if a.ndim and not np.all(a == a.flat[0]):
        raise ValueError(f"{name}: the binomial population takes one birth probability, got {value!r}")
    return float(a.flat[0]) if a.ndim else float(a)


# ------------------------------------------------------------------ several sensors
@dataclass(frozen=True, eq=False)
class SensorEntry:
    """One sensor of a :class:`MultiSensorProblem`: what a :class:`TrackingProblem` holds of its sensor.

    Parameters
    ----------
    sensor : hypotrack.models.sensors.Sensor or a sensor of the same shape
        Its measurement model and frame (``H``, ``R``, or a nonlinear model), detection (``detection.p_D``, a
        constant, and optionally ``detection.p_D_of(means) -> (n,)``, ``p_D`` as a function of the state) and
        clutter (rate, region).
    in_view : callable
        ``in_view(x) -> (n,) bool``: where this sensor sees. Required: a sensor of several sees part of the scene,
        and GNN/JPDA count a miss of its scan only there (:mod:`hypotrack.trackers.multisensor`). The hypothesis
        filters see through ``sensor.detection`` (``p_D`` 0 outside its field of view), which should agree.
    births : None, SingleEventBirthDeath, LabeledMultiBernoulliPopulation or MeasurementBirths
        The birth model of this sensor's scans (e.g. births started at *its* returns; :class:`TrackingProblem`).
    """

    sensor: object
    in_view: object = field(repr=False)
    births: object = None


@dataclass(frozen=True, eq=False)
class MultiSensorProblem:
    """The models and known objects the trackers of several fused sensors share, and one :class:`SensorEntry` per
    sensor. :func:`hypotrack.registry.build` makes one tracker per sensor on :meth:`problem` ``(s)`` (a
    :class:`TrackingProblem`: the shared parts and sensor ``s``'s) and fuses them; the tracker's
    ``step(Z, time, sensor=s)`` takes a scan of sensor ``s``.

    A sibling of :class:`TrackingProblem`, not an extension of it: a preset's builder reads one ``sensor``,
    ``in_view`` and ``births`` from its problem, and keeps doing so — it is handed each sensor's problem in turn.

    Parameters
    ----------
    motion : motion model
        The one motion model of every sensor's tracker (the fused trackers share it).
    sensors : sequence of SensorEntry
        One per sensor, at least one; every sensor's measurement model of the same state dimension; the births of
        every sensor of one kind (``None`` for all, or one type; measurement births with one ``r_birth``).
    means, covs, labels, time, dt, validity
        As :class:`TrackingProblem`'s (shared by the sensors).

    Examples
    --------
    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> def sensor(r, x0, x1):
    ...     s = Sensor(LinearPositionSensor(np.eye(2) * r, ndim_state=4), DetectionModel(0.9, Box([x0, -50], [x1, 50])),
    ...                PoissonClutter(1.0, Box([x0, -50], [x1, 50])))
    ...     return SensorEntry(s, in_view=lambda x: (x[:, 0] >= x0) & (x[:, 0] <= x1))
    >>> problem = MultiSensorProblem(ConstantVelocity(0.1), [sensor(1.0, -50, 10), sensor(0.2, -10, 50)],
    ...                              means=[[0, 0, 1, 0]], covs=np.eye(4)[None])
    >>> problem.n_sensors, float(problem.problem(1).sensor.measurement.R[0, 0])
    (2, 0.2)
    >>> MultiSensorProblem(ConstantVelocity(0.1), [])
    Traceback (most recent call last):
    ...
    ValueError: sensors must hold one SensorEntry per sensor, got none
    """

    motion: object
    sensors: tuple
    means: np.ndarray | None = None
    covs: np.ndarray | None = None
    labels: np.ndarray | None = None
    time: float = 0.0
    dt: float = 1.0
    validity: object = field(default=None, repr=False)

    def __post_init__(self):
        if isinstance(self.sensors, (str, bytes, SensorEntry)) or not hasattr(self.sensors, "__iter__"):
            raise TypeError(f"sensors must be a sequence of SensorEntry (one per sensor), got "
                            f"{type(self.sensors).__name__}")
        sensors = tuple(self.sensors)
        if not sensors:
            raise ValueError("sensors must hold one SensorEntry per sensor, got none")
        dims = []
        for i, e in enumerate(sensors):
            _check_entry(e, i)
            dims.append(_state_dim(e.sensor.measurement))
            if dims[i] != dims[0]:
                raise ValueError(f"sensors[{i}].sensor.measurement is of {dims[i]}-D states, sensors[0]'s of "
                                 f"{dims[0]}-D: the fused sensors observe one state")
            kind, first = type(e.births), type(sensors[0].births)
            if kind is not first:
                raise ValueError(f"sensors[{i}].births is a {kind.__name__}, sensors[0].births a {first.__name__}: "
                                 "the fused tracker has one birth model, its terms per sensor (births of one kind "
                                 "for every sensor, or None for every sensor)")
            if isinstance(e.births, MeasurementBirths) and e.births.r_birth != sensors[0].births.r_birth:
                raise ValueError(f"sensors[{i}].births.r_birth = {e.births.r_birth} must equal "
                                 f"sensors[0].births.r_birth = {sensors[0].births.r_birth} (one existence of a "
                                 "measurement-driven birth term)")
        problems = tuple(TrackingProblem(self.motion, e.sensor, self.means, self.covs, self.labels, time=self.time,
                                         dt=self.dt, births=e.births, in_view=e.in_view, validity=self.validity)
                         for e in sensors)
        first = problems[0]
        object.__setattr__(self, "sensors", sensors)
        object.__setattr__(self, "_problems", problems)
        for name in ("means", "covs", "labels", "time", "dt"):
            object.__setattr__(self, name, getattr(first, name))

    @classmethod
    def from_problems(cls, problems) -> "MultiSensorProblem":
        """The problem of several single-sensor ``problems`` (one :class:`TrackingProblem` per sensor) that share their
        motion model and physics test (the same objects), known objects, time and scan interval; each gives its
        sensor, field of view and births (:class:`SensorEntry`)."""
        problems = list(problems)
        if not problems:
            raise ValueError("problems must hold one TrackingProblem per sensor, got none")
        for i, p in enumerate(problems):
            if not isinstance(p, TrackingProblem):
                raise TypeError(f"problems[{i}] must be a TrackingProblem, got {type(p).__name__}")
        p0 = problems[0]
        for i, p in enumerate(problems[1:], 1):
            for name in ("motion", "validity"):
                if getattr(p, name) is not getattr(p0, name):
                    raise ValueError(f"problems[{i}].{name} must be problems[0].{name} (the same object): the fused "
                                     "trackers share it")
            for name in ("means", "covs", "labels", "time", "dt"):
                a, b = getattr(p, name), getattr(p0, name)
                if np.shape(a) != np.shape(b) or not np.array_equal(a, b):
                    raise ValueError(f"problems[{i}].{name} must equal problems[0].{name}: the sensors share the "
                                     "known objects, their time and the scan interval")
        return cls(p0.motion, [SensorEntry(p.sensor, p.in_view, p.births) for p in problems], p0.means, p0.covs,
                   p0.labels, time=p0.time, dt=p0.dt, validity=p0.validity)

    @property
    def n_sensors(self) -> int:
        return len(self.sensors)

    @property
    def ndim(self) -> int:
        return self.means.shape[1]

    @property
    def problems(self) -> tuple:
        """One :class:`TrackingProblem` per sensor (:meth:`problem`)."""
        return self._problems

    def problem(self, sensor: int) -> TrackingProblem:
        """Sensor ``sensor``'s :class:`TrackingProblem`: the shared motion model, known objects, time, interval and
        physics test with that sensor's model, field of view and births."""
        return self._problems[check_int(sensor, "sensor", minimum=0, maximum=self.n_sensors - 1)]


def _check_entry(e, i: int) -> None:
    """Sensor ``i``'s entry: an error naming the parameter (``sensors[i]....``) otherwise."""
    if not isinstance(e, SensorEntry):
        raise TypeError(f"sensors[{i}] must be a SensorEntry, got {type(e).__name__}")
    if e.in_view is None:
        raise ValueError(f"sensors[{i}].in_view is required: in_view(x) -> (n,) bool, where the sensor sees (a "
                         "sensor of several sees part of the scene)")
    if not callable(e.in_view):
        raise TypeError(f"sensors[{i}].in_view must be callable (x -> (n,) bool), got {type(e.in_view).__name__}")
    for name in ("measurement", "detection"):
        if getattr(e.sensor, name, None) is None:
            raise TypeError(f"sensors[{i}].sensor must have a {name} model, got {type(e.sensor).__name__}")
    p_of = getattr(e.sensor.detection, "p_D_of", None)
    if p_of is not None and not callable(p_of):
        raise TypeError(f"sensors[{i}].sensor.detection.p_D_of must be callable (means -> p_D per track) or absent, "
                        f"got {type(p_of).__name__}")
    if e.births is not None and not isinstance(e.births, _BIRTHS):
        raise TypeError(f"sensors[{i}].births must be None, a SingleEventBirthDeath, a "
                        f"LabeledMultiBernoulliPopulation or MeasurementBirths, got {type(e.births).__name__}")

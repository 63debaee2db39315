"""One tracker from a specification and a problem: the registry's single construction path.

On a :class:`~.problem.MultiSensorProblem` the tracker is the fused one: the preset's builder makes one tracker per
sensor (on :meth:`~.problem.MultiSensorProblem.problem` ``(s)``) and the family's multi-sensor form joins them —
:class:`~hypotrack.hypotheses.factored.multisensor.MultiSensorFactored` for the ``engine`` family (on the factored
engine: ``factored`` options are required), :class:`~hypotrack.trackers.multisensor.MultiSensorSHT` for the
``single`` family. The ``poisson_mb`` family and a kind whose preset states ``no_fusion`` have no fused form.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..hypotheses import HypothesisFilter
from ..hypotheses.factored import FactoredFilter
from ..hypotheses.factored.multisensor import MultiSensorFactored
from ..trackers import SingleHypothesisTracker
from ..trackers.multisensor import MultiSensorSHT
from .problem import MultiSensorProblem, TrackingProblem
from .spec import TrackerSpec, preset

__all__ = ["build", "FUSED"]

#: The families with a multi-sensor form: what each sensor's tracker must be, and the fused tracker's class.
FUSED = {"engine": (HypothesisFilter, MultiSensorFactored), "single": (SingleHypothesisTracker, MultiSensorSHT)}


def build(spec, problem: TrackingProblem | MultiSensorProblem, *, seed=None, where: str = ""):
    """The tracker of ``spec`` (a :class:`TrackerSpec` or a config mapping ``{kind: ..., ...}``) on ``problem``.

    The preset's builder makes the tracker; with ``factored`` options an engine preset runs on the
    factored engine (:class:`~hypotrack.hypotheses.factored.FactoredFilter`, with the problem's
    adaptive birth terms when its birth model has them and the preset a population); the known
    objects of the problem are then given to it (``initialise(means, covs, labels, time=...)``).
    ``seed`` (an int, a ``SeedSequence`` or a ``numpy.random.Generator``) feeds every random draw.
    Returns a :class:`hypotrack.protocol.Tracker`. On a :class:`~.problem.MultiSensorProblem`, the fused
    tracker of the module docstring (its ``step(Z, time, sensor=s)`` takes a scan of sensor ``s``):
    :func:`build_fused`.

    Examples
    --------
    >>> import numpy as np
    >>> from hypotrack.models import ConstantVelocity
    >>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    >>> from hypotrack.registry import TrackingProblem, build
    >>> sensor = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4, position_indices=(0, 1)),
    ...                 DetectionModel(0.9), PoissonClutter(2.0, Box([-50, -50], [50, 50])))
    >>> problem = TrackingProblem(ConstantVelocity(0.1), sensor, means=[[0, 0, 1, 0], [10, 0, -1, 0]],
    ...                           covs=np.stack([np.eye(4)] * 2), labels=[7, 9])
    >>> tracker = build({"kind": "homht", "max_hypotheses": 10}, problem, seed=1)
    >>> _ = tracker.step(np.array([[1.1, 0.2], [9.0, -0.1], [30.0, 30.0]]), 1.0)
    >>> est = tracker.estimates()
    >>> est.labels.tolist(), np.round(est.x[:, 0], 1).tolist()
    ([7, 9], [1.1, 9.0])
    """
    if isinstance(problem, MultiSensorProblem):
        return build_fused(spec, problem, seed=seed, where=where)
    if not isinstance(problem, TrackingProblem):
        raise TypeError(f"problem must be a TrackingProblem or a MultiSensorProblem, got {type(problem).__name__}")
    spec = _spec(spec, where)
    options = dict(spec.options)
    p = preset(spec.kind)
    factored = options.pop("factored", None) if p.family == "engine" else None
    tracker = p.builder(problem, seed=seed, **options)
    tracker.initialise(problem.means, problem.covs, problem.labels, time=problem.time)
    if factored is not None:
        if not isinstance(tracker, HypothesisFilter):
            raise ValueError(f"{where or spec.kind}.factored: kind {spec.kind!r} does not build a hypothesis "
                             "filter, so it cannot run on the factored engine")
        adaptive = problem.adaptive_birth() if _takes_adaptive(tracker) else None
        tracker = FactoredFilter.from_filter(tracker, adaptive_birth=adaptive, **factored)
    return tracker


def _spec(spec, where: str) -> TrackerSpec:
    if isinstance(spec, TrackerSpec):
        return spec
    if not isinstance(spec, Mapping):
        raise TypeError(f"spec must be a TrackerSpec or a mapping with a 'kind', got {type(spec).__name__}")
    return TrackerSpec.from_config(spec, where)


def build_fused(spec, problem: MultiSensorProblem, *, seed=None, where: str = ""):
    """The fused tracker of ``spec`` on the sensors of ``problem`` (module docstring).

    One tracker per sensor from the preset's builder on that sensor's problem, each given the known objects and
    ``seed`` (the fused tracker draws from the first one's generator, which it copies or shares); then
    :meth:`MultiSensorFactored.from_filters` with each sensor's adaptive birth terms (when the preset has a
    population) and the ``factored`` options, or :meth:`MultiSensorSHT.from_trackers`. A kind that cannot fuse is a
    ``ValueError`` naming it.
    """
    if not isinstance(problem, MultiSensorProblem):
        raise TypeError(f"problem must be a MultiSensorProblem, got {type(problem).__name__}")
    spec = _spec(spec, where)
    p, at = preset(spec.kind), where or spec.kind
    if p.no_fusion:
        raise ValueError(f"{at}: kind {spec.kind!r} cannot fuse several sensors: {p.no_fusion}")
    if p.family not in FUSED:
        raise ValueError(f"{at}: kind {spec.kind!r} (family {p.family}) has no multi-sensor form; the kinds of the "
                         f"{' and '.join(FUSED)} families fuse (MultiSensorFactored, MultiSensorSHT)")
    options = dict(spec.options)
    factored = options.pop("factored", None) if p.family == "engine" else None
    if p.family == "engine" and factored is None:
        raise ValueError(f"{at}.factored: kind {spec.kind!r} fuses sensors on the factored engine "
                         "(MultiSensorFactored): give factored options ({} for their defaults)")
    member, fused = FUSED[p.family]
    trackers = []
    for s, sp in enumerate(problem.problems):
        t = p.builder(sp, seed=seed, **options)
        if not isinstance(t, member):
            raise ValueError(f"{at}: kind {spec.kind!r} built a {type(t).__name__} for sensors[{s}], not a "
                             f"{member.__name__}: its {p.family} family's fused tracker ({fused.__name__}) needs one")
        t.initialise(sp.means, sp.covs, sp.labels, time=sp.time)
        trackers.append(t)
    if p.family == "single":
        return MultiSensorSHT.from_trackers(trackers)
    births = [sp.adaptive_birth() if _takes_adaptive(t) else None for sp, t in zip(problem.problems, trackers)]
    return MultiSensorFactored.from_filters(trackers, births, **factored)


def _takes_adaptive(tracker) -> bool:
    """Whether a preset's filter takes the problem's adaptive birth terms: it has a population and no births
    seeded at the returns (HOMHT's population then only holds the tracks' survival, :meth:`TrackingProblem.reid_births`)."""
    return tracker.population is not None and not getattr(tracker.weights, "seeded_births", False)

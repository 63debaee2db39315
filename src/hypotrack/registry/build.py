"""One tracker from a specification and a problem: the registry's single construction path."""

from __future__ import annotations

from collections.abc import Mapping

from ..hypotheses import HypothesisFilter
from ..hypotheses.factored import FactoredFilter
from .problem import TrackingProblem
from .spec import TrackerSpec, preset

__all__ = ["build"]


def build(spec, problem: TrackingProblem, *, seed=None, where: str = ""):
    """The tracker of ``spec`` (a :class:`TrackerSpec` or a config mapping ``{kind: ..., ...}``) on ``problem``.

    The preset's builder makes the tracker; with ``factored`` options an engine preset runs on the
    factored engine (:class:`~hypotrack.hypotheses.factored.FactoredFilter`, with the problem's
    adaptive birth terms when its birth model has them and the preset a population); the known
    objects of the problem are then given to it (``initialise(means, covs, labels, time=...)``).
    ``seed`` (an int, a ``SeedSequence`` or a ``numpy.random.Generator``) feeds every random draw.
    Returns a :class:`hypotrack.protocol.Tracker`.

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
    if not isinstance(problem, TrackingProblem):
        raise TypeError(f"problem must be a TrackingProblem, got {type(problem).__name__}")
    if not isinstance(spec, TrackerSpec):
        if not isinstance(spec, Mapping):
            raise TypeError(f"spec must be a TrackerSpec or a mapping with a 'kind', got {type(spec).__name__}")
        spec = TrackerSpec.from_config(spec, where)
    options = dict(spec.options)
    p = preset(spec.kind)
    factored = options.pop("factored", None) if p.family == "engine" else None
    tracker = p.builder(problem, seed=seed, **options)
    tracker.initialise(problem.means, problem.covs, problem.labels, time=problem.time)
    if factored is not None:
        if not isinstance(tracker, HypothesisFilter):
            raise ValueError(f"{where or spec.kind}.factored: kind {spec.kind!r} does not build a hypothesis "
                             "filter, so it cannot run on the factored engine")
        adaptive = problem.adaptive_birth() if tracker.population is not None else None
        tracker = FactoredFilter.from_filter(tracker, adaptive_birth=adaptive, **factored)
    return tracker

"""hypotrack's trackers as Stone Soup trackers (Stone Soup >= 1.9, optional dependency).

A Stone Soup user keeps Stone Soup's vocabulary — a *detector* yielding ``(time, detections)``,
a ``CombinedLinearGaussianTransitionModel`` and a ``LinearGaussian`` measurement model — and swaps
the tracker::

    from hypotrack.interop.stonesoup import HypotrackTracker

    tracker = HypotrackTracker(
        detector=detection_sim, transition_model=transition_model, measurement_model=measurement_model,
        algorithm="rfisst", detection_probability=0.9, clutter_rate=3.0, clutter_region=[[-50, 50], [-50, 50]],
        initial_states=priors, options={"n_steps": 2000, "max_hypotheses": 50, "seed": 1})
    for time, tracks in tracker:                # Stone Soup Tracks with stable ids
        ...

The models are translated **once**, at construction (:func:`translate_models`): Stone Soup orders a
2-D nearly-constant-velocity state ``[x, vx, y, vy]`` (one ``ConstantVelocity`` per axis), hypotrack
``[x, y, vx, vy]`` (:class:`hypotrack.models.ConstantVelocity`); the adapter keeps the permutation
and maps states in and out, so inside it runs exactly hypotrack's own API on numpy scans. Both
libraries' constant-velocity model is ``Q(dt) = q [[dt³/3, dt²/2], [dt²/2, dt]]`` per axis. A
detection carrying its own ``measurement_model`` is translated once per model object
(:class:`~._models.DetectionFrame`): linear-Gaussian models of the same measured components (any
order, any noise) are honoured, anything else raises ``ValueError`` naming ``measurement_model``.

Algorithms: ``gnn``, ``jpda``, ``pdaf`` (:class:`hypotrack.trackers.SingleHypothesisTracker`;
tracks are its confirmed tracks) and ``hfisst``, ``rfisst``, ``homht``, ``homht_kbest``, ``glmb``,
``glmb_murty`` (the presets of :mod:`hypotrack.hypotheses`; tracks are the objects of the
maximum-a-posteriori hypothesis, a track id being the object's label, so an object keeps its id
while it is in the MAP hypothesis). The δ-GLMB presets take their labeled multi-Bernoulli births
in Stone Soup's terms through ``options`` (``birth_states``, ``birth_probability``,
``survival_probability``). Clutter is Poisson with ``clutter_rate`` returns per scan, uniform over
``clutter_region`` (Stone Soup's ``SimpleDetectionSimulator`` ``meas_range``).

Tracks hold Stone Soup's state types: a ``GaussianStateUpdate`` (with the hypothesis: prediction
and ``Detection``) for a scan at which the object was associated with a detection, a
``GaussianStatePrediction`` for a missed scan. Scan times follow Stone Soup's predictors: a scan
at the previous scan's time (or a first scan at the priors' time) is an additional scan with no
prediction; see :class:`HypotrackTracker` for the rules.

Detections of a scan are a Python ``set`` in Stone Soup; they are sorted (lexicographically by
measurement) before they reach the tracker, so a seeded run is reproducible.
"""

from __future__ import annotations

# _build and _region are the pieces interop.benchmark builds its own-API runs from.
from ._build import _build  # noqa: F401
from ._common import ALGORITHMS, GLMB, HYPOTHESIS_FILTERS, SINGLE_HYPOTHESIS  # noqa: F401
from ._models import DetectionFrame, _region, translate_models  # noqa: F401

__all__ = ["ALGORITHMS", "HypotrackTracker", "TrajectoryGOSPAMetric", "translate_models"]  # noqa: F822 (module __getattr__)

_CLASS = None


def __getattr__(name):
    # The Stone Soup subclass is built on first use so that importing hypotrack never needs Stone Soup.
    global _CLASS
    if name == "HypotrackTracker":
        if _CLASS is None:
            from ._tracker import tracker_class

            _CLASS = tracker_class()
        return _CLASS
    if name == "TrajectoryGOSPAMetric":  # trajectory GOSPA as a Stone Soup metric generator (.metric)
        from .metric import metric_class

        return metric_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

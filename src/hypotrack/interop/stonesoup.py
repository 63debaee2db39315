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
libraries' constant-velocity model is ``Q(dt) = q [[dt³/3, dt²/2], [dt²/2, dt]]`` per axis.

Algorithms: ``gnn``, ``jpda``, ``pdaf`` (:class:`hypotrack.trackers.SingleHypothesisTracker`;
tracks are its confirmed tracks) and ``hfisst``, ``rfisst``, ``homht``, ``homht_kbest`` (the
presets of :mod:`hypotrack.hypotheses`; tracks are the objects of the maximum-a-posteriori
hypothesis, a track id being the object's label, so an object keeps its id while it is in the MAP
hypothesis). Clutter is Poisson with ``clutter_rate`` returns per scan, uniform over
``clutter_region`` (Stone Soup's ``SimpleDetectionSimulator`` ``meas_range``).

Detections of a scan are a Python ``set`` in Stone Soup; they are sorted (lexicographically by
measurement) before they reach the tracker, so a seeded run is reproducible.
"""

from __future__ import annotations

import datetime

import numpy as np

from ..hypotheses import presets
from ..models import ConstantVelocity
from ..models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from ..trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker

__all__ = ["ALGORITHMS", "HypotrackTracker", "translate_models"]  # noqa: F822 (module __getattr__)

SINGLE_HYPOTHESIS = ("gnn", "jpda", "pdaf")
HYPOTHESIS_FILTERS = ("hfisst", "rfisst", "homht", "homht_kbest")
ALGORITHMS = SINGLE_HYPOTHESIS + HYPOTHESIS_FILTERS


def _require_stonesoup():
    try:
        import stonesoup  # noqa: F401
    except ImportError as err:  # pragma: no cover - exercised only without Stone Soup
        raise ImportError(
            "hypotrack.interop.stonesoup needs Stone Soup (>= 1.9): pip install 'hypotrack[stonesoup]'"
        ) from err


def translate_models(transition_model, measurement_model):
    """Translate Stone Soup models into hypotrack's, once.

    Parameters
    ----------
    transition_model : stonesoup CombinedLinearGaussianTransitionModel or ConstantVelocity
        One ``ConstantVelocity`` per spatial axis (1 to 3), all with the same ``noise_diff_coeff``.
    measurement_model : stonesoup LinearGaussian
        Position measurement: ``mapping`` selects position components, ``noise_covar`` is ``R``.

    Returns
    -------
    motion : hypotrack.models.ConstantVelocity
    measurement : hypotrack.models.sensors.LinearPositionSensor
    perm : (d,) int array
        hypotrack state component ``i`` is Stone Soup component ``perm[i]``.
    """
    _require_stonesoup()
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel
    from stonesoup.models.transition.linear import ConstantVelocity as SSConstantVelocity

    parts = (
        list(transition_model.model_list)
        if isinstance(transition_model, CombinedLinearGaussianTransitionModel) else [transition_model]
    )
    if not 1 <= len(parts) <= 3 or not all(type(p) is SSConstantVelocity for p in parts):
        raise ValueError(
            "transition_model must be a ConstantVelocity or a CombinedLinearGaussianTransitionModel of 1 to 3 "
            f"ConstantVelocity models, got {[type(p).__name__ for p in parts]}"
        )
    qs = {float(p.noise_diff_coeff) for p in parts}
    if len(qs) != 1:
        raise ValueError(f"transition_model: every axis must share one noise_diff_coeff, got {sorted(qs)}")
    k = len(parts)
    perm = np.concatenate([2 * np.arange(k), 2 * np.arange(k) + 1])  # [x, y, ..] then [vx, vy, ..]
    inverse = np.argsort(perm)
    if int(measurement_model.ndim_state) != 2 * k:
        raise ValueError(
            f"measurement_model.ndim_state must be {2 * k} (the transition model's), got {measurement_model.ndim_state}"
        )
    position_indices = tuple(int(inverse[i]) for i in measurement_model.mapping)
    R = np.asarray(measurement_model.covar(), dtype=float)
    measurement = LinearPositionSensor(R, ndim_state=2 * k, position_indices=position_indices)
    return ConstantVelocity(q=qs.pop(), n_spatial=k), measurement, perm


def _region(clutter_region, dim):
    region = np.asarray(clutter_region, dtype=float)
    if region.shape != (dim, 2):
        raise ValueError(f"clutter_region must have shape ({dim}, 2) ([[low, high], ...] per measured axis), "
                         f"got {region.shape}")
    return Box(region[:, 0], region[:, 1])


def _build(algorithm, motion, measurement, p_D, clutter_rate, region, means, covs, options):
    """The hypotrack tracker, constructed exactly as a hypotrack user would."""
    options = dict(options)
    if algorithm in SINGLE_HYPOTHESIS:
        initiation = options.pop("initiator", None)
        model = ScanModel(measurement.H, measurement.R, p_D, options.pop("p_gate", 0.99), clutter_rate / region.area,
                          options.pop("new_target_density", 0.0))
        initiator = None if initiation is None else MOfNInitiator(motion, model, **initiation)
        tracker = SingleHypothesisTracker(motion, model, association=algorithm, initiator=initiator, **options)
        tracker.initialise(means, covs, time=0.0)
        return tracker
    sensor = Sensor(measurement, DetectionModel(p_D=p_D), PoissonClutter(rate=clutter_rate, region=region))
    return getattr(presets, algorithm)(motion, sensor, means=means, covs=covs, **options)


def _tracker_class():
    _require_stonesoup()
    from stonesoup.base import Property
    from stonesoup.tracker.base import Tracker
    from stonesoup.types.state import GaussianState
    from stonesoup.types.track import Track

    class HypotrackTracker(Tracker):
        """A hypotrack tracker driven by a Stone Soup detector (see :mod:`hypotrack.interop.stonesoup`).

        ``options`` go to the hypotrack constructor: for ``gnn``/``jpda``/``pdaf`` those of
        :class:`~hypotrack.trackers.SingleHypothesisTracker` plus ``p_gate``, ``new_target_density``
        and ``initiator`` (a dict of :class:`~hypotrack.trackers.MOfNInitiator` options, or absent for
        no initiation); for the hypothesis filters those of the preset (``n_steps``,
        ``max_hypotheses``, ``gate_probability``, ``population``, ``seed``, ...).
        """

        transition_model = Property(object, doc="CombinedLinearGaussianTransitionModel of ConstantVelocity.")
        measurement_model = Property(object, doc="LinearGaussian position measurement model.")
        algorithm: str = Property(doc=f"One of {ALGORITHMS}.")
        detection_probability: float = Property(doc="P_D of every object, in (0, 1).")
        clutter_rate: float = Property(doc="Expected clutter returns per scan (> 0).")
        clutter_region = Property(object, doc="[[low, high], ...] per measured axis: where clutter falls.")
        detector = Property(object, default=None, doc="Detector yielding (time, set of detections).")
        initial_states = Property(list, default=None,
                                  doc="GaussianStates of the objects known at the start (ids 0, 1, ...).")
        options: dict = Property(default=None, doc="Keyword options of the hypotrack tracker.")

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            if self.algorithm not in ALGORITHMS:
                raise ValueError(f"algorithm must be one of {ALGORITHMS}, got {self.algorithm!r}")
            motion, measurement, self._perm = translate_models(self.transition_model, self.measurement_model)
            self._inverse = np.argsort(self._perm)
            self._p = measurement.dim
            region = _region(self.clutter_region, self._p)
            priors = list(self.initial_states or [])
            d = motion.ndim
            means = np.array([np.ravel(s.state_vector)[self._perm] for s in priors]).reshape(-1, d)
            covs = np.array([np.asarray(s.covar)[np.ix_(self._perm, self._perm)] for s in priors]).reshape(-1, d, d)
            times = {s.timestamp for s in priors}
            if len(times) > 1:
                raise ValueError(f"initial_states must share one timestamp, got {sorted(map(str, times))}")
            self._time = times.pop() if times else None
            self._epoch = self._time
            self.tracker = _build(self.algorithm, motion, measurement, self.detection_probability,
                                  self.clutter_rate, region, means, covs, self.options or {})
            self._tracks = {}
            self._current = set()
            self._detector_iter = None

        @property
        def tracks(self) -> set:
            """Tracks present at the current scan."""
            return set(self._current)

        @property
        def all_tracks(self) -> set:
            """Every track seen so far (what metric managers want at the end of a run)."""
            return set(self._tracks.values())

        def __iter__(self):
            if self.detector is None:
                raise AttributeError("detector is not set: pass detector=... or call update_tracker(time, detections)")
            self._detector_iter = iter(self.detector)
            return self

        def __next__(self):
            time, detections = next(self._detector_iter)
            return self.update_tracker(time, detections)

        def update_tracker(self, time: datetime.datetime, detections) -> tuple:
            """Process one scan; returns ``(time, tracks present now)``."""
            # Plain ndarray views: numpy's conversion of Stone Soup's StateVector subclass is 3x slower.
            Z = np.array([det.state_vector.view(np.ndarray) for det in detections], dtype=float).reshape(-1, self._p)
            Z = Z[np.lexsort(Z.T[::-1])]
            if self._epoch is None:
                self._epoch = time
            if self.algorithm in SINGLE_HYPOTHESIS:
                est = self.tracker.step(((time - self._epoch).total_seconds(), Z))
                ids, means, covs = est.ids, est.x, est.P
            else:
                dt = None if self._time is None else (time - self._time).total_seconds()
                if dt is not None and dt <= 0:
                    raise ValueError(f"scan times must increase for {self.algorithm} (the hypothesis filters "
                                     f"predict over dt > 0): scan at {time} after {self._time}; give "
                                     "initial_states a timestamp before the first scan")
                best = self.tracker.step(Z, dt).map_estimate
                ids, means, covs = best.labels, best.means, best.covs
            self._time = time
            inv = self._inverse
            means, covs = means[:, inv, None], covs[:, inv][:, :, inv]  # back to Stone Soup's state order
            self._current = set()
            for track_id, mean, cov in zip(ids.tolist(), means, covs):
                track = self._tracks.get(track_id)
                if track is None:
                    track = self._tracks[track_id] = Track(id=str(track_id))
                track.append(GaussianState(mean, cov, timestamp=time))
                self._current.add(track)
            return time, self.tracks

    return HypotrackTracker


_CLASS = None


def __getattr__(name):
    # The Stone Soup subclass is built on first use so that importing hypotrack never needs Stone Soup.
    global _CLASS
    if name == "HypotrackTracker":
        if _CLASS is None:
            _CLASS = _tracker_class()
        return _CLASS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

"""GNN/JPDA over the scans of several sensors: each scan gated, associated and updated with its own sensor.

:class:`MultiSensorSHT` is a :class:`~.tracker.SingleHypothesisTracker` with one scan model per sensor (measurement model
and frame, ``p_D`` — constant or ``p_detect`` of the state —, gate, clutter and new-target densities) and one field of
view per sensor (``in_view``). A scan of sensor ``s`` (:meth:`MultiSensorSHT.step` with ``sensor=s``) uses sensor
``s``'s: the tracks in its view are predicted (``lazy``), gated and updated with its EKF, missed where it sees them; the
returns it leaves go to the initiator, which gates and updates its tentative tracks and starts new ones with the same
model (so a tentative track started from one sensor's return is confirmed by another's). Scans at one instant are
processed one after the other (a zero interval: an update without prediction) — the sequential, iterated-corrector
update of :mod:`hypotrack.hypotheses.factored.multisensor`, which cites it. An M-of-N window counts scans of any sensor.

Misses: a track is deleted after ``max_misses`` consecutive scans in which it was in the scanning sensor's view and not
detected. A scan of a sensor that does not see a track neither misses it nor forgives the misses another sensor counted
— unless no sensor sees it (``miss_view``, the union of the views), where, as with one sensor, its count is reset.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .._validation import check_int
from .tracker import SingleHypothesisTracker

__all__ = ["MultiSensorSHT"]


class MultiSensorSHT(SingleHypothesisTracker):
    """A single-hypothesis tracker fusing several sensors scan by scan (module docstring).

    Made with :meth:`from_trackers`: one configured tracker per sensor (the same motion model, association and
    settings; each with its sensor's scan model, ``in_view`` and ``p_detect``), the first one's tracks the initial
    ones. Needs ``in_view`` for every sensor (a sensor sees part of the sky).

    Attributes
    ----------
    sensors : list of ``(model, in_view, p_detect, missed_distance)``, one per sensor.
    sensor : int, the sensor of the last scan.
    """

    @classmethod
    def from_trackers(cls, trackers: Sequence[SingleHypothesisTracker]) -> "MultiSensorSHT":
        """The fused tracker of ``trackers`` (not stepped yet; the first one's known tracks and time)."""
        trackers = list(trackers)
        if not trackers:
            raise ValueError("trackers must hold one SingleHypothesisTracker per sensor, got none")
        for i, t in enumerate(trackers):
            if not isinstance(t, SingleHypothesisTracker):
                raise TypeError(f"trackers[{i}] must be a SingleHypothesisTracker, got {type(t).__name__}")
            if t.in_view is None:
                raise ValueError(f"trackers[{i}] needs in_view (the sensor's field of view)")
            if t.model.ndim_state != trackers[0].model.ndim_state or t.motion is not trackers[0].motion:
                raise ValueError(f"trackers[{i}] must share trackers[0]'s motion model (the same object) and state dimension")
            if (t.initiator is None) != (trackers[0].initiator is None):
                raise ValueError(f"trackers[{i}]: initiation on one sensor needs it on every sensor")
        t0 = trackers[0]
        obj = cls(t0.motion, t0.model, association=t0.association, jpda_marginals=t0.jpda_marginals,
                  initiator=t0.initiator, max_misses=t0.max_misses, gnn_score=t0.gnn_score,
                  missed_distance=t0.missed_distance, in_view=t0.in_view, gate_out_of_view=t0.gate_out_of_view,
                  lazy=t0.lazy, lazy_prediction=t0.lazy_prediction, validity=t0.validity, p_detect=t0.p_detect)
        if t0.time is not None:
            obj.initialise(t0.x, t0.P, t0.ids, time=t0.time)
        obj.sensors = [(t.model, t.in_view, t.p_detect, t.missed_distance) for t in trackers]
        # a mixture initiator's admissible region is its sensor's (site, frame)
        obj._mixtures = [getattr(t.initiator, "mixture", None) for t in trackers]
        views = [t.in_view for t in trackers]
        obj.miss_view = lambda x: np.logical_or.reduce([np.asarray(v(x), dtype=bool) for v in views]) if len(x) \
            else np.zeros(0, dtype=bool)
        obj.sensor = 0
        return obj

    @property
    def n_sensors(self) -> int:
        return len(self.sensors)

    def _use(self, sensor: int) -> None:
        self.model, self.in_view, self.p_detect, self.missed_distance = self.sensors[sensor]
        if self.initiator is not None:
            self.initiator.set_model(self.model, self._mixtures[sensor])
        self.sensor = sensor

    def step(self, Z, time=None, sensor: int = 0):
        """One scan of sensor ``sensor`` (index into :meth:`from_trackers`' ``trackers``): returns ``Z`` in its frame
        at ``time``. All-or-nothing, as :meth:`SingleHypothesisTracker.step`, the sensor included."""
        sensor = check_int(sensor, "sensor", minimum=0, maximum=self.n_sensors - 1)
        before = self.sensor
        self._use(sensor)
        try:
            return super().step(Z, time)
        except BaseException:
            self._use(before)
            raise

"""Trajectory GOSPA as a Stone Soup metric generator (:class:`TrajectoryGOSPAMetric`; Stone Soup >= 1.9).

Stone Soup's ``GOSPAMetric`` scores one time at a time; the trajectory metric of García-Fernández,
Rahmathullah & Svensson (IEEE TSP 68, 2020; :mod:`hypotrack.metrics_trajectory`) scores a whole run's
tracks against the ground-truth paths, with the track switches that a per-time metric cannot see. The
generator reads the two sets from a metric manager (``tracks_key``, ``truths_key``, as Stone Soup's own
generators), places every track and path on the union of their timestamps (a track's last state at a
timestamp; absent elsewhere), keeps the state components ``position_mapping`` and returns one
``TimeRangeMetric`` whose value holds the distance and its decomposition
(``distance**p = localisation + missed + false + switches``).

Usage::

    from stonesoup.metricgenerator.manager import MultiManager
    from hypotrack.interop.stonesoup import TrajectoryGOSPAMetric

    manager = MultiManager([TrajectoryGOSPAMetric(c=10, p=2, gamma=1, position_mapping=(0, 2))])
    manager.add_data({"tracks": tracks, "groundtruth_paths": truths})
    manager.generate_metrics()["trajectory_gospa_generator"]["Trajectory GOSPA"].value
"""

from __future__ import annotations

import functools

import numpy as np

from ...metrics_trajectory import trajectory_gospa
from ._common import require_stonesoup

__all__ = ["metric_class", "trajectory_array"]


def trajectory_array(sequences, timestamps, mapping) -> np.ndarray:
    """``(n, T, d)`` states of ``sequences`` (Stone Soup tracks or paths) at ``timestamps``, NaN where absent."""
    index = {t: k for k, t in enumerate(timestamps)}
    seqs = list(sequences)
    out = np.full((len(seqs), len(timestamps), len(mapping)), np.nan)
    for i, seq in enumerate(seqs):
        for state in seq.last_timestamp_generator():
            out[i, index[state.timestamp]] = np.asarray(state.state_vector, dtype=float).ravel()[list(mapping)]
    return out


@functools.cache
def metric_class():
    """The Stone Soup class (built on first use, so that importing hypotrack never needs Stone Soup)."""
    require_stonesoup()
    from stonesoup.base import Property
    from stonesoup.metricgenerator.base import MetricGenerator
    from stonesoup.types.metric import TimeRangeMetric
    from stonesoup.types.time import TimeRange

    class TrajectoryGOSPAMetric(MetricGenerator):
        """Trajectory GOSPA (García-Fernández, Rahmathullah & Svensson 2020, LP relaxation; α = 2) between the
        tracks and the ground-truth paths of a metric manager, over all their timestamps."""

        c: float = Property(doc="cut-off c > 0 (a missed or false target costs c^p/2 per time step)")
        p: float = Property(default=2.0, doc="order, 1 <= p < inf")
        gamma: float = Property(default=None, doc="switch cost gamma > 0 (None: gamma = c)")
        position_mapping: tuple = Property(default=(0, 2), doc="state components compared (Stone Soup's x, y)")
        integral: bool = Property(default=False, doc="solve the assignment metric itself (a MILP), not the LP")
        generator_name: str = Property(default="trajectory_gospa_generator",
                                       doc="unique identifier of the generated metrics in a MultiManager")
        tracks_key: str = Property(default="tracks", doc="key of the tracks in the manager")
        truths_key: str = Property(default="groundtruth_paths", doc="key of the ground-truth paths in the manager")

        def compute_metric(self, manager, **kwargs):
            tracks = list(self._get_data(manager, self.tracks_key))
            truths = list(self._get_data(manager, self.truths_key))
            times = sorted({s.timestamp for seq in tracks + truths for s in seq})
            if not times:
                raise ValueError(f"{self.tracks_key!r} and {self.truths_key!r} hold no states: nothing to score")
            X = trajectory_array(tracks, times, self.position_mapping)
            Y = trajectory_array(truths, times, self.position_mapping)
            r = trajectory_gospa(X, Y, c=self.c, p=self.p, gamma=self.gamma, integral=self.integral)
            value = {"distance": r.value, "localisation": r.localisation, "missed": r.missed, "false": r.false,
                     "switches": r.switches, "n_switches": r.n_switches, "integral": r.integral}
            return TimeRangeMetric(title="Trajectory GOSPA", value=value, time_range=TimeRange(times[0], times[-1]),
                                   generator=self)

    return TrajectoryGOSPAMetric

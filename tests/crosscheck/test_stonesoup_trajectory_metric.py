"""Trajectory GOSPA as a Stone Soup metric generator, through Stone Soup's own MultiManager."""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.metricgenerator.manager import MultiManager  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402

from hypotrack.interop.stonesoup import TrajectoryGOSPAMetric  # noqa: E402
from hypotrack.metrics_trajectory import trajectory_gospa  # noqa: E402

T0 = datetime.datetime(2026, 1, 1)


def _at(k):
    return T0 + datetime.timedelta(seconds=k)


def _path(xy, start=0, cls=GroundTruthPath):
    states = [GroundTruthState([[x], [0.0], [y], [0.0]], timestamp=_at(start + k)) for k, (x, y) in enumerate(xy)]
    return GroundTruthPath(states)


def _track(xy, start=0):
    return Track([GaussianState([[x], [0.0], [y], [0.0]], np.eye(4), timestamp=_at(start + k))
                  for k, (x, y) in enumerate(xy)])


def _metric(tracks, truths, **kw):
    gen = TrajectoryGOSPAMetric(**kw)
    manager = MultiManager([gen])
    manager.add_data({"tracks": set(tracks), "groundtruth_paths": set(truths)})
    return manager.generate_metrics()["trajectory_gospa_generator"]["Trajectory GOSPA"]


def test_switch_and_a_late_truth_by_hand():
    """Truths A (0, 0) and B (0, 20) over steps 0-2, B from step 1; one track on A at step 0, then on B
    (3 m off in x) at steps 1-2. c = 10, p = 2, γ = 2: assigning the track to A then B costs
    localisation 0 + 9 + 9, one switch γ² = 4, A missed at steps 1-2 (2 × 50): 122. Leaving the
    track on A throughout costs 50 + 50 for the far pair at steps 1-2 counted as missed plus false each (200),
    more; so the value is √122."""
    A, B = _path([(0, 0), (0, 0), (0, 0)]), _path([(0, 20), (0, 20)], start=1)
    track = _track([(0, 0), (3, 20), (3, 20)])
    m = _metric([track], [A, B], c=10.0, p=2.0, gamma=2.0)
    v = m.value
    assert v["distance"] == pytest.approx(np.sqrt(122))
    assert (v["localisation"], v["missed"], v["false"], v["switches"]) == pytest.approx((18, 100, 0, 4))
    assert m.time_range.start_timestamp == _at(0) and m.time_range.end_timestamp == _at(2)


def test_same_as_the_array_api():
    rng = np.random.default_rng(0)
    truths = [_path(rng.uniform(0, 30, (5, 2)), start=s) for s in (0, 2)]
    tracks = [_track(rng.uniform(0, 30, (4, 2)), start=s) for s in (0, 1, 3)]
    v = _metric(tracks, truths, c=8.0, p=1.0, gamma=3.0).value
    times = [_at(k) for k in range(7)]

    def arr(seqs):
        out = np.full((len(seqs), 7, 2), np.nan)
        for i, s in enumerate(seqs):
            for st in s:
                out[i, times.index(st.timestamp)] = st.state_vector.ravel()[[0, 2]]
        return out

    # the manager's sets have no order; the metric does not depend on it
    r = trajectory_gospa(arr(tracks), arr(truths), c=8.0, p=1.0, gamma=3.0)
    assert v["distance"] == pytest.approx(r.value) and v["switches"] == pytest.approx(r.switches)


def test_empty_manager_is_an_error():
    with pytest.raises(ValueError, match="hold no states"):
        _metric([], [], c=1.0)

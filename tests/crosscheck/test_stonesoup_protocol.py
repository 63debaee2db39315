"""Stone Soup's own tracker tests, ported to HypotrackTracker for every algorithm.

``stonesoup/tracker/tests/test_base.py`` (Stone Soup 1.9) checks the iteration protocol of a
``Tracker``: ``iter`` creates the detector's iterator once (``detector_iter``), ``next`` advances it,
a finished tracker does not restart, ``heapq.merge`` of two trackers interleaves them, and
``update_tracker`` can be called between iterations. Its fake trackers turn each detection into
a track whose state *is* the detection; here the check is the hypotrack equivalent: each track's
state at the scan comes from that scan's detection (its hypothesis holds it).

``stonesoup/tracker/tests/test_simple.py`` runs the trackers on the ``detector`` fixture of
``stonesoup/tracker/tests/conftest.py`` (rewritten below: three objects 10 apart moving one unit per
minute, each missed every fifth scan, then three empty scans) and checks the scan times, at most
three tracks, tracks 10 apart when all three are present, and track turnover with an initiator
and a deleter. The hypotrack trackers get real models for it (a 1-D constant-velocity model and
the fixture's measurement variance 2) and the checks are made numeric: every track is near an
object, and the number of tracks over the run is counted exactly.
"""

import datetime
import heapq

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import ConstantVelocity  # noqa: E402
from stonesoup.types.array import StateVector  # noqa: E402
from stonesoup.types.detection import Detection, GaussianDetection  # noqa: E402
from stonesoup.types.multihypothesis import MultipleHypothesis  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.update import Update  # noqa: E402

from hypotrack.interop.stonesoup import ALGORITHMS, HypotrackTracker  # noqa: E402

OPTIONS = {
    "gnn": {}, "jpda": {}, "pdaf": {},
    "hfisst": {"max_hypotheses": 10}, "rfisst": {"n_steps": 200, "max_hypotheses": 10, "seed": 1},
    "homht": {"max_hypotheses": 10}, "homht_kbest": {"max_hypotheses": 10},
    "glmb": {"max_hypotheses": 10, "n_sweeps": 50, "seed": 1}, "glmb_murty": {"max_hypotheses": 10},
    "pmbm_murty": {"max_hypotheses": 10}, "pmbm_gibbs": {"max_hypotheses": 10, "n_sweeps": 50, "seed": 1},
}
DAY = datetime.timedelta(days=1)


def test_every_algorithm_is_covered():
    assert set(OPTIONS) == set(ALGORITHMS) and len(ALGORITHMS) == 11


# ---------------------------------------------------------------- test_base.py


@pytest.fixture
def detector():
    """test_base.py's ``detector``: one detection per day at position ``i`` on 2023-11-i."""
    detections = [Detection(timestamp=datetime.datetime(2023, 11, i), state_vector=[i]) for i in range(1, 10)]
    return [(det.timestamp, {det}) for det in detections]


def _tracker(algorithm, detector=None, **kw):
    """One object moving one unit per day, known at the first scan's time (no prediction there)."""
    v = 1.0 / DAY.total_seconds()
    prior = GaussianState([[1.0], [v]], np.diag([1.0, (0.1 * v) ** 2]), timestamp=datetime.datetime(2023, 11, 1))
    return HypotrackTracker(
        transition_model=ConstantVelocity(1e-16), measurement_model=LinearGaussian(2, (0,), [[0.25]]),
        algorithm=algorithm, detection_probability=0.9, clutter_rate=1e-3, clutter_region=[[-10.0, 30.0]],
        detector=detector, initial_states=[prior], options=OPTIONS[algorithm], **kw)


def _detections_of(state):
    """The detections a track's state was updated with (test_base's ``{track.state}``)."""
    if not isinstance(state, Update):
        return set()
    if isinstance(state.hypothesis, MultipleHypothesis):
        return {h.measurement for h in state.hypothesis if h}
    return {state.hypothesis.measurement}


def _check_scan(tracker, tracks, detections, position):
    assert tracks == tracker.tracks and len(tracks) == 1
    (track,) = tracks
    assert track.id == "0"
    assert _detections_of(track.state) == detections
    assert abs(float(track.state_vector[0]) - position) < 0.5


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_update_tracker(algorithm, detector):
    tracker = _tracker(algorithm)  # no detector: driven by update_tracker
    for k, (input_time, detections) in enumerate(detector):
        time, tracks = tracker.update_tracker(input_time, detections)
        assert time == input_time
        _check_scan(tracker, tracks, detections, k + 1)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_without_detector_iter_error(algorithm):
    tracker = _tracker(algorithm)
    with pytest.raises(AttributeError):
        iter(tracker)
    with pytest.raises(TypeError):
        next(tracker)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_detector_iter_creation(algorithm, detector):
    assert _tracker(algorithm).detector_iter is None
    assert _tracker(algorithm, detector).detector_iter is None  # created by iter(), not before


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_with_detector_iter(algorithm):
    tracker = _tracker(algorithm, [])
    assert iter(tracker) is tracker
    assert tracker.detector_iter is not None
    with pytest.raises(StopIteration):
        next(tracker)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_with_detector_for_loop(algorithm, detector):
    tracker = _tracker(algorithm, detector)
    n = 0
    for (tracker_time, tracks), (detect_time, detections) in zip(tracker, detector):
        assert tracker_time == detect_time
        _check_scan(tracker, tracks, detections, n + 1)
        n += 1
    assert n == 9 and len(next(iter(tracker.all_tracks))) == 9


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_with_detector_next(algorithm, detector):
    tracker = _tracker(algorithm, detector)
    assert iter(tracker) is tracker
    for k, (detect_time, detections) in enumerate(detector):
        tracker_time, tracks = next(tracker)
        assert tracker_time == detect_time
        _check_scan(tracker, tracks, detections, k + 1)
    with pytest.raises(StopIteration):
        next(tracker)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_wont_restart(algorithm, detector):
    tracker = _tracker(algorithm, detector)
    for _ in tracker:
        pass
    iter(tracker)  # before: a fresh detector iterator, whose first scan was "earlier than the previous"
    with pytest.raises(StopIteration):
        next(tracker)
    assert len(next(iter(tracker.all_tracks))) == 9


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_for_loop_continues_after_next_calls(algorithm, detector):
    # test_simple.py calls next(iter(tracker)) twice and expects the second scan.
    tracker = _tracker(algorithm, detector)
    assert next(iter(tracker))[0] == detector[0][0]
    assert next(iter(tracker))[0] == detector[1][0]
    times = [time for time, _ in tracker]
    assert times == [t for t, _ in detector[2:]]


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_heapq_merge_with_tracker(algorithm, detector):
    merge_output = list(heapq.merge(_tracker(algorithm, detector), _tracker(algorithm, detector)))
    assert len(merge_output) == len(detector) * 2
    for idx, (tracker_time, tracks) in enumerate(merge_output):
        detect_time, detections = detector[idx // 2]
        assert tracker_time == detect_time
        (track,) = tracks  # the Track keeps growing after merge has yielded it: its state at that time
        (state,) = [s for s in track if s.timestamp == tracker_time]
        assert _detections_of(state) == detections
        assert abs(float(state.state_vector[0]) - (idx // 2 + 1)) < 0.5


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_tracker_with_detections_mid_iter(algorithm, detector):
    # test_base.py interrupts at times unrelated to the detector's (2024 between 2023 scans); a
    # tracker's scan times cannot go back, so here the interruption is half a day after each scan,
    # where the object is at k + 1.5.
    tracker = _tracker(algorithm, detector)
    n = 0
    for k, ((tracker_time, tracks), (detect_time, detections)) in enumerate(zip(tracker, detector)):
        assert tracker_time == detect_time
        _check_scan(tracker, tracks, detections, k + 1)
        interrupt_time = detect_time + DAY / 2
        interrupt_detections = {Detection(timestamp=interrupt_time, state_vector=[k + 1.5])}
        time, interrupt_tracks = tracker.update_tracker(interrupt_time, interrupt_detections)
        assert time == interrupt_time
        _check_scan(tracker, interrupt_tracks, interrupt_detections, k + 1.5)
        n += 1
    assert n == 9 and len(next(iter(tracker.all_tracks))) == 18


# ---------------------------------------------------------------- test_simple.py

T0 = datetime.datetime(2018, 1, 1, 14)
MINUTE = datetime.timedelta(minutes=1)


def conftest_detector():
    """conftest.py's ``detector``: 20 one-minute scans of objects at ``step + 10 i`` (i = 0, 1, 2),
    object ``i`` missed when ``(step - i) % 5 == 0``, then three empty scans."""
    scans, time = [], T0
    for step in range(20):
        scans.append((time, {GaussianDetection(StateVector([[step + (10 * i)]]), [[2]], timestamp=time)
                             for i in range(3) if (step - i) % 5}))
        time += MINUTE
    for _ in range(3):
        scans.append((time, set()))
        time += MINUTE
    return scans


def _simple_tracker(algorithm):
    """The fixture's objects known one minute before the first scan. GNN/JPDA/PDAF get test_simple's
    turnover: a track is deleted at its first miss (``max_misses=1``, the fixture's deleter) and
    every unused detection starts a confirmed track (1-of-1, the fixture's initiator)."""
    v = 1.0 / 60.0
    priors = [GaussianState([[10.0 * i - 1.0], [v]], np.diag([1.0, (0.2 * v) ** 2]), timestamp=T0 - MINUTE)
              for i in range(3)]
    options = dict(OPTIONS[algorithm])
    if algorithm in ("gnn", "jpda", "pdaf"):
        options.update(max_misses=1, m_of_n=[1, 1], initial_velocity_std=0.02)
    return HypotrackTracker(
        transition_model=ConstantVelocity(1e-8), measurement_model=LinearGaussian(2, (0,), [[2.0]]),
        algorithm=algorithm, detection_probability=0.8, clutter_rate=1e-3, clutter_region=[[-20.0, 50.0]],
        detector=conftest_detector(), initial_states=priors, options=options)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_multi_target_tracker(algorithm):
    tracker = _simple_tracker(algorithm)
    previous_time = datetime.datetime(2018, 1, 1, 13, 59)
    max_tracks = 0
    total_tracks = set()
    tolerance = 0.5
    for step, (time, tracks) in enumerate(tracker):
        assert time == previous_time + MINUTE
        assert len(tracks) <= 3  # Shouldn't have more than three tracks
        truth = np.minimum(step, 19) + 10.0 * np.arange(3)  # objects stop being observed after step 19
        for track in tracks:
            x = float(track.state_vector[0])
            assert np.min(np.abs(truth - x)) < tolerance + max(step - 19, 0), (step, x)
        if len(tracks) == 3:
            sorted_vectors = sorted(float(track.state_vector[0]) for track in tracks)
            assert abs(sorted_vectors[0] + 10 - sorted_vectors[1]) < tolerance
            assert abs(sorted_vectors[1] + 10 - sorted_vectors[2]) < tolerance
        max_tracks = max(max_tracks, len(tracks))
        total_tracks |= tracks
        previous_time = time
    assert max_tracks >= 3  # Should of had at least 3 tracks in single step
    if algorithm in ("gnn", "jpda", "pdaf"):
        # Every miss deletes a track and the next detection starts one: object i is missed at
        # steps i, i + 5, i + 10, i + 15, so 4 new tracks each besides the known ones; object 0's
        # known track is deleted at the first scan (a miss) before it has a state: 12 + 2 tracks.
        assert len(total_tracks) == 14
        assert all(len(track) <= 4 for track in total_tracks)  # at most 4 detections between misses
    else:
        # The hypothesis filters keep each object through its misses, with its label as id.
        assert {track.id for track in total_tracks} == {"0", "1", "2"}
        assert all(len(track) == 23 for track in total_tracks)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_single_target_tracker(algorithm):
    # test_simple.py's single-target trackers keep at most one track on the same detector. Here:
    # only object 0 is known and nothing initiates, so the other objects' detections are clutter
    # to the tracker; GNN/JPDA/PDAF delete the track after 2 misses (the three empty scans).
    v = 1.0 / 60.0
    prior = GaussianState([[-1.0], [v]], np.diag([1.0, (0.2 * v) ** 2]), timestamp=T0 - MINUTE)
    single = algorithm in ("gnn", "jpda", "pdaf")
    tracker = HypotrackTracker(
        transition_model=ConstantVelocity(1e-8), measurement_model=LinearGaussian(2, (0,), [[2.0]]),
        algorithm=algorithm, detection_probability=0.8, clutter_rate=1.0, clutter_region=[[-20.0, 50.0]],
        detector=conftest_detector(), initial_states=[prior],
        options={**OPTIONS[algorithm], **({"max_misses": 2} if single else {})})
    previous_time = datetime.datetime(2018, 1, 1, 13, 59)
    total_tracks = set()
    for step, (time, tracks) in enumerate(tracker):
        assert time == previous_time + MINUTE
        assert len(tracks) <= 1  # Shouldn't have more than one track
        assert len(tracks) == (0 if single and step >= 21 else 1)
        for track in tracks:
            assert abs(float(track.state_vector[0]) - min(step, 19)) < 0.5 + max(step - 19, 0)
        total_tracks |= tracks
        previous_time = time
    assert len(total_tracks) == 1 and len(next(iter(total_tracks))) == (21 if single else 23)

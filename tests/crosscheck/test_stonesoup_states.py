"""Scan times and the state types of HypotrackTracker's tracks (hypotrack.interop.stonesoup).

One rule for every algorithm, Stone Soup's: a scan is predicted over the time since the previous
scan (or the priors), and a zero interval — a first scan at the priors' time, a repeated
timestamp — is an update without prediction, appended as another state at that time. Stone
Soup's ``KalmanPredictor`` and ``KalmanUpdater`` are the oracle.

A Stone Soup user tells detected from missed scans by type: ``GaussianStateUpdate`` (whose
hypothesis holds the ``Detection`` and the prediction) or ``GaussianStatePrediction``.
"""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.array import StateVector  # noqa: E402
from stonesoup.types.detection import Detection, GaussianDetection  # noqa: E402
from stonesoup.types.hypothesis import SingleHypothesis, SingleProbabilityHypothesis  # noqa: E402
from stonesoup.types.multihypothesis import MultipleHypothesis  # noqa: E402
from stonesoup.types.prediction import GaussianStatePrediction  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.update import GaussianStateUpdate  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402

from hypotrack.interop.stonesoup import ALGORITHMS, HypotrackTracker  # noqa: E402

OPTIONS = {
    "gnn": {}, "jpda": {}, "pdaf": {},
    "hfisst": {"max_hypotheses": 10}, "rfisst": {"n_steps": 200, "max_hypotheses": 10, "seed": 1},
    "homht": {"max_hypotheses": 10}, "homht_kbest": {"max_hypotheses": 10},
    "glmb": {"max_hypotheses": 10, "n_sweeps": 50, "seed": 1}, "glmb_murty": {"max_hypotheses": 10},
    "pmbm_murty": {"max_hypotheses": 10}, "pmbm_gibbs": {"max_hypotheses": 10, "n_sweeps": 50, "seed": 1},
}
T0 = datetime.datetime(2025, 1, 1)
SECOND = datetime.timedelta(seconds=1)
R = np.diag([1.0, 2.0])


def _tol(algorithm):
    # JPDA/PDAF's update is a mixture; with clutter 1e-6 per scan the miss weight β_0 is < 1e-7.
    return 1e-6 if algorithm in ("jpda", "pdaf") else 1e-9


def _models():
    return (CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05), ConstantVelocity(0.05)]),
            LinearGaussian(4, (0, 2), R))


def _tracker(algorithm, priors, detector=None):
    tm, mm = _models()
    return HypotrackTracker(transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=0.9,
                            clutter_rate=1e-6, clutter_region=[[-60, 60], [-60, 60]], initial_states=priors,
                            detector=detector, options=OPTIONS[algorithm])


def _prior(timestamp):
    return GaussianState([[0.0], [1.0], [0.0], [-1.0]], np.diag([4.0, 1.0, 4.0, 1.0]), timestamp=timestamp)


def _kalman_update(prediction, detection):
    return KalmanUpdater(_models()[1]).update(SingleHypothesis(prediction, detection))


def _assert_state(state, oracle, tol):
    np.testing.assert_allclose(state.state_vector, oracle.state_vector, rtol=tol, atol=tol)
    np.testing.assert_allclose(state.covar, oracle.covar, rtol=tol, atol=tol)


def _measurement(state):
    """The detection an update used (the most probable one for JPDA/PDAF)."""
    h = state.hypothesis
    if isinstance(h, MultipleHypothesis):
        return max((x for x in h if x), key=lambda x: float(x.probability)).measurement
    return h.measurement


@pytest.mark.parametrize("stamp", ["first scan", "none"])
@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_priors_at_the_first_scan_time_are_not_predicted(algorithm, stamp):
    # Priors stamped at the first scan's time, or without a timestamp: dt = 0, the scan updates
    # the prior itself (before: the hypothesis filters raised "scan times must increase", and
    # priors without a timestamp were predicted over the filters' default dt of 1 s).
    prior = _prior(T0 if stamp == "first scan" else None)
    det = Detection(np.array([[0.8], [-0.5]]), timestamp=T0)
    _, (track,) = _tracker(algorithm, [prior]).update_tracker(T0, {det})
    state = track.state
    assert isinstance(state, GaussianStateUpdate) and state.timestamp == T0 and len(track) == 1
    prediction = state.hypothesis.prediction if algorithm not in ("jpda", "pdaf") else state.hypothesis[0].prediction
    np.testing.assert_array_equal(prediction.state_vector, prior.state_vector)  # nothing predicted
    np.testing.assert_array_equal(prediction.covar, prior.covar)
    _assert_state(state, _kalman_update(GaussianStatePrediction(prior.state_vector, prior.covar, timestamp=T0), det),
                  _tol(algorithm))
    # Hand check of the x variance: 1 / (1/4 + 1/1) = 0.8.
    assert abs(state.covar[0, 0] - 0.8) < _tol(algorithm)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_a_repeated_scan_time_is_an_update_without_prediction(algorithm):
    prior = _prior(T0)
    tracker = _tracker(algorithm, [prior])
    t1 = T0 + SECOND
    first, second = (Detection(np.array([[1.2], [-0.7]]), timestamp=t1),
                     Detection(np.array([[0.9], [-1.3]]), timestamp=t1))
    tracker.update_tracker(t1, {first})
    _, (track,) = tracker.update_tracker(t1, {second})
    assert [s.timestamp for s in track] == [t1, t1]
    assert all(isinstance(s, GaussianStateUpdate) for s in track)
    tm, _ = _models()
    expected_first = _kalman_update(KalmanPredictor(tm).predict(prior, timestamp=t1), first)
    _assert_state(track[0], expected_first, _tol(algorithm))
    # The second scan predicts over dt = 0 (Stone Soup: F = I, Q = 0) and updates again.
    expected_second = _kalman_update(KalmanPredictor(tm).predict(expected_first, timestamp=t1), second)
    _assert_state(track[1], expected_second, _tol(algorithm))
    assert _measurement(track[1]) is second and _measurement(track[0]) is first


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_scan_times_must_not_decrease(algorithm):
    tracker = _tracker(algorithm, [_prior(T0)])
    early = Detection(np.array([[0.0], [0.0]]), timestamp=T0 - SECOND)
    with pytest.raises(ValueError, match="time: scan times must not decrease.*earlier than initial_states'"):
        tracker.update_tracker(T0 - SECOND, {early})
    tracker.update_tracker(T0 + 2 * SECOND, set())
    with pytest.raises(ValueError, match="time: .* earlier than the previous scan's time 2025-01-01 00:00:02"):
        tracker.update_tracker(T0 + SECOND, set())
    # The refused scans left the tracker as it was: one state, the prediction to T0 + 2 s.
    _, (track,) = tracker.update_tracker(T0 + 3 * SECOND, set())
    assert [s.timestamp for s in track] == [T0 + 2 * SECOND, T0 + 3 * SECOND]
    tm, _ = _models()
    predicted = KalmanPredictor(tm).predict(_prior(T0), timestamp=T0 + 3 * SECOND)
    _assert_state(track.state, predicted, 1e-9)


# ---------------------------------------------------------------- detected or missed

MINUTE = datetime.timedelta(minutes=1)


def _fixture_scans():
    """Stone Soup's tracker-test detector (stonesoup/tracker/tests/conftest.py): objects at
    ``step + 10 i`` moving one unit per minute, object ``i`` missed when ``(step - i) % 5 == 0``,
    then three empty scans."""
    scans, time = [], T0
    for step in range(20):
        scans.append((time, {i: GaussianDetection(StateVector([[step + (10 * i)]]), [[2]], timestamp=time)
                             for i in range(3) if (step - i) % 5}))
        time += MINUTE
    for _ in range(3):
        scans.append((time, {}))
        time += MINUTE
    return scans


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_updates_when_detected_predictions_when_missed(algorithm):
    tm, mm = ConstantVelocity(1e-8), LinearGaussian(2, (0,), [[2.0]])
    v = 1.0 / 60.0
    priors = [GaussianState([[10.0 * i - 1.0], [v]], np.diag([1.0, (0.2 * v) ** 2]), timestamp=T0 - MINUTE)
              for i in range(3)]
    scans = _fixture_scans()
    options = {"max_misses": 4} if algorithm in ("gnn", "jpda", "pdaf") else {}  # keep them through the 3 empty scans
    tracker = HypotrackTracker(
        transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=0.8, clutter_rate=1e-3,
        clutter_region=[[-20.0, 50.0]], detector=[(t, set(d.values())) for t, d in scans], initial_states=priors,
        options={**OPTIONS[algorithm], **options})
    for _ in tracker:
        pass
    tracks = {t.id: t for t in tracker.all_tracks}
    assert tracks.keys() == {"0", "1", "2"}
    predictor, updater = KalmanPredictor(tm), KalmanUpdater(mm)
    n_updates = n_predictions = 0
    for i in range(3):
        track = tracks[str(i)]
        assert len(track) == len(scans)
        previous = priors[i]
        for (time, dets), state in zip(scans, track):
            assert state.timestamp == time
            prediction = predictor.predict(previous, timestamp=time)
            if i in dets:  # detected: an update with this object's detection and its prediction
                assert isinstance(state, GaussianStateUpdate)
                assert _measurement(state) is dets[i]
                h = state.hypothesis
                if algorithm in ("jpda", "pdaf"):
                    assert isinstance(h, MultipleHypothesis)
                    assert all(isinstance(x, SingleProbabilityHypothesis) for x in h)
                    assert abs(sum(float(x.probability) for x in h) - 1.0) < 1e-12
                    # The miss first, with PDA's β_0 = (1 − P_D P_G) / (1 − P_D P_G + P_D N(z; ẑ, S) / β_FA)
                    # (the other objects' detections, 10 away, are outside the gate).
                    assert not h[0] and len(h) == 2
                    mp = updater.predict_measurement(prediction)
                    nu, S = float(dets[i].state_vector[0, 0] - mp.state_vector[0, 0]), float(mp.covar[0, 0])
                    lik = 0.8 * np.exp(-0.5 * nu**2 / S) / np.sqrt(2 * np.pi * S) / (1e-3 / 70.0)
                    miss = 1 - 0.8 * 0.99
                    np.testing.assert_allclose(float(h[0].probability), miss / (miss + lik), rtol=1e-6)
                    h = h[1]
                assert isinstance(h, SingleHypothesis) and isinstance(h.prediction, GaussianStatePrediction)
                _assert_state(h.prediction, prediction, 1e-9)
                # JPDA/PDAF: β_0 ~ 1e-5 here, so the PDA update is the Kalman update to ~1e-4.
                tol = 1e-4 if algorithm in ("jpda", "pdaf") else 1e-9
                _assert_state(state, updater.update(SingleHypothesis(prediction, dets[i])), tol)
                n_updates += 1
            else:  # missed: a prediction, and the state is the prediction
                assert type(state) is GaussianStatePrediction
                _assert_state(state, prediction, 1e-9)
                n_predictions += 1
            previous = state
    assert (n_updates, n_predictions) == (48, 21)  # 60 detections in 20 scans, 12 misses + 3 × 3 empty


@pytest.mark.parametrize("algorithm", ["gnn", "jpda"])
def test_an_initiated_track_starts_with_its_confirming_detection(algorithm):
    # 2-of-3 initiation, no known object: a tentative track from scan 0's return (x = z0, zero
    # velocity with variance 3², position covariance R) is confirmed by scan 1's return. The
    # track's first state is an update with that detection; its prediction is the tentative
    # track predicted over 1 s (Stone Soup's KalmanPredictor from the one-point initial state).
    # The initiator associates by GNN whatever the tracker: a SingleHypothesis, also for JPDA.
    tm, mm = _models()
    z = [np.array([[5.0], [-3.0]]), np.array([[6.1], [-2.4]]), np.array([[7.0], [-2.1]])]
    scans = [(T0 + k * SECOND, {Detection(z[k], timestamp=T0 + k * SECOND)}) for k in range(3)]
    tracker = HypotrackTracker(
        transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=0.9,
        clutter_rate=1e-6, clutter_region=[[-60, 60], [-60, 60]], detector=scans,
        options={"m_of_n": [2, 3], "initial_velocity_std": 3.0})
    out = [tracks for _, tracks in tracker]
    assert out[0] == set() and len(out[1]) == 1
    (track,) = out[2]
    assert [s.timestamp for s in track] == [T0 + SECOND, T0 + 2 * SECOND]
    first = track[0]
    assert isinstance(first, GaussianStateUpdate) and _measurement(first) is next(iter(scans[1][1]))
    tentative = GaussianState([[5.0], [0.0], [-3.0], [0.0]], np.diag([1.0, 9.0, 2.0, 9.0]), timestamp=T0)
    prediction = KalmanPredictor(tm).predict(tentative, timestamp=T0 + SECOND)
    assert type(first.hypothesis) is SingleHypothesis
    _assert_state(first.hypothesis.prediction, prediction, 1e-12)
    _assert_state(first, _kalman_update(prediction, _measurement(first)), 1e-9)
    assert isinstance(track[1], GaussianStateUpdate)

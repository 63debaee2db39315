"""A detection's own ``measurement_model`` in HypotrackTracker (hypotrack.interop.stonesoup).

Stone Soup's updaters use the model a detection carries. The adapter honours it when it is
linear-Gaussian on the tracker's state and measures the tracker's components: swapped axes give
the same tracks as the unswapped detections (bit for bit), another noise covariance is used as
such (Stone Soup's own Kalman predictor and updater are the oracle), and anything else raises a
``ValueError`` that names ``measurement_model`` (or ``state_vector``).
"""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.base import Property  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.measurement.nonlinear import CartesianToBearingRange  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.detection import Clutter, Detection, TrueDetection  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.hypothesis import SingleHypothesis  # noqa: E402
from stonesoup.types.multihypothesis import MultipleHypothesis  # noqa: E402
from stonesoup.types.prediction import GaussianStatePrediction  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.update import GaussianStateUpdate  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402

from hypotrack.interop.stonesoup import ALGORITHMS, HypotrackTracker  # noqa: E402

Q, P_D, REGION = 0.05, 0.9, [[-60.0, 60.0], [-60.0, 60.0]]
R = np.diag([1.0, 2.0])
T0 = datetime.datetime(2025, 1, 1)
SECOND = datetime.timedelta(seconds=1)
STARTS = [[-20.0, 1.0, -5.0, 0.2], [20.0, -1.0, 5.0, -0.2], [0.0, 0.0, 25.0, -1.0]]  # x, vx, y, vy
OPTIONS = {
    "gnn": {"m_of_n": [2, 3], "initial_velocity_std": 2.0}, "jpda": {}, "pdaf": {},
    "hfisst": {"max_hypotheses": 10, "gate_probability": 0.999},
    "rfisst": {"n_steps": 300, "max_hypotheses": 10, "gate_probability": 0.999, "seed": 7},
    "homht": {"max_hypotheses": 10, "gate_probability": 0.999},
    "homht_kbest": {"max_hypotheses": 10, "gate_probability": 0.999},
    "glmb": {"max_hypotheses": 10, "n_sweeps": 100, "seed": 3, "survival_probability": 0.99,
             "birth_states": [GaussianState([[0.0], [0.0], [0.0], [0.0]], np.diag([900.0, 1.0, 900.0, 1.0]))],
             "birth_probability": 0.01},
    "glmb_murty": {"max_hypotheses": 10, "survival_probability": 0.99},
    "pmbm_murty": {"max_hypotheses": 10, "gate_probability": 0.999, "survival_probability": 0.99},
    "pmbm_gibbs": {"max_hypotheses": 10, "n_sweeps": 100, "seed": 3, "gate_probability": 0.999},
}


def _transition():
    return CombinedLinearGaussianTransitionModel([ConstantVelocity(Q), ConstantVelocity(Q)])


def _tracker(algorithm, scans=None, measurement_model=None, clutter_rate=3.0, priors=None, **options):
    priors = [GaussianState(np.array(s)[:, None], np.diag([4.0, 1.0, 4.0, 1.0]), timestamp=T0 - SECOND)
              for s in STARTS] if priors is None else priors
    return HypotrackTracker(
        transition_model=_transition(), measurement_model=measurement_model or LinearGaussian(4, (0, 2), R),
        algorithm=algorithm, detection_probability=P_D, clutter_rate=clutter_rate, clutter_region=REGION,
        detector=scans, initial_states=priors, options={**OPTIONS[algorithm], **options})


def _scenario(n_steps=8, seed=11):
    """Three objects and Poisson clutter, detections with the tracker's own model."""
    tm, mm = _transition(), LinearGaussian(4, (0, 2), R)
    rng = np.random.default_rng(seed)
    F, Lq = tm.matrix(time_interval=SECOND), np.linalg.cholesky(tm.covar(time_interval=SECOND))
    paths = [GroundTruthPath([GroundTruthState(np.array(s)[:, None], timestamp=T0)]) for s in STARTS]
    scans = []
    for k in range(n_steps):
        t = T0 + k * SECOND
        if k:
            for path in paths:
                path.append(GroundTruthState(F @ path[-1].state_vector + Lq @ rng.standard_normal((4, 1)), timestamp=t))
        dets = [TrueDetection(mm.matrix() @ p[-1].state_vector + np.linalg.cholesky(R) @ rng.standard_normal((2, 1)),
                              timestamp=t, measurement_model=mm, groundtruth_path=p)
                for p in paths if rng.random() < P_D]
        dets += [Clutter(rng.uniform(-60, 60, (2, 1)), timestamp=t, measurement_model=mm)
                 for _ in range(rng.poisson(3.0))]
        scans.append((t, dets))
    return scans


def _with_model(scans, model, swap):
    """The same detections re-expressed under ``model`` (components swapped when ``swap``)."""
    out = []
    for t, dets in scans:
        new = [Detection(d.state_vector[::-1] if swap else d.state_vector, timestamp=t, measurement_model=model,
                         metadata={"original": d}) for d in dets]
        out.append((t, set(new)))
    return out


def _run(tracker):
    for _ in tracker:
        pass
    return {t.id: t for t in tracker.all_tracks}


def _assert_same_tracks(mine, theirs):
    assert mine.keys() == theirs.keys() and len(mine) >= 3
    for i in mine:
        assert [s.timestamp for s in mine[i]] == [s.timestamp for s in theirs[i]]
        assert [type(s) for s in mine[i]] == [type(s) for s in theirs[i]]
        np.testing.assert_array_equal(np.hstack([s.state_vector for s in mine[i]]),
                                      np.hstack([s.state_vector for s in theirs[i]]))
        np.testing.assert_array_equal(np.stack([s.covar for s in mine[i]]), np.stack([s.covar for s in theirs[i]]))


def _measurements(state):
    h = state.hypothesis
    return [x.measurement for x in h if x] if isinstance(h, MultipleHypothesis) else [h.measurement]


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_swapped_axis_detections_give_the_unswapped_tracks(algorithm):
    scans = _scenario()
    plain = _run(_tracker(algorithm, [(t, set(d)) for t, d in scans]))
    # mapping (2, 0): the detection is [y, x]; its noise is R with the axes swapped.
    swapped_model = LinearGaussian(4, (2, 0), R[::-1, ::-1])
    swapped = _run(_tracker(algorithm, _with_model(scans, swapped_model, swap=True)))
    _assert_same_tracks(swapped, plain)
    # The updates hold the swapped detections themselves, each the one the unswapped run used.
    n_updates = 0
    for i in swapped:
        for mine, theirs in zip(swapped[i], plain[i]):
            if isinstance(mine, GaussianStateUpdate):
                assert all(d.measurement_model is swapped_model for d in _measurements(mine))
                assert [d.metadata["original"] for d in _measurements(mine)] == _measurements(theirs)
                n_updates += 1
    assert n_updates >= 15  # 3 objects, 8 scans, P_D = 0.9


@pytest.mark.parametrize("algorithm", ["gnn", "jpda", "rfisst", "glmb_murty"])
def test_swapped_axes_with_unswapped_noise_run_with_that_noise(algorithm):
    # mapping (2, 0) with noise_covar diag(1, 2): x has variance 2 and y 1, the transpose of the
    # tracker's R. The run equals one whose tracker model has R = diag(2, 1), on [x, y] returns.
    scans = _scenario()
    mine = _run(_tracker(algorithm, _with_model(scans, LinearGaussian(4, (2, 0), R), swap=True)))
    oracle = _run(_tracker(algorithm, [(t, set(d)) for t, d in _with_model(scans, None, swap=False)],
                           measurement_model=LinearGaussian(4, (0, 2), R[::-1, ::-1])))
    _assert_same_tracks(mine, oracle)
    plain = _run(_tracker(algorithm, [(t, set(d)) for t, d in scans]))
    assert any(not np.array_equal(mine[i][-1].covar, plain[i][-1].covar) for i in mine.keys() & plain.keys())


def _one_object_scan(model, z):
    prior = GaussianState([[0.0], [1.0], [0.0], [-1.0]], np.diag([4.0, 1.0, 4.0, 1.0]), timestamp=T0 - SECOND)
    return prior, Detection(np.array(z, dtype=float)[:, None], timestamp=T0, measurement_model=model)


@pytest.mark.parametrize("algorithm", ALGORITHMS)
def test_detection_noise_400_is_used(algorithm):
    # R = 400 I on the detection, diag(1, 2) on the tracker. The track's state is Stone Soup's own
    # Kalman prediction and update with the detection's model (KalmanUpdater reads the
    # detection's measurement_model). Clutter 1e-6 per scan: the miss probability β_0 of JPDA/PDAF
    # is below 1e-7, so their PDA update is the Kalman update to that order.
    tol = 1e-6 if algorithm in ("jpda", "pdaf") else 1e-9
    model = LinearGaussian(4, (0, 2), 400.0 * np.eye(2))
    prior, det = _one_object_scan(model, [6.0, -4.0])
    tracker = _tracker(algorithm, clutter_rate=1e-6, priors=[prior])
    _, (track,) = tracker.update_tracker(T0, {det})
    prediction = KalmanPredictor(_transition()).predict(prior, timestamp=T0)
    oracle = KalmanUpdater(LinearGaussian(4, (0, 2), R)).update(SingleHypothesis(prediction, det))
    assert isinstance(track.state, GaussianStateUpdate) and _measurements(track.state) == [det]
    np.testing.assert_allclose(track.state_vector, oracle.state_vector, rtol=tol, atol=tol)
    np.testing.assert_allclose(track.covar, oracle.covar, rtol=tol, atol=tol)
    # Hand check: the position variance is 1 / (1/(4 + 1 + Q/3) + 1/400) on each axis.
    prior_var = 4.0 + 1.0 + Q / 3
    np.testing.assert_allclose(np.diag(track.covar)[[0, 2]], 1.0 / (1.0 / prior_var + 1.0 / 400.0), rtol=tol)
    # The tracker's own R is back for the next scan (diag(1, 2)).
    plain = Detection(np.array([[7.0], [-5.0]]), timestamp=T0 + SECOND)
    _, (track,) = tracker.update_tracker(T0 + SECOND, {plain})
    oracle2 = KalmanUpdater(LinearGaussian(4, (0, 2), R)).update(
        SingleHypothesis(KalmanPredictor(_transition()).predict(oracle, timestamp=T0 + SECOND), plain))
    np.testing.assert_allclose(track.state_vector, oracle2.state_vector, rtol=tol, atol=tol)
    np.testing.assert_allclose(track.covar, oracle2.covar, rtol=tol, atol=tol)


class RotatedLinearGaussian(LinearGaussian):
    """``z = A H x + v``: a linear-Gaussian model in a rotated measurement frame."""

    rotation: np.ndarray = Property(doc="(2, 2) invertible matrix A")

    def matrix(self, **kwargs):
        return self.rotation @ super().matrix(**kwargs)


@pytest.mark.parametrize("algorithm", ["gnn", "pdaf", "homht"])
def test_rotated_linear_model_is_translated(algorithm):
    c, s = np.cos(0.3), np.sin(0.3)
    model = RotatedLinearGaussian(4, (0, 2), np.array([[3.0, 0.5], [0.5, 1.0]]), rotation=np.array([[c, -s], [s, c]]))
    prior, det = _one_object_scan(model, [5.0, -2.0])
    _, (track,) = _tracker(algorithm, clutter_rate=1e-6, priors=[prior]).update_tracker(T0, {det})
    oracle = KalmanUpdater(model).update(SingleHypothesis(KalmanPredictor(_transition()).predict(prior, timestamp=T0),
                                                          det))
    tol = 1e-6 if algorithm == "pdaf" else 1e-9
    np.testing.assert_allclose(track.state_vector, oracle.state_vector, rtol=tol, atol=tol)
    np.testing.assert_allclose(track.covar, oracle.covar, rtol=tol, atol=tol)


def test_initiator_starts_tracks_with_the_detection_noise():
    # 1-of-1 initiation: a track starts at its return with position covariance R (the detection's
    # 400 I, not the tracker's diag(1, 2)) and velocity variance initial_velocity_std².
    model = LinearGaussian(4, (0, 2), 400.0 * np.eye(2))
    tracker = _tracker("gnn", priors=[], m_of_n=[1, 1], initial_velocity_std=3.0)
    det = Detection(np.array([[10.0], [20.0]]), timestamp=T0, measurement_model=model)
    _, (track,) = tracker.update_tracker(T0, {det})
    np.testing.assert_array_equal(track.state_vector.ravel(), [10.0, 0.0, 20.0, 0.0])
    np.testing.assert_array_equal(track.covar, np.diag([400.0, 9.0, 400.0, 9.0]))
    assert isinstance(track.state, GaussianStateUpdate)
    assert track.state.hypothesis.measurement is det and track.state.hypothesis.prediction is None


@pytest.mark.parametrize("algorithm", ["glmb", "glmb_murty"])
def test_glmb_birth_uses_the_detection_noise(algorithm):
    # An object born from a birth term at a detection with R = 400 I: its state is the birth
    # density updated with that detection and that noise (Stone Soup's KalmanUpdater).
    birth = GaussianState([[0.0], [0.0], [0.0], [0.0]], np.diag([100.0, 1.0, 100.0, 1.0]))
    model = LinearGaussian(4, (0, 2), 400.0 * np.eye(2))
    tracker = _tracker(algorithm, priors=[], clutter_rate=1e-6, birth_states=[birth], birth_probability=0.5)
    det = Detection(np.array([[8.0], [-6.0]]), timestamp=T0, measurement_model=model)
    _, (track,) = tracker.update_tracker(T0, {det})
    oracle = KalmanUpdater(model).update(SingleHypothesis(
        GaussianStatePrediction(birth.state_vector, birth.covar, timestamp=T0), det))
    np.testing.assert_allclose(track.state_vector, oracle.state_vector, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(track.covar, oracle.covar, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(track.covar[0, 0], 1.0 / (1.0 / 100.0 + 1.0 / 400.0), rtol=1e-12)  # = 80
    assert track.state.hypothesis.measurement is det
    np.testing.assert_array_equal(track.state.hypothesis.prediction.covar, birth.covar)


@pytest.mark.parametrize("algorithm", ["gnn", "homht"])
def test_bearing_range_detections_raise_a_named_error(algorithm):
    model = CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 1.0]))
    tracker = _tracker(algorithm)
    det = Detection(np.array([[0.3], [20.0]]), timestamp=T0, measurement_model=model)
    with pytest.raises(ValueError, match=r"measurement_model CartesianToBearingRange.*not a linear-Gaussian") as err:
        tracker.update_tracker(T0, {det})
    assert "ndim_meas=2" in str(err.value) and "mapping (0, 2)" in str(err.value)  # what is allowed
    assert tracker.tracks == set()  # nothing processed: the next good scan is the first
    _, tracks = tracker.update_tracker(T0, {Detection(np.array([[-19.0], [-5.0]]), timestamp=T0)})
    assert len(tracks) == 3 and all(len(t) == 1 for t in tracks)


def test_three_dimensional_detections_are_never_reshaped():
    # Before: two 3-D detections became three fake 2-D returns.
    tracker = _tracker("jpda")
    dets = {Detection(np.array([[1.0], [2.0], [3.0]]), timestamp=T0),
            Detection(np.array([[4.0], [5.0], [6.0]]), timestamp=T0)}
    with pytest.raises(ValueError, match=r"state_vector of a detection .* shape \(3, 1\).*must have shape \(2, 1\)"):
        tracker.update_tracker(T0, dets)
    with pytest.raises(ValueError, match="measurement_model LinearGaussian .*ndim_meas is 3"):
        tracker.update_tracker(T0, {Detection(np.array([[1.0], [2.0], [3.0]]), timestamp=T0,
                                              measurement_model=LinearGaussian(4, (0, 1, 2), np.eye(3)))})


@pytest.mark.parametrize(("model", "message"), [
    (LinearGaussian(4, (1, 3), np.eye(2)), r"measures state components \[1, 3\], not .* \[0, 2\]"),
    (LinearGaussian(4, (0, 0), np.eye(2)), r"measures state components \[0\]"),
    (LinearGaussian(6, (0, 2), np.eye(2)), "ndim_state is 6, the tracker's state has 4"),
])
def test_other_components_or_state_sizes_raise_a_named_error(model, message):
    det = Detection(np.array([[1.0], [2.0]]), timestamp=T0, measurement_model=model)
    with pytest.raises(ValueError, match="measurement_model LinearGaussian .*" + message):
        _tracker("gnn").update_tracker(T0, {det})


def test_one_scan_with_two_noise_covariances_is_refused():
    a = Detection(np.array([[1.0], [2.0]]), timestamp=T0, measurement_model=LinearGaussian(4, (0, 2), 400 * np.eye(2)))
    b = Detection(np.array([[9.0], [2.0]]), timestamp=T0)  # the tracker's model
    tracker = _tracker("rfisst")
    with pytest.raises(ValueError, match="measurement_model: detections at .* carry 2 different noise covariances"):
        tracker.update_tracker(T0, {a, b})
    # As two scans at the same time (one per sensor) they are accepted.
    tracker.update_tracker(T0, {a})
    _, tracks = tracker.update_tracker(T0, {b})
    assert len(tracks) == 3 and all(len(t) == 2 for t in tracks)

"""The δ-GLMB and PMBM presets in a Stone Soup pipeline: objects born from the labeled population.

No object is known at the start. Two labeled-Bernoulli birth terms are given as Stone Soup
``GaussianState``\\s through ``options`` (``birth_states``, ``birth_probability``,
``survival_probability``); the ground truth has one object appear at each, at different scans,
drawn from the birth densities, observed in Poisson clutter (Stone Soup types throughout). Both
``glmb`` (Gibbs) and ``glmb_murty`` must give each object one track whose label was born from its
birth term at its first detection (every state equals Stone Soup's Kalman filter started from the
birth density there and fed the object's detections), and no other track: positions against the
truth, numerically, and Stone Soup's OSPA.
"""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.measures import Euclidean  # noqa: E402
from stonesoup.metricgenerator.manager import MultiManager  # noqa: E402
from stonesoup.metricgenerator.ospametric import OSPAMetric  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.detection import Clutter, TrueDetection  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.hypothesis import SingleHypothesis  # noqa: E402
from stonesoup.types.prediction import GaussianStatePrediction  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.update import GaussianStateUpdate  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402

from hypotrack.interop.stonesoup import HypotrackTracker  # noqa: E402

Q, P_D, CLUTTER, REGION = 0.05, 0.9, 2.0, [[-60.0, 60.0], [-60.0, 60.0]]
T0 = datetime.datetime(2025, 1, 1)
SECOND = datetime.timedelta(seconds=1)
BIRTHS = [GaussianState([[-30.0], [1.5], [-10.0], [0.5]], np.diag([25.0, 0.25, 25.0, 0.25])),  # x, vx, y, vy
          GaussianState([[30.0], [-1.0], [20.0], [-1.0]], np.diag([25.0, 0.25, 25.0, 0.25]))]
BORN_AT = (0, 6)  # object b appears at scan BORN_AT[b] from BIRTHS[b]
N_SCANS = 20


def _models():
    return (CombinedLinearGaussianTransitionModel([ConstantVelocity(Q), ConstantVelocity(Q)]),
            LinearGaussian(4, (0, 2), np.eye(2)))


def _simulate(seed=21):
    """Truth paths and scans; noise from one seeded stream in list order (reproducible)."""
    tm, mm = _models()
    rng = np.random.default_rng(seed)
    F, Lq = tm.matrix(time_interval=SECOND), np.linalg.cholesky(tm.covar(time_interval=SECOND))
    paths, scans = [], []
    for k in range(N_SCANS):
        t = T0 + k * SECOND
        for path in paths:
            path.append(GroundTruthState(F @ path[-1].state_vector + Lq @ rng.standard_normal((4, 1)), timestamp=t))
        for b, k_b in enumerate(BORN_AT):
            if k == k_b:
                x0 = BIRTHS[b].state_vector + np.linalg.cholesky(BIRTHS[b].covar) @ rng.standard_normal((4, 1))
                paths.append(GroundTruthPath([GroundTruthState(x0, timestamp=t)], id=f"object {b}"))
        dets = {TrueDetection(mm.matrix() @ p[-1].state_vector + rng.standard_normal((2, 1)), timestamp=t,
                              measurement_model=mm, groundtruth_path=p) for p in paths if rng.random() < P_D}
        dets |= {Clutter(rng.uniform(-60.0, 60.0, (2, 1)), timestamp=t, measurement_model=mm)
                 for _ in range(rng.poisson(CLUTTER))}
        scans.append((t, dets))
    return scans, paths


def _kalman_oracle(b, path, scans):
    """Stone Soup's Kalman filter for object ``b`` born from its birth term at its first detection:
    the birth density updated with that detection, then predicted and updated with the object's own
    detections. ``{time: (state, detection or None)}`` from the first detection on."""
    tm, mm = _models()
    predictor, updater = KalmanPredictor(tm), KalmanUpdater(mm)
    own = {t: d for t, dets in scans for d in dets if getattr(d, "groundtruth_path", None) is path}
    oracle, state = {}, None
    for t, _ in scans:
        det = own.get(t)
        if state is None and det is None:
            continue
        prediction = (GaussianStatePrediction(BIRTHS[b].state_vector, BIRTHS[b].covar, timestamp=t) if state is None
                      else predictor.predict(state, timestamp=t))
        state = updater.update(SingleHypothesis(prediction, det)) if det is not None else prediction
        oracle[t] = (state, det)
    return oracle


@pytest.mark.parametrize(("algorithm", "options"), [
    ("glmb", {"n_sweeps": 200, "seed": 5}),
    ("glmb_murty", {}),
    # the PMBM with Bernoulli births is the δ-GLMB (tests/crosscheck/test_equivalence_pmbm_glmb.py): the same tracks
    ("pmbm_murty", {"birth": "bernoulli", "estimator": "joint_map"}),
    ("pmbm_gibbs", {"birth": "bernoulli", "estimator": "joint_map", "n_sweeps": 200, "seed": 5}),
])
def test_glmb_births_from_the_labeled_population_are_tracked(algorithm, options):
    scans, paths = _simulate()
    tm, mm = _models()
    tracker = HypotrackTracker(
        transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=P_D,
        clutter_rate=CLUTTER, clutter_region=REGION, detector=scans,
        options={"birth_states": BIRTHS, "birth_probability": 0.05, "survival_probability": 0.99,
                 "max_hypotheses": 30, "gate_probability": 0.999, **options})
    per_scan = [tracks for _, tracks in tracker]
    assert len(per_scan) == N_SCANS

    # Each object has one track (the one nearest it at the last scan), whose label was born from
    # the object's birth term at its first detection: every state of the track is Stone Soup's
    # Kalman filter started there (an update with the object's detection when it had one, else
    # a prediction), to rounding.
    owner, first_seen = {}, {}
    for b, path in enumerate(paths):
        last = path[-1].state_vector[[0, 2]].ravel()
        owner[b] = track = min(per_scan[-1], key=lambda t: np.hypot(*(t.state_vector[[0, 2]].ravel() - last)))
        oracle = _kalman_oracle(b, path, scans)
        first_seen[b] = int((min(oracle) - T0).total_seconds())
        assert first_seen[b] >= BORN_AT[b]
        assert len(track) >= N_SCANS - first_seen[b] - 3  # in the MAP hypothesis within 3 scans of its first return
        for state in track:
            expected, det = oracle[state.timestamp]
            if det is None:
                assert type(state) is GaussianStatePrediction
            else:
                assert isinstance(state, GaussianStateUpdate) and state.hypothesis.measurement is det
            np.testing.assert_allclose(state.state_vector, expected.state_vector, rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(state.covar, expected.covar, rtol=1e-9, atol=1e-9)
        if track[0].timestamp == min(oracle):  # output from its birth scan: the prediction is the birth term
            np.testing.assert_array_equal(track[0].hypothesis.prediction.state_vector, BIRTHS[b].state_vector)
    assert owner[0].id != owner[1].id
    assert first_seen == {0: 0, 1: 7}  # object 1, born at scan 6, is first detected at scan 7

    # From three scans after each object's first detection: exactly the live objects have tracks
    # (no false track from the clutter), each within 3 m of its object (R = I), ~1 m on average.
    errors = []
    for k, tracks in enumerate(per_scan):
        live = [b for b in range(2) if k >= first_seen[b] + 3]
        if not live:
            continue
        assert len(tracks) == len(live) or len(tracks) == sum(k >= first_seen[b] for b in range(2)), k
        for b in live:
            assert owner[b] in tracks
            truth = paths[b][k - BORN_AT[b]]
            state = owner[b][truth.timestamp]
            errors.append(float(np.hypot(*(state.state_vector[[0, 2]] - truth.state_vector[[0, 2]]).ravel())))
            assert errors[-1] < 3.0, (algorithm, b, k, errors[-1])
    assert len(errors) == (N_SCANS - 3) + (N_SCANS - 7 - 3)
    assert np.mean(errors) < 1.0

    # Stone Soup's OSPA (c = 10 m, p = 1) once both are tracked is about the measurement noise.
    manager = MultiManager([OSPAMetric(c=10.0, p=1, measure=Euclidean(mapping=(0, 2)))])
    manager.add_data({"tracks": tracker.all_tracks, "groundtruth_paths": set(paths)})
    ospa = manager.generate_metrics()["ospa_generator"]["OSPA distances"].value
    late = [m.value for m in ospa if (m.timestamp - T0).total_seconds() >= 7 + 3]
    assert len(late) == N_SCANS - 10 and np.mean(late) < 1.5


@pytest.mark.parametrize(("algorithm", "options", "message"), [
    ("glmb", {"birth_states": BIRTHS}, r"options\['birth_probability'\] .* is required with birth_states"),
    ("glmb", {"birth_states": BIRTHS, "birth_probability": 1.0}, r"options\['birth_probability'\] must lie in \(0, 1\)"),
    ("glmb_murty", {"birth_states": BIRTHS, "birth_probability": [0.1, 0.2, 0.3]},
     r"options\['birth_probability'\] must lie in \(0, 1\), one value or one per birth state \(2\)"),
    ("glmb", {"survival_probability": 0.0}, r"options\['survival_probability'\] .* must lie in \(0, 1\], got 0.0"),
    ("glmb", {"birth_states": [GaussianState([[0.0], [0.0]], np.eye(2))], "birth_probability": 0.1},
     r"options\['birth_states'\]\[0\] must be a GaussianState with a 4-component state vector"),
    ("glmb", {"birth_states": [GaussianState(np.zeros((4, 1)), -np.eye(4))], "birth_probability": 0.1},
     r"options\['birth_states'\]\[0\]: cov"),
    ("rfisst", {"birth_states": BIRTHS}, r"options \['birth_states'\] describe the labeled population"),
    ("glmb", {"population": object(), "survival_probability": 0.9}, "give either population"),
])
def test_bad_birth_options_are_named(algorithm, options, message):
    tm, mm = _models()
    with pytest.raises(ValueError, match=message):
        HypotrackTracker(transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=P_D,
                         clutter_rate=CLUTTER, clutter_region=REGION, options=options)


@pytest.mark.parametrize("algorithm", ["pmbm_murty", "pmbm_gibbs"])
def test_pmbm_with_poisson_births_tracks_both_objects(algorithm):
    """The PMBM's own birth model (the terms' r_B as Poisson birth weights): a track starts from the
    Poisson part at an object's first detection, is reported once its existence passes 0.5, and from
    there on follows Stone Soup's Kalman filter fed the object's own returns."""
    scans, paths = _simulate()
    tm, mm = _models()
    tracker = HypotrackTracker(
        transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=P_D,
        clutter_rate=CLUTTER, clutter_region=REGION, detector=scans,
        options={"birth_states": BIRTHS, "birth_probability": 0.05, "survival_probability": 0.99,
                 "max_hypotheses": 30, "gate_probability": 0.999, "seed": 5})
    per_scan = [tracks for _, tracks in tracker]
    predictor, updater = KalmanPredictor(tm), KalmanUpdater(mm)
    for path in paths:
        last = path[-1].state_vector[[0, 2]].ravel()
        track = min(per_scan[-1], key=lambda t: np.hypot(*(t.state_vector[[0, 2]].ravel() - last)))
        assert np.hypot(*(track.state_vector[[0, 2]].ravel() - last)) < 3.0
        # reported once its existence passes 0.5: at or after its first detection, an update with its own return
        own = [t for t, dets in scans for d in dets if getattr(d, "groundtruth_path", None) is path]
        first = track[0]
        assert first.timestamp >= own[0] and isinstance(first, GaussianStateUpdate)
        assert all(s.hypothesis.measurement.groundtruth_path is path for s in track if isinstance(s, GaussianStateUpdate))
        # from its second state on, each is Stone Soup's Kalman prediction/update of the one before
        for before, state in zip(track, track[1:]):
            prediction = predictor.predict(before, timestamp=state.timestamp)
            expected = (updater.update(SingleHypothesis(prediction, state.hypothesis.measurement))
                        if isinstance(state, GaussianStateUpdate) else prediction)
            np.testing.assert_allclose(state.state_vector, expected.state_vector, rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(state.covar, expected.covar, rtol=1e-9, atol=1e-9)
    assert len(per_scan[-1]) == 2

"""GNN, JPDA and the PDA update against Stone Soup on the same seeded cluttered scenarios.

Five closely spaced constant-velocity targets in Poisson clutter, 25 scans, tracks started on
the truth (no initiation), both libraries run side by side scan by scan, each on its own
filtered states. Stone Soup orders the state [x, vx, y, vy], hypotrack [x, y, vx, vy].

Conventions matched: the clutter spatial density is passed explicitly to
``PDAHypothesiser`` (otherwise Stone Soup estimates it from the data); GNN is compared in the
criterion Stone Soup's ``GNNWith2DAssignment`` + ``DistanceHypothesiser`` actually solves (sum
of unsquared Mahalanobis distances, ``gnn_score="mahalanobis"``) — the lecture's log-likelihood
criterion is tested separately in ``tests/unit/trackers/test_gnn.py``; Stone Soup's updaters use the
Joseph form as hypotrack does.
"""

import datetime

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.dataassociator.neighbour import GNNWith2DAssignment  # noqa: E402
from stonesoup.dataassociator.probability import JPDA, JPDAwithEHM2  # noqa: E402
from stonesoup.hypothesiser.distance import DistanceHypothesiser  # noqa: E402
from stonesoup.hypothesiser.probability import PDAHypothesiser  # noqa: E402
from stonesoup.measures import Mahalanobis  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity as SSConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.state import GaussianState as SSGaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402
from stonesoup.updater.probability import PDAUpdater  # noqa: E402

from hypotrack.association import find_clusters  # noqa: E402
from hypotrack.models import ConstantVelocity  # noqa: E402
from hypotrack.scenarios.cluttered import closely_spaced_targets  # noqa: E402
from hypotrack.trackers._sht_common import ScanModel, gate_tracks, predict_tracks  # noqa: E402
from hypotrack.trackers.gnn import gnn_associate, gnn_update, mahalanobis_gains  # noqa: E402
from hypotrack.trackers.jpda import jpda_probabilities, pda_update  # noqa: E402

PERM = [0, 2, 1, 3]  # hypotrack [x, y, vx, vy] -> Stone Soup [x, vx, y, vy]
Q_FILTER = 0.5
P0 = np.diag([25.0, 25.0, 4.0, 4.0])
T0 = datetime.datetime(2026, 1, 1)
TOL = 1e-9


def _scenario(seed):
    return closely_spaced_targets(
        5, spacing=12.0, speed=10.0, n_scans=25, q_truth=0.5, sigma=5.0, p_D=0.9, clutter_rate=30.0, rng=seed
    )


def _stonesoup_models(sc):
    R = sc.sensor.measurement.R
    trans = CombinedLinearGaussianTransitionModel([SSConstantVelocity(Q_FILTER), SSConstantVelocity(Q_FILTER)])
    meas = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=R)
    return KalmanPredictor(trans), meas


def _ss_tracks(x0):
    return [Track([SSGaussianState(x[PERM].reshape(-1, 1), P0[np.ix_(PERM, PERM)], timestamp=T0)]) for x in x0]


def _detections(Z, t, meas):
    ts = T0 + datetime.timedelta(seconds=float(t))
    return ts, [Detection(z.reshape(-1, 1), timestamp=ts, measurement_model=meas) for z in Z]


def _ss_state(track):
    return np.ravel(track.state_vector)[np.argsort(PERM)], track.covar[np.ix_(np.argsort(PERM), np.argsort(PERM))]


def _assert_states_equal(x, P, tracks, diffs):
    for i, tr in enumerate(tracks):
        xs, Ps = _ss_state(tr)
        diffs.append(max(np.max(np.abs(x[i] - xs)), np.max(np.abs(P[i] - Ps))))
        np.testing.assert_allclose(x[i], xs, rtol=TOL, atol=TOL)
        np.testing.assert_allclose(P[i], Ps, rtol=TOL, atol=TOL)


@pytest.mark.parametrize("seed", [4, 5])
def test_gnn_equals_stonesoup_gnn_with_2d_assignment(seed):
    sc = _scenario(seed)
    model = ScanModel.from_sensor(sc.sensor, p_gate=0.99)
    g = float(np.sqrt(model.gate))
    predictor, meas = _stonesoup_models(sc)
    updater = KalmanUpdater(meas, use_joseph_cov=True)
    associator = GNNWith2DAssignment(DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=g))
    motion = ConstantVelocity(Q_FILTER)
    x0 = sc.initial_states
    x, P = x0.copy(), np.broadcast_to(P0, (len(x0), 4, 4)).copy()
    tracks = _ss_tracks(x0)
    t_prev, n_contested, diffs = 0.0, 0, []
    for t, Z in sc.scan_list()[1:]:
        ts, dets = _detections(Z, t, meas)
        assoc = associator.associate(set(tracks), set(dets), ts)
        ss_event = np.full(len(Z), -1)
        for i, tr in enumerate(tracks):
            hyp = assoc[tr]
            if hyp:
                ss_event[next(k for k, d in enumerate(dets) if d is hyp.measurement)] = i
                tr.append(updater.update(hyp))
            else:
                tr.append(hyp.prediction)

        x, P = predict_tracks(motion, x, P, t - t_prev)
        t_prev = t
        gated = gate_tracks(x, P, Z, model, gate=g**2)
        a = gnn_associate(mahalanobis_gains(gated, g))
        n_contested += int(((gated.valid.sum(axis=1) > 1)).any())
        np.testing.assert_array_equal(a, ss_event)
        x, P, _ = gnn_update(gated, a, model)
        _assert_states_equal(x, P, tracks, diffs)
    assert n_contested >= 10, "scenario too easy: returns rarely fall in two gates"
    assert max(diffs) < TOL


def _run_jpda_crosscheck(seed, associator_cls, min_cluster=3):
    sc = _scenario(seed)
    model = ScanModel.from_sensor(sc.sensor, p_gate=0.95)
    predictor, meas = _stonesoup_models(sc)
    updater = PDAUpdater(meas, use_joseph_cov=True)
    hypothesiser = PDAHypothesiser(
        predictor, updater, clutter_spatial_density=model.clutter_density, prob_detect=model.p_D,
        prob_gate=model.p_gate,
    )
    associator = associator_cls(hypothesiser)
    motion = ConstantVelocity(Q_FILTER)
    x0 = sc.initial_states
    x, P = x0.copy(), np.broadcast_to(P0, (len(x0), 4, 4)).copy()
    tracks = _ss_tracks(x0)
    t_prev, biggest, beta_diffs, state_diffs = 0.0, 0, [], []
    for t, Z in sc.scan_list()[1:]:
        ts, dets = _detections(Z, t, meas)
        hyps = associator.associate(set(tracks), set(dets), ts)
        ss_beta = np.zeros((len(tracks), len(Z) + 1))
        for i, tr in enumerate(tracks):
            for h in hyps[tr]:
                col = 0 if not h else 1 + next(k for k, d in enumerate(dets) if d is h.measurement)
                ss_beta[i, col] = float(h.probability)
            tr.append(updater.update(hyps[tr]))

        x, P = predict_tracks(motion, x, P, t - t_prev)
        t_prev = t
        gated = gate_tracks(x, P, Z, model)
        beta = jpda_probabilities(gated, model)
        biggest = max([biggest, *(len(c.tracks) for c in find_clusters(gated.valid))])
        beta_diffs.append(np.max(np.abs(beta - ss_beta)))
        np.testing.assert_allclose(beta, ss_beta, rtol=0, atol=TOL)
        x, P = pda_update(gated, beta, model)
        _assert_states_equal(x, P, tracks, state_diffs)
    assert biggest >= min_cluster, f"largest cluster only {biggest} tracks"
    return max(beta_diffs), max(state_diffs)


@pytest.mark.parametrize("seed", [4, 5])
def test_jpda_equals_stonesoup_brute_force_jpda(seed):
    beta_diff, state_diff = _run_jpda_crosscheck(seed, JPDA)
    assert beta_diff < TOL and state_diff < TOL


@pytest.mark.parametrize("seed", [6])
def test_jpda_equals_stonesoup_jpda_with_ehm2(seed):
    beta_diff, state_diff = _run_jpda_crosscheck(seed, JPDAwithEHM2)
    assert beta_diff < TOL and state_diff < TOL


def test_jpda_equals_pyehm_plugin():
    """pyehm's C++ EHM2 (Stone Soup's ``[ehm]`` extra) gives the same marginals."""
    pytest.importorskip("pyehm")
    from pyehm.plugins.stonesoup import JPDAWithEHM2 as PyEHM2

    beta_diff, state_diff = _run_jpda_crosscheck(7, PyEHM2)
    assert beta_diff < TOL and state_diff < TOL

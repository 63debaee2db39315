"""M-of-N initiation, deletion after misses and stable ids in the complete tracker."""

import numpy as np
import pytest

from hypotrack.gaussian import predict_with, update
from hypotrack.metrics import ospa
from hypotrack.models import ConstantVelocity
from hypotrack.scenarios.cluttered import crossing_targets
from hypotrack.trackers._sht_common import ScanModel
from hypotrack.trackers.initiation import MOfNInitiator
from hypotrack.trackers.tracker import SingleHypothesisTracker

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
MODEL = ScanModel(H, np.eye(2), 0.9, 0.99, 1e-4)
MOTION = ConstantVelocity(0.1)


def target_return(k, start=(0.0, 0.0), vel=(5.0, 0.0)):
    return np.array([[start[0] + vel[0] * k, start[1] + vel[1] * k]])


def run_pattern(hit_pattern, m, n):
    """Feed one target's returns on the scans where ``hit_pattern`` is True; record confirmations."""
    init = MOfNInitiator(MOTION, MODEL, m=m, n=n, initial_velocity_std=8.0)
    confirmed_at = []
    for k, hit in enumerate(hit_pattern):
        x, _ = init.step(float(k), target_return(k) if hit else np.zeros((0, 2)))
        confirmed_at += [k] * len(x)
    return confirmed_at, init


@pytest.mark.parametrize(
    "pattern, m, n, expected",
    [
        ([1, 1, 0, 0], 2, 3, [1]),  # second hit confirms
        ([1, 0, 1, 0], 2, 3, [2]),  # 2 of 3 with a gap
        ([1, 0, 0, 1, 1], 2, 3, [4]),  # first tentative dies at scan 2; a new one starts at 3
        ([1, 1, 0, 1, 0], 3, 4, [3]),  # 3 of 4
        ([1, 1, 0, 0, 0], 3, 4, []),  # never 3 hits
        ([1, 0, 0, 0], 1, 1, [0]),  # 1 of 1: every return confirms at once
    ],
)
def test_m_of_n_confirmation_scans(pattern, m, n, expected):
    confirmed_at, _ = run_pattern([bool(h) for h in pattern], m, n)
    assert confirmed_at == expected


def test_confirmed_state_is_the_kalman_filter_from_one_point_initiation():
    """x₀ = [z, 0, 0], P₀ = diag(R, σ_v² I), then the ordinary Kalman filter on the target's returns."""
    _, init = run_pattern([True], 3, 3)
    for k in range(1, 3):
        x_conf, P_conf = init.step(float(k), target_return(k))
    assert len(x_conf) == 1
    x = np.array([0.0, 0.0, 0.0, 0.0])
    P = np.diag([1.0, 1.0, 64.0, 64.0])  # R = I, initial_velocity_std = 8
    for k in range(1, 3):
        x, P = predict_with(MOTION, x, P, 1.0)
        x, P = update(x, P, target_return(k)[0], H, MODEL.R)
    np.testing.assert_allclose(x_conf[0], x, atol=1e-10)
    np.testing.assert_allclose(P_conf[0], P, atol=1e-10)


def test_scattered_clutter_never_confirms():
    """Returns far apart (beyond any gate) every scan: tentative tracks start and die, none confirm."""
    rng = np.random.default_rng(1)
    init = MOfNInitiator(MOTION, MODEL, m=3, n=4, initial_velocity_std=2.0)
    for k in range(15):
        x, _ = init.step(float(k), rng.uniform(-1e5, 1e5, size=(5, 2)))
        assert len(x) == 0
    assert len(init) <= 5 * 4  # each lives at most n scans


def tracker(association, **kw):
    return SingleHypothesisTracker(
        MOTION, MODEL, association=association,
        initiator=MOfNInitiator(MOTION, MODEL, m=2, n=3, initial_velocity_std=8.0), **kw,
    )


@pytest.mark.parametrize("association", ["gnn", "jpda", "pdaf"])
def test_ids_are_stable_and_deleted_tracks_are_not_reused(association):
    tr = tracker(association, max_misses=3)
    ids_seen = []
    for k in range(12):
        Z = [target_return(k, (0, 0)), target_return(k, (0, 500))]
        if k >= 6:
            Z = Z[:1]  # the second target disappears after scan 5
        est = tr.step(np.concatenate(Z), float(k))
        ids_seen.append(est.ids.tolist())
    assert ids_seen[0] == [] and ids_seen[1] == [0, 1]
    assert all(ids == [0, 1] for ids in ids_seen[1:8])  # misses at scans 6, 7 …
    assert all(ids == [0] for ids in ids_seen[8:])  # … and 8: deleted after 3 misses
    est = tr.step(np.concatenate([target_return(12, (0, 0)), np.array([[2000.0, 2000.0]])]), 12.0)
    est = tr.step(np.concatenate([target_return(13, (0, 0)), np.array([[2000.0, 2000.0]])]), 13.0)
    assert est.ids.tolist() == [0, 2]  # a new track gets a new id


def test_known_tracks_then_initiation_on_crossing_scenario():
    """GNN tracker on a clutter-free crossing: both tracks kept, OSPA at the end below 2σ."""
    sc = crossing_targets(2, crossing_angle_deg=40.0, clutter_rate=0.0, p_D=1.0, sigma=2.0, n_scans=30, rng=3)
    model = ScanModel(H, sc.sensor.measurement.R, 0.99, 0.99, 1e-6)
    tr = SingleHypothesisTracker(MOTION, model, association="gnn",
                                 initiator=MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=15.0))
    for t, Z in sc.scan_list():
        est = tr.step(Z, t)
    truth = sc.truth_list()[-1][2]
    assert len(est) == 2
    assert ospa(est.x[:, :2], truth[:, :2], c=50.0, p=2) < 4.0


def test_bad_input():
    with pytest.raises(ValueError, match="m"):
        MOfNInitiator(MOTION, MODEL, m=4, n=3)
    with pytest.raises(ValueError, match="n"):
        MOfNInitiator(MOTION, MODEL, m=1, n=0)
    with pytest.raises(ValueError, match="initial_velocity_std"):
        MOfNInitiator(MOTION, MODEL, initial_velocity_std=0.0)
    with pytest.raises(TypeError, match="model"):
        MOfNInitiator(MOTION, "model")
    init = MOfNInitiator(MOTION, MODEL)
    init.step(1.0, np.zeros((0, 2)))
    with pytest.raises(ValueError, match="time"):
        init.step(0.5, np.zeros((0, 2)))
    with pytest.raises(ValueError, match="Z"):
        init.step(2.0, np.array([[np.nan, 1.0]]))
    with pytest.raises(ValueError, match="max_misses"):
        tracker("gnn", max_misses=0)

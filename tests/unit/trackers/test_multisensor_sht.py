"""GNN/JPDA over two sensors (hypotrack.trackers.multisensor): each scan with its own sensor's model and view; misses
counted in the scanning sensor's view and never forgiven by a sensor that cannot see the track."""

import numpy as np
import pytest

from hypotrack.models.motion import ConstantVelocity
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker
from hypotrack.trackers.multisensor import MultiSensorSHT

MOTION = ConstantVelocity(q=0.01)
H = np.hstack([np.eye(2), np.zeros((2, 2))])
R_A, R_B = np.eye(2) * 0.2, np.diag([0.05, 0.8])
MODEL_A, MODEL_B = ScanModel(H, R_A, 0.9, 0.999, 1e-3), ScanModel(H, R_B, 0.7, 0.999, 1e-3)
# a seen by A only, b by both, c by B only, d by neither
X0 = np.array([[-5.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [5.0, 0.0, 0.0, 0.0], [20.0, 0.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([0.5, 0.5, 0.01, 0.01])[None], 4, axis=0)


def _view(lo, hi):
    return lambda x: (np.asarray(x)[:, 0] >= lo) & (np.asarray(x)[:, 0] <= hi)


def _tracker(association, lazy, initiator=False):
    out = []
    for model, view in ((MODEL_A, _view(-10, 1)), (MODEL_B, _view(-1, 10))):
        ini = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=1.0) if initiator else None
        t = SingleHypothesisTracker(MOTION, model, association=association, max_misses=3, in_view=view, lazy=lazy,
                                    initiator=ini)
        t.initialise(X0, P0, [10, 11, 12, 13])
        out.append(t)
    return MultiSensorSHT.from_trackers(out)


@pytest.mark.parametrize("association", ["gnn", "jpda"])
@pytest.mark.parametrize("lazy", [False, True])
def test_misses_count_in_the_scanning_sensors_view_only(association, lazy):
    """Empty scans A, B, A, B, A at t = 1, 1, 2, 2, 3: a (A only) is missed at each A scan and B's scans neither miss
    nor forgive it — deleted at the third A scan; c (B only) has two B misses and stays; d (no sensor) stays; b,
    in both views, is missed at every scan and goes at the third (t = 2, A)."""
    t = _tracker(association, lazy)
    seen = []
    for time, s in ((1.0, 0), (1.0, 1), (2.0, 0), (2.0, 1), (3.0, 0)):
        t.step(np.zeros((0, 2)), time, sensor=s)
        seen.append(sorted(t.ids.tolist()))
    assert seen == [[10, 11, 12, 13], [10, 11, 12, 13], [10, 12, 13], [10, 12, 13], [12, 13]]
    assert dict(zip(t.ids.tolist(), t.misses.tolist())) == {12: 2, 13: 0}


def test_a_return_of_sensor_b_updates_with_b_s_model():
    """c (B only) takes B's return: the Kalman update with R_B (by hand), not R_A; zero interval after A's scan."""
    t = _tracker("gnn", False)
    t.step(np.zeros((0, 2)), 0.0, sensor=0)
    z = np.array([5.4, -0.3])
    t.step(z[None], 0.0, sensor=1)
    P = P0[2]
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R_B)
    j = int(np.flatnonzero(t.ids == 12)[0])
    np.testing.assert_allclose(t.x[j], X0[2] + K @ (z - H @ X0[2]), atol=1e-12)
    np.testing.assert_allclose(t.P[j], (np.eye(4) - K @ H) @ P @ (np.eye(4) - K @ H).T + K @ R_B @ K.T, atol=1e-12)
    assert t.sensor == 1


def test_a_tentative_track_from_a_is_confirmed_by_b_at_the_same_instant():
    """A new object at (0, 5) (both views): A's return starts a tentative track (R_A), B's return at the same instant
    is its second hit (2 of 3): confirmed then, with B's update of A's one-point state."""
    t = _tracker("gnn", False, initiator=True)
    t.step(np.array([[0.1, 5.0]]), 0.0, sensor=0)
    assert len(t.ids) == 4 and len(t.initiator) == 1
    t.step(np.array([[0.0, 5.2]]), 0.0, sensor=1)
    assert len(t.ids) == 5 and len(t.initiator) == 0
    P = np.diag([0.2, 0.2, 1.0, 1.0])
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R_B)
    np.testing.assert_allclose(t.x[-1], np.array([0.1, 5.0, 0, 0]) + K @ (np.array([0.0, 5.2]) - [0.1, 5.0]), atol=1e-12)


def test_bad_input():
    t = _tracker("gnn", False)
    with pytest.raises(ValueError, match="sensor"):
        t.step(np.zeros((0, 2)), 1.0, sensor=2)
    with pytest.raises(ValueError):
        t.step(np.zeros((1, 3)), 1.0, sensor=1)
    assert t.sensor == 0
    with pytest.raises(ValueError, match="in_view"):
        MultiSensorSHT.from_trackers([SingleHypothesisTracker(MOTION, MODEL_A)])


class _Mixture:
    """One component at the return with velocity ``(vx, 0)``: each sensor's admissible region differs."""

    def __init__(self, vx):
        self.vx = vx

    def components(self, z):
        return np.ones(1), np.array([[z[0], z[1], self.vx, 0.0]]), np.diag([0.01, 0.01, 0.01, 0.01])[None]


def test_each_sensors_return_starts_from_that_sensors_mixture():
    """A's return (−5, 0) and B's (5, 0), each in its own view only: A's tentative track moves at +1 (A's mixture),
    B's at −1 (B's); the mixture of the sensor scanned last would give both one velocity."""
    trackers = []
    for model, view, vx in ((MODEL_A, _view(-10, 1), 1.0), (MODEL_B, _view(-1, 10), -1.0)):
        ini = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=1.0, mixture=_Mixture(vx))
        trackers.append(SingleHypothesisTracker(MOTION, model, association="gnn", max_misses=3, in_view=view,
                                                initiator=ini))
    t = MultiSensorSHT.from_trackers(trackers)
    t.step(np.array([[-5.0, 0.0]]), 0.0, sensor=0)
    t.step(np.array([[5.0, 0.0]]), 0.0, sensor=1)
    tentative = {float(x[0]): float(x[2]) for x in t.initiator.x}
    assert tentative == {-5.0: 1.0, 5.0: -1.0}

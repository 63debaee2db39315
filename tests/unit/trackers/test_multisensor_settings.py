"""MultiSensorSHT.from_trackers keeps every setting of trackers[0] (association, JPDA marginals, GNN criterion,
deletion, views, lazy prediction, validity) and its known tracks and time: scanned by sensor 0 only, the fused
tracker is sensor 0's own tracker, byte for byte. Each setting is checked on a scene where it changes the outcome
(asserted: the setting's run differs from the default's). Also: the checks of from_trackers and of ``sensor``, and
the views never asked about an empty set of states."""

import numpy as np
import pytest

from hypotrack.models.motion import ConstantVelocity
from hypotrack.trackers import ScanModel, SingleHypothesisTracker
from hypotrack.trackers.multisensor import MultiSensorSHT

MOTION = ConstantVelocity(q=0.01)
H = np.hstack([np.eye(2), np.zeros((2, 2))])
MODEL_0, MODEL_1 = ScanModel(H, np.eye(2) * 0.2, 0.9, 0.999, 1e-3), ScanModel(H, np.diag([0.05, 0.8]), 0.7, 0.999, 1e-3)
# A (broad) and B (tight) both gate the return at x = 7 (the lecture's score prefers B, Mahalanobis A), then both
# gate both returns of the second scan (a cycle: loopy BP is not exact); C is out
# of view (x < −20) with a return beside it; D is in view but fails validity (x > 50); E is in view and missed.
X0 = np.array([[0.0, 0.0, 0.0, 0.0], [10.0, 0.0, 0.0, 0.0], [-30.0, 0.0, 0.5, 0.0], [60.0, 0.0, 0.0, 0.0],
               [30.0, 0.0, 0.0, 0.0]])
P0 = np.stack([np.diag([p, p, 0.01, 0.01]) for p in (99.8, 0.8, 0.5, 0.5, 0.5)])
SCANS = [(6.0, [[7.0, 0.0], [-29.5, 0.1]]), (7.0, [[7.5, 0.1], [9.0, 0.3]]), (8.0, np.zeros((0, 2)))]


def _view(x):
    return np.asarray(x)[:, 0] >= -20.0


def _valid(x):
    return np.asarray(x)[:, 0] <= 50.0


SETTINGS = {
    "jpda": dict(association="jpda"),
    "jpda_lbp": dict(association="jpda", jpda_marginals="lbp"),
    "pdaf": dict(association="pdaf"),
    "mahalanobis": dict(gnn_score="mahalanobis"),
    "no_gating_out_of_view": dict(gate_out_of_view=False),
    "lazy": dict(lazy=True),
    "max_misses_1": dict(max_misses=1),
    "validity": dict(validity=_valid),
}


def _sensor_tracker(model, settings, known=True):
    t = SingleHypothesisTracker(MOTION, model, in_view=_view, **settings)
    if known:
        t.initialise(X0, P0, [10, 11, 12, 13, 14], time=5.0)
    return t


def _run(t):
    """Per scan: the estimates' labels and means, the held moments (a lazy tracker's deferred ones as held), the
    miss counts and the number of tracks predicted."""
    out = []
    for time, Z in SCANS:
        est = t.step(np.asarray(Z, dtype=float), time)
        out.append((est.ids.copy(), est.x.copy(), t.x.copy(), t.P.copy(), t.misses.copy(), t.last_predicted))
    return out


def _same(a, b):
    return all(len(u) == len(v) and all(np.array_equal(p, q) for p, q in zip(u, v)) for u, v in zip(a, b))


@pytest.mark.parametrize("name", [None, *SETTINGS])
def test_scanned_by_sensor_0_the_fused_tracker_is_sensor_0s_own(name):
    settings = SETTINGS.get(name, {})
    own = _run(_sensor_tracker(MODEL_0, settings))
    # trackers[1] has another model and no known tracks: the fused tracker takes trackers[0]'s
    fused = MultiSensorSHT.from_trackers([_sensor_tracker(MODEL_0, settings),
                                          _sensor_tracker(MODEL_1, settings, known=False)])
    assert _same(_run(fused), own)  # step without sensor=: sensor 0
    assert fused.misses.dtype == np.int64  # miss counts stay exact integers
    if name is not None:  # the setting matters here
        assert not _same(own, _run(_sensor_tracker(MODEL_0, {})))


def test_one_sensor_is_a_fused_tracker_too():
    fused = MultiSensorSHT.from_trackers([_sensor_tracker(MODEL_1, {})])
    assert fused.n_sensors == 1
    assert _same(_run(fused), _run(_sensor_tracker(MODEL_1, {})))


def test_the_views_are_never_asked_about_no_states():
    """As the tracker itself never calls ``in_view`` on an empty state array, nor does the union of the views."""
    def strict(x):
        assert len(x), "in_view called with no states"
        return np.ones(len(x), dtype=bool)

    ts = []
    for model in (MODEL_0, MODEL_1):
        t = SingleHypothesisTracker(MOTION, model, in_view=strict, max_misses=3)
        t.initialise(X0[:2], P0[:2], [1, 2])
        ts.append(t)
    fused = MultiSensorSHT.from_trackers(ts)
    fused.step(np.array([[0.1, 0.0]]), 1.0, sensor=1)  # every track in view: none out of it
    assert fused.misses.tolist() == [0, 1]


def test_checks_of_the_trackers_and_the_sensor():
    t0 = _sensor_tracker(MODEL_0, {})
    with pytest.raises(ValueError, match=r"^trackers must hold one SingleHypothesisTracker per sensor, got none$"):
        MultiSensorSHT.from_trackers([])
    with pytest.raises(TypeError, match=r"^trackers\[1\] must be a SingleHypothesisTracker, got str$"):
        MultiSensorSHT.from_trackers([t0, "B"])
    other = SingleHypothesisTracker(ConstantVelocity(q=0.01), MODEL_1, in_view=_view)  # equal, not the same object
    with pytest.raises(ValueError, match=r"^trackers\[1\] must share trackers\[0\]'s motion model \(the same object\) "
                                         r"and state dimension$"):
        MultiSensorSHT.from_trackers([t0, other])
    from hypotrack.trackers import MOfNInitiator
    with_init = SingleHypothesisTracker(MOTION, MODEL_1, in_view=_view, initiator=MOfNInitiator(MOTION, MODEL_1))
    with pytest.raises(ValueError, match=r"^trackers\[1\]: initiation on one sensor needs it on every sensor$"):
        MultiSensorSHT.from_trackers([t0, with_init])
    fused = MultiSensorSHT.from_trackers([t0, _sensor_tracker(MODEL_1, {})])
    with pytest.raises(ValueError, match=r"^sensor must be an integer in \[0, 1\], got -1$"):
        fused.step(np.zeros((0, 2)), 6.0, sensor=-1)
    assert fused.sensor == 0 and fused.time == 5.0


def test_before_its_first_scan_the_fused_tracker_holds_trackers_0s_settings():
    """Settings the scenes above cannot tell apart are carried over too: the lazy prediction's form (``gap`` equals
    ``replay`` for constant velocity), and the missed distance and ``p_detect`` (each scan takes its sensor's)."""
    def p_detect(x):
        return np.full(len(x), 0.8)

    settings = dict(association="jpda", jpda_marginals="lbp", max_misses=2, gnn_score="mahalanobis",
                    missed_distance=2.5, lazy=True, lazy_prediction="gap", validity=_valid, p_detect=p_detect)
    t0 = _sensor_tracker(MODEL_0, settings)
    fused = MultiSensorSHT.from_trackers([t0, _sensor_tracker(MODEL_1, settings, known=False)])
    for name in ("association", "jpda_marginals", "max_misses", "gnn_score", "missed_distance", "gate_out_of_view",
                 "lazy", "lazy_prediction", "validity", "p_detect", "in_view", "model", "time"):
        assert getattr(fused, name) == getattr(t0, name), name
    assert fused.missed_distance == 2.5 and fused.lazy_prediction == "gap" and fused.time == 5.0
    assert fused.ids.tolist() == [10, 11, 12, 13, 14] and np.array_equal(fused.x, X0)

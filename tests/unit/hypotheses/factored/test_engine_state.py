"""The factored filter's public state (``state()``, ``same_posterior``), its scan times and its
``estimates()``; its zero-interval scan against the unfactored engine's."""

import copy

import numpy as np
import pytest

from hypotrack.hypotheses import FactoredFilter, homht
from hypotrack.hypotheses.factored import FactoredState
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.protocol import HypothesisTracker, TrackEstimates

REGION = Box([-20.0, -20.0], [20.0, 20.0])
SENSOR = Sensor(LinearPositionSensor(np.eye(2) * 0.5, ndim_state=4, position_indices=(0, 1)),
                DetectionModel(0.8, REGION), PoissonClutter(1.0, REGION))
MOTION = ConstantVelocity(q=0.05)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 8.0, 1.0, 0.0], [-10.0, -10.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 3, axis=0)
Z = np.array([[0.4, 0.1], [-0.3, 0.2], [0.2, 8.3], [15.0, -15.0]])  # a: 2 returns, b: 1, c: none; clutter


def _engine():
    return homht(MOTION, SENSOR, max_hypotheses=1000, gate_probability=0.99, means=X0, covs=P0, seed=0)


def test_zero_interval_scan_equals_the_engines_and_predicts_nothing():
    """HOMHT with a fixed number of objects is separable (package docstring): at a zero interval the
    factored posterior is the unfactored one, and object c (no return) keeps its prior moments bit for bit."""
    f = _engine()
    ff = FactoredFilter.from_filter(_engine(), lazy=True)
    f.step(Z, 0.0)
    ff.step(Z, 0.0)
    assert ff.time == f.time == 0.0 and ff.last_stats["n_predicted"] == 3
    joint = ff.joint_hypotheses()
    want = f.posterior(n_top=len(f.state))
    np.testing.assert_allclose([h.log_weight for h in joint], want.log_weights, rtol=0, atol=1e-12)
    def key(h):  # a hypothesis by its tracks, labels in order
        o = np.argsort(h.labels)
        return np.concatenate([h.labels[o], h.means[o].ravel(), h.covs[o].ravel()])

    rest = [key(h) for h in want.top]
    for a in joint:  # the same hypotheses (in any order among near-equal weights)
        k = key(a)
        match = [i for i, r in enumerate(rest) if len(r) == len(k) and np.allclose(r, k, rtol=0, atol=1e-12)]
        assert len(match) == 1
        rest.pop(match[0])
    assert rest == []
    (c,) = [g for g in ff.groups if g.labels.tolist() == [2]]
    assert np.array_equal(c.store.means[0], X0[2]) and np.array_equal(c.store.covs[0], P0[2])
    est = ff.estimates()
    assert isinstance(est, TrackEstimates) and est.P is None and est.time == 0.0
    assert sorted(est.labels.tolist()) == [0, 1, 2] and isinstance(ff, HypothesisTracker)
    ff.step(Z + 1.0, 1.0)  # then a scan one second later
    assert ff.time == 1.0
    with pytest.raises(ValueError, match="^time must be >= the filter's time 1.0"):
        ff.step(Z, 0.5)
    assert ff.time == 1.0 and ff.scan_index == 2


def test_state_and_same_posterior():
    a, b = FactoredFilter.from_filter(_engine()), FactoredFilter.from_filter(_engine())
    for t, Zk in enumerate([Z, Z + 0.5], start=1):
        a.step(Zk, float(t))
        b.step(Zk, dt=1.0)
    s = a.state()
    assert isinstance(s, FactoredState) and s.time == 2.0 and s.next_label == a.next_label == 3
    assert a.same_posterior(b) and b.same_posterior(a)
    c = copy.deepcopy(b)
    held = c.state()  # the filter's own arrays
    if len(held.groups):
        held.groups.states[0].log_w[0] += 1e-12
    else:
        held.lane.store.means[0, 0] += 1e-12
    assert not a.same_posterior(c)
    d = FactoredFilter.from_filter(_engine())
    d.initialise(X0, P0, labels=[0, 1, 5], time=0.0)
    d.step(Z, 1.0)
    d.step(Z + 0.5, 2.0)
    assert not a.same_posterior(d)  # the next label differs (6 against 3)


def test_object_ids_forget_exactly_the_labels_no_longer_held():
    """Newborn labels 100 and 101 are one object (id 100), 205 its own; held: 101, 205 and objects outside
    the mapping's range (below and above it): 100 is forgotten, the others kept with their ids."""
    from hypotrack.hypotheses.factored.planner import ObjectIds

    ids = ObjectIds({100: 100, 101: 100, 205: 205})
    ids.keep_held(np.array([1, 2, 101, 150, 205, 999_999]))
    assert ids.mapping == {101: 100, 205: 205}
    np.testing.assert_array_equal(ids.of([101, 205, 7]), [100, 205, 7])
    ids.keep_held(np.zeros(0, dtype=np.int64))
    assert ids.mapping == {}

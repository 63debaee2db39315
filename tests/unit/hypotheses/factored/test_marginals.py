"""The marginal probability of the MAP's track of each label (:mod:`hypotrack.hypotheses.factored.marginals`): a
hand-computed posterior (three labels, a swap hypothesis, a hypothesis without a label, a lane singleton) and, on a
factored filter, the brute-force sum over its expanded joint hypotheses."""

from types import SimpleNamespace

import numpy as np
import pytest

from hypotrack.hypotheses import FactoredFilter, homht
from hypotrack.hypotheses.factored.marginals import map_label_marginals, map_track_marginals
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor


def _group():
    """Store: 0 = label 10 (history A), 1 = label 20 (B), 2 = label 30, 3 = label 10 on B's return, 4 = label 20 on
    A's (the swap), 5 = label 30 missed. Hypotheses (weights 0.2, 0.5, 0.25, 0.05): h0 = {10:A, 20:B} with 30 dead,
    h1 = {10:A, 20:B, 30} the MAP, h2 = the swap {10:B', 20:A', 30}, h3 = {10:A, 20:B, 30 missed}."""
    d = 4
    store = TrackStore(np.arange(6 * d, dtype=float).reshape(6, d), np.repeat(np.eye(d)[None], 6, axis=0),
                       np.array([10, 20, 30, 10, 20, 30]))
    tracks = [np.array([0, 1]), np.array([2, 0, 1]), np.array([3, 4, 2]), np.array([0, 1, 5])]
    log_w = np.log([0.2, 0.5, 0.25, 0.05]) + 3.0  # not normalised: the function normalises
    return FilterState(store, log_w, tracks, [0, 1, 2, 3], 0)


def test_hand_computed_marginals_with_a_swap_and_a_missing_label():
    g = _group()
    h, p = map_track_marginals(g.log_w, g.tracks)
    assert h == 1
    # in h1's order (2, 0, 1): label 30 in h1 and h2 (0.5 + 0.25; h3 holds another entry, h0 none); labels 10 and 20
    # in h0, h1, h3 (0.2 + 0.5 + 0.05; the swap h2 holds other entries)
    np.testing.assert_allclose(p, [0.75, 0.75, 0.75], rtol=0, atol=1e-12)
    # the swap made the MAP (weights 0.2, 0.25, 0.5, 0.05): its entries 3, 4 are held by it alone (0.5), entry 2 by
    # h1 and h2 (0.25 + 0.5)
    lw = np.log([0.2, 0.25, 0.5, 0.05])
    h, p = map_track_marginals(lw, g.tracks)
    assert h == 2
    np.testing.assert_allclose(p, [0.5, 0.5, 0.75], rtol=0, atol=1e-12)
    lane = SimpleNamespace(store=TrackStore(np.zeros((2, 4)), np.repeat(np.eye(4)[None], 2, axis=0), np.array([7, 8])))
    state = SimpleNamespace(groups=SimpleNamespace(states=(g,)), lane=lane)
    labels, p = map_label_marginals(state)
    assert labels.tolist() == [30, 10, 20, 7, 8]
    np.testing.assert_allclose(p, [0.75, 0.75, 0.75, 1.0, 1.0], rtol=0, atol=1e-12)


def test_an_empty_map_and_bad_input():
    h, p = map_track_marginals([0.0, -1.0], [np.zeros(0, np.int64), np.array([0])])
    assert h == 0 and p.shape == (0,)
    with pytest.raises(ValueError, match="log_w must be a non-empty"):
        map_track_marginals([], [])
    with pytest.raises(ValueError, match="log_w must be a non-empty"):
        map_track_marginals([0.0, 0.0], [np.array([0])])
    with pytest.raises(ValueError, match="log_w must be finite or -inf"):
        map_track_marginals([np.nan, 0.0], [np.array([0]), np.array([0])])


REGION = Box([-20.0, -20.0], [20.0, 20.0])
SENSOR = Sensor(LinearPositionSensor(np.eye(2) * 0.5, ndim_state=4, position_indices=(0, 1)),
                DetectionModel(0.8, REGION), PoissonClutter(1.0, REGION))
# a and b 1.2 apart (returns between them: a swap is nearly as likely), c alone with one return, d far with none
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.2, 1.0, 0.0], [8.0, 8.0, 0.0, 0.0], [-10.0, -10.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 4, axis=0)
Z = np.array([[1.0, 0.5], [1.1, 0.8], [8.1, 7.9], [15.0, -15.0]])


def test_equals_the_sum_over_the_expanded_joint_hypotheses():
    """Brute force: a label's marginal is the total weight of the joint hypotheses holding a track of that label with
    the MAP's moments (the same association history); the order is :meth:`estimates`'."""
    ff = FactoredFilter.from_filter(homht(ConstantVelocity(q=0.05), SENSOR, max_hypotheses=1000, gate_probability=0.99,
                                          means=X0, covs=P0, seed=0), lazy=False)
    ff.step(Z, 1.0)
    ff.step(Z + np.array([1.0, 0.0]), 2.0)
    labels, p = map_label_marginals(ff.state())
    assert labels.tolist() == ff.estimates().labels.tolist()
    joint = ff.joint_hypotheses()
    w = np.exp([h.log_weight for h in joint])
    w = w / w.sum()
    best = joint[0]
    want = []
    for a in labels:
        (j,) = np.flatnonzero(best.labels == a)
        want.append(sum(wh for wh, h in zip(w, joint) if any(
            b == a and np.allclose(m, best.means[j], rtol=0, atol=1e-12) for b, m in zip(h.labels, h.means))))
    np.testing.assert_allclose(p, want, rtol=0, atol=1e-9)
    assert min(p) < 0.5 and max(p) == 1.0  # the case is ambiguous for a and b, certain for d


def test_a_marginal_split_keeps_every_labels_alternatives():
    """Splitting the hand-computed group (Beard et al.'s marginal product, :func:`factorise`) with labels 10, 20 and
    30 in three parts keeps each label's weight on each of its association histories: 10 on A 0.75 and on B's return
    (the swap) 0.25, 20 the same, 30 0.75 (0.2 of the mass has no label 30, 0.05 has it missed). A swap alternative is
    not collapsed by the split (the MAP-history marginal does not read 1); only the joint (which label 20 goes with
    which label 10) is lost."""
    from hypotrack.hypotheses.factored_groups import factorise

    g = _group()
    part_of = {10: 0, 20: 1, 30: 2}
    record, pieces = factorise(g, np.array([part_of[int(a)] for a in g.store.labels]))
    assert not record.exact  # the swap correlates 10 and 20: the product is an approximation
    want = {(10, 0.0): 0.75, (10, 12.0): 0.25, (20, 4.0): 0.75, (20, 16.0): 0.25, (30, 8.0): 0.75, (30, 20.0): 0.05}
    got = {}
    for s in pieces:
        w = np.exp(s.log_w - np.logaddexp.reduce(s.log_w))
        for h, t in enumerate(s.tracks):
            for i in t:
                key = (int(s.store.labels[i]), float(s.store.means[i, 0]))  # means[i, 0] names the store entry
                got[key] = got.get(key, 0.0) + w[h]
    assert got.keys() == want.keys()
    np.testing.assert_allclose([got[k] for k in want], list(want.values()), rtol=0, atol=1e-12)
    state = SimpleNamespace(groups=SimpleNamespace(states=tuple(pieces)), lane=SimpleNamespace(store=TrackStore(
        np.zeros((0, 4)), np.zeros((0, 4, 4)), np.zeros(0, dtype=np.int64))))
    labels, p = map_label_marginals(state)
    assert sorted(zip(labels.tolist(), p.round(12).tolist())) == [(10, 0.75), (20, 0.75), (30, 0.75)]

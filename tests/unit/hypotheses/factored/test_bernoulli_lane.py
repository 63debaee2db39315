"""Bernoulli singletons in the lane (``bernoulli_lane``, :mod:`hypotrack.hypotheses.factored.lane`).

A lone track of existence ``r`` is, in the general engine, a group of two hypotheses (exists / not); the lane
holds it as ``r`` beside its moments: ``r ← p_S r`` each scan out of view, ``r ← r p_S (1 − p_D) / (1 − r p_S p_D)``
on a scan in view with no return for it, and the engine's step (as its two hypotheses) when a return or birth
term reaches it. Checked against the general engine (every track a group) label by label each scan, and against
hand-computed existences and deletion scans.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import (ExhaustiveGenerator, GLMBWeights, HypothesisFilter, LabeledMultiBernoulliPopulation,
                                  UnconfirmedDecay)
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredFilter
from hypotrack.hypotheses.factored.lane import bernoulli, bernoulli_existence, bernoulli_prune, missed
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor, hypotheses_by_label, label_existence

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
MOTION = ConstantVelocity(0.01)
CONF = np.diag([0.5, 0.5, 0.01, 0.01])
BIRTH = AdaptiveBirth(position_std=0.0, velocity_std=2.0, r_birth=0.05, gate_probability=0.999)
# the catalogue at scan 0 (all r = 1): A seen, B leaving the view, C with no object behind it, D out of view
# throughout (asleep), E seen
X0 = np.array([[0.0, 0.0, 1.0, 0.0],        # A
               [80.0, 0.0, 6.0, 0.0],       # B: out of view from scan 4 (x = 104)
               [-50.0, 50.0, 0.0, 0.0],     # C: nothing there
               [500.0, 500.0, 0.0, 0.0],    # D: out of view
               [-80.0, -80.0, 0.0, 1.0],    # E
               [0.0, 2.5, 1.0, 0.0]])       # F: nothing there, beside A (A's returns are in its gate)
TRUTH = X0[[0, 1, 4]]
NEWBORN = np.array([30.0, -60.0, 0.0, 1.5])  # unknown, first seen at scan 3


def _returns(k):
    """The returns of scan ``k`` (deterministic): A (missed at 4 and 7), B while in view (missed at 2), E (missed at
    5), the newborn from scan 3 (missed at 6), a clutter return at (60, 60) at scans 2 and 8 and one beside E at 9."""
    off = np.array([0.3, -0.2]) * np.cos(k)  # a small measurement error, different each scan
    Z = []
    for i, x in enumerate(TRUTH):
        pos = x[:2] + k * x[2:]
        seen = {0: k not in (4, 7), 1: k != 2 and np.all(np.abs(pos) <= 100), 2: k != 5}[i]
        if seen:
            Z.append(pos + off)
    if k >= 3 and k != 6:
        Z.append(NEWBORN[:2] + (k - 3) * NEWBORN[2:] - off)
    if k in (2, 4, 8):  # at 4: the undetected newborn of 2's return (r ~ 0.01) detected, alone in its gate
        Z.append(np.array([60.0, 60.0]))
    if k == 9:  # a second return at E: E's group keeps both associations for a while
        Z.append(TRUTH[2, :2] + k * TRUTH[2, 2:] + [0.0, 1.0])
    return np.array(Z).reshape(-1, 2)


def _filter(bern, population, means=X0, covs=None, lazy=True, min_weight=1e-3, p_D=0.8, adaptive=BIRTH, fast=False,
            validity=None):
    covs = np.repeat(CONF[None], len(means), axis=0) if covs is None else covs
    f = HypothesisFilter(MOTION, position_sensor(R=0.25, p_D=p_D, view=VIEW, clutter_rate=1.0), GLMBWeights(),
                         ExhaustiveGenerator(), population=population, dt=1.0, max_hypotheses=100, means=means,
                         covs=covs, seed=0, gate_probability=0.999, validity=validity)
    return FactoredFilter.from_filter(f, adaptive_birth=adaptive, min_weight=min_weight, lazy=lazy, replay=True,
                                      gate_out_of_view=False, bernoulli_lane=bern, fast_path=fast)


def _assert_same(a, b):
    la, lb = hypotheses_by_label(a), hypotheses_by_label(b)
    assert sorted(la) == sorted(lb)
    for lab in la:
        assert len(la[lab]) == len(lb[lab])
        assert sum(w for w, _, _ in la[lab]) == pytest.approx(sum(w for w, _, _ in lb[lab]), abs=1e-12, rel=0)
        for (wa, ma, Pa), (wb, mb, Pb) in zip(la[lab], lb[lab]):
            assert wa == pytest.approx(wb, abs=1e-12, rel=0)
            np.testing.assert_allclose(ma, mb, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(Pa, Pb, rtol=1e-12, atol=1e-12)
    pa, pb = a.posterior(), b.posterior()
    assert pa.expected_number == pytest.approx(pb.expected_number, abs=1e-12, rel=0)
    np.testing.assert_allclose(pa.cardinality, pb.cardinality, rtol=0, atol=1e-12)
    assert sorted(a.estimates().labels.tolist()) == sorted(b.estimates().labels.tolist())


POPULATIONS = {
    "p_S 0.95": LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=0.95),
    "decay": LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0, survival=UnconfirmedDecay(
        p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))),
}


@pytest.mark.parametrize("lazy, use_fast", [(True, False), (False, False), (True, True)])
@pytest.mark.parametrize("pop", sorted(POPULATIONS))
def test_bernoulli_lane_is_the_general_engine(pop, lazy, use_fast):
    """Six catalogued objects (A, E seen with misses, B leaving the view, C and F with nothing behind them, F in
    A's gate so that the two merge and split, D out of view) and births from the returns (a newborn object,
    clutter), 12 scans: with Bernoulli singletons in the lane each label's existence, every hypothesis weight and
    moments holding it, the cardinality, the joint hypotheses' number and the MAP labels are the general engine's (every track a group stepped every scan) to 1e-12. With the fast path the posterior is the
    Bernoulli lane's general path's bit for bit, and the fast path took lone tracks of r < 1 (their "not" child one
    more alternative: the newborn of r ~ 0.01 detected at scan 4 keeps it, so takes the general path)."""
    population = POPULATIONS[pop]
    fast, general = _filter(True, population, lazy=lazy, fast=use_fast), _filter(False, population, lazy=lazy)
    plain = _filter(True, population, lazy=lazy)
    n_fast = 0
    assert len(fast.state().lane) == 6 and len(general.state().lane) == 0
    n_unsure = n_asleep_low = 0
    for k in range(1, 13):
        Z = _returns(k)
        fast.step(Z, float(k))
        general.step(Z, float(k))
        plain.step(Z, float(k))
        _assert_same(fast, general)
        assert fast.same_posterior(plain)
        assert fast.n_joint_hypotheses == general.n_joint_hypotheses == len(fast.joint_hypotheses())
        n_fast += fast.last_stats["n_fast_path"]
        lane = fast.state().lane
        n_unsure += int(np.sum(lane.r < 1))  # Bernoulli singletons of r < 1 held in the lane
        n_asleep_low += int(lazy and fast.last_stats["n_predicted"] < general.last_stats["n_predicted"])
        assert fast.last_stats["n_singletons"] >= 3  # A..E (while they live) stay in the lane, not groups
    # the check has power: r < 1 in the lane, singletons asleep, lone tracks the fast path took
    assert n_unsure >= 20 and (n_asleep_low >= 10 or not lazy) and (n_fast >= 15 or not use_fast)
    # C and F (nothing behind them) were deleted, the newborn (label 7) is held, D (asleep) decays as p_S^12
    assert 2 not in hypotheses_by_label(fast) and 5 not in hypotheses_by_label(fast)
    assert sorted(fast.estimates().labels.tolist()) == [0, 1, 3, 4, 7]
    p_s = 0.95 if pop == "p_S 0.95" else 0.97
    assert label_existence(fast, 3) == pytest.approx(p_s**12, rel=1e-12)


def _south_west(means):
    """A validity test that D (asleep at x = 500) and C (in view at y = 50) fail from the start."""
    return (means[:, 0] < 400) & (means[:, 1] < 40)


@pytest.mark.parametrize("lazy, use_fast", [(True, False), (False, False), (True, True)])
def test_a_track_failing_the_validity_test_leaves_as_in_the_general_engine(lazy, use_fast):
    """With the engine's validity test the general engine's empty-scan step gives the "missed" child of a track
    failing it weight 0, so the track leaves at the first scan it may die in: C (quiet in view) and D (asleep out of
    view, tested at its mean at the scan) at scan 1, in the lane as there; every label as the general engine's."""
    population = POPULATIONS["p_S 0.95"]
    fast = _filter(True, population, lazy=lazy, fast=use_fast, validity=_south_west)
    general = _filter(False, population, lazy=lazy, validity=_south_west)
    for k in range(1, 13):
        Z = _returns(k)
        fast.step(Z, float(k))
        general.step(Z, float(k))
        _assert_same(fast, general)
        assert 2 not in hypotheses_by_label(fast) and 3 not in hypotheses_by_label(fast)
    assert sorted(fast.estimates().labels.tolist()) == [0, 1, 4, 6]  # (the clutter return's newborn failed it too)


def test_the_recursion_over_a_gap_hand_computed():
    """p_S = 0.9, p_D = 0.8, min_weight = 1e-3, no return ever. Object O (x = −155 + 10 k) is out of view at scans
    1–5, asleep (never predicted): r = 0.9^5 = 0.59049; it enters the view at scan 6 and is missed there:
    r' = r p_S (1 − p_D) / (1 − r p_S p_D),
    scan 6: 0.531441 · 0.2 / (1 − 0.531441 · 0.8) = 0.1062882 / 0.5748472 = 0.18489818,
    scan 7: 0.18489818 · 0.9 · 0.2 / (1 − 0.16640836 · 0.8) = 0.03328167 / 0.86687331 = 0.03839278.
    Object S sits in view, missed from scan 1: 0.18 / 0.28 = 0.64285714, 0.11571429 / 0.53714286 = 0.21542553,
    0.03877660 / 0.84489362 = 0.04589524, 0.00826114 / 0.96695543 = 0.00854346, 0.00153782 / 0.99384871 =
    0.00154734, then 0.00027852 / 0.99888591 = 0.00027883 < 1e-3: deleted at scan 6."""
    pop = LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=0.9)
    means = np.array([[-155.0, 0.0, 10.0, 0.0], [0.0, 50.0, 0.0, 0.0]])
    f = _filter(True, pop, means=means, adaptive=None)
    hand_o = [0.9, 0.81, 0.729, 0.6561, 0.59049, 0.18489818, 0.03839278]
    hand_s = [0.64285714, 0.21542553, 0.04589524, 0.00854346, 0.00154734, 0.0]
    for k in range(1, 8):
        f.step(np.zeros((0, 2)), float(k))
        assert label_existence(f, 0) == pytest.approx(hand_o[k - 1], abs=1e-8)
        if k <= 6:
            assert label_existence(f, 1) == pytest.approx(hand_s[k - 1], abs=1e-8)
        # both stay lane singletons (no group) until S leaves at scan 6; O predicted only from scan 6 on
        assert (f.last_stats["n_singletons"], len(f.state().groups)) == (1 + (k <= 5), 0)
        assert f.last_stats["n_predicted"] == (k >= 6) + (k <= 6)
    assert 1 not in f.state().lane.store.labels and f.state().lane.r.tolist() == pytest.approx([0.03839278], abs=1e-8)


def test_a_track_with_nothing_behind_it_is_deleted_when_the_recursion_says():
    """min_weight = 1e-3, p_S = 0.99, p_D = 0.8, a track in view never detected: r' = r p_S (1 − p_D) / (1 − r p_S p_D)
    = 0.95192308, 0.76594248, 0.38552823, 0.10988744, 0.02383182, 0.00480948, then 0.00095592 < 1e-3: deleted at
    scan 7. Out of view, p_S = 0.9: r = 0.9^k, 0.9^65 = 0.00106 ≥ 1e-3 > 0.9^66 = 0.000955, i.e. deleted at
    k = ceil(log(1e-3) / log 0.9) = ceil(65.56) = 66. Both at those scans, in the lane (never a group) and in the
    general engine."""
    pop_in = LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=0.99)
    hand = [0.95192308, 0.76594248, 0.38552823, 0.10988744, 0.02383182, 0.00480948]
    for bern in (True, False):
        f = _filter(bern, pop_in, means=np.array([[0.0, 0.0, 0.0, 0.0]]), adaptive=None)
        for k in range(1, 8):
            f.step(np.zeros((0, 2)), float(k))
            assert f.n_objects_held == (k < 7)
            if k < 7:
                assert label_existence(f, 0) == pytest.approx(hand[k - 1], abs=1e-8)
                assert (len(f.state().lane), len(f.state().groups)) == ((1, 0) if bern else (0, 1))
        assert len(f.estimates().labels) == 0
    pop_out = LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=0.9)
    for bern in (True, False):
        f = _filter(bern, pop_out, means=np.array([[500.0, 0.0, 0.0, 0.0]]), adaptive=None)
        for k in range(1, 67):
            f.step(np.zeros((0, 2)), float(k))
            assert f.n_objects_held == (k < 66)
            if k < 66:
                assert label_existence(f, 0) == pytest.approx(0.9**k, rel=1e-12)
            if bern:
                assert f.last_stats["n_predicted"] == 0  # asleep throughout: r decays without a prediction


def test_the_lane_s_bernoulli_is_the_engine_s_two_hypotheses():
    store = TrackStore(np.zeros((2, 4)), np.repeat(np.eye(4)[None], 2, axis=0), np.array([7, 9]))
    s = bernoulli(store, 1, 0.3)
    assert s.store.labels.tolist() == [9] and [len(t) for t in s.tracks] == [1, 0]
    np.testing.assert_allclose(np.exp(s.log_w), [0.3, 0.7], rtol=1e-15)
    assert bernoulli_existence(s) == pytest.approx(0.3, rel=1e-15)
    assert len(bernoulli(store, 0, 1.0).log_w) == 1 and bernoulli_existence(bernoulli(store, 0, 1.0)) == 1.0
    # the miss update: p_S = 1 and r = 1 stay exactly 1; out of view (p_D = 0) r p_S
    assert missed(np.array([1.0]), 1.0, np.array([0.9]))[0] == 1.0
    assert missed(np.array([0.5]), 0.8, np.array([0.0]))[0] == pytest.approx(0.4, rel=1e-15)
    assert missed(np.array([0.5]), 0.8, np.array([0.5]))[0] == pytest.approx(0.2 / 0.8, rel=1e-15)
    # the engine's pruning: "exists" below min_weight (and lighter) deleted; "not" below it: r = 1
    alive, r = bernoulli_prune(np.array([0.0009, 0.001, 0.5, 0.9995, 0.998]), 1e-3)
    assert alive.tolist() == [False, True, True, True, True] and r[3] == 1.0 and r[4] == 0.998
    # the heavier hypothesis is kept whatever min_weight (planner.prune): at 0.6, r = 0.55 stays and becomes 1
    alive, r = bernoulli_prune(np.array([0.55, 0.45]), 0.6)
    assert alive.tolist() == [True, False] and r[0] == 1.0

"""Per-track survival through the lane (:func:`hypotrack.hypotheses.factored.lane.survival_lane`).

Five objects, ``UnconfirmedDecay(p_tentative = 0.5)``, ``p_D = 0.5``, ``min_weight = 1e-3``, 10 scans:

* A confirmed, in view, detected every scan — a lane singleton the fast path takes;
* B tentative, out of view — existence ``0.5^k``, deleted at scan 10 (``0.5^10 < 1e-3 < 0.5^9``);
* C tentative, in view, never detected — existence ``r' = r · 0.5 · (1 − p_D) / (1 − r · 0.5 · p_D)``
  (the labeled multi-Bernoulli update of a missed track): 1/3, 1/11, 0.0233, 0.00585, 0.00146, then
  ``3.7e-4`` < ``min_weight``: deleted at scan 6;
* D confirmed, out of view — asleep in the lane (lazy), existence 1;
* E confirmed, in view, never detected — quiet in the lane, existence 1 (``p_S = 1``: no decay).

Checked each scan against the hand-computed existences, the unfactored engine (exhaustive, no pruning) and the
lane's membership; a confirmed lane track whose prediction turns tentative leaves the lane and decays.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import (ExhaustiveGenerator, GLMBWeights, HypothesisFilter, LabeledMultiBernoulliPopulation,
                                  UnconfirmedDecay)
from hypotrack.hypotheses.factored import FactoredFilter
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

VIEW = Box([-1000.0, -1000.0], [1000.0, 1000.0])
SENSOR = Sensor(LinearPositionSensor(np.eye(2) * 0.25, 4), DetectionModel(0.5, VIEW), PoissonClutter(1.0, VIEW))
CONF, TENT = np.diag([0.1, 0.1, 0.01, 0.01]), np.diag([0.25, 0.25, 100.0, 100.0])
X0 = np.array([[0.0, 0.0, 1.0, 0.0],          # A
               [5000.0, 5000.0, 0.0, 0.0],    # B (out of view)
               [700.0, 700.0, 0.0, 0.0],      # C
               [-5000.0, 5000.0, 0.0, 0.0],   # D (out of view)
               [-700.0, -700.0, 0.0, 0.0]])   # E
P0 = np.stack([CONF, TENT, TENT, CONF, CONF])
DECAY = UnconfirmedDecay(p_tentative=0.5, velocity_std=1.0, velocity_components=(2, 3))
MIN_WEIGHT = 1e-3
N_SCANS = 10


def _hand(k_max):
    """Existences of B and C after each scan (0 once deleted by the pruning)."""
    rb, rc, out = 1.0, 1.0, []
    for _ in range(k_max):
        rb *= 0.5
        rc = rc * 0.5 * 0.5 / (1 - rc * 0.5 * 0.5)
        rb, rc = (rb if rb >= MIN_WEIGHT else 0.0), (rc if rc >= MIN_WEIGHT else 0.0)
        out.append((rb, rc))
    return out


def _filters(lazy=True):
    pop = LabeledMultiBernoulliPopulation([], r_birth=[], p_survive=1.0, survival=DECAY)
    kw = dict(population=pop, dt=1.0, max_hypotheses=100, means=X0, covs=P0, seed=0, gate_probability=0.999)
    f = FactoredFilter(ConstantVelocity(0.01), SENSOR, GLMBWeights(), ExhaustiveGenerator(), min_weight=MIN_WEIGHT,
                       lazy=lazy, fast_path=True, gate_out_of_view=False, **kw)
    return f, HypothesisFilter(ConstantVelocity(0.01), SENSOR, GLMBWeights(), ExhaustiveGenerator(), **kw)


def _existence(f, label):
    return sum(float(np.exp(lw)) for g in f.groups for lw, t in zip(g.log_w, g.tracks) if label in g.store.labels[t])


def test_the_decay_through_the_lane_is_the_hand_computed_one():
    f, ref = _filters()
    assert len(f.state().lane) == 3 and len(f.state().groups) == 2  # A, D, E in the lane; B, C groups
    hand = _hand(N_SCANS)
    for k in range(1, N_SCANS + 1):
        Z = np.array([[float(k), 0.0]])  # A's return (A moves at 1 per scan)
        f.step(Z)
        ref.step(Z)
        rb, rc = hand[k - 1]
        assert _existence(f, 1) == pytest.approx(rb, rel=1e-9)
        assert _existence(f, 2) == pytest.approx(rc, rel=1e-9)
        assert f.posterior().expected_number == pytest.approx(3.0 + rb + rc, rel=1e-9)
        # the unfactored engine (no pruning) holds the decay unpruned: 0.5^k for B
        w = np.exp(ref.log_weights)
        assert sum(wi for wi, t in zip(w, ref.track_lists) if 1 in ref.store.labels[t]) == pytest.approx(0.5**k, rel=1e-9)
        st = f.last_stats
        assert st["n_singletons"] == 3 and st["n_fast_path"] == 1  # A, D, E stay singletons; A the fast path's
        assert st["n_asleep"] == 0  # groups (B while it lives) are predicted every scan: they may die out of view
        # A's moments: the unfactored engine's MAP track
        i = list(f.estimates().labels).index(0)
        j = int(np.flatnonzero(ref.store.labels == 0)[0])
        np.testing.assert_allclose(f.estimates().x[i], ref.store.means[j], rtol=0, atol=1e-9)
    assert hand[5][1] == 0.0 and hand[4][1] > 0 and hand[9][0] == 0.0 and hand[8][0] > 0  # C at 6, B at 10
    assert sorted(f.estimates().labels.tolist()) == [0, 3, 4]


def test_lazy_and_eager_lanes_hold_the_same_posterior():
    (lazy, _), (eager, _) = _filters(True), _filters(False)
    for k in range(1, N_SCANS + 1):
        Z = np.array([[float(k), 0.0]])
        lazy.step(Z)
        eager.step(Z)
        for s, u in zip(lazy.groups, eager.groups):
            np.testing.assert_allclose(s.log_w, u.log_w, rtol=0, atol=1e-12)
            np.testing.assert_array_equal(s.store.labels, u.store.labels)
            np.testing.assert_allclose(s.store.means, u.store.means, rtol=0, atol=1e-9)
    assert eager.last_stats["n_predicted"] > lazy.last_stats["n_predicted"]  # D asleep in the lazy lane


def test_a_lane_track_turning_tentative_leaves_the_lane_and_decays():
    """E's velocity variance 0.85, grown by the process noise (q = 0.1: + 0.1 per scan) to 0.95 at scan 1 (p_S = 1)
    and past 1 at scan 2: from then on it is a candidate of p_S = 0.5, stepped on the empty scan, and decays as
    a missed tentative track, out of the lane."""
    pop = LabeledMultiBernoulliPopulation([], r_birth=[], p_survive=1.0, survival=DECAY)
    P = np.diag([0.1, 0.1, 0.85, 0.85])
    f = FactoredFilter(ConstantVelocity(0.1), SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=pop, dt=1.0,
                       max_hypotheses=100, means=X0[[4]], covs=P[None], seed=0, min_weight=MIN_WEIGHT, lazy=True,
                       gate_probability=0.999, gate_out_of_view=False,
                       fast_path=True)
    f.step(np.zeros((0, 2)))
    assert len(f.state().lane) == 1 and _existence(f, 0) == 1.0
    r = 1.0
    for _ in range(3):
        f.step(np.zeros((0, 2)))
        r = r * 0.5 * 0.5 / (1 - r * 0.5 * 0.5)
        assert len(f.state().lane) == 0 and _existence(f, 0) == pytest.approx(r, rel=1e-9)

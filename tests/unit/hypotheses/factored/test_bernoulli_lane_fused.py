"""The fused multi-sensor filter (:class:`~hypotrack.hypotheses.factored.multisensor.MultiSensorFactored`) with
Bernoulli singletons in the lane (``bernoulli_lane``) against the same fused run with every track a group stepped by
the general engine: two sensors of different noise, ``p_D``, clutter and field of view, scans of each in turn and two
at one instant, objects seen by one sensor, by both, by neither, one with nothing behind it, births from the returns;
survival below 1 (one ``p_S``; per track). Every label's hypotheses, the cardinality and the MAP to 1e-12 each scan.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import (BinomialPopulation, ExhaustiveGenerator, GLMBWeights, HFISSTWeights, HypothesisFilter,
                                  LabeledMultiBernoulliPopulation, UnconfirmedDecay)
from hypotrack.hypotheses.factored import AdaptiveBirth
from hypotrack.hypotheses.factored.multisensor import MultiSensorFactored
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor, hypotheses_by_label

MOTION = ConstantVelocity(q=0.02)
SENSOR_A = position_sensor(np.eye(2) * 0.3, 0.85, Box([-10.0, -10.0], [1.0, 10.0]), 1.0)  # sees x <= 1
SENSOR_B = position_sensor(np.diag([0.1, 0.6]), 0.7, Box([-1.0, -10.0], [10.0, 10.0]), 0.5)  # sees x >= -1
# a (A only), b (both), c (B only), d (both, nothing behind it), e (neither)
X0 = np.array([[-6.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.0, 0.5], [6.0, 0.0, -0.5, 0.0], [0.0, -6.0, 0.0, 0.0],
               [50.0, 50.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([0.3, 0.3, 0.02, 0.02])[None], len(X0), axis=0)
NEWBORN = np.array([0.2, 6.0, 0.0, 0.0])  # seen by both from t = 1
BIRTH = AdaptiveBirth(position_std=0.0, velocity_std=1.0, r_birth=0.1, gate_probability=0.999)
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=0.5, p_confirmed=0.95, velocity_components=(2, 3))


def _scans():
    """(time, sensor, returns): sensor A at t = 1, 2, ..., B at t = 1, 2.5, 3.5, ... (t = 1: both at one instant);
    each object its sensor sees returned but for a few misses; a clutter return at scan 4."""
    out = []
    times = [(1.0, 0), (1.0, 1)] + [(t, s) for k in range(2, 8) for t, s in ((float(k), 0), (k + 0.5, 1))]
    for i, (t, s) in enumerate(times):
        off = np.array([0.1, -0.15]) * np.cos(3 * i)
        Z = []
        for j, x in enumerate(list(X0[:3]) + [NEWBORN]):
            pos = x[:2] + t * x[2:]
            sees = pos[0] <= 1 if s == 0 else pos[0] >= -1
            if sees and (i + j) % 5 != 3:
                Z.append(pos + off)
        if i == 4:
            Z.append(np.array([-3.0, -8.0]))
        out.append((t, s, np.array(Z).reshape(-1, 2)))
    return out


def _fused(weights, population, bern):
    def engine(sensor):
        return HypothesisFilter(MOTION, sensor, weights, ExhaustiveGenerator(), population=population,
                                max_hypotheses=10**4, gate_probability=0.999, means=X0, covs=P0, seed=0)
    return MultiSensorFactored.from_filters([engine(SENSOR_A), engine(SENSOR_B)], [BIRTH, BIRTH], min_weight=1e-4,
                                            lazy=True, replay=True, gate_out_of_view=False, bernoulli_lane=bern)


CASES = {
    "glmb p_S 0.95": (GLMBWeights(), LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=0.95)),
    "glmb decay": (GLMBWeights(), LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0, survival=DECAY)),
    "fisst binomial decay": (HFISSTWeights(), BinomialPopulation([], alpha=BIRTH.r_birth, p_survive=1.0, survival=DECAY)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_fused_bernoulli_lane_is_the_fused_general_engine(case):
    weights, population = CASES[case]
    lane, general = _fused(weights, population, True), _fused(weights, population, False)
    assert lane._bern and not general._bern
    n_unsure = 0
    for t, s, Z in _scans():
        lane.step(Z, t, sensor=s)
        general.step(Z, t, sensor=s)
        la, lb = hypotheses_by_label(lane), hypotheses_by_label(general)
        assert sorted(la) == sorted(lb)
        for lab in la:
            assert len(la[lab]) == len(lb[lab])
            for (wa, ma, Pa), (wb, mb, Pb) in zip(la[lab], lb[lab]):
                assert wa == pytest.approx(wb, abs=1e-12, rel=0)
                np.testing.assert_allclose(ma, mb, rtol=1e-12, atol=1e-12)
                np.testing.assert_allclose(Pa, Pb, rtol=1e-12, atol=1e-12)
        pa, pb = lane.posterior(), general.posterior()
        np.testing.assert_allclose(pa.cardinality, pb.cardinality, rtol=0, atol=1e-12)
        assert sorted(lane.estimates().labels.tolist()) == sorted(general.estimates().labels.tolist())
        n_unsure += int(np.sum(lane.state().lane.r < 1))
    assert n_unsure >= 10  # the lane held Bernoulli singletons of r < 1
    assert 3 not in hypotheses_by_label(lane)  # d (nothing behind it, in both views) deleted
    e = sum(w for w, _, _ in hypotheses_by_label(lane)[4])  # e (in neither view) decays as p_S per sensor scan: 14 scans
    assert e == pytest.approx(0.95**14, rel=1e-12)

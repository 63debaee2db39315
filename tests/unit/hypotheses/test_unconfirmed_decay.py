"""Existence decay of never-confirmed tracks: ``UnconfirmedDecay`` as the labeled multi-Bernoulli's survival.

Hand-computed: two objects out of view (no return can re-detect them), p_S = 1 for a confirmed track and
0.5 for a tentative one (velocity σ 3 km/s, as born from one return). The tentative track's existence is
``0.5^k`` after ``k`` scans; with ``min_weight = 1e-3`` the factored filter deletes it at scan 10
(``0.5^9 = 1.95e-3``, ``0.5^10 = 9.8e-4``) while the confirmed track stays, existence 1.
"""

import math

import numpy as np
import pytest

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    UnconfirmedDecay,
)
from hypotrack.hypotheses.factored import FactoredFilter
from hypotrack.models.orbit3d import TwoBodyOrbit3D
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

VIEW = Box([-100.0, -100.0, -100.0], [100.0, 100.0, 100.0])  # far from both objects: never in view
SENSOR = Sensor(LinearPositionSensor(np.eye(3) * 0.25, 6, (0, 1, 2)), DetectionModel(0.9, VIEW),
                PoissonClutter(1.0, VIEW))
X0 = np.array([[6778.0, 0.0, 0.0, 0.0, 7.668558, 0.0], [0.0, 6878.0, 0.0, -7.6, 0.0, 0.5]])
P0 = np.stack([np.diag([0.1, 0.1, 0.1, 1e-4, 1e-4, 1e-4]),  # confirmed: velocity known to 10 m/s
               np.diag([0.25, 0.25, 0.25, 9.0, 9.0, 9.0])])  # tentative: velocity sigma 3 km/s
DECAY = UnconfirmedDecay(p_tentative=0.5, velocity_std=1.0)
MIN_WEIGHT = 1e-3
N_SCANS = math.ceil(math.log(MIN_WEIGHT) / math.log(0.5))  # 10


def _population(survival=DECAY):
    return LabeledMultiBernoulliPopulation([], r_birth=[], p_survive=1.0, survival=survival)



def test_hypothesis_filter_existence_is_p_tentative_to_the_k():
    f = HypothesisFilter(TwoBodyOrbit3D(), SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=_population(),
                         dt=10.0, max_hypotheses=100, means=X0, covs=P0, seed=0)
    for k in range(1, 6):
        f.step(np.zeros((0, 3)))
        w = np.exp(f.log_weights)
        labels = [set(f.store.labels[t].tolist()) for t in f.track_lists]
        r_tent = sum(wi for wi, ls in zip(w, labels) if 1 in ls)
        r_conf = sum(wi for wi, ls in zip(w, labels) if 0 in ls)
        assert r_tent == pytest.approx(0.5**k, rel=1e-12)
        assert r_conf == pytest.approx(1.0, rel=1e-12)


def test_default_survival_is_unchanged():
    f = HypothesisFilter(TwoBodyOrbit3D(), SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=_population(None),
                         dt=10.0, max_hypotheses=100, means=X0, covs=P0, seed=0)
    for _ in range(3):
        f.step(np.zeros((0, 3)))
    assert len(f.log_weights) == 1 and len(f.track_lists[0]) == 2


def test_factored_filter_deletes_the_tentative_track_after_the_hand_computed_number_of_scans():
    assert N_SCANS == 10
    f = FactoredFilter(TwoBodyOrbit3D(), SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=_population(),
                       dt=10.0, max_hypotheses=100, means=X0, covs=P0, seed=0, min_weight=MIN_WEIGHT)
    for k in range(1, N_SCANS + 1):
        f.step(np.zeros((0, 3)))
        est = f.posterior().expected_number
        if k < N_SCANS:
            assert est == pytest.approx(1.0 + 0.5**k, rel=1e-9), k  # still there, existence 0.5^k
    assert f.posterior().expected_number == pytest.approx(1.0)  # deleted at scan 10
    assert f.estimates().labels.tolist() == [0]  # the confirmed object survives


def test_decay_model_values_and_bad_input():
    covs = np.stack([np.diag([1, 1, 1, 1.5, 0.5, 0.5]), np.diag([1, 1, 1, 0.5, 0.5, 0.5])])
    np.testing.assert_array_equal(DECAY(np.zeros((2, 6)), covs), [0.5, 1.0])
    assert DECAY(np.zeros((0, 6)), np.zeros((0, 6, 6))).shape == (0,)
    with pytest.raises(ValueError, match="p_tentative"):
        UnconfirmedDecay(p_tentative=1.0, velocity_std=1.0)
    with pytest.raises(ValueError, match="velocity_std"):
        UnconfirmedDecay(p_tentative=0.5, velocity_std=0.0)
    with pytest.raises(TypeError, match="survival must be callable"):
        LabeledMultiBernoulliPopulation([], r_birth=[], survival=0.5)
    bad = _population(lambda m, c: np.full(len(m), 1.5))
    f = HypothesisFilter(TwoBodyOrbit3D(), SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=bad,
                         dt=10.0, means=X0, covs=P0)
    with pytest.raises(ValueError, match="one p_S in \\(0, 1\\] per track"):
        f.step(np.zeros((0, 3)))

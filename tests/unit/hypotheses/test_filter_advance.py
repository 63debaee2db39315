"""The engine's public step on a state (``advance``), its configured copies (``with_options``) and
its extension points (``parent_generators``, ``children_of``)."""

import numpy as np
import pytest

from hypotrack.hypotheses import (BinomialPopulation, ExhaustiveGenerator, GaussianBirthTerm, GLMBWeights,
                                  HypothesisFilter, LabeledMultiBernoulliPopulation, MurtyGenerator, ReidWeights,
                                  homht_kbest)
from hypotrack.hypotheses.state import FilterState, StepResult
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

REGION = Box([-20.0, -20.0], [20.0, 20.0])
R = np.eye(2) * 0.5
SENSOR = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)), DetectionModel(0.85, REGION),
                PoissonClutter(1.0, REGION))
H = SENSOR.measurement.H
MOTION = ConstantVelocity(q=0.1)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [3.0, 1.0, 0.0, 1.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.2, 0.2])[None], 2, axis=0)
SCANS = [np.array([[1.1, 0.1], [3.2, 2.0], [-8.0, 5.0]]), np.array([[2.0, 0.0], [2.9, 3.1], [2.5, 1.5], [9.0, 9.0]])]


def _glmb(**kw):
    birth = GaussianBirthTerm(np.array([-8.0, 5.0, 0.0, 0.0]), np.diag([2.0, 2.0, 0.5, 0.5]), H, R)
    pop = LabeledMultiBernoulliPopulation([birth], r_birth=0.2, p_survive=0.95)
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=pop, means=X0, covs=P0,
                            max_hypotheses=50, seed=3, **kw)


def test_step_is_advance_on_the_filters_state():
    """``advance`` maps a state to the next exactly as ``step`` does (a birth and a death possible),
    and changes nothing of the filter it is called on."""
    f, g = _glmb(), _glmb()
    for Z in SCANS:
        before = g.state
        pred = g.predict(g.store, 1.0)
        result = g.advance(before, pred, g.scan_context(pred, Z))
        assert isinstance(result, StepResult) and g.state is before and g.scan_index == 0
        f.step(Z)
        assert result.state.same_as(f.state) and result.state.keys == f.lineage_keys
        np.testing.assert_array_equal(result.sources, f.last_track_sources)
        assert result.n_new_labels == f.next_label - before.next_label
        g.state = result.state
    top = f.posterior(n_top=50).top  # a death and a birth are among the hypotheses
    assert any(len({0, 1} & set(h.labels.tolist())) < 2 for h in top) and any(h.labels.max() >= 2 for h in top)


def test_state_assignment_is_checked():
    f = _glmb()
    with pytest.raises(TypeError, match="state must be a FilterState"):
        f.state = "x"
    s = f.state
    with pytest.raises(ValueError, match="one track list and key per weight"):
        f.state = FilterState(s.store, np.zeros(2), s.tracks, s.keys, 2)


def test_with_options_copies_the_configuration_not_the_hypotheses():
    f = _glmb()
    f.step(SCANS[0])
    c = f.with_options()
    assert c.configuration() == f.configuration() and c.scan_index == 0 and len(c.store) == 0
    assert c.rng is not f.rng and c.rng.bit_generator.state == f.rng.bit_generator.state
    assert f.scan_index == 1 and len(f.store) > 0  # f untouched
    d = f.with_options(max_hypotheses=7, seed=5)
    assert d.max_hypotheses == 7 and d.population is f.population
    assert d.rng.bit_generator.state == np.random.default_rng(5).bit_generator.state
    with pytest.raises(ValueError, match="max_hypotheses"):
        f.with_options(max_hypotheses=0)
    with pytest.raises(ValueError, match=r"unknown options \['means'\]"):
        f.with_options(means=X0)
    birth = GaussianBirthTerm(np.zeros(4), np.eye(4), H, R)
    seeded = homht_kbest(MOTION, SENSOR, birth_intensity=1e-3, birth_density=birth)
    with pytest.raises(ValueError, match="two birth models"):
        seeded.with_options(population=BinomialPopulation([birth], alpha=0.1))


def test_parent_generators_give_each_parent_its_own_generator():
    """An override giving parent ``h`` a Murty generator with ``k = h + 1`` children: each parent's
    association children are its ``h + 1`` best, and ``children_of`` receives that generator."""

    class PerParent(HypothesisFilter):
        seen = []

        def parent_generators(self, state):
            return [MurtyGenerator(k=h + 1) for h in range(len(state.log_w))]

        def children_of(self, ctx, state, h, keep, keys_rng, generator=None):
            self.seen.append((h, generator.k))
            return super().children_of(ctx, state, h, keep, keys_rng, generator)

    f = PerParent(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=X0, covs=P0, max_hypotheses=10, seed=0)
    f.step(SCANS[0])
    assert PerParent.seen == [(0, 1)] and len(f.state) == 1
    f.max_hypotheses = 3
    f.step(SCANS[1])  # one parent again: the MAP child of the first scan
    ch = f.expand(SCANS[1])
    assert [int(np.sum(ch.parent == h)) for h in range(len(f.state))] == [h + 1 for h in range(len(f.state))]

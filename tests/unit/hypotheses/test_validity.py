"""The engine's validity hook: children holding a track that fails the test are pruned before the cap.

Hand-checkable scene: one known object on a circular LEO orbit, one birth term at zero velocity (the
old one-point birth), one return at the object's predicted position, δ-GLMB with p_S = 1. Of the five
association maps only two keep the birth term unborn; every other child holds a newborn with (almost)
zero velocity, which falls: with ``plausible_orbits`` as the validity test exactly those two children
remain, weighted ``p_D g(z) / κ`` against ``1 − p_D`` and renormalised.
"""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
)
from hypotrack.models.orbit3d import TwoBodyOrbit3D
from hypotrack.models.plausibility import plausible_orbits
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

P_D, RATE = 0.9, 1.0
VIEW = Box([-1e4] * 3, [1e4] * 3)
R = np.eye(3) * 0.25
SENSOR = Sensor(LinearPositionSensor(R, 6, (0, 1, 2)), DetectionModel(P_D, VIEW), PoissonClutter(RATE, VIEW))
H = SENSOR.measurement.H
MOTION = TwoBodyOrbit3D()
X0 = np.array([[6778.0, 0.0, 0.0, 0.0, 7.668558, 0.0]])  # circular at 400 km
P0 = np.diag([0.1, 0.1, 0.1, 1e-6, 1e-6, 1e-6])[None]
BIRTH = GaussianBirthTerm([6700.0, 500.0, 0.0, 0.0, 0.0, 0.0], np.diag([1e4, 1e4, 1e4, 1e-4, 1e-4, 1e-4]), H, R)
DT = 10.0


def _filter(validity=None, r_birth=0.1):
    pop = LabeledMultiBernoulliPopulation([BIRTH], r_birth=r_birth, p_survive=1.0)
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=pop, dt=DT,
                            max_hypotheses=100, means=X0, covs=P0, seed=1, validity=validity)


def _scan():
    return MOTION.propagate(X0[0], DT)[:3][None].copy()


def test_a_hypothesis_with_an_implausible_newborn_is_pruned_and_the_rest_renormalised():
    Z = _scan()
    plain, checked = _filter(), _filter(plausible_orbits)
    plain.step(Z)
    checked.step(Z)
    assert len(plain.log_weights) == 5  # (track on z | missed) x (birth not born | born undetected | on z)
    assert len(checked.log_weights) == 2 and checked.last_stats["n_invalid_pruned"] == 3
    # hand value: p_D g(z | predicted track) / kappa against 1 - p_D (the unborn factor 1 - r_B is common)
    x_pred, F = MOTION.transition(X0, DT)
    P_pred = F[0] @ P0[0] @ F[0].T + MOTION.Q(DT)
    g = multivariate_normal(H @ x_pred[0], H @ P_pred @ H.T + R).pdf(Z[0])
    kappa = RATE / VIEW.area
    odds = P_D * g / kappa / (1 - P_D)
    w = np.sort(np.exp(checked.log_weights))
    np.testing.assert_allclose(w, np.sort([odds / (1 + odds), 1 / (1 + odds)]), rtol=1e-9)
    # the same two children in the unchecked filter, renormalised, give the same weights
    n_tracks = np.array([len(t) for t in plain.track_lists])
    kept = np.exp(plain.log_weights[n_tracks == 1])
    np.testing.assert_allclose(np.sort(kept / kept.sum()), w, rtol=1e-9)
    assert np.all(plausible_orbits(checked.store.means))


def test_a_validity_that_accepts_everything_changes_nothing():
    Z = _scan()
    plain, always = _filter(), _filter(lambda m: np.ones(len(m), bool))
    plain.step(Z)
    always.step(Z)
    np.testing.assert_array_equal(always.log_weights, plain.log_weights)
    np.testing.assert_array_equal(always.store.means, plain.store.means)
    assert plain.configuration()["validity"] is None


def test_a_prediction_failing_the_test_is_deleted_and_a_failed_step_leaves_the_filter_as_it_was():
    """A test no state passes: the known object's prediction fails it and no child lacks it (p_S = 1), so the track
    is deleted, as a single-hypothesis tracker deletes an unphysical track; every newborn fails too, leaving one
    empty hypothesis of weight 1. Before, the step raised."""
    f = _filter(lambda m: np.zeros(len(m), bool))
    f.step(_scan())
    assert [len(t) for t in f.track_lists] == [0] and f.log_weights[0] == pytest.approx(0.0, abs=1e-12)
    assert f.last_stats["n_invalid_deleted"] == 1
    assert f.posterior().expected_number == 0.0
    g = _filter(plausible_orbits)
    g.step(_scan())
    assert "n_invalid_deleted" not in g.last_stats  # a valid prediction is never deleted
    with pytest.raises(TypeError, match="validity must be callable"):
        _filter(validity=3)
    h = _filter(lambda m: np.ones(len(m) + 1, bool))
    before = h.log_weights.copy(), h.time
    with pytest.raises(ValueError, match="one bool per track"):
        h.step(_scan())
    np.testing.assert_array_equal(h.log_weights, before[0])
    assert h.time == before[1]


def test_the_factored_engine_applies_the_same_hook():
    from hypotrack.hypotheses.factored import FactoredFilter

    Z = _scan()
    checked, plain = _filter(plausible_orbits), _filter()
    fac, fac_plain = FactoredFilter.from_filter(_filter(plausible_orbits)), FactoredFilter.from_filter(_filter())
    for f in (checked, plain, fac, fac_plain):
        f.step(Z)
    assert checked.posterior().expected_number == pytest.approx(1.0)  # no newborn survives the test
    assert fac.posterior().expected_number == pytest.approx(1.0)
    assert fac_plain.posterior().expected_number == pytest.approx(plain.posterior().expected_number)
    assert plain.posterior().expected_number > 1.01  # the control holds newborns (r_B (1 - p_D) / (1 - r_B p_D))


def test_with_options_carries_or_replaces_the_hook():
    f = _filter(plausible_orbits)
    assert f.with_options(merge_duplicates=False).validity is plausible_orbits
    assert f.with_options(validity=None).validity is None


def _searched_filter(validity, generator):
    """Reid's weights without a population, a generator that returns the heaviest child only."""
    from hypotrack.hypotheses import ReidWeights

    return HypothesisFilter(MOTION, SENSOR, ReidWeights(), generator, dt=DT, max_hypotheses=10, means=X0, covs=P0,
                            seed=1, validity=validity)


@pytest.mark.parametrize("generator", ["murty", "mcmc"])
def test_a_search_that_finds_only_invalid_children_falls_back_to_the_null_association(generator):
    """The return 2 km off the prediction pulls the updated track past a wall the prediction is inside; the search
    finds only that child (the missed one is ~10^12 times lighter). The step falls back to the null association
    alone: the missed child, the prediction itself, of weight 1."""
    from hypotrack.hypotheses import MCMCGenerator, MurtyGenerator

    x_pred = MOTION.propagate(X0[0], DT)
    wall = x_pred[0] + 0.3
    Z = (x_pred[:3] + [2.0, 0.0, 0.0])[None]
    gen = MurtyGenerator(k=1) if generator == "murty" else MCMCGenerator(n_steps=50, init="best", completion_rounds=0)
    unchecked = _searched_filter(None, gen)
    unchecked.step(Z)
    assert len(unchecked.log_weights) == 1 and unchecked.store.means[0, 0] > wall  # the search's only child
    f = _searched_filter(lambda m: m[:, 0] < wall, gen)
    f.step(Z)
    assert len(f.log_weights) == 1 and f.log_weights[0] == pytest.approx(0.0, abs=1e-12)
    x_p, F = MOTION.transition(X0, DT)
    np.testing.assert_allclose(f.store.means, x_p, rtol=0, atol=1e-9)
    np.testing.assert_allclose(f.store.covs[0], F[0] @ P0[0] @ F[0].T + MOTION.Q(DT), rtol=1e-9, atol=1e-15)
    # the prediction outside the wall too: no child is valid, so the track is deleted and the return is clutter
    g = _searched_filter(lambda m: m[:, 0] < x_pred[0] - 1.0, gen)
    g.step(Z)
    assert [len(t) for t in g.track_lists] == [0] and g.last_stats["n_invalid_deleted"] == 1


def test_the_labeled_multi_bernoulli_fallback_adds_every_object_missed_and_every_object_died():
    """δ-GLMB (labeled multi-Bernoulli, p_S = 0.9, no birth term) whose search returns only the detected map, past
    the wall: the fallback's maps are "the object missed" (the prediction, valid) and "the object died" (no track),
    weighted p_S (1 − p_D) against 1 − p_S."""
    from hypotrack.hypotheses import MurtyGenerator

    x_pred = MOTION.propagate(X0[0], DT)
    wall = x_pred[0] + 0.3
    Z = (x_pred[:3] + [2.0, 0.0, 0.0])[None]
    pop = LabeledMultiBernoulliPopulation([], r_birth=0.1, p_survive=0.9)
    f = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), MurtyGenerator(k=1), population=pop, dt=DT, max_hypotheses=10,
                         means=X0, covs=P0, seed=1, validity=lambda m: m[:, 0] < wall)
    f.step(Z)
    n_tracks = np.array([len(t) for t in f.track_lists])
    assert sorted(n_tracks.tolist()) == [0, 1]
    w = np.exp(f.log_weights)
    np.testing.assert_allclose(w[n_tracks == 1], [0.9 * (1 - P_D) / (0.9 * (1 - P_D) + 0.1)], rtol=1e-12)
    np.testing.assert_allclose(f.store.means[f.track_lists[int(np.flatnonzero(n_tracks == 1)[0])]],
                               MOTION.transition(X0, DT)[0], rtol=0, atol=1e-9)

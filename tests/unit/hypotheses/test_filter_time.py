"""The engine's scan times: ``step(Z, time)``, a zero interval (an update without prediction) by
hand, a negative interval refused without change, and ``estimates()`` as ``TrackEstimates``."""

import numpy as np
import pytest
from scipy.special import logsumexp

from hypotrack.hypotheses import (ExhaustiveGenerator, GaussianBirthTerm, GLMBWeights, HypothesisFilter,
                                  LabeledMultiBernoulliPopulation, ReidWeights)
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.protocol import HypothesisTracker, TrackEstimates

P_D, RATE = 0.8, 2.0
REGION = Box([-20.0, -20.0], [20.0, 20.0])  # area 1600
R = np.diag([0.5, 0.25])
SENSOR = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)), DetectionModel(P_D, REGION),
                PoissonClutter(RATE, REGION))
H = SENSOR.measurement.H
MOTION = ConstantVelocity(q=0.3)
X0 = np.array([[1.0, 2.0, 3.0, -1.0]])
P0 = np.diag([2.0, 1.0, 0.5, 0.5])[None]
Z = np.array([[1.5, 1.7], [0.2, 2.9], [9.0, -7.0]])  # two returns near the object, one far (clutter)


def _homht(**kw):
    return HypothesisFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=X0, covs=P0,
                            max_hypotheses=100, seed=0, **kw)


def test_zero_interval_is_an_update_of_the_unpredicted_prior_by_hand():
    """One object, three returns, Reid's weights (document 001 Eq. 30): the object missed weighs
    ``(1 − p_D) λ_C``, the object on return ``i`` weighs ``p_D N(z_i; H x₀, S)`` with ``S = H P₀ Hᵀ + R``
    — the prior moments, no motion and no process noise — and each track is the Kalman update of
    ``(x₀, P₀)``."""
    f = _homht()
    f.step(Z, 0.0)
    x0, P = X0[0], P0[0]
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    lam = RATE / REGION.area
    nu = Z - x0 @ H.T
    loglik = -0.5 * (np.einsum("ij,jk,ik->i", nu, np.linalg.inv(S), nu) + np.log(np.linalg.det(2 * np.pi * S)))
    want = np.concatenate([[np.log1p(-P_D) + np.log(lam)], np.log(P_D) + loglik])
    want -= logsumexp(want)
    post = f.posterior(n_top=4)
    # weights, best first: the hand values sorted
    np.testing.assert_allclose(post.log_weights, np.sort(want)[::-1], rtol=0, atol=1e-12)
    means = {round(float(w), 12): h for w, h in zip(post.log_weights, post.top)}
    for i in range(3):
        h = means[round(float(want[1 + i]), 12)]
        np.testing.assert_allclose(h.means[0], x0 + K @ nu[i], rtol=0, atol=1e-12)
        np.testing.assert_allclose(h.covs[0], (np.eye(4) - K @ H) @ P, rtol=0, atol=1e-12)
    missed = means[round(float(want[0]), 12)]
    assert np.array_equal(missed.means[0], x0) and np.array_equal(missed.covs[0], P)  # not predicted at all
    assert f.time == 0.0 and f.scan_index == 1
    # the same scan one second later is predicted first: every weight and moment differs
    g = _homht()
    g.step(Z, 1.0)
    assert g.time == 1.0 and not np.allclose(np.sort(g.posterior().log_weights), np.sort(post.log_weights))
    # dt=0 is the same zero interval
    h = _homht()
    h.step(Z, dt=0.0)
    assert h.state.same_as(f.state) and h.time == 0.0


def test_zero_interval_skips_the_kinematics_not_the_scans_population_events():
    """δ-GLMB with ``p_S = 0.9`` and a birth term at the returns: the population's probabilities are
    per scan (no interval in them), so a scan at the same time still weighs a death and a birth —
    what a first scan at the priors' epoch needs to start an object. Its tracks are the updates of
    the unpredicted moments: the object's surviving, missed track is the prior itself."""
    birth = GaussianBirthTerm(np.array([0.5, 2.5, 0.0, 0.0]), np.diag([4.0, 4.0, 1.0, 1.0]), H, R)

    def make():
        pop = LabeledMultiBernoulliPopulation([birth], r_birth=0.3, p_survive=0.9)
        return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=pop,
                                means=X0, covs=P0, max_hypotheses=1000, seed=0)

    later, same = make(), make()
    card = later.step(Z, 1.0).cardinality
    assert len(card) == 3 and card[0] > 0 and card[2] > 0
    post = same.step(Z, 0.0)
    assert len(post.cardinality) == 3 and post.cardinality[0] > 0 and post.cardinality[2] > 0
    assert same.next_label > 1  # an object born at the zero-interval scan
    tracks = same.store.means[same.store.labels == 0]
    assert any(np.array_equal(x, X0[0]) for x in tracks)  # the missed track: the prior, not predicted


def test_negative_interval_is_refused_and_leaves_the_filter_unchanged():
    f = _homht()
    f.step(Z, 2.0)
    before = (f.state, f.time, f.scan_index, f.rng.bit_generator.state, f.last_stats)
    with pytest.raises(ValueError, match="^time must be >= the filter's time 2.0"):
        f.step(Z, 1.5)
    with pytest.raises(ValueError, match="^dt must be a finite number >= 0, got -0.1"):
        f.step(Z, dt=-0.1)
    with pytest.raises(ValueError, match="^time must be a finite number"):
        f.step(Z, float("nan"))
    after = (f.state, f.time, f.scan_index, f.rng.bit_generator.state, f.last_stats)
    assert all(a is b or a == b for a, b in zip(before, after))


def test_initialise_at_a_time_and_estimates_with_labels():
    f = _homht()
    f.initialise(np.vstack([X0, X0 + 5.0]), np.repeat(P0, 2, axis=0), labels=[7, 3], time=10.0)
    assert f.time == 10.0 and isinstance(f, HypothesisTracker)
    est = f.estimates()
    assert isinstance(est, TrackEstimates) and est.time == 10.0 and est.labels.tolist() == [7, 3]
    np.testing.assert_array_equal(est.x, np.vstack([X0, X0 + 5.0]))
    assert est.P.shape == (2, 4, 4)
    f.step(np.zeros((0, 2)), 12.5)  # an interval of 2.5
    np.testing.assert_allclose(f.estimates().x, np.vstack([X0, X0 + 5.0]) @ MOTION.F(2.5).T, atol=1e-12)
    assert f.estimates().time == 12.5
    f.step(np.zeros((0, 2)))  # neither time nor dt: the filter's dt
    assert f.time == 13.5

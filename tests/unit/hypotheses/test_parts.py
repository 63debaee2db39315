"""The hypothesis engine's parts by hand: scan context, track store, hypotheses and child sets,
association problems, posterior summaries, presets and synthetic problems."""

import re

import numpy as np
import pytest
from scipy import stats

from hypotrack.hypotheses import (
    AssociationProblem,
    BinomialPopulation,
    ChildSet,
    ExhaustiveGenerator,
    GibbsGenerator,
    GLMBWeights,
    HFISSTWeights,
    Hypothesis,
    LabeledMultiBernoulliPopulation,
    MCMCGenerator,
    MurtyGenerator,
    ReidWeights,
    ScanContext,
    SingleEventPopulation,
    TrackStore,
    glmb,
    glmb_murty,
    hfisst,
    homht,
    homht_kbest,
    rfisst,
)
from hypotrack.hypotheses.posterior import summarise
from hypotrack.hypotheses.problems import DIFFICULTY_SPACING, synthetic_problem
from hypotrack.hypotheses.tracks import update_pairs
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box, FieldOfView
from scenes import position_sensor


def _ctx(m=3, n=2, B=1, rate=2.0, volume=400.0):
    return ScanContext(Z=np.zeros((m, 2)), loglik=np.zeros((m, n)), allowed=np.ones((m, n), bool),
                       p_detect=np.full(n, 0.9), birth_loglik=np.zeros((m, B)), p_detect_birth=0.9,
                       clutter_rate=rate, clutter_volume=volume)


def test_scan_context_counts_and_clutter_terms():
    ctx = _ctx(m=3, n=2, B=4, rate=2.0, volume=400.0)
    assert ctx.n_returns == 3
    assert ctx.n_birth_regions == 4
    assert ctx.clutter_intensity == 2.0 / 400.0
    assert ctx.log_clutter_density == pytest.approx(-np.log(400.0), abs=1e-15)


# ---------------------------------------------------------------- track store
def _kalman(x, P, z, H, R):
    """Textbook Kalman update with the Joseph-form covariance (an independent oracle)."""
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    A = np.eye(len(x)) - K @ H
    return x + K @ (z - H @ x), A @ P @ A.T + K @ R @ K.T


def test_track_store_validation_and_empty_store():
    with pytest.raises(ValueError, match="^an empty track store needs ndim$"):
        TrackStore.from_arrays(np.zeros((0, 4)), None)
    for means, match in ((np.zeros(4), r"^means must be a 2-D array, got shape \(4,\)$"),
                         ([[0.0, np.nan]], r"^means must be finite")):
        with pytest.raises(ValueError, match=match):
            TrackStore.from_arrays(means, np.eye(2)[None])
    with pytest.raises(ValueError, match=r"^covs must be 2x2, got shape \(1, 3, 3\)$"):
        TrackStore.from_arrays(np.zeros((1, 2)), np.eye(3)[None])
    empty = TrackStore.from_arrays([], None, ndim=3)
    assert empty.means.shape == (0, 3) and empty.covs.shape == (0, 3, 3)
    assert empty.labels.shape == (0,) and empty.labels.dtype == np.int64
    assert len(empty) == 0 and empty.ndim == 3
    assert empty.predict(ConstantVelocity(0.1), 1.0) is empty
    covs = np.repeat(np.eye(2)[None], 3, axis=0)
    with pytest.raises(ValueError, match=r"covs must have shape \(2, 2, 2\), got \(3, 2, 2\)"):
        TrackStore.from_arrays(np.zeros((2, 2)), covs)
    with pytest.raises(ValueError, match=r"labels must have shape \(3,\), got \(2,\)"):
        TrackStore.from_arrays(np.zeros((3, 2)), covs, labels=[4, 5])
    store = TrackStore.from_arrays(np.arange(6.0).reshape(3, 2), covs)
    np.testing.assert_array_equal(store.labels, [0, 1, 2])
    assert store.labels.dtype == np.int64 and len(store) == 3 and store.ndim == 2
    labelled = TrackStore.from_arrays(np.zeros((3, 2)), covs, labels=np.array([7.0, 3.0, 9.0]))
    np.testing.assert_array_equal(labelled.labels, [7, 3, 9])
    assert labelled.labels.dtype == np.int64  # labels are integers even when given as floats


def test_track_store_predicts_every_track_and_keeps_labels():
    motion = ConstantVelocity(0.3)
    means = np.array([[0.0, 1.0, 2.0, -1.0], [5.0, 0.0, 0.0, 0.5]])
    covs = np.stack([np.diag([1.0, 2.0, 0.5, 0.25]), np.eye(4) * 3.0])
    store = TrackStore.from_arrays(means, covs, labels=[11, 4])
    pred = store.predict(motion, 2.0)
    F, Q = motion.F(2.0), motion.Q(2.0)
    for j in range(2):
        np.testing.assert_allclose(pred.means[j], F @ means[j], atol=1e-12)
        np.testing.assert_allclose(pred.covs[j], F @ covs[j] @ F.T + Q, atol=1e-12)
    np.testing.assert_array_equal(pred.labels, [11, 4])


def test_update_pairs_updates_each_pair_and_keeps_missed_tracks_predicted():
    H = np.hstack([np.eye(2), np.zeros((2, 2))])
    R = np.diag([0.5, 0.8])
    means = np.array([[0.0, 1.0, 2.0, -1.0], [5.0, 0.0, 0.0, 0.5]])
    covs = np.stack([np.diag([1.0, 2.0, 0.5, 0.25]), np.eye(4) * 3.0])
    pred = TrackStore.from_arrays(means, covs)
    Z = np.array([[0.3, 0.9], [4.0, 1.0], [9.0, 9.0]])
    sources, returns = [0, 0, 1, 1, 0], [0, -1, 1, 0, 2]
    x, P = update_pairs(pred, Z, H, R, sources, returns)
    for q, (s, r) in enumerate(zip(sources, returns)):
        want = (means[s], covs[s]) if r < 0 else _kalman(means[s], covs[s], Z[r], H, R)
        np.testing.assert_allclose(x[q], want[0], atol=1e-12)
        np.testing.assert_allclose(P[q], want[1], atol=1e-12)
    np.testing.assert_array_equal(pred.means, means)  # the predicted store is not touched
    x, P = update_pairs(pred, Z, H, R, [1, 0], [-1, -1])
    np.testing.assert_array_equal(x, means[[1, 0]])
    np.testing.assert_array_equal(P, covs[[1, 0]])
    x, P = update_pairs(pred, Z, H, R, [], [])  # no pair: empty stores
    assert x.shape == (0, 4) and P.shape == (0, 4, 4)
    x, P = update_pairs(pred, Z, H, R, np.array([1.0, 0.0]), np.array([0.0, -1.0]))  # integer-coded floats
    np.testing.assert_allclose(x[0], _kalman(means[1], covs[1], Z[0], H, R)[0], atol=1e-12)
    np.testing.assert_array_equal(x[1], means[0])


# ---------------------------------------------------------------- hypotheses and child sets
def test_hypothesis_counts_its_tracks():
    assert Hypothesis(-1.5, (3, 0, 7)).n_objects == 3
    assert Hypothesis(0.0, ()).n_objects == 0


def test_child_set_silent_events_take_and_concatenate():
    ev = np.array([[0, -1], [-1, -1], [1, 0], [-1, 2], [-1, -1]], dtype=np.int32)
    kind = np.array([ChildSet.ASSOCIATION, ChildSet.UNDETECTED_BIRTH, ChildSet.DEATH,
                     ChildSet.POPULATION_SET, ChildSet.POPULATION_SET])
    # bit j < M = 3: object j died; bit M + r: birth term r born undetected
    arg = np.array([-1, 1, 2, (1 << 0) | (1 << 2) | (1 << 4), 1 << 3], dtype=np.int64)
    cs = ChildSet(np.array([0, 0, 1, 1, 2]), ev, kind, arg, np.array([-1.0, -2.0, -3.0, -4.0, -5.0]))
    assert len(cs) == 5
    assert cs.silent_events(0, 3) == ([], [])
    assert cs.silent_events(1, 3) == ([], [1])
    assert cs.silent_events(2, 3) == ([2], [])
    assert cs.silent_events(3, 3) == ([0, 2], [1])
    assert cs.silent_events(4, 3) == ([], [0])
    assert cs.silent_events(4, 4) == ([3], [])
    sub = cs.take([3, 0])
    np.testing.assert_array_equal(sub.parent, [1, 0])
    np.testing.assert_array_equal(sub.events, ev[[3, 0]])
    np.testing.assert_array_equal(sub.kind, kind[[3, 0]])
    np.testing.assert_array_equal(sub.arg, arg[[3, 0]])
    np.testing.assert_array_equal(sub.log_weights, [-4.0, -1.0])
    empty = ChildSet.concatenate([sub.take([]), cs.take(np.zeros(0, int))], n_returns=2)
    assert len(empty) == 0 and empty.events.shape == (0, 2) and empty.events.dtype == np.int32
    for f in ("parent", "kind", "arg"):
        assert getattr(empty, f).shape == (0,) and getattr(empty, f).dtype == np.int64
    assert empty.log_weights.shape == (0,)
    both = ChildSet.concatenate([sub, cs.take([]), cs.take([4])], n_returns=2)
    np.testing.assert_array_equal(both.parent, [1, 0, 2])
    np.testing.assert_array_equal(both.events, ev[[3, 0, 4]])
    np.testing.assert_array_equal(both.kind, kind[[3, 0, 4]])
    np.testing.assert_array_equal(both.arg, arg[[3, 0, 4]])
    np.testing.assert_array_equal(both.log_weights, [-4.0, -1.0, -5.0])


# ---------------------------------------------------------------- association problems
def _problem():
    """m = 3 returns, 2 objects + 1 birth column, clutter and seeded-birth options."""
    ts = np.array([[-1.0, -2.0, -4.0], [-3.0, -np.inf, -5.0], [-0.5, -1.5, -2.5]])
    os_ = np.array([[-6.0, -7.0], [-8.0, -9.0], [-6.5, -np.inf]])
    ct = np.array([[0.0, -0.1], [-0.2, -0.3], [-0.4, -0.5]])
    return AssociationProblem(ts, os_, 2, ct, constant=1.25)


def test_association_problem_shapes_scores_and_counts():
    p = _problem()
    assert (p.n_returns, p.n_exclusive, p.n_objects, p.n_birth_columns, p.n_options) == (3, 3, 2, 1, 2)
    np.testing.assert_array_equal(p.score, np.hstack([p.target_scores, p.option_scores]))
    np.testing.assert_array_equal(p.allowed, [[1, 1, 1], [1, 0, 1], [1, 1, 1]])
    assert not p.count_term_is_constant
    flat = AssociationProblem(p.target_scores, p.option_scores, 2, np.full((3, 2), -0.7))
    assert flat.count_term_is_constant and flat.constant == 0.0
    ev = np.array([[0, -1, 1], [2, 0, -2], [-1, -2, -1], [1, 2, 0]])
    k, b = p.counts(ev)
    np.testing.assert_array_equal(k, [2, 1, 0, 2])
    np.testing.assert_array_equal(b, [0, 1, 0, 1])
    np.testing.assert_array_equal(p.detected(ev), [[1, 1], [1, 0], [0, 0], [1, 1]])
    # constant + Σ_i score[i, a_i] + φ[k, b]; clutter is option column 0, a seeded birth column 1
    want = [1.25 + (-1.0) + (-8.0) + (-1.5) + (-0.4),
            1.25 + (-4.0) + (-3.0) + (-np.inf) + (-0.3),
            1.25 + (-6.0) + (-9.0) + (-6.5) + 0.0,
            1.25 + (-2.0) + (-5.0) + (-0.5) + (-0.5)]
    np.testing.assert_allclose(p.log_weights(ev), want, rtol=0, atol=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(target_scores=np.zeros(3)), r"target_scores \(m, C\) and option_scores \(m, T>=1\) must share m"),
    (dict(option_scores=np.zeros(3)), "must share m"),
    (dict(option_scores=np.zeros((2, 1))), r"got \(3, 3\) and \(2, 1\)"),
    (dict(option_scores=np.zeros((3, 0))), "must share m"),
    (dict(n_objects=4), r"n_objects must lie in \[0, 3\], got 4"),
    (dict(n_objects=-1), r"n_objects must lie in \[0, 3\], got -1"),
    (dict(count_term=np.zeros((3, 1))), r"count_term must have shape \(3, 2\), got \(3, 1\)"),
])
def test_association_problem_bad_shapes(kwargs, match):
    args = dict(target_scores=np.zeros((3, 3)), option_scores=np.zeros((3, 1)), n_objects=2,
                count_term=np.zeros((3, 2)))
    with pytest.raises(ValueError, match=match):
        AssociationProblem(**{**args, **kwargs})


def test_association_problem_refuses_events_of_the_wrong_shape():
    p = _problem()
    for ev in (np.zeros(3, int), np.zeros((2, 2), int)):
        with pytest.raises(ValueError, match=rf"^events must have shape \(E, 3\), got {re.escape(str(ev.shape))}$"):
            p.log_weights(ev)


def test_association_problem_stores_float_arrays():
    p = AssociationProblem([[1, 2]], [[0]], 1, [[0, 0], [0, 0]], constant=2)
    for a in (p.target_scores, p.option_scores, p.count_term, p.score):
        assert a.dtype == np.float64
    assert isinstance(p.constant, float)
    np.testing.assert_array_equal(p.log_weights(np.array([[0], [1], [-1]])), [3.0, 4.0, 2.0])


def test_association_problem_accepts_the_extreme_object_counts():
    assert AssociationProblem(np.zeros((2, 3)), np.zeros((2, 1)), 3, np.zeros((4, 1))).n_birth_columns == 0
    assert AssociationProblem(np.zeros((2, 3)), np.zeros((2, 1)), 0, np.zeros((1, 4))).n_birth_columns == 3


# ---------------------------------------------------------------- posterior summaries
def test_summarise_orders_counts_and_truncates():
    store = TrackStore.from_arrays(np.arange(8.0).reshape(4, 2), np.repeat(np.eye(2)[None], 4, axis=0),
                                   labels=[10, 11, 12, 13])
    lw = np.log([0.2, 0.5, 0.1, 0.2])
    lists = [[0, 1], [2], [], [3, 1, 0]]
    post = summarise(lw, lists, store, n_top=3)
    np.testing.assert_allclose(post.log_weights, np.log([0.5, 0.2, 0.2, 0.1]), atol=1e-15)
    np.testing.assert_array_equal(post.n_objects, [1, 2, 3, 0])  # ties keep the input order
    np.testing.assert_allclose(post.cardinality, [0.1, 0.5, 0.2, 0.2], atol=1e-15)
    assert post.expected_number == pytest.approx(0.5 + 0.4 + 0.6, abs=1e-14)
    np.testing.assert_allclose(post.weights, [0.5, 0.2, 0.2, 0.1], atol=1e-15)
    assert len(post.top) == 3
    best = post.map_estimate
    assert best is post.top[0] and best.weight == pytest.approx(0.5) and best.n_objects == 1
    assert best.log_weight == pytest.approx(np.log(0.5))
    np.testing.assert_array_equal(best.labels, [12])
    np.testing.assert_array_equal(best.means, [[4.0, 5.0]])
    np.testing.assert_array_equal(post.top[1].labels, [10, 11])
    np.testing.assert_array_equal(post.top[2].labels, [13, 11, 10])
    np.testing.assert_array_equal(post.top[2].covs, np.repeat(np.eye(2)[None], 3, axis=0))
    assert len(summarise(lw, lists, store).top) == 4  # default n_top = 10 keeps all four
    many = summarise(np.log(np.full(12, 1 / 12)), [[0]] * 12, store)
    assert len(many.top) == 10


def test_summarise_breaks_ties_in_input_order():
    """Equal weights keep their input order (a stable sort), also beyond insertion-sort sizes."""
    rng = np.random.default_rng(0)
    lw = np.log(rng.choice([0.1, 0.2, 0.3], size=200))
    store = TrackStore.from_arrays(np.zeros((200, 2)), np.repeat(np.eye(2)[None], 200, axis=0),
                                   labels=np.arange(200))
    post = summarise(lw, [[i] for i in range(200)], store, n_top=200)
    order = [int(h.labels[0]) for h in post.top]
    assert order == sorted(range(200), key=lambda i: (-lw[i], i))


def test_summarise_of_empty_hypotheses_has_one_cardinality_entry():
    store = TrackStore.from_arrays([], None, ndim=2)
    post = summarise(np.log([0.25, 0.75]), [[], []], store)
    np.testing.assert_allclose(post.cardinality, [1.0], atol=1e-15)
    assert post.expected_number == 0.0


def test_summarise_of_no_hypothesis_has_unit_mass_at_zero_objects():
    store = TrackStore.from_arrays([], None, ndim=2)
    post = summarise(np.zeros(0), [], store)
    np.testing.assert_array_equal(post.cardinality, [1.0])
    assert post.n_objects.dtype == np.int64 and post.log_weights.dtype == float
    assert post.expected_number == 0.0 and post.top == ()


# ---------------------------------------------------------------- presets
_VIEW = Box([-20.0, -20.0], [20.0, 20.0])
_SENSOR = position_sensor(0.5, 0.9, _VIEW, 1.0)
_BIRTH = UniformBirthDensity(_VIEW, np.eye(2))


def test_presets_wire_their_weight_model_generator_and_options():
    motion = ConstantVelocity(0.1)
    se = SingleEventBirthDeath(0.01, 0.02, 2, fov=FieldOfView(0, 90, 1, 15))
    f = hfisst(motion, _SENSOR, max_events=77, population=se, max_hypotheses=9, seed=4, dt=2.0)
    assert isinstance(f.weights, HFISSTWeights) and f.generator == ExhaustiveGenerator(max_events=77)
    assert isinstance(f.population, SingleEventPopulation) and f.population.model is se
    assert f.population.n_birth_regions == 2
    assert f.max_hypotheses == 9 and f.dt == 2.0
    assert hfisst(motion, _SENSOR).generator == ExhaustiveGenerator(max_events=10**7)
    assert hfisst(motion, _SENSOR).population is None
    f = rfisst(motion, _SENSOR, n_steps=500, burn_in=20, mcmc_variant="symmetric", init="best", completion_rounds=1)
    assert isinstance(f.weights, HFISSTWeights)
    assert f.generator == MCMCGenerator(n_steps=500, burn_in=20, variant="symmetric", init="best",
                                        completion_rounds=1)
    assert rfisst(motion, _SENSOR).generator == MCMCGenerator(n_steps=10_000, burn_in=None, variant="paper",
                                                              init="random", completion_rounds=2)
    f = homht(motion, _SENSOR, birth_intensity=1e-3, birth_density=_BIRTH, max_events=55)
    assert f.weights == ReidWeights(birth_intensity=1e-3, birth_density=_BIRTH)
    assert f.generator == ExhaustiveGenerator(max_events=55)
    assert homht(motion, _SENSOR).weights == ReidWeights() and homht(motion, _SENSOR).generator.max_events == 10**7
    assert homht_kbest(motion, _SENSOR, k=7).generator == MurtyGenerator(k=7)
    assert homht_kbest(motion, _SENSOR, max_hypotheses=13).generator == MurtyGenerator(k=13)
    assert homht_kbest(motion, _SENSOR).generator == MurtyGenerator(k=100)
    kb = homht_kbest(motion, _SENSOR, birth_intensity=2e-3, birth_density=_BIRTH)
    assert kb.weights == ReidWeights(birth_intensity=2e-3, birth_density=_BIRTH)
    lmb = LabeledMultiBernoulliPopulation([_BIRTH], r_birth=0.1, p_survive=0.95)
    g = glmb(motion, _SENSOR, population=lmb, n_sweeps=33)
    assert g.weights == GLMBWeights() and g.generator == GibbsGenerator(n_sweeps=33) and g.population is lmb
    assert glmb(motion, _SENSOR, population=lmb).generator == GibbsGenerator(n_sweeps=1000)
    gm = glmb_murty(motion, _SENSOR, population=lmb, k=6)
    assert gm.weights == GLMBWeights() and gm.generator == MurtyGenerator(k=6)
    gm8 = glmb_murty(motion, _SENSOR, population=lmb, max_hypotheses=8, seed=1)
    assert gm8.generator == MurtyGenerator(k=8) and gm8.max_hypotheses == 8
    assert glmb(motion, _SENSOR, population=lmb, max_hypotheses=8).max_hypotheses == 8
    survival = BinomialPopulation([], p_survive=0.9)
    for preset in (hfisst, rfisst, homht, homht_kbest):
        assert preset(motion, _SENSOR, population=survival).population is survival
        assert preset(motion, _SENSOR, max_hypotheses=6).max_hypotheses == 6
    assert glmb_murty(motion, _SENSOR, population=lmb).generator == MurtyGenerator(k=100)
    for preset in (glmb, glmb_murty):
        with pytest.raises(ValueError, match="population must be a LabeledMultiBernoulliPopulation for the GLMB "
                                             "presets, got SingleEventBirthDeath"):
            preset(motion, _SENSOR, population=se)


# ---------------------------------------------------------------- synthetic problems
def _recover_objects(sp):
    """Each object's predicted return and scale from the problem's log-likelihoods alone:
    ``L_i = log N(z_i; ẑ, (σ s)² I₂)`` is a quadratic ``a |z|² + b·z + c`` in the return."""
    Z, L = sp.context.Z, sp.context.loglik
    A = np.column_stack([np.sum(Z * Z, axis=1), Z, np.ones(len(Z))])
    coef, *_ = np.linalg.lstsq(A, L, rcond=None)
    a, b, c = coef[0], coef[1:3].T, coef[3]
    var = -0.5 / a  # (σ s_j)²
    z_pred = b * var[:, None]
    np.testing.assert_allclose(c, -0.5 * np.sum(z_pred**2, axis=1) / var - np.log(2 * np.pi * var), atol=1e-6)
    return z_pred, np.sqrt(var)


@pytest.mark.parametrize("M, m, sigma, spacing", [(7, 9, 1.0, 8.0), (5, 12, 2.0, 3.0), (1, 4, 0.5, 6.0)])
def test_paper_problem_objects_lie_on_a_jittered_grid_and_clutter_fills_the_square(M, m, sigma, spacing):
    sp = synthetic_problem(M, m, seed=11, sigma=sigma, spacing=spacing, sigma_spread=0.3)
    side_n = int(np.ceil(np.sqrt(M)))
    side = side_n * spacing * sigma
    assert sp.context.clutter_volume == pytest.approx(side**2, rel=1e-12)
    z_pred, scale = _recover_objects(sp)
    cell = spacing * sigma
    centre = (np.floor(z_pred / cell) + 0.5) * cell
    assert np.all(np.abs(z_pred - centre) <= cell / 4 + 1e-6)  # jitter within ±spacing/4
    ids = np.floor(z_pred / cell) @ np.array([1, side_n])
    assert len(set(ids.tolist())) == M and np.all((z_pred > 0) & (z_pred < side))
    assert np.all((scale > sigma * np.exp(-4 * 0.3)) & (scale < sigma * np.exp(4 * 0.3)))
    clutter = sp.context.Z[sp.truth < 0]
    assert len(clutter) == m - M and np.all((clutter >= 0) & (clutter <= side))
    # a detected object's return is N(ẑ_j, (σ s_j)² I): the truth is the heaviest child here
    det = np.flatnonzero(sp.truth >= 0)
    r = (sp.context.Z[det] - z_pred[sp.truth[det]]) / scale[sp.truth[det], None]
    assert np.all(np.abs(r) < 5)
    assert sp.context.p_detect_birth == 0.95 and sp.context.clutter_rate == 1.0
    np.testing.assert_array_equal(sp.context.p_detect, np.full(M, 0.95))


def test_grid_jitter_is_uniform_over_a_quarter_cell_each_way():
    offsets = []
    for s in range(3):
        z_pred, _ = _recover_objects(synthetic_problem(49, 52, seed=s, sigma=1.5, spacing=6.0))
        cell = 6.0 * 1.5
        offsets.append((z_pred - (np.floor(z_pred / cell) + 0.5) * cell) / cell)
    offsets = np.concatenate(offsets).ravel()
    assert stats.kstest(offsets, stats.uniform(-0.25, 0.5).cdf).pvalue > 1e-3


def test_object_scales_spread_as_log_normal_and_sigma_spread_zero_is_uniform():
    sp = synthetic_problem(64, 70, seed=2, sigma=1.5, spacing=8.0, sigma_spread=0.0)
    _, scale = _recover_objects(sp)
    np.testing.assert_allclose(scale, 1.5, rtol=1e-6)
    logs = np.concatenate([np.log(_recover_objects(synthetic_problem(64, 70, seed=s, sigma=1.5))[1] / 1.5)
                           for s in range(3)])
    assert abs(logs.mean()) < 0.05 and logs.std() == pytest.approx(0.25, abs=0.03)  # default sigma_spread


def test_returns_scatter_with_the_objects_scale():
    r2 = []
    for s in range(6):
        sp = synthetic_problem(36, 36, seed=s, sigma=0.7)
        z_pred, scale = _recover_objects(sp)
        t = sp.truth
        r2.append(np.sum(((sp.context.Z - z_pred[t]) / scale[t, None]) ** 2, axis=1))
    r2 = np.concatenate(r2)
    assert r2.mean() == pytest.approx(2.0, abs=0.25)  # χ² with 2 degrees of freedom


def _fingerprint(sp):
    c = sp.context
    return (sp.problem.score.tobytes(), sp.problem.count_term.tobytes(), sp.problem.constant, sp.truth.tobytes(),
            c.clutter_rate, c.clutter_volume, c.p_detect_birth, c.p_detect.tobytes())


def test_problem_defaults_are_the_documented_values():
    x = synthetic_problem(6, 5, seed=4)
    y = synthetic_problem(6, 5, seed=4, p_D=0.95, clutter_rate=1.0, spacing=8.0, sigma=1.0, sigma_spread=0.25)
    assert _fingerprint(x) == _fingerprint(y)
    for change in (dict(p_D=0.8), dict(clutter_rate=3.0), dict(spacing=5.0), dict(sigma=2.0), dict(sigma_spread=0.1)):
        assert _fingerprint(synthetic_problem(6, 5, seed=4, **change)) != _fingerprint(x), change
    for diff, spacing in DIFFICULTY_SPACING.items():
        M = 30
        x = synthetic_problem(M, difficulty=diff, seed=9)
        y = synthetic_problem(M, difficulty=diff, seed=9, p_D=0.9, clutter_rate=(1 - 0.9) * M, spacing=spacing,
                              sigma=1.0, sigma_spread=0.25)
        assert _fingerprint(x) == _fingerprint(y)
        assert x.context.clutter_rate == pytest.approx(3.0) and x.context.p_detect_birth == 0.9
        assert x.context.clutter_volume == pytest.approx((6 * spacing) ** 2)
        for change in (dict(p_D=0.7), dict(clutter_rate=1.5), dict(spacing=spacing * 2), dict(sigma=3.0),
                       dict(sigma_spread=0.5)):
            assert _fingerprint(synthetic_problem(M, difficulty=diff, seed=9, **change)) != _fingerprint(x), change
    small = synthetic_problem(4, difficulty="2sigma", seed=1)
    assert small.context.clutter_rate == 1.0  # max(1, 0.1 × 4)
    fisst = synthetic_problem(4, 4, seed=1, weights="fisst_poisson")
    assert np.all(fisst.problem.option_scores == 0.0)  # the FISST weight model, not H-FISST's 1/V
    one = synthetic_problem(1, 1, seed=0)
    assert one.context.clutter_volume == pytest.approx(64.0)
    none = synthetic_problem(0, 2, seed=0, sigma=2.0)
    assert none.context.clutter_volume == pytest.approx(256.0) and none.context.loglik.shape == (2, 0)


@pytest.mark.parametrize("difficulty", ["paper", "4sigma"])
@pytest.mark.parametrize("kwargs, match", [
    (dict(seed=-1), r"seed must be an integer in \[0, inf\], got -1"),
    (dict(n_objects=-2), r"n_objects must be an integer in \[0, inf\], got -2"),
    (dict(p_D=0.0), r"p_D must lie in \(0, 1\), got 0.0"),
    (dict(p_D=1.0), r"p_D must lie in \(0, 1\), got 1.0"),
    (dict(clutter_rate=0.0), r"clutter_rate must be a finite number > 0, got 0.0"),
    (dict(sigma=-1.0), r"sigma must be a finite number > 0, got -1.0"),
    (dict(spacing=0.0), r"spacing must be a finite number > 0, got 0.0"),
])
def test_synthetic_problem_names_the_bad_parameter_and_its_range(difficulty, kwargs, match):
    args = dict(n_objects=3, seed=0, difficulty=difficulty, **({"n_returns": 3} if difficulty == "paper" else {}))
    with pytest.raises(ValueError, match=match):
        synthetic_problem(**{**args, **kwargs})


def test_synthetic_problem_whole_messages():
    with pytest.raises(ValueError, match=r"^give exactly one of rng \(a numpy Generator\) and seed \(an int\)$"):
        synthetic_problem(3, 3, np.random.default_rng(0), seed=0)
    with pytest.raises(ValueError, match=r"^n_returns \(m >= 0\) is required for the paper difficulty$"):
        synthetic_problem(3, seed=0)
    with pytest.raises(ValueError, match=r"^n_returns must be None for difficulty '2sigma' \(m is drawn\), got 3$"):
        synthetic_problem(3, 3, seed=0, difficulty="2sigma")
    with pytest.raises(ValueError, match=r"n_returns must be an integer in \[0, inf\], got -1"):
        synthetic_problem(3, -1, seed=0)
    with pytest.raises(ValueError, match=r"^difficulty must be one of \('paper', '1sigma', '2sigma', '4sigma', "
                                         r"'8sigma'\), got 'hard'$"):
        synthetic_problem(3, seed=0, difficulty="hard")


def test_clutter_is_uniform_over_the_square_and_types_are_exact():
    sp = synthetic_problem(1, 301, seed=5, spacing=8.0, sigma=1.0)  # one object, 300 clutter returns
    clutter = sp.context.Z[sp.truth < 0]
    assert clutter.shape == (300, 2)
    for axis in range(2):  # uniform on [0, side = 8]
        assert stats.kstest(clutter[:, axis], stats.uniform(0.0, 8.0).cdf).pvalue > 1e-3
    assert sp.truth.dtype == np.int64 and sp.context.allowed.dtype == bool
    assert sp.context.allowed.shape == (301, 1) and sp.context.allowed.all()
    amb = synthetic_problem(40, difficulty="8sigma", seed=5, clutter_rate=30.0)
    clutter = amb.context.Z[amb.truth < 0]
    assert stats.poisson(30.0).ppf(1e-4) <= len(clutter) <= stats.poisson(30.0).ppf(1 - 1e-4)
    assert stats.kstest(clutter[:, 0] / (7 * 8.0), "uniform").pvalue > 1e-3

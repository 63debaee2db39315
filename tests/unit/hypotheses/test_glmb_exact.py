"""δ-GLMB pieces against hand values and brute-force enumeration of association maps
(population_lmb, weights_glmb, gibbs).

The oracle enumerates every association map γ of a parent (each object died / missed / on one
return, no two objects on one return) and weighs it by Vo, Vo & Hoang (2017) Eq. 8–12 written
out with scipy's Gaussian densities: ``log w = −λ + m log κ + Σ_i log η_i(γ_i)``.
"""

import itertools
import warnings

import numpy as np
import pytest
from scipy.stats import chi2, multivariate_normal

from hypotrack.hypotheses import (
    AssociationProblem,
    ChildSet,
    ExhaustiveGenerator,
    GaussianBirthTerm,
    GibbsGenerator,
    GLMBWeights,
    HFISSTWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    MurtyGenerator,
    ScanContext,
)
from hypotrack.hypotheses.gibbs import gibbs_search
from hypotrack.hypotheses.population_lmb import DIED, MAX_OBJECTS, MISSED
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor

VIEW = Box([-10.0, -10.0], [10.0, 10.0])
R = np.diag([0.5, 0.3])
P_D, RATE, V = 0.85, 1.5, 400.0
SENSOR = position_sensor(R, P_D, VIEW, RATE)
H = SENSOR.measurement.H
MOTION = ConstantVelocity(q=0.1)
# two objects in view, one out of view (x = 30: p_D = 0, it can only be missed or die)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [3.0, 2.0, 0.0, -1.0], [30.0, 0.0, 0.0, 0.0]])
P0 = np.stack([np.diag([1.0, 1.0, 0.3, 0.3]), np.diag([0.6, 0.9, 0.2, 0.2]), np.eye(4)])
Z = np.array([[1.2, 0.3], [3.1, 0.8], [-6.0, 7.0]])
BIRTH = GaussianBirthTerm([-5.0, 6.0, 0.0, 0.0], np.diag([4.0, 4.0, 1.0, 1.0]), H, R)


def _population(p_s=0.9, r_b=0.2, births=1):
    return LabeledMultiBernoulliPopulation([BIRTH] * births, r_birth=r_b, p_survive=p_s)


def _filter(pop, n=3, generator=None, **kw):
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), generator or ExhaustiveGenerator(), population=pop,
                            max_hypotheses=10**6, means=X0[:n], covs=P0[:n], seed=3, **kw)


def oracle_children(p_s, r_b, n=3, births=1, gate=None, kappa=RATE / V):
    """{(events over the returns, silent mask): log-weight} by brute force over γ."""
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    g, p = [], []
    for i in range(n):
        x, P = F @ X0[i], F @ P0[i] @ F.T + Q
        S = H @ P @ H.T + R
        logg = multivariate_normal(H @ x, S).logpdf(Z)
        if gate is not None:
            d = Z - H @ x
            d2 = np.einsum("ij,jk,ik->i", d, np.linalg.inv(S), d)
            logg = np.where(d2 <= chi2.ppf(gate, 2), logg, -np.inf)
        g.append(logg)
        p.append(P_D if VIEW.contains((H @ x)[None])[0] else 0.0)
    Sb = H @ BIRTH.cov @ H.T + R
    for _ in range(births):
        g.append(multivariate_normal(H @ BIRTH.mean, Sb).logpdf(Z))
        p.append(P_D)
    r = [p_s] * n + [r_b] * births
    m = len(Z)
    out = {}
    for gamma in itertools.product([DIED, MISSED, *range(m)], repeat=n + births):
        used = [j for j in gamma if j >= 0]
        if len(used) != len(set(used)):
            continue
        lw = -RATE + m * np.log(kappa)
        events, mask = [-1] * m, 0
        for i, j in enumerate(gamma):
            if j == DIED:
                lw += np.log1p(-r[i])
                mask |= 1 << i if i < n else 0
            elif j == MISSED:
                lw += np.log(r[i]) + np.log1p(-p[i])
                mask |= 1 << i if i >= n else 0
            else:
                with np.errstate(divide="ignore"):
                    lw += np.log(r[i]) + np.log(p[i]) + g[i][j] - np.log(kappa)
                events[j] = i
        if np.isfinite(lw):
            out[(tuple(events), mask)] = lw
    return out


def engine_children(ch: ChildSet):
    assert np.all(ch.kind == ChildSet.POPULATION_SET)
    return {(tuple(int(e) for e in ev), int(a)): lw for ev, a, lw in zip(ch.events, ch.arg, ch.log_weights)}


def assert_same_children(got, want, atol=1e-10):
    assert got.keys() == want.keys()
    for k, lw in want.items():
        assert got[k] == pytest.approx(lw, abs=atol), k


def test_log_existence_is_survival_for_tracks_and_birth_probability_for_terms():
    pop = LabeledMultiBernoulliPopulation([None, None], r_birth=[0.1, 0.3], p_survive=0.8)
    log_r, log_not = pop.log_existence(3)
    np.testing.assert_allclose(log_r, np.log([0.8, 0.8, 0.8, 0.1, 0.3]), rtol=0, atol=1e-15)
    np.testing.assert_allclose(log_not, np.log([0.2, 0.2, 0.2, 0.9, 0.7]), rtol=0, atol=1e-15)
    one = LabeledMultiBernoulliPopulation([None, None, None], r_birth=0.25)  # a scalar is every term's r_B
    np.testing.assert_array_equal(one.r_birth, [0.25, 0.25, 0.25])
    assert one.p_survive == 1.0
    log_r, log_not = one.log_existence(1)
    assert log_not[0] == -np.inf and log_r[0] == 0.0


@pytest.mark.parametrize("p_s, r_b", [(0.9, 0.2), (0.6, 0.45)])
def test_children_equal_brute_force_with_deaths_births_and_an_object_out_of_view(p_s, r_b):
    f = _filter(_population(p_s, r_b))
    want = oracle_children(p_s, r_b)
    got = engine_children(f.expand(Z))
    assert_same_children(got, want)
    # the out-of-view object (parent-local 2) is never on a return, but it can die
    assert not any(2 in ev for ev, _ in got)
    assert any(mask & 0b100 for _, mask in got)
    post = f.step(Z)
    w = np.array(sorted(want.values(), reverse=True))
    np.testing.assert_allclose(post.log_weights, w - np.logaddexp.reduce(w), atol=1e-10)


def test_two_birth_terms_with_gating_and_a_clutter_intensity_override():
    pop = _population(0.8, 0.3, births=2)
    f = HypothesisFilter(MOTION, SENSOR, GLMBWeights(clutter_intensity=0.01), ExhaustiveGenerator(), population=pop,
                         max_hypotheses=10**6, means=X0[:2], covs=P0[:2], gate_probability=0.9)
    want = oracle_children(0.8, 0.3, n=2, births=2, gate=0.9, kappa=0.01)
    assert_same_children(engine_children(f.expand(Z)), want)


def test_labeled_problem_rows_are_the_objects():
    pop = _population(0.9, 0.2)
    f = _filter(pop, n=2)
    pred = f.store.predict(MOTION, 1.0)
    ctx = f.scan_context(pred, Z)
    log_r, log_not = pop.log_existence(2)
    problem = GLMBWeights().labeled_problem(ctx, [1, 0], log_r, log_not, constant=-0.75)
    assert problem.n_returns == 3 and problem.n_objects == 3 and problem.n_exclusive == 3
    kappa = RATE / V
    assert problem.constant == pytest.approx(-0.75 - RATE + 3 * np.log(kappa), abs=1e-12)
    default = GLMBWeights().labeled_problem(ctx, [1, 0], log_r, log_not)  # the parent's log-weight defaults to 0
    assert default.constant == pytest.approx(-RATE + 3 * np.log(kappa), abs=1e-12)
    np.testing.assert_array_equal(problem.count_term, np.zeros((4, 1)))
    # row 0 is parent track 1: option 0 missed, option 1 died
    np.testing.assert_allclose(problem.option_scores[0], [np.log(0.9 * (1 - P_D)), np.log(0.1)], atol=1e-12)
    np.testing.assert_allclose(problem.option_scores[2], [np.log(0.2 * (1 - P_D)), np.log(0.8)], atol=1e-12)
    det = np.log(0.9 * P_D) + ctx.loglik[:, 1] - np.log(kappa)
    np.testing.assert_allclose(problem.target_scores[0], det, atol=1e-12)
    with pytest.raises(ValueError, match=r"log_exist and log_not_exist must have shape \(3,\), got \(2,\) and \(3,\)"):
        GLMBWeights().labeled_problem(ctx, [1, 0], log_r[:2], log_not)
    with pytest.raises(ValueError, match=r"must have shape \(3,\), got \(3,\) and \(4,\)"):
        GLMBWeights().labeled_problem(ctx, [1, 0], log_r, np.zeros(4))
    with pytest.raises(ValueError, match=r"^GLMB weights index children by object: use a "
                                         r"LabeledMultiBernoulliPopulation, whose children\(\) calls labeled_problem$"):
        GLMBWeights().problem(ctx, [0, 1])
    with pytest.raises(ValueError, match="clutter_intensity"):
        GLMBWeights(clutter_intensity=0.0)
    with pytest.raises(ValueError, match="needs GLMB weights, got HFISSTWeights"):
        pop.children(HFISSTWeights(), ExhaustiveGenerator(), ctx, [0, 1], 0.0, None)


def test_murty_k_best_children_are_the_exact_top_k():
    pop = _population(0.7, 0.3)
    want = sorted(oracle_children(0.7, 0.3).values(), reverse=True)
    f = _filter(pop, generator=MurtyGenerator(k=7))
    got = np.sort(f.expand(Z).log_weights)[::-1]
    np.testing.assert_allclose(got, want[:7], atol=1e-10)
    # capped step: the generator is asked for the best H∞ only, and the stats count just those
    f = _filter(pop, generator=MurtyGenerator(k=50))
    f.max_hypotheses = 3
    f.step(Z)
    np.testing.assert_allclose(np.sort(f.last_kept.log_weights)[::-1], want[:3], atol=1e-10)
    assert f.last_stats["n_association_children"] == 3
    assert f.last_stats["log_mass_generated"] == pytest.approx(np.logaddexp.reduce(want[:3]), abs=1e-10)


def test_gibbs_finds_every_child_above_1e3_of_the_mass_with_exact_weights():
    pop = _population(0.7, 0.3)
    want = oracle_children(0.7, 0.3, n=2)
    f = _filter(pop, n=2, generator=GibbsGenerator(n_sweeps=3000))
    got = engine_children(f.expand(Z))
    total = np.logaddexp.reduce(list(want.values()))
    heavy = {k for k, lw in want.items() if lw >= total + np.log(1e-3)}  # each met ~3 times in 3000 sweeps
    assert heavy <= got.keys() <= want.keys() and len(heavy) >= 10
    assert_same_children(got, {k: want[k] for k in got})
    g = _filter(pop, n=2, generator=GibbsGenerator(n_sweeps=3000))
    g.max_hypotheses = 5  # keep: the best five by exact weight
    g.step(Z)
    best = sorted(want.values(), reverse=True)[:5]
    np.testing.assert_allclose(np.sort(g.last_kept.log_weights)[::-1], best, atol=1e-10)


def test_gibbs_search_starts_all_missed_and_refuses_an_impossible_start():
    pop = _population(0.7, 0.3)
    f = _filter(pop, n=2)
    ctx = f.scan_context(f.store.predict(MOTION, 1.0), Z)
    log_r, log_not = pop.log_existence(2)
    problem = GLMBWeights().labeled_problem(ctx, [0, 1], log_r, log_not)
    events, lw = gibbs_search(problem, 0, seed=5)  # no sweep: the start only, every object missed
    np.testing.assert_array_equal(events, [[-1, -1, -1]])
    np.testing.assert_allclose(lw, problem.log_weights(events), atol=0)
    events, lw = gibbs_search(problem, 40, seed=5)
    np.testing.assert_array_equal(events[0], [-1, -1, -1])
    assert len({e.tobytes() for e in events}) == len(events)  # distinct samples
    np.testing.assert_array_equal(lw, problem.log_weights(events))
    again = gibbs_search(problem, 40, seed=5)
    np.testing.assert_array_equal(again[0], events)
    with pytest.raises(ValueError, match=r"^n_sweeps must be an integer in \[0, inf\], got -1$"):
        gibbs_search(problem, -1, seed=5)
    with pytest.raises(ValueError, match="n_sweeps"):
        GibbsGenerator(n_sweeps=-2)
    bad = type(problem)(problem.target_scores, np.column_stack([np.r_[-np.inf, 0.0, 0.0], np.zeros(3)]),
                        problem.n_objects, problem.count_term)
    with pytest.raises(ValueError, match="^row option 0 must be finite for every row: it is the sampler's "
                                         "starting point$"):
        gibbs_search(bad, 10, seed=1)


def test_gibbs_on_a_parent_without_objects_or_births_is_the_one_empty_child():
    pop = LabeledMultiBernoulliPopulation([], p_survive=0.9)
    f = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), GibbsGenerator(n_sweeps=10), population=pop)
    ch = f.expand(Z)
    np.testing.assert_array_equal(ch.events, [[-1, -1, -1]])
    np.testing.assert_array_equal(ch.arg, [0])
    assert ch.log_weights[0] == pytest.approx(-RATE + 3 * np.log(RATE / V) + 3 * np.log(V / RATE) * 0, abs=1e-12)


def test_to_events_beyond_int64_masks_uses_python_integers():
    P = MAX_OBJECTS + 3
    gammas = np.full((2, P), MISSED)
    gammas[0, 0], gammas[0, P - 1], gammas[1, 63] = DIED, 1, 0  # object 0 died; last birth term on return 1
    n_objects = P - 2
    events, masks = LabeledMultiBernoulliPopulation.to_events(gammas, n_objects, 2)
    np.testing.assert_array_equal(events, [[-1, P - 1], [63, -1]])
    births = sum(1 << j for j in range(n_objects, P))
    assert masks[0] == (1 | births) - (1 << (P - 1))
    assert masks[1] == births - (1 << 63)  # term 63 is on return 0, term 64 unseen
    assert isinstance(masks[0], int) and masks[0] > 2**63
    small_events, small = LabeledMultiBernoulliPopulation.to_events([[DIED, MISSED, 0]], 2, 1)
    np.testing.assert_array_equal(small_events, [[2]])
    assert small.dtype == np.int64 and small.tolist() == [1]


def test_gaussian_birth_term_likelihood_first_update_and_checks():
    z = np.array([[-4.0, 5.5], [0.0, 0.0]])
    Sb = H @ BIRTH.cov @ H.T + R
    np.testing.assert_allclose(BIRTH.loglik(z), multivariate_normal(H @ BIRTH.mean, Sb).logpdf(z), atol=1e-12)
    np.testing.assert_allclose(BIRTH.loglik(z[0]), multivariate_normal(H @ BIRTH.mean, Sb).logpdf(z[0]),
                               atol=1e-12)
    x, P = BIRTH.initial_state(z[0], R)
    K = BIRTH.cov @ H.T @ np.linalg.inv(Sb)
    np.testing.assert_allclose(x, BIRTH.mean + K @ (z[0] - H @ BIRTH.mean), atol=1e-12)
    A = np.eye(4) - K @ H
    np.testing.assert_allclose(P, A @ BIRTH.cov @ A.T + K @ R @ K.T, atol=1e-12)
    mean, cov = BIRTH.prior()
    np.testing.assert_array_equal(mean, BIRTH.mean)
    np.testing.assert_array_equal(cov, BIRTH.cov)
    with pytest.raises(ValueError, match=r"H must have 4 columns, got shape \(2, 3\)"):
        GaussianBirthTerm(np.zeros(4), np.eye(4), np.zeros((2, 3)), R)
    with pytest.raises(ValueError, match="R"):
        GaussianBirthTerm(np.zeros(4), np.eye(4), H, np.eye(3))
    with pytest.raises(ValueError, match="cov"):
        GaussianBirthTerm(np.zeros(4), np.eye(3), H, R)


@pytest.mark.parametrize("kwargs, match", [
    (dict(r_birth=0.0), "r_birth"), (dict(r_birth=1.0), "r_birth"), (dict(r_birth=[0.2, 1.5]), "r_birth"),
    (dict(p_survive=0.0), "p_survive"), (dict(p_survive=1.2), "p_survive"),
])
def test_population_refuses_probabilities_out_of_range(kwargs, match):
    with pytest.raises(ValueError, match=match):
        LabeledMultiBernoulliPopulation(**{"birth_densities": [BIRTH, BIRTH], "r_birth": 0.1, **kwargs})


def test_gibbs_search_and_generator_return_int32_events_also_without_rows():
    empty = AssociationProblem(np.zeros((0, 3)), np.zeros((0, 2)), 3, np.zeros((4, 1)), constant=-2.5)
    events, lw = gibbs_search(empty, 5, seed=0)
    assert events.shape == (1, 0) and events.dtype == np.int32
    np.testing.assert_array_equal(lw, [-2.5])
    pop = _population(0.7, 0.3)
    f = _filter(pop, n=2)
    ctx = f.scan_context(f.store.predict(MOTION, 1.0), Z)
    log_r, log_not = pop.log_existence(2)
    problem = GLMBWeights().labeled_problem(ctx, [0, 1], log_r, log_not)
    events, lw = GibbsGenerator(n_sweeps=200).generate(problem, np.random.default_rng(1), keep=4)
    assert events.dtype == np.int32 and events.shape == (4, 3)
    full_ev, full_lw = GibbsGenerator(n_sweeps=200).generate(problem, np.random.default_rng(1))
    np.testing.assert_array_equal(lw, np.sort(full_lw)[::-1][:4])
    np.testing.assert_array_equal(lw, problem.log_weights(events))


def test_to_events_takes_integer_coded_floats_and_uses_int64_masks_up_to_62_objects():
    events, masks = LabeledMultiBernoulliPopulation.to_events(np.array([[-2.0, -1.0, 0.0]]), 2, 1)
    np.testing.assert_array_equal(events, [[2]])
    assert masks.tolist() == [1]
    gammas = np.full((1, MAX_OBJECTS), MISSED)
    gammas[0, MAX_OBJECTS - 1] = DIED
    _, masks = LabeledMultiBernoulliPopulation.to_events(gammas, MAX_OBJECTS, 0)
    assert masks.dtype == np.int64 and masks[0] == 1 << (MAX_OBJECTS - 1)
    _, masks = LabeledMultiBernoulliPopulation.to_events(np.full((1, MAX_OBJECTS + 1), DIED), MAX_OBJECTS + 1, 0)
    assert masks.dtype == object and masks[0] == (1 << (MAX_OBJECTS + 1)) - 1


def test_gaussian_birth_term_stores_validated_float_arrays():
    cov = [[4.0, 1e-12], [0.0, 2.0]]  # asymmetric by 1e-12: symmetrised
    term = GaussianBirthTerm([1, 2], cov, [[1, 0]], [[0.5]])
    for name, shape in (("mean", (2,)), ("cov", (2, 2)), ("H", (1, 2)), ("R", (1, 1))):
        value = getattr(term, name)
        assert isinstance(value, np.ndarray) and value.dtype == float and value.shape == shape, name
    assert term.cov[0, 1] == term.cov[1, 0] == 5e-13
    np.testing.assert_array_equal(term.mean, [1.0, 2.0])
    np.testing.assert_array_equal(term.H, [[1.0, 0.0]])
    np.testing.assert_array_equal(term.R, [[0.5]])


@pytest.mark.parametrize("kwargs, match", [
    (dict(mean=np.zeros((2, 2))), r"^mean must be a 1-D array, got shape \(2, 2\)$"),
    (dict(mean=[0.0, np.nan]), r"^mean must be finite"),
    (dict(cov=np.eye(3)), r"^cov must be 2x2, got shape \(3, 3\)$"),
    (dict(H=[1.0, 0.0]), r"^H must be a 2-D array, got shape \(2,\)$"),
    (dict(H=[[np.inf, 0.0]]), r"^H must be finite"),
    (dict(R=[[-1.0]]), r"^R must be positive definite"),
])
def test_gaussian_birth_term_names_the_bad_argument(kwargs, match):
    args = dict(mean=[0.0, 0.0], cov=np.eye(2), H=[[1.0, 0.0]], R=[[0.5]])
    with pytest.raises(ValueError, match=match):
        GaussianBirthTerm(**{**args, **kwargs})


def test_gibbs_buffers_grow_when_every_sweep_is_a_new_sample():
    """12 objects with flat conditionals: every sweep visits a new map, so the visited set fills
    its first buffer (4096) one sweep before the end and must grow to take the last sample."""
    rng = np.random.default_rng(0)
    P, m = 12, 12
    problem = AssociationProblem(rng.normal(scale=0.1, size=(P, m)), np.zeros((P, 2)), m, np.zeros((m + 1, 1)))
    events, lw = gibbs_search(problem, 4096, seed=3)
    assert len(events) == 4097 and len({e.tobytes() for e in events}) == 4097
    np.testing.assert_array_equal(lw, problem.log_weights(events))
    short, _ = gibbs_search(problem, 100, seed=3)
    np.testing.assert_array_equal(short, events[:101])  # a longer run extends the same chain
    assert GibbsGenerator(n_sweeps=1).n_sweeps == 1
    with pytest.raises(ValueError, match=r"^n_sweeps must be an integer in \[1, inf\], got -2$"):
        GibbsGenerator(n_sweeps=-2)


def test_zero_survival_risk_and_out_of_view_objects_raise_no_warning():
    """p_S = 1 (log(1 − p_S) = −inf) and an object out of view (log p_D = −inf) are exact
    impossibilities, computed without a floating-point warning."""
    pop = LabeledMultiBernoulliPopulation([BIRTH], r_birth=0.2, p_survive=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        log_r, log_not = pop.log_existence(2)
        ch = _filter(pop).expand(Z)
    assert log_not[0] == -np.inf and log_r[0] == 0.0
    assert not any(int(a) & 0b111 for a in ch.arg)  # no track died


def test_labeled_problem_of_a_parent_without_tracks_and_its_messages():
    pop = _population(0.9, 0.2, births=2)
    f = _filter(pop, n=0)
    ctx = f.scan_context(f.store.predict(MOTION, 1.0), Z)
    log_r, log_not = pop.log_existence(0)
    problem = GLMBWeights().labeled_problem(ctx, [], log_r, log_not)
    assert problem.n_returns == 2 and problem.n_objects == 3  # rows: the two birth terms
    np.testing.assert_allclose(problem.option_scores[:, 1], np.log([0.8, 0.8]), atol=1e-15)
    dead = ScanContext(Z=Z, loglik=np.zeros((3, 0)), allowed=np.ones((3, 0), bool), p_detect=np.zeros(0),
                       birth_loglik=np.zeros((3, 2)), p_detect_birth=0.9, clutter_rate=0.0, clutter_volume=4.0)
    with pytest.raises(ValueError, match=r"^clutter intensity must be a finite number > 0, got 0.0$"):
        GLMBWeights().labeled_problem(dead, [], log_r, log_not)
    with pytest.raises(ValueError, match=r"^clutter_intensity must be a finite number > 0, got -1.0$"):
        GLMBWeights(clutter_intensity=-1.0)
    with pytest.raises(ValueError, match=r"^r_birth must lie in \(0, 1\), got "):
        LabeledMultiBernoulliPopulation([BIRTH], r_birth=1.0)
    with pytest.raises(ValueError, match=r"^p_survive must lie in \(0, 1\], got 0.0$"):
        LabeledMultiBernoulliPopulation([BIRTH], r_birth=0.5, p_survive=0.0)


def test_glmb_step_stats_and_the_sampled_cap():
    pop = _population(0.7, 0.3)
    want = oracle_children(0.7, 0.3)
    f = _filter(pop)
    f.step(Z)
    st = f.last_stats
    assert st["n_association_children"] == len(want) and st["n_twin_children"] == 0
    assert st["log_mass_generated"] == pytest.approx(np.logaddexp.reduce(list(want.values())), abs=1e-10)
    keys = list(want)
    lw = np.array([want[k] for k in keys])
    p = np.exp(lw - np.logaddexp.reduce(lw))
    counts, n = dict.fromkeys(keys, 0), 120
    for seed in range(n):
        g = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=pop, max_hypotheses=1,
                             cap="sample", means=X0, covs=P0, seed=seed)
        g.step(Z)
        (key,) = engine_children(g.last_kept)
        counts[key] += 1
    for i in np.argsort(-p)[:2]:  # 45 % and 19 % of the mass
        assert counts[keys[i]] / n == pytest.approx(p[i], abs=4 * np.sqrt(p[i] * (1 - p[i]) / n))

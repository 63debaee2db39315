"""Property tests of the hypothesis engine on random small problems (hypothesis library)."""

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import logsumexp

from hypotrack.hypotheses import AssociationProblem, ExhaustiveGenerator, MCMCGenerator, hfisst
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor


@st.composite
def problems(draw):
    m = draw(st.integers(0, 4))
    n_obj = draw(st.integers(0, 3))
    n_birth = draw(st.integers(0, 2))
    n_opt = draw(st.integers(1, 2))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    target = rng.normal(size=(m, n_obj + n_birth))
    target[rng.random(target.shape) < 0.3] = -np.inf
    options = rng.normal(size=(m, n_opt))
    phi = rng.normal(size=(n_obj + 1, n_birth + 1))
    if n_birth:
        phi[:, 2:] = -np.inf
    return AssociationProblem(target, options, n_obj, phi, constant=float(rng.normal()))


def brute_force(problem):
    C, T, m = problem.n_exclusive, problem.n_options, problem.n_returns
    choices = list(range(C)) + [-1 - t for t in range(T)]
    events, weights = [], []
    for a in itertools.product(choices, repeat=m):
        excl = [x for x in a if x >= 0]
        if len(set(excl)) != len(excl):
            continue
        k = sum(x < problem.n_objects for x in excl)
        b = len(excl) - k
        w = problem.constant + problem.count_term[k, b]
        w += sum(problem.target_scores[i, x] if x >= 0 else problem.option_scores[i, -1 - x] for i, x in enumerate(a))
        if np.isfinite(w):
            events.append(a)
            weights.append(w)
    return {tuple(e): w for e, w in zip(events, weights)}


@settings(max_examples=60, deadline=None)
@given(problems())
def test_exhaustive_generator_equals_brute_force(problem):
    oracle = brute_force(problem)
    ev, lw = ExhaustiveGenerator().generate(problem)
    got = {tuple(int(x) for x in e): w for e, w in zip(ev, lw)}
    assert got.keys() == oracle.keys()
    for key, w in oracle.items():
        assert abs(got[key] - w) < 1e-10


@settings(max_examples=30, deadline=None)
@given(problems(), st.integers(1, 5))
def test_keep_returns_the_best_and_mcmc_is_a_subset(problem, keep):
    oracle = brute_force(problem)
    ev, lw = ExhaustiveGenerator(chunk_size=3).generate(problem, keep=keep)
    best = sorted(oracle.values(), reverse=True)[:keep]
    np.testing.assert_allclose(lw, best, atol=1e-10)
    mev, mlw = MCMCGenerator(n_steps=2000).generate(problem, np.random.default_rng(0))
    for e, w in zip(mev, mlw):
        assert abs(oracle[tuple(int(x) for x in e)] - w) < 1e-10


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, 3), st.integers(1, 6))
def test_filter_invariants(seed, n_objects, cap):
    rng = np.random.default_rng(seed)
    region = Box([0.0, 0.0], [30.0, 30.0])
    sensor = position_sensor(1.0, 0.8, region, 1.0)
    X = np.hstack([region.sample_uniform(n_objects, rng), rng.normal(size=(n_objects, 2))])
    f = hfisst(ConstantVelocity(0.1), sensor, max_hypotheses=cap, means=X, covs=np.repeat(np.eye(4)[None], n_objects, 0))
    for _ in range(3):
        X = X @ ConstantVelocity(0.1).F(1.0).T
        post = f.step(sensor.observe(X, rng)[0])
        assert 1 <= len(post.log_weights) <= cap
        assert abs(logsumexp(post.log_weights)) < 1e-12
        assert np.all(np.diff(post.log_weights) <= 0)
        assert abs(post.cardinality.sum() - 1) < 1e-12
        assert np.all(post.n_objects == n_objects)  # no population model: the count is fixed

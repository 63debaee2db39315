"""The Gibbs sampler of the δ-GLMB filter (Vo, Vo & Hoang 2017) against exhaustive enumeration.

On random small δ-GLMB association problems (objects with per-object survival, a birth term,
clutter): every Gibbs child is an exhaustive child with the same exact weight; given enough sweeps
Gibbs finds every child above 10⁻⁶ of the mass; Murty's ranked assignment returns exactly the
exhaustive top k.
"""

import dataclasses

import numpy as np
import pytest

from hypotrack.hypotheses import ExhaustiveGenerator, GibbsGenerator, GLMBWeights, MurtyGenerator
from hypotrack.hypotheses.problems import synthetic_problem


def glmb_problem(seed, n_objects=3, n_returns=4, p_survive=0.95, r_birth=0.1, spacing=2.0):
    rng = np.random.default_rng(seed)
    ctx = synthetic_problem(n_objects, n_returns, rng, weights="reid", p_D=0.9, clutter_rate=1.0,
                            spacing=spacing).context
    # one birth term whose predicted return sits on a random return (so births compete)
    z0 = ctx.Z[rng.integers(n_returns)]
    d2 = np.sum((ctx.Z - z0) ** 2, axis=1) / 4.0
    ctx = dataclasses.replace(ctx, birth_loglik=(-0.5 * d2 - np.log(2 * np.pi * 4.0))[:, None])
    r = np.concatenate([np.full(n_objects, p_survive), [r_birth]])
    return GLMBWeights().labeled_problem(ctx, np.arange(n_objects), np.log(r), np.log1p(-r), 0.0)


def by_event(events, lw):
    return {e.tobytes(): w for e, w in zip(np.asarray(events), lw)}


@pytest.mark.parametrize("seed", range(4))
def test_gibbs_children_are_exhaustive_children_with_exact_weights(seed):
    problem = glmb_problem(seed)
    exact = by_event(*ExhaustiveGenerator().generate(problem))
    gibbs = by_event(*GibbsGenerator(n_sweeps=300).generate(problem, np.random.default_rng(seed)))
    assert len(gibbs) > 10
    assert set(gibbs) <= set(exact)
    for key, w in gibbs.items():
        assert w == exact[key]


@pytest.mark.parametrize("seed", range(3))
def test_gibbs_finds_every_child_above_1e6_of_the_mass(seed):
    problem = glmb_problem(100 + seed, n_objects=3, n_returns=3)
    events, lw = ExhaustiveGenerator().generate(problem)
    p = np.exp(lw - np.logaddexp.reduce(lw))
    wanted = {e.tobytes() for e, q in zip(events, p) if q > 1e-6}
    found = by_event(*GibbsGenerator(n_sweeps=3_000_000).generate(problem, np.random.default_rng(seed)))
    assert len(wanted) >= 30  # light children exist: the check is not about the few heavy ones
    assert wanted <= set(found)


@pytest.mark.parametrize("seed", range(3))
def test_murty_on_the_glmb_matrix_is_the_exhaustive_top_k(seed):
    problem = glmb_problem(200 + seed)
    ev, lw = ExhaustiveGenerator().generate(problem)
    order = np.argsort(-lw, kind="stable")[:25]
    mev, mlw = MurtyGenerator(k=25).generate(problem)
    np.testing.assert_allclose(mlw, lw[order], rtol=0, atol=1e-10)
    assert set(by_event(mev, mlw)) <= set(by_event(ev, lw))

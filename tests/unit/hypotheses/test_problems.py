"""Synthetic Fig. 15 problems, truth ranking and the generation-time driver."""

import numpy as np
import pytest

from hypotrack.association import count_associations
from hypotrack.experiments.generation_time.run import generation_time_point
from hypotrack.hypotheses import ExhaustiveGenerator
from hypotrack.hypotheses.problems import synthetic_problem, truth_rank

PARAMS = dict(exhaustive_max_events=10**4, exhaustive_chunk_size=1 << 10, mcmc_steps=20_000, mcmc_burn_in=2000,
              mcmc_variant="paper", mcmc_init="random", mcmc_completion_rounds=0, keep=20, repeats=1, p_D=0.95,
              clutter_rate=1.0, spacing=8.0)


@pytest.mark.parametrize("M, m", [(0, 3), (3, 0), (4, 4), (6, 3), (2, 5)])
def test_synthetic_problem_truth(M, m):
    sp = synthetic_problem(M, m, np.random.default_rng(M * 10 + m), weights="hfisst")
    assert sp.truth.shape == (m,) and sp.problem.n_returns == m and sp.problem.n_objects == M
    assert np.sum(sp.truth >= 0) == min(M, m)  # min(M, m) detections, the rest clutter
    ev, lw = ExhaustiveGenerator().generate(sp.problem)
    assert len(ev) == count_associations(M, m)
    assert truth_rank(ev, lw, sp.truth) is not None
    if m <= M:  # well separated objects and no clutter: the true association is the heaviest child
        assert truth_rank(ev, lw, sp.truth) == 1
        assert np.all(ev[np.argmax(lw)] == sp.truth)


def test_truth_rank():
    events = np.array([[0, 1], [1, 0], [-1, -1]])
    lw = np.array([-1.0, -0.5, -1.0])
    assert truth_rank(events, lw, [1, 0]) == 1
    assert truth_rank(events, lw, [0, 1]) == 2
    assert truth_rank(events, lw, [-1, -1]) == 3  # tie with an earlier child counts against it
    assert truth_rank(events, lw, [0, -1]) is None


def test_generation_time_point_rows():
    ok = generation_time_point("homht", 4, 4, PARAMS, seed=1)
    assert not ok["broken"] and ok["truth_found"] and ok["truth_rank"] == 1 and ok["n_generated"] == 20
    broken = generation_time_point("homht", 7, 7, PARAMS, seed=1)  # A(7,7) = 130922 > 1e4
    assert broken["broken"] and np.isnan(broken["seconds"]) and not broken["truth_found"]
    mc = generation_time_point("rfisst", 12, 12, PARAMS, seed=1)
    assert mc["map_is_truth"] and mc["log10_hypotheses"] == pytest.approx(np.log10(count_associations(12, 12)))
    kb = generation_time_point("homht_kbest", 12, 12, PARAMS, seed=1)
    assert kb["map_is_truth"] and kb["n_generated"] == 20


def test_paper_difficulty_is_the_default_problem():
    a = synthetic_problem(5, 4, np.random.default_rng(3))
    b = synthetic_problem(5, 4, seed=3, difficulty="paper")
    assert np.array_equal(a.truth, b.truth) and np.array_equal(a.problem.score, b.problem.score)


@pytest.mark.parametrize("difficulty", ["1sigma", "2sigma", "4sigma", "8sigma"])
def test_ambiguous_difficulties(difficulty):
    M = 20
    draws = [synthetic_problem(M, difficulty=difficulty, seed=s) for s in range(40)]
    m = np.array([d.problem.n_returns for d in draws])
    assert (m > M).any() and (m < M).any()  # clutter-rich and miss-rich problems both occur
    for d in draws:
        det = d.truth[d.truth >= 0]
        assert len(np.unique(det)) == len(det) and d.problem.n_objects == M
    missed = M - np.array([np.sum(d.truth >= 0) for d in draws])
    assert 0.05 < missed.mean() / M < 0.15  # p_D = 0.9
    clutter = np.array([np.sum(d.truth < 0) for d in draws])
    assert 1.0 < clutter.mean() < 3.5  # Poisson mean max(1, 0.1 M) = 2
    again = synthetic_problem(M, difficulty=difficulty, seed=0)
    assert np.array_equal(again.problem.score, draws[0].problem.score)  # seeded, deterministic


def test_spacing_sets_ambiguity():
    """At 1 sigma a detection is often more likely under a wrong object; at 8 sigma rarely."""
    def confusable(difficulty):
        n = 0
        for s in range(10):
            sp = synthetic_problem(16, difficulty=difficulty, seed=s)
            t = sp.truth
            for i in np.flatnonzero(t >= 0):
                n += int(np.argmax(sp.context.loglik[i]) != t[i])
        return n
    assert confusable("1sigma") > 5 * max(confusable("8sigma"), 1)


def test_synthetic_problem_bad_input():
    with pytest.raises(ValueError, match="difficulty"):
        synthetic_problem(3, difficulty="3sigma", seed=0)
    with pytest.raises(ValueError, match="n_returns"):
        synthetic_problem(3, 3, difficulty="4sigma", seed=0)
    with pytest.raises(ValueError, match="n_returns"):
        synthetic_problem(3, seed=0)
    with pytest.raises(ValueError, match="exactly one"):
        synthetic_problem(3, 3)
    empty = synthetic_problem(0, difficulty="2sigma", seed=0)
    assert empty.problem.n_objects == 0 and np.all(empty.truth == -1)


@pytest.mark.parametrize("completion_rounds", [0, 2])
def test_mcmc_generator_is_the_public_search(completion_rounds):
    """The generator's per-parent path (problem validated once, no re-check of its options) gives
    the events and weights of the public ``mcmc_search`` with the same starting event and seed."""
    from hypotrack.association.mcmc import mcmc_search
    from hypotrack.hypotheses import MCMCGenerator

    problem = synthetic_problem(6, 5, seed=3, spacing=1.0).problem  # ambiguous: many children
    gen = MCMCGenerator(n_steps=3000, completion_rounds=completion_rounds)
    ev, lw = gen.generate(problem, np.random.default_rng(9))
    rng = np.random.default_rng(9)
    init = gen._initial_event(problem, rng)
    ev2, lw2 = mcmc_search(problem.score, problem.n_objects, problem.n_exclusive, problem.count_term,
                           n_steps=3000, burn_in=300, seed=int(rng.integers(2**63 - 1)), init=init,
                           completion_rounds=completion_rounds)
    order = np.argsort(-(lw2 + problem.constant), kind="stable")
    assert len(ev) > 5
    np.testing.assert_array_equal(ev, ev2[order])
    np.testing.assert_array_equal(lw, lw2[order] + problem.constant)

"""The neighbour completion's memory bound (:func:`hypotrack.association.samplers.chain._complete`): on brute-force
problems (5 returns, 5 objects, every event enumerated) whose completion finds 200-1,500 events, a bound of 20, 50
or 200 events is never exceeded; what is held is a subset of the unbounded completion's events with their weights
(to rounding; brute-force weights to 1e-12), the mode first, and holds every event the unbounded completion finds
when run at the final threshold from the start (the heaviest: the lightest went); with a bound it does not reach,
the result is the unbounded one exactly. Through the search and the generator: the chain plus a bounded completion
holds at most the bound and a subset of the unbounded search's events; the generator's memory budget is the
bound (:func:`completion_limit`, hand-computed); rows are int32; bad bounds are refused by name."""

import itertools

import numpy as np
import pytest

from hypotrack.association.mcmc import event_log_weights, mcmc_search, neighbour_completion
from hypotrack.association.samplers import Visited, completion_limit
from hypotrack.hypotheses.association_problem import AssociationProblem
from hypotrack.hypotheses.generators import MCMCGenerator


def _brute(m, n_excl):
    opts = list(range(n_excl)) + [-1]
    rows = [a for a in itertools.product(opts, repeat=m) if len({x for x in a if x >= 0}) == sum(x >= 0 for x in a)]
    return np.array(rows, dtype=np.int64)


def _problem(seed, m=5, n_obj=5):
    rng = np.random.default_rng(seed)
    score = rng.normal(scale=1.5, size=(m, n_obj + 1))  # near-flat: many events within 1e-6 of the best
    return score, n_obj, np.zeros((n_obj + 1, 1))


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("rounds", [2, 3, 10])
def test_a_bounded_completion_holds_the_heaviest_found_within_the_bound(seed, rounds):
    score, n_obj, phi = _problem(seed)
    every = _brute(5, n_obj)
    lw_all = event_log_weights(score, n_obj, n_obj, phi, every)
    exact = {tuple(e): w for e, w in zip(every, lw_all)}
    mode, lw0 = every[np.argmax(lw_all)], lw_all.max()

    def complete(tau=1e-6, bound=None):
        return neighbour_completion(score, n_obj, n_obj, phi, mode[None], np.array([lw0]), rounds=rounds,
                                    relative_threshold=tau, max_events=bound)

    full_ev, full_lw = complete()
    full = {tuple(e): w for e, w in zip(full_ev, full_lw)}
    for bound in (20, 50, 200):
        ev, lw = complete(bound=bound)
        if len(full_lw) <= bound:  # not reached: the unbounded result, exactly
            np.testing.assert_array_equal(ev, full_ev)
            np.testing.assert_array_equal(lw, full_lw)
            continue
        held = [tuple(e) for e in ev]
        assert len(held) <= bound and len(set(held)) == len(held) and held[0] == tuple(mode)
        assert set(held) <= set(full)
        np.testing.assert_allclose(lw, [full[e] for e in held], rtol=0, atol=1e-12)
        np.testing.assert_allclose(lw, [exact[e] for e in held], rtol=0, atol=1e-12)
        # the completion run at the final threshold from the start: all of it held (the lightest went, not these)
        at_final = complete(tau=np.exp(lw.min() - lw0 + 1e-12))[0]
        assert {tuple(e) for e in at_final} <= set(held)
        assert min(full_lw) < lw.min()  # the bound cut: lighter events of the unbounded run are not held


def test_the_bound_through_the_search_and_the_generator():
    score, n_obj, phi = _problem(3, m=6, n_obj=6)
    kw = dict(n_steps=3000, seed=5, completion_rounds=3, completion_threshold=1e-6)
    ev, lw = mcmc_search(score, n_obj, n_obj, phi, **kw)
    ev_b, lw_b = mcmc_search(score, n_obj, n_obj, phi, completion_max_events=100, **kw)
    assert len(lw) > 100 >= len(lw_b) and {tuple(e) for e in ev_b} <= {tuple(e) for e in ev}
    np.testing.assert_allclose(lw_b, event_log_weights(score, n_obj, n_obj, phi, ev_b), atol=1e-12)
    assert lw_b.max() == lw.max()
    same = mcmc_search(score, n_obj, n_obj, phi, completion_max_events=len(lw), **kw)
    np.testing.assert_array_equal(same[0], ev)
    np.testing.assert_array_equal(same[1], lw)
    # the generator: its memory budget in MiB is the bound; the default (2 GiB) is not reached here
    problem = AssociationProblem(score[:, :n_obj], score[:, n_obj:], n_obj, np.zeros((n_obj + 1, 1)))
    big = MCMCGenerator(n_steps=3000, completion_rounds=3, completion_threshold=1e-6)
    tiny = MCMCGenerator(n_steps=3000, completion_rounds=3, completion_threshold=1e-6,
                         completion_memory_mb=100 * (4 * 6 + 32) / 2**20)
    e_big, w_big = big.generate(problem, 7)
    e_tiny, w_tiny = tiny.generate(problem, 7)
    assert len(w_big) > 100 >= len(w_tiny) and {tuple(e) for e in e_tiny} <= {tuple(e) for e in e_big}
    assert completion_limit(6, 100 * 56 / 2**20) == 100


def test_completion_limit_rows_and_bad_bounds():
    assert completion_limit(100, 1.0) == 2**20 // 432 == 2427  # 4 m + 32 bytes an event
    assert completion_limit(0, 1.0) == 2**20 // 32 and completion_limit(10**6, 1.0) == 2  # at least two
    assert Visited(4, 6, 10).rows.dtype == np.int32
    score, n_obj, phi = _problem(0)
    with pytest.raises(ValueError, match="completion_max_events"):
        mcmc_search(score, n_obj, n_obj, phi, n_steps=10, seed=0, completion_rounds=1, completion_max_events=0)
    with pytest.raises(ValueError, match="max_events"):
        neighbour_completion(score, n_obj, n_obj, phi, np.full((1, 5), -1), np.zeros(1), max_events=0)
    with pytest.raises(ValueError, match="completion_memory_mb"):
        MCMCGenerator(completion_memory_mb=0.0)
    with pytest.raises(ValueError, match="memory_mb"):
        completion_limit(5, -1.0)

"""The completion's ``keep`` (:func:`hypotrack.association.samplers.chain._complete`): its last round holds only the
events that can be among the ``keep`` heaviest, and what it returns is exactly the ``keep`` heaviest of the search
without ``keep``.

Brute-force problems (5 returns, 4 objects and 2 birth columns, at most one birth, a count term in ``k`` and ``b``,
some pairs gated out, clutter always possible) where the unbounded completion finds far more than ``keep`` events:
the events and weights returned with ``keep`` are those of :func:`top_k_first` of the unbounded result, bit for bit,
for 1-3 rounds and ``keep`` 1-40, also with two objects of identical scores (exact ties at the ``keep``-th weight,
kept the first visited); their weights are the brute-force weights (1e-12) and the ``keep`` heaviest of every event
above the threshold that the completion reaches. Through the MCMC search and the generator the same holds; on a
problem whose unbounded completion holds ~10⁵ events the ``keep`` search allocates a small fraction of the memory
(tracemalloc). The int32 conversion; the budget counting the copy
returned (hand-computed); bad ``keep`` refused by name. :func:`top_k_first` itself: test_selection.py."""

import itertools
import tracemalloc

import numpy as np
import pytest

from hypotrack.association.mcmc import event_log_weights, mcmc_search, neighbour_completion
from hypotrack.association.samplers import completion_limit, to_events, top_k_first
from hypotrack.hypotheses.association_problem import AssociationProblem
from hypotrack.hypotheses.generators import MCMCGenerator, top_k

N_OBJ, N_BIRTH = 4, 2
N_EXCL = N_OBJ + N_BIRTH


def _problem(seed, m=5, tie=False):
    """Scores (m, 4 objects + 2 births + clutter): near-flat (many events within 1e-6 of the best), about a fifth
    of the (return, object) pairs gated out, births lighter; a count term of the detections ``k`` and the births
    ``b`` (two births forbidden). ``tie``: objects 0 and 1 score the same for every return."""
    rng = np.random.default_rng(seed)
    score = rng.normal(scale=1.2, size=(m, N_EXCL + 1))
    score[:, N_OBJ:N_EXCL] -= 1.0
    gated = rng.random((m, N_OBJ)) < 0.2
    score[:, :N_OBJ][gated] = -np.inf
    if tie:
        score[:, 1] = score[:, 0]
    k, b = np.meshgrid(np.arange(N_OBJ + 1), np.arange(N_BIRTH + 1), indexing="ij")
    phi = -0.3 * k + 0.5 * b - 0.1 * k * b
    phi[:, 2:] = -np.inf
    return score, phi


def _brute(m):
    opts = list(range(N_EXCL)) + [-1]
    rows = [a for a in itertools.product(opts, repeat=m) if len({x for x in a if x >= 0}) == sum(x >= 0 for x in a)]
    return np.array(rows, dtype=np.int64)


@pytest.mark.parametrize("tie", [False, True])
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("rounds", [1, 2, 3])
def test_keep_returns_the_keep_heaviest_of_the_unbounded_completion(seed, rounds, tie):
    """(seed 3, 2 rounds, tie: the start event and its twin weigh one rounding apart, 7.67984562613123 and
    7.679845626131229, at the 2nd weight; the twin met first from a lighter path must not stand in for it.)"""
    score, phi = _problem(seed, tie=tie)
    every = _brute(5)
    lw_all = event_log_weights(score, N_OBJ, N_EXCL, phi, every)
    exact = {tuple(e): w for e, w in zip(every, lw_all)}
    start = every[np.argsort(-lw_all, kind="stable")[3]][None]  # not the mode: the rounds have something to find
    lw0 = lw_all[np.argsort(-lw_all, kind="stable")[3]][None]
    kw = dict(rounds=rounds, relative_threshold=1e-6)
    full_ev, full_lw = neighbour_completion(score, N_OBJ, N_EXCL, phi, start, lw0, **kw)
    assert len(full_lw) > (10 if rounds == 1 else 80)  # keep binds (40: not with one round)
    for keep in (1, 2, 7, 40):
        ev, lw = neighbour_completion(score, N_OBJ, N_EXCL, phi, start, lw0, keep=keep, **kw)
        sel = top_k_first(full_lw, keep)
        np.testing.assert_array_equal(ev, full_ev[sel])
        np.testing.assert_array_equal(lw, full_lw[sel])
        assert ev.dtype == np.int32 and len(lw) == min(keep, len(full_lw)) and np.all(np.diff(lw) <= 0)
        np.testing.assert_allclose(lw, [exact[tuple(e)] for e in ev], rtol=0, atol=1e-12)


def test_ties_at_the_keep_th_weight_occur_and_keep_the_first_found():
    """With two objects of identical scores, events that swap them tie exactly; at some ``keep`` the tie straddles
    the ``keep``-th weight, and the first found are returned (the same as from the unbounded completion)."""
    straddled = 0
    for seed in range(6):
        score, phi = _problem(seed, tie=True)
        every = _brute(5)
        lw_all = event_log_weights(score, N_OBJ, N_EXCL, phi, every)
        i0 = int(np.argmax(lw_all))
        full_ev, full_lw = neighbour_completion(score, N_OBJ, N_EXCL, phi, every[i0][None], lw_all[i0][None],
                                                rounds=2, relative_threshold=1e-6)
        order = np.sort(full_lw)[::-1]
        for keep in range(1, 30):
            if order[keep - 1] != order[keep]:
                continue
            straddled += 1
            ev, lw = neighbour_completion(score, N_OBJ, N_EXCL, phi, every[i0][None], lw_all[i0][None], rounds=2,
                                          relative_threshold=1e-6, keep=keep)
            tied = np.flatnonzero(full_lw == order[keep - 1])
            n_tied_kept = int(np.sum(lw == order[keep - 1]))
            got = {tuple(e) for e in ev[lw == order[keep - 1]]}
            assert got == {tuple(e) for e in full_ev[tied[:n_tied_kept]]}  # the first found of the tied
            assert n_tied_kept < len(tied)
    assert straddled >= 3


@pytest.mark.parametrize("seed", range(4))
def test_the_search_and_the_generator_with_keep_equal_the_keep_heaviest_without(seed):
    score, phi = _problem(seed, m=6)
    kw = dict(n_steps=400, seed=11 + seed, completion_rounds=2, completion_threshold=1e-6)
    ev, lw = mcmc_search(score, N_OBJ, N_EXCL, phi, **kw)
    assert len(lw) > 100
    for keep in (1, 5, 30):
        ev_k, lw_k = mcmc_search(score, N_OBJ, N_EXCL, phi, keep=keep, **kw)
        sel = top_k_first(lw, keep)
        np.testing.assert_array_equal(ev_k, ev[sel])
        np.testing.assert_array_equal(lw_k, lw[sel])
    # the generator: keep is the filter's cap; with distinct weights the old selection (top_k) is the same
    problem = AssociationProblem(score[:, :N_EXCL], score[:, N_EXCL:], N_OBJ, phi, constant=-3.25)
    gen = MCMCGenerator(n_steps=400, completion_rounds=2, completion_threshold=1e-6)
    e_all, w_all = gen.generate(problem, 5)
    assert len(np.unique(w_all)) == len(w_all)
    for keep in (1, 5, 30):
        e_k, w_k = gen.generate(problem, 5, keep=keep)
        sel = top_k(w_all, keep)
        np.testing.assert_array_equal(e_k, e_all[sel])
        np.testing.assert_array_equal(w_k, w_all[sel])
        np.testing.assert_allclose(w_k, problem.log_weights(e_k), rtol=0, atol=1e-12)


def _wide_problem(m=14):
    """m returns, m objects (each return gates 4 of them), no births: a flat problem whose completion near the
    mode holds ~10⁵ events."""
    rng = np.random.default_rng(3)
    score = np.full((m, m + 1), -np.inf)
    for i in range(m):
        score[i, (i + np.arange(4)) % m] = rng.normal(scale=0.5, size=4)
    score[:, m] = rng.normal(scale=0.5, size=m) - 0.5
    return score, np.zeros((m + 1, 1))


def _peak(f):
    tracemalloc.start()
    try:
        out = f()
        return out, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_keep_holds_a_fraction_of_the_memory_and_the_same_result():
    score, phi = _wide_problem()
    m = score.shape[0]
    kw = dict(n_steps=200, seed=2, completion_rounds=3, completion_threshold=1e-6)
    (ev, lw), peak_all = _peak(lambda: mcmc_search(score, m, m, phi, **kw))
    (ev_k, lw_k), peak_keep = _peak(lambda: mcmc_search(score, m, m, phi, keep=20, **kw))
    assert len(lw) > 50_000
    sel = top_k_first(lw, 20)
    np.testing.assert_array_equal(ev_k, ev[sel])
    np.testing.assert_array_equal(lw_k, lw[sel])
    assert peak_keep < peak_all / 4


def test_to_events_converts_in_int32_and_the_budget_counts_the_copy_returned():
    states = np.array([[0, 2, 3, 1], [3, 3, 2, 0]], dtype=np.int32)
    for st in (states, states.astype(np.int64)):
        ev = to_events(st, 2)
        assert ev.dtype == np.int32 and ev.tolist() == [[0, -1, -2, 1], [-2, -2, -1, 0]]
    assert states.tolist() == [[0, 2, 3, 1], [3, 3, 2, 0]]  # the input untouched
    assert completion_limit(100, 1.0) == 2**20 // 432 == 2427
    assert completion_limit(100, 1.0, returned=True) == 2**20 // (432 + 408) == 1248


@pytest.mark.parametrize("keep", [0, -3, 2.5])
def test_bad_keep_is_refused_by_name(keep):
    score, phi = _problem(0)
    with pytest.raises((ValueError, TypeError), match="keep"):
        mcmc_search(score, N_OBJ, N_EXCL, phi, n_steps=10, seed=0, keep=keep)
    with pytest.raises((ValueError, TypeError), match="keep"):
        neighbour_completion(score, N_OBJ, N_EXCL, phi, np.full((1, 5), -1), np.zeros(1), keep=keep)

"""Best / k-best assignments against brute-force permutation and event-enumeration oracles."""

import itertools

import numpy as np
import pytest

from hypotrack.association import (
    association_score_matrix,
    best_assignment,
    columns_to_event,
    enumerate_associations,
    k_best_events,
    murty_k_best,
)


def brute_force_totals(score):
    """Totals of every feasible assignment (distinct columns, no -inf entry), best first."""
    m, N = score.shape
    totals = []
    for perm in itertools.permutations(range(N), m):
        t = score[np.arange(m), list(perm)].sum()
        if np.isfinite(t):
            totals.append(t)
    return sorted(totals, reverse=True)


def event_scores(events, target_scores, clutter_scores):
    """Score every event row: Σ target score of assigned returns + Σ clutter score of the rest."""
    a = events.astype(int)
    rows = np.arange(a.shape[1])
    ext = np.concatenate([target_scores, clutter_scores[:, None]], axis=1)  # last column = clutter
    return ext[rows, np.where(a >= 0, a, target_scores.shape[1])].sum(axis=1)


def random_score(rng, m, N, p_forbid=0.3):
    score = rng.normal(size=(m, N))
    score[rng.random((m, N)) < p_forbid] = -np.inf
    return score


def test_best_assignment_matches_brute_force():
    rng = np.random.default_rng(0)
    checked = 0
    for _ in range(200):
        m = int(rng.integers(1, 5))
        score = random_score(rng, m, int(rng.integers(m, 7)))
        totals = brute_force_totals(score)
        if not totals:
            with pytest.raises(ValueError, match="no feasible assignment"):
                best_assignment(score)
            continue
        total, cols = best_assignment(score)
        assert total == pytest.approx(totals[0])
        assert len(set(cols.tolist())) == m
        assert score[np.arange(m), cols].sum() == pytest.approx(total)
        checked += 1
    assert checked > 100


def test_best_assignment_of_empty_problem():
    total, cols = best_assignment(np.zeros((0, 3)))
    assert total == 0.0 and cols.shape == (0,)


def test_murty_matches_brute_force_in_order():
    rng = np.random.default_rng(1)
    for _ in range(150):
        m = int(rng.integers(0, 5))
        score = random_score(rng, m, int(rng.integers(max(m, 1), 6)))
        totals = brute_force_totals(score)
        k = int(rng.integers(1, 40))
        ranked = murty_k_best(score, k)
        assert len(ranked) == min(k, len(totals))  # fewer than k when fewer exist
        np.testing.assert_allclose([t for t, _ in ranked], totals[:k], rtol=0, atol=1e-9)
        assert len({tuple(c.tolist()) for _, c in ranked}) == len(ranked)
        for t, cols in ranked:
            assert score[np.arange(m), cols].sum() == pytest.approx(t)


@pytest.mark.parametrize("seed", range(4))
def test_murty_on_independent_blocks_matches_scored_enumeration(seed):
    """A gated problem that falls into independent blocks — returns 0–2 share objects 0–1, returns
    3–4 share object 2, return 5 gates object 3 alone, return 6 gates nothing (clutter only) — is
    ranked per block and the block rankings combined: the k best totals and events equal those of
    every event scored exhaustively, for k cutting inside the product and beyond its size."""
    rng = np.random.default_rng(seed)
    allowed = np.zeros((7, 4), dtype=bool)
    allowed[:3, :2] = rng.random((3, 2)) < 0.8
    allowed[0, 0] = allowed[1, 1] = allowed[3, 2] = allowed[4, 2] = allowed[5, 3] = True
    ell = np.where(allowed, rng.normal(size=(7, 4)), -np.inf)
    clutter = rng.normal(-1.0, 0.5, size=7)
    events = enumerate_associations(4, 7, allowed=allowed)
    scores = event_scores(events, ell, clutter)
    order = np.argsort(-scores, kind="stable")
    matrix = association_score_matrix(ell, clutter)
    for k in (1, 7, 40, len(events) + 5):
        ranked = murty_k_best(matrix, k)
        assert len(ranked) == min(k, len(events))
        np.testing.assert_allclose([t for t, _ in ranked], scores[order][:k], rtol=0, atol=1e-12)
        got = {tuple(columns_to_event(c, 4).tolist()) for _, c in ranked}
        assert len(got) == len(ranked)
        assert got <= {tuple(e) for e in events.tolist()}
        for t, c in ranked:
            assert matrix[np.arange(7), c].sum() == pytest.approx(t, abs=1e-12)
        assert ranked[0][0] == best_assignment(matrix)[0]
    # a block with no allowed assignment makes the whole problem infeasible
    bad = matrix.copy()
    bad[6, :] = -np.inf
    assert murty_k_best(bad, 5) == []


def test_murty_edge_cases():
    assert murty_k_best(np.ones((2, 2)), 0) == []
    assert murty_k_best(np.full((2, 2), -np.inf), 5) == []
    # A 3x3 all-ones matrix has 3! = 6 assignments, all with total 3.
    ranked = murty_k_best(np.ones((3, 3)), 10)
    assert len(ranked) == 6 and all(t == 3 for t, _ in ranked)


def test_k_best_events_match_scored_enumeration_lecture_example():
    # Paper 004's assignment matrix: targets T1..T3 gated as in its validation matrix, one
    # external-source column per return (log β_EX on the diagonal).
    validation = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)
    rng = np.random.default_rng(2)
    ell = np.where(validation, rng.normal(size=(4, 3)), -np.inf)
    log_beta = np.full(4, np.log(0.3))
    matrix = association_score_matrix(ell, log_beta)
    assert matrix.shape == (4, 7)
    assert np.all(np.isneginf(matrix[:, 3:][~np.eye(4, dtype=bool)]))
    np.testing.assert_array_equal(np.diag(matrix[:, 3:]), log_beta)
    events = enumerate_associations(3, 4, allowed=validation)
    scores = event_scores(events, ell, log_beta)
    best = k_best_events(ell, log_beta, 100)
    assert len(best) == len(events) == 10
    np.testing.assert_allclose([s for s, _ in best], np.sort(scores)[::-1])
    for s, event in best:
        row = np.flatnonzero((events == event).all(axis=1))
        assert row.size == 1 and scores[row[0]] == pytest.approx(s)


def test_k_best_events_match_scored_enumeration_medium_problem():
    # 7 objects, 7 returns, light gating: ~10^5 events scored exhaustively as the oracle.
    rng = np.random.default_rng(3)
    allowed = rng.random((7, 7)) < 0.8
    ell = np.where(allowed, rng.normal(size=(7, 7)), -np.inf)
    clutter = rng.normal(-1.0, 0.5, size=7)
    scores = np.sort(event_scores(enumerate_associations(7, 7, allowed=allowed), ell, clutter))[::-1]
    best = k_best_events(ell, clutter, 60)
    np.testing.assert_allclose([s for s, _ in best], scores[:60], rtol=0, atol=1e-9)


def test_murty_large_problem_is_consistent():
    # The size the generation-time experiment needs: 67 returns against 67 objects + clutter.
    rng = np.random.default_rng(4)
    matrix = association_score_matrix(np.log(rng.random((67, 67))), np.full(67, np.log(0.05)))
    ranked = murty_k_best(matrix, 100)
    totals = np.array([t for t, _ in ranked])
    assert len(ranked) == 100
    assert totals[0] == pytest.approx(best_assignment(matrix)[0])
    assert np.all(np.diff(totals) <= 1e-12)
    assert len({tuple(c.tolist()) for _, c in ranked}) == 100


def test_columns_to_event():
    event = columns_to_event(np.array([2, 5, 0, 3]), 3)
    np.testing.assert_array_equal(event, [2, -1, 0, -1])
    assert event.dtype == np.int8
    assert columns_to_event(np.zeros(0, dtype=int), 3).shape == (0,)


@pytest.mark.parametrize(
    "score, match",
    [
        (np.array([[1.0, np.nan]]), "score"),
        (np.array([[1.0, np.inf]]), "score"),
        (np.ones((3, 2)), "score"),
        (np.ones(3), "score"),
    ],
)
def test_bad_score_matrices(score, match):
    with pytest.raises(ValueError, match=match):
        best_assignment(score)
    with pytest.raises(ValueError, match=match):
        murty_k_best(score, 3)


def test_bad_arguments():
    with pytest.raises(ValueError, match="k"):
        murty_k_best(np.ones((2, 2)), -1)
    with pytest.raises(TypeError, match="k"):
        murty_k_best(np.ones((2, 2)), 1.5)
    with pytest.raises(ValueError, match="clutter_scores"):
        association_score_matrix(np.ones((2, 3)), [0.0, np.nan])
    with pytest.raises(ValueError, match="target_scores"):
        association_score_matrix(np.ones((3, 3)), [0.0, 0.0])
    with pytest.raises(ValueError, match="target_scores"):
        association_score_matrix(np.array([[np.nan]]), [0.0])
    with pytest.raises(ValueError, match="cols"):
        columns_to_event(np.array([0.5]), 2)
    with pytest.raises(ValueError, match="cols"):
        columns_to_event(np.array([-1]), 2)
    with pytest.raises(ValueError, match="n_tracks"):
        columns_to_event(np.array([0]), -2)


def test_integer_scores_rank_like_floats():
    """Integer score matrices (e.g. counts) rank exactly like their float copies; Murty forbids
    entries by writing -inf, which needs a float working copy. 3 x 3, all six assignments:
    totals 15 (0,1,2); 11 (1,0,2) and (0,2,1); 7 (1,2,0), (2,0,1) and (2,1,0)."""
    score = np.array([[5, 3, 1], [3, 5, 3], [1, 3, 5]])
    assert best_assignment(score)[0] == 15.0
    ranked = murty_k_best(score, 6)
    assert [t for t, _ in ranked] == [15.0, 11.0, 11.0, 7.0, 7.0, 7.0]
    assert {tuple(c.tolist()) for _, c in ranked} == set(itertools.permutations(range(3)))
    assert [t for t, _ in ranked] == brute_force_totals(score.astype(float))


def test_messages_name_the_argument_and_the_rule():
    with pytest.raises(ValueError, match=r"^score must be a 2-D \(m, N\) array, got shape \(3,\)$"):
        best_assignment(np.ones(3))
    with pytest.raises(ValueError, match="^score admits no feasible assignment: every complete assignment "
                                         "uses a -inf entry$"):
        best_assignment(np.array([[0.0, -np.inf], [1.0, -np.inf]]))
    with pytest.raises(ValueError, match=r"^clutter_scores must be a 1-D array, got shape \(2, 1\)$"):
        association_score_matrix(np.ones((2, 3)), [[0.0], [0.0]])
    with pytest.raises(ValueError, match=r"^target_scores entries must be finite or -inf \(gated out\); "
                                         r"NaN and \+inf are not allowed$"):
        association_score_matrix(np.array([[np.nan]]), [0.0])
    with pytest.raises(ValueError, match="^cols must be non-negative column indices$"):
        columns_to_event(np.array([-1]), 2)
    with pytest.raises(ValueError, match=r"^n_tracks must be an integer in \[0, inf\], got -2$"):
        columns_to_event(np.array([0]), -2)
    with pytest.raises(ValueError, match=r"^n_tracks must be"):  # checked before the columns
        columns_to_event(np.array([-1]), -2)


def test_score_matrix_reads_exact_rationals_as_numbers():
    """target_scores given as Python fractions become the same float matrix."""
    from fractions import Fraction

    out = association_score_matrix([[Fraction(1, 2)], [Fraction(-3, 4)]], [0.25, -1.0])
    np.testing.assert_array_equal(out, [[0.5, 0.25, -np.inf], [-0.75, -np.inf, -1.0]])

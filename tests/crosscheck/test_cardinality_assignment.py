"""Exact per-cardinality MAP / k best (H-FISST count term) against exhaustive enumeration."""

import numpy as np
import pytest

from hypotrack.association import count_associations
from hypotrack.association.cardinality_assignment import cardinality_k_best, cardinality_map
from hypotrack.hypotheses.association_problem import AssociationProblem
from hypotrack.hypotheses.generators import ExhaustiveGenerator, MurtyGenerator, top_k
from hypotrack.hypotheses.problems import DIFFICULTIES, synthetic_problem


def _exhaustive_top(problem, k):
    ev, lw = ExhaustiveGenerator().generate(problem)
    sel = top_k(lw, k)
    return ev[sel], lw[sel]


def _same_ranking(ev_a, lw_a, ev_b, lw_b):
    assert len(lw_a) == len(lw_b)
    np.testing.assert_allclose(lw_a, lw_b, rtol=0, atol=1e-9)
    # same children: compare as sets (random scores, so no ties at the cut)
    assert {tuple(e) for e in ev_a} == {tuple(e) for e in ev_b}


def _random_problem(rng, M, B, m, gate=0.3, single_birth=True):
    """Random scores with gated-out pairs, birth columns and an arbitrary count term."""
    target = rng.normal(0.0, 2.0, size=(m, M + B))
    target[rng.random(target.shape) < gate] = -np.inf
    clutter = rng.normal(-1.0, 1.0, size=(m, 1))
    phi = rng.normal(0.0, 3.0, size=(M + 1, B + 1))
    if single_birth:
        phi[:, 2:] = -np.inf  # document 000's single-event model: at most one birth
    return AssociationProblem(target, clutter, M, phi, constant=float(rng.normal()))


@pytest.mark.parametrize("seed", range(25))
def test_k_best_equals_enumeration_with_births_and_gating(seed):
    rng = np.random.default_rng(seed)
    M, B, m = int(rng.integers(0, 5)), int(rng.integers(0, 3)), int(rng.integers(0, 6))
    p = _random_problem(rng, M, B, m)
    k = int(rng.integers(1, 40))
    gen = MurtyGenerator(k=k)
    ev, lw = gen.generate(p)
    ev_x, lw_x = _exhaustive_top(p, k)
    _same_ranking(ev, lw, ev_x, lw_x)
    np.testing.assert_allclose(p.log_weights(ev), lw, atol=1e-9)  # weights are the exact child weights


@pytest.mark.parametrize("difficulty", DIFFICULTIES[1:])
def test_k_best_equals_enumeration_on_difficulties(difficulty):
    for seed in range(12):
        sp = synthetic_problem(1 + seed % 6, difficulty=difficulty, seed=seed)
        ev, lw = MurtyGenerator(k=50).generate(sp.problem)
        _same_ranking(ev, lw, *_exhaustive_top(sp.problem, 50))


def test_all_children_when_k_exceeds_their_number():
    sp = synthetic_problem(4, 4, seed=5)  # paper problem, H-FISST weights: A(4, 4) = 209 children
    p = sp.problem
    ev, lw = cardinality_k_best(p.target_scores, p.option_scores[:, 0], p.n_objects, p.count_term, 10_000)
    assert len(ev) == count_associations(4, 4) == 209
    assert np.all(np.diff(lw) <= 1e-12)
    _same_ranking(ev, lw + p.constant, *_exhaustive_top(p, 10_000))


def test_equals_bounded_murty():
    """The previous exact path (rank separable totals until a bound proves the top k) agrees; it
    is reached by adding a second, impossible row option."""
    rng = np.random.default_rng(11)
    for M, m in [(3, 4), (5, 5), (6, 4)]:
        sp = synthetic_problem(M, m, rng, weights="hfisst", spacing=2.0)
        p = sp.problem
        legacy = AssociationProblem(p.target_scores, np.hstack([p.option_scores, np.full((m, 1), -np.inf)]),
                                    p.n_objects, p.count_term, p.constant)
        ev, lw = MurtyGenerator(k=15).generate(p)
        ev_l, lw_l = MurtyGenerator(k=15).generate(legacy)
        _same_ranking(ev, lw, ev_l, lw_l)


def test_map_hand_computed():
    """Two objects, two returns: scores favour detecting both, but the count term −log(C(m,n) n!)
    penalises n = 2 by log 2 more than n = 1; with these numbers the MAP has one detection."""
    target = np.array([[1.0, 0.2], [0.1, 0.3]])
    clutter = np.array([0.0, 0.0])
    phi = -np.log([[1.0], [2.0], [2.0]])  # C(2,n) n! = 1, 2, 2
    ev, lw = cardinality_map(target, clutter, 2, phi)
    # n = 0: 0; n = 1: best single pair 1.0 - log 2 = 0.307; n = 2: max(1.0+0.3, 0.2+0.1) - log 2 = 0.607
    assert lw == pytest.approx(1.3 - np.log(2.0))
    assert ev.tolist() == [0, 1]
    phi2 = -np.log([[1.0], [2.0], [20.0]])
    ev2, lw2 = cardinality_map(target, clutter, 2, phi2)
    assert lw2 == pytest.approx(1.0 - np.log(2.0)) and ev2.tolist() == [0, -1]


def test_empty_and_infeasible():
    ev, lw = cardinality_k_best(np.zeros((0, 3)), np.zeros(0), 3, np.zeros((4, 1)), 5)
    assert ev.shape == (1, 0) and lw.tolist() == [0.0]
    ev, lw = cardinality_k_best(np.zeros((2, 0)), np.array([-1.0, -2.0]), 0, np.zeros((1, 1)), 5)
    assert ev.tolist() == [[-1, -1]] and lw.tolist() == [-3.0]
    ev, lw = cardinality_k_best(np.zeros((2, 0)), np.array([-1.0, -2.0]), 0, np.full((1, 1), -np.inf), 5)
    assert ev.shape == (0, 2)
    assert cardinality_map(np.zeros((2, 0)), np.zeros(2), 0, np.full((1, 1), -np.inf)) == (None, -np.inf)


def test_bad_input():
    with pytest.raises(ValueError, match="count_term"):
        cardinality_k_best(np.zeros((2, 2)), np.zeros(2), 2, np.zeros((2, 1)), 3)
    with pytest.raises(ValueError, match="k"):
        cardinality_k_best(np.zeros((2, 2)), np.zeros(2), 2, np.zeros((3, 1)), 0)
    with pytest.raises(ValueError, match="clutter_scores"):
        cardinality_k_best(np.zeros((2, 2)), np.array([0.0, np.inf]), 2, np.zeros((3, 1)), 3)


@pytest.mark.parametrize(
    "target, clutter, n_objects, message",
    [
        (np.zeros((2, 3)), np.zeros(3), 2,
         r"^target_scores must be \(m, C\) and clutter_scores \(m,\), got \(2, 3\), \(3,\)$"),
        (np.array([[np.nan, 0.0, 0.0], [0.0, 0.0, 0.0]]), np.zeros(2), 2,
         r"^target_scores entries must be finite or -inf \(gated out\)$"),
        (np.zeros((2, 3)), np.array([0.0, np.inf]), 2, "^clutter_scores must be finite$"),
        (np.zeros((2, 3)), np.zeros(2), -1, r"^n_objects must be an integer in \[0, 3\], got -1$"),
        (np.zeros((2, 3)), np.zeros(2), 4, r"^n_objects must be an integer in \[0, 3\], got 4$"),
    ],
)
def test_bad_input_messages(target, clutter, n_objects, message):
    with pytest.raises(ValueError, match=message):
        cardinality_k_best(target, clutter, n_objects, np.zeros((3, 2)), 3)


def test_rational_scores_read_as_floats():
    """One object, one return: detected (1/2 + φ[1] = 1/2 - 1) or clutter (-1/4 + φ[0] = -1/4)."""
    from fractions import Fraction

    ev, lw = cardinality_k_best([[Fraction(1, 2)]], [Fraction(-1, 4)], 1, [[Fraction(0)], [Fraction(-1)]], 5)
    assert ev.tolist() == [[-1], [0]] and ev.dtype == np.int32
    np.testing.assert_array_equal(lw, [-0.25, -0.5])


def test_empty_scan_weight_is_the_no_detection_count_term():
    """m = 0: the one event detects nothing, so its weight is φ[0, 0] whatever φ[k > 0]."""
    phi = np.array([[0.5], [-np.inf], [2.0], [3.0]])
    ev, lw = cardinality_k_best(np.zeros((0, 3)), np.zeros(0), 3, phi, 5)
    assert ev.shape == (1, 0) and ev.dtype == np.int32 and lw.tolist() == [0.5]


def test_no_feasible_event_gives_empty_int_events():
    ev, lw = cardinality_k_best(np.zeros((2, 0)), np.zeros(2), 0, np.full((1, 1), -np.inf), 5)
    assert ev.shape == (0, 2) and ev.dtype == np.int32 and lw.shape == (0,)


def test_count_term_and_k_messages():
    with pytest.raises(ValueError, match=r"^count_term must have shape \(3, 2\), got \(2, 1\)$"):
        cardinality_k_best(np.zeros((2, 3)), np.zeros(2), 2, np.zeros((2, 1)), 3)
    with pytest.raises(ValueError, match=r"^k must be an integer in \[1, inf\], got 0$"):
        cardinality_k_best(np.zeros((2, 3)), np.zeros(2), 2, np.zeros((3, 2)), 0)

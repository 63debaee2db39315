"""Trajectory GOSPA against brute force over assignment sequences, GOSPA at one time step, the
switch penalty, the metric axioms, and bad input.

The oracle scores every sequence of per-step assignments (estimate i ↦ truth j or nothing, no truth
used twice) with the assignment-sequence objective of García-Fernández, Rahmathullah & Svensson
(2020), written here independently of the module, and takes the minimum. The MILP (``integral=True``)
must equal it always; the LP relaxation must never exceed it and must equal it whenever its optimum
is integral. Measured: the LP optimum was integral, hence exact, in all 60 random cases below (seed 7)
and in 700 more tried while writing them (2–4 trajectories a side, 3–6 steps, p ∈ {1, 2}, γ from 0.2 to
2), so they check the LP's value exactly. A wider search found cases where it is not (8 fractional
optima in 3000, one strictly below the assignment metric); that one is kept as a test.
"""

import itertools

import numpy as np
import pytest

from hypotrack.metrics import gospa
from hypotrack.metrics_trajectory import (
    TrajectoryGospaResult,
    trajectories_from_estimates,
    trajectory_cost_matrices,
    trajectory_gospa,
)

NAN = np.nan


def base(x, y, c, p):
    """d(x, y)^p on sets of at most one point (None = absent)."""
    if x is None and y is None:
        return 0.0
    if x is None or y is None:
        return c**p / 2
    return min(float(np.linalg.norm(x - y)), c) ** p


def state(T, i, k):
    s = T[i, k]
    return None if np.isnan(s).all() else s


def switch(a, b):
    if a == b:
        return 0.0
    return 1.0 if a and b else 0.5


def brute_force(X, Y, c, p, gamma, dp=False):
    """min over assignment sequences of the per-step costs plus γ^p × switches (value^p); every
    sequence is enumerated, or with ``dp`` the same minimum is found step by step."""
    nx, ny, T = X.shape[0], Y.shape[0], X.shape[1]
    vectors = [v for v in itertools.product(range(ny + 1), repeat=nx)
               if len([a for a in v if a]) == len({a for a in v if a})]
    step_cost = np.empty((T, len(vectors)))
    for k in range(T):
        for q, v in enumerate(vectors):
            cost = sum(base(state(X, i, k), state(Y, a - 1, k) if a else None, c, p) for i, a in enumerate(v))
            cost += sum(base(None, state(Y, j, k), c, p) for j in range(ny) if j + 1 not in v)
            step_cost[k, q] = cost
    sw = np.array([[sum(switch(a, b) for a, b in zip(u, v)) for v in vectors] for u in vectors])
    if dp:
        # The same minimum by dynamic programming over the steps (the objective is a chain sum).
        best_to = step_cost[0].copy()
        for k in range(1, T):
            best_to = step_cost[k] + (best_to[:, None] + gamma**p * sw).min(axis=0)
        return float(best_to.min())
    best = np.inf
    for seq in itertools.product(range(len(vectors)), repeat=T):
        total = step_cost[np.arange(T), seq].sum() + gamma**p * sum(sw[a, b] for a, b in zip(seq, seq[1:]))
        best = min(best, total)
    return best


def random_trajectories(rng, n, T, d=1, spread=4.0):
    """n trajectories on [0, spread]^d with random contiguous lifetimes (some with a gap)."""
    X = rng.uniform(0, spread, size=(n, T, d)) + np.cumsum(rng.normal(0, 0.5, size=(n, T, d)), axis=1)
    for i in range(n):
        birth = int(rng.integers(0, T))
        death = int(rng.integers(birth + 1, T + 1))
        X[i, :birth] = NAN
        X[i, death:] = NAN
        if rng.random() < 0.2 and death - birth > 2:
            X[i, birth + 1] = NAN
    return X


def lp_objective(r, D, gamma, p):
    W = r.weights
    nx, ny = W.shape[1] - 1, W.shape[2] - 1
    return float((D * W).sum() + gamma**p / 2 * np.abs(np.diff(W[:, :nx, :ny], axis=0)).sum())


def test_equals_brute_force_over_assignment_sequences():
    rng = np.random.default_rng(7)
    n_cases = n_integral = 0
    for _ in range(60):
        nx, ny = int(rng.integers(0, 3)), int(rng.integers(0, 3))
        T = int(rng.integers(1, 5))
        X, Y = random_trajectories(rng, nx, T), random_trajectories(rng, ny, T)
        c, p, gamma = float(rng.uniform(1, 4)), float(rng.choice([1.0, 2.0])), float(rng.uniform(0.3, 3))
        oracle = brute_force(X, Y, c, p, gamma)
        milp = trajectory_gospa(X, Y, c=c, p=p, gamma=gamma, integral=True)
        lp = trajectory_gospa(X, Y, c=c, p=p, gamma=gamma)
        assert milp.value**p == pytest.approx(oracle, abs=1e-7)
        assert lp.value**p <= oracle + 1e-7
        if lp.integral:
            assert lp.value**p == pytest.approx(oracle, abs=1e-7)
            n_integral += 1
        # The decomposition adds up to the LP objective of the returned weights.
        D = trajectory_cost_matrices(X, Y, c, p)
        parts = lp.localisation + lp.missed + lp.false + lp.switches
        assert parts == pytest.approx(lp.value**p, abs=1e-9)
        assert lp_objective(lp, D, gamma, p) == pytest.approx(parts, abs=1e-7)
        n_cases += 1
    assert n_integral >= 50, n_integral


def test_three_by_three_cases_against_brute_force():
    rng = np.random.default_rng(3)
    for _ in range(4):
        X, Y = random_trajectories(rng, 3, 3), random_trajectories(rng, 3, 3)
        oracle = brute_force(X, Y, 2.0, 1.0, 1.0)
        milp = trajectory_gospa(X, Y, c=2.0, p=1, gamma=1.0, integral=True)
        lp = trajectory_gospa(X, Y, c=2.0, p=1, gamma=1.0)
        assert milp.value == pytest.approx(oracle, abs=1e-7)
        assert lp.value <= oracle + 1e-7
        assert lp.integral <= (abs(lp.value - oracle) < 1e-7)


def test_weights_are_feasible():
    rng = np.random.default_rng(1)
    X, Y = random_trajectories(rng, 3, 5, d=2), random_trajectories(rng, 2, 5, d=2)
    W = trajectory_gospa(X, Y, c=3.0, p=2, gamma=1.0).weights
    assert W.shape == (5, 4, 3)
    np.testing.assert_allclose(W[:, :3, :].sum(axis=2), 1.0, atol=1e-9)
    np.testing.assert_allclose(W[:, :, :2].sum(axis=1), 1.0, atol=1e-9)
    assert np.all(W[:, 3, 2] == 0) and np.all(W >= 0)


@pytest.mark.parametrize("p", [1.0, 2.0, 3.0])
def test_one_time_step_is_gospa(p):
    rng = np.random.default_rng(int(p))
    for _ in range(30):
        nx, ny = int(rng.integers(0, 5)), int(rng.integers(0, 5))
        A, B = rng.uniform(0, 10, size=(nx, 2)), rng.uniform(0, 10, size=(ny, 2))
        c = float(rng.uniform(1, 6))
        g = gospa(A, B, c=c, p=p)
        r = trajectory_gospa(A[:, None, :], B[:, None, :], c=c, p=p, gamma=1.0)
        assert r.value == pytest.approx(g.value, abs=1e-9)
        assert r.localisation == pytest.approx(g.localisation, abs=1e-7)
        assert r.missed == pytest.approx(g.missed, abs=1e-7)
        assert r.false == pytest.approx(g.false, abs=1e-7)
        assert r.switches == 0 and r.integral


def test_a_label_swap_costs_two_switches_and_a_handover_one():
    # Estimates follow the two truths exactly, then swap labels: each estimate switches once.
    Y = np.array([[[0.0], [1.0], [2.0], [3.0], [4.0]], [[9.0], [8.0], [7.0], [6.0], [5.0]]])
    X = Y[:, [0, 1, 2, 3, 4]].copy()
    X[0, 3:], X[1, 3:] = Y[1, 3:], Y[0, 3:]
    for gamma, p in ((1.0, 1.0), (2.0, 2.0), (0.5, 1.0)):
        r = trajectory_gospa(X, Y, c=100.0, p=p, gamma=gamma)
        assert r.value**p == pytest.approx(2 * gamma**p, abs=1e-9)
        assert r.switches == pytest.approx(2 * gamma**p, abs=1e-9)
        assert r.localisation == pytest.approx(0, abs=1e-9) and r.missed == r.false == pytest.approx(0, abs=1e-9)
    # One estimate hands over from truth A (dies after step 2) to truth B (born at step 3): one full
    # switch γ^p (cheaper than ending and starting, γ^p/2 + γ^p/2 plus a step unassigned).
    A = np.array([[0.0], [1.0], [2.0], [NAN], [NAN]])
    B = np.array([[NAN], [NAN], [NAN], [3.0], [4.0]])
    est = np.array([[[0.0], [1.0], [2.0], [3.0], [4.0]]])
    r = trajectory_gospa(est, np.stack([A, B]), c=10.0, p=2, gamma=1.5)
    assert r.value**2 == pytest.approx(1.5**2, abs=1e-9) and r.n_switches == pytest.approx(1.0, abs=1e-9)
    # With a switch dearer than leaving both unassigned for the rest, the metric does that instead.
    r = trajectory_gospa(est, np.stack([A, B]), c=1.0, p=1, gamma=10.0)
    assert r.switches == 0 and r.value == pytest.approx(2 * 1.0, abs=1e-9)  # 2 steps × (c/2 + c/2)


def test_metric_axioms_on_random_sets():
    rng = np.random.default_rng(11)
    kw = dict(c=2.0, p=1.0, gamma=1.0)
    worst = -np.inf
    for _ in range(25):
        T = int(rng.integers(1, 5))
        S = [random_trajectories(rng, int(rng.integers(0, 4)), T, d=2, spread=3.0) for _ in range(3)]
        X, Y, Z = S
        dxy = trajectory_gospa(X, Y, **kw).value
        assert dxy == pytest.approx(trajectory_gospa(Y, X, **kw).value, abs=1e-9)
        assert trajectory_gospa(X, X, **kw).value == pytest.approx(0, abs=1e-9)
        assert trajectory_gospa(X, X[::-1], **kw).value == pytest.approx(0, abs=1e-9)  # a set: order is irrelevant
        if len(X) != len(Y) or not np.array_equal(np.nan_to_num(X, nan=-1), np.nan_to_num(Y, nan=-1)):
            assert dxy > 1e-6
        dxz = trajectory_gospa(X, Z, **kw).value
        dyz = trajectory_gospa(Y, Z, **kw).value
        worst = max(worst, dxz - dxy - dyz)
        assert dxz <= dxy + dyz + 1e-7
    assert worst <= 1e-7


def test_symmetry_swaps_missed_and_false():
    rng = np.random.default_rng(4)
    X, Y = random_trajectories(rng, 2, 4), random_trajectories(rng, 3, 4)
    a, b = trajectory_gospa(X, Y, c=2.0), trajectory_gospa(Y, X, c=2.0)
    assert a.missed == pytest.approx(b.false, abs=1e-7) and a.false == pytest.approx(b.missed, abs=1e-7)


def test_empty_sets_and_defaults():
    Y = np.array([[[0.0, 0.0], [1.0, 0.0], [NAN, NAN]]])
    r = trajectory_gospa([], Y, c=4.0, p=2)
    assert r.value**2 == pytest.approx(2 * 16 / 2) and r.n_missed == 2 and r.false == 0
    assert trajectory_gospa([], [], c=1.0).value == 0.0
    # gamma=None is γ = c.
    assert trajectory_gospa(Y, Y[:, ::-1], c=3.0).value == trajectory_gospa(Y, Y[:, ::-1], c=3.0, gamma=3.0).value
    assert isinstance(trajectory_gospa(Y, Y, c=1.0), TrajectoryGospaResult)
    # A row that never exists changes nothing.
    ghost = np.full((1, 3, 2), NAN)
    X = np.concatenate([Y + 0.5, ghost])
    assert trajectory_gospa(X, Y, c=4.0).value == pytest.approx(trajectory_gospa(Y + 0.5, Y, c=4.0).value, abs=1e-9)


@pytest.mark.parametrize(
    "X, Y, kwargs, exc, match",
    [
        (np.zeros((1, 3)), np.zeros((1, 3, 1)), {}, ValueError, r"X must be an \(n, T, d\) array"),
        (np.zeros((1, 3, 1)), np.zeros((2, 2)), {}, ValueError, r"Y must be an \(n, T, d\) array"),
        (np.zeros((1, 3, 1)), np.zeros((1, 4, 1)), {}, ValueError, "same time steps T, got 3 and 4"),
        (np.zeros((1, 3, 1)), np.zeros((1, 3, 2)), {}, ValueError, "same dimension d, got 1 and 2"),
        (np.array([[[0.0, NAN]]]), np.zeros((1, 1, 2)), {}, ValueError, r"X\[0, 0\] is partly NaN"),
        (np.zeros((1, 1, 1)), np.array([[[np.inf]]]), {}, ValueError, "Y must not contain inf"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"c": 0.0}, ValueError, "c must be a finite number > 0"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"p": 0.5}, ValueError, r"p must lie in \[1, inf\)"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"p": np.inf}, ValueError, r"p must lie in \[1, inf\)"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"p": "2"}, TypeError, "p must be a real number"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"gamma": 0.0}, ValueError, "gamma must be a finite number > 0"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"gamma": -1.0}, ValueError, "gamma must be a finite number > 0"),
        (np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), {"integral": 1}, TypeError, "integral must be a bool"),
    ],
)
def test_bad_inputs_are_named(X, Y, kwargs, exc, match):
    kw = {"c": 1.0} | kwargs
    with pytest.raises(exc, match=match):
        trajectory_gospa(X, Y, **kw)


def test_fixing_never_close_pairs_leaves_the_optimum_unchanged():
    """The program leaves out pairs never both present and closer than c; with every pair kept the
    LP and MILP optima are the same."""
    from hypotrack import metrics_trajectory as mt

    rng = np.random.default_rng(21)
    pruned_somewhere = 0
    for _ in range(20):
        X, Y = random_trajectories(rng, 3, 5, spread=6.0), random_trajectories(rng, 3, 5, spread=6.0)
        c, p, gamma = 1.5, 1.0, float(rng.uniform(0.3, 2.0))
        D = trajectory_cost_matrices(X, Y, c, p)
        for integral in (False, True):
            r = trajectory_gospa(X, Y, c=c, p=p, gamma=gamma, integral=integral)
            W = mt._solve(D, gamma**p, integral, np.ones((3, 3), bool))
            full = (D * W).sum() + gamma**p / 2 * np.abs(np.diff(W[:, :3, :3], axis=0)).sum()
            assert r.value**p == pytest.approx(full, abs=1e-7)
        ex, ey = ~np.isnan(X[..., 0]).T, ~np.isnan(Y[..., 0]).T
        pruned_somewhere += int(not (ex[:, :, None] & ey[:, None, :] & (D[:, :3, :3] < c**p)).any(axis=0).all())
    assert pruned_somewhere > 10


def test_trajectories_from_estimates_feed_the_metric():
    from hypotrack.protocol import TrackEstimates

    # A tracker's run over 3 scans: label 1 follows truth 0; label 4 appears at scan 1.
    run = [TrackEstimates(0.0, np.array([1]), np.array([[0.0, 0.0, 1.0, 0.0]])),
           TrackEstimates(1.0, np.array([4, 1]), np.array([[5.0, 5.0, 0, 0], [1.0, 0.0, 1.0, 0.0]])),
           TrackEstimates(2.0, np.array([1, 4]), np.array([[2.0, 0.0, 1.0, 0.0], [5.0, 6.0, 0, 0]]))]
    labels, X = trajectories_from_estimates(run, components=[0, 1])
    assert labels.tolist() == [1, 4] and X.shape == (2, 3, 2)
    np.testing.assert_array_equal(X[0], [[0, 0], [1, 0], [2, 0]])
    assert np.isnan(X[1, 0]).all()
    np.testing.assert_array_equal(X[1, 1:], [[5, 5], [5, 6]])
    truth = np.array([[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]])
    r = trajectory_gospa(X, truth, c=2.0, p=1, gamma=1.0)
    assert r.value == pytest.approx(2 * 1.0)  # label 4 is false at two steps, c/2 each
    with pytest.raises(ValueError, match="holds a label twice"):
        trajectories_from_estimates([TrackEstimates(0.0, np.array([1, 1]), np.zeros((2, 2)))])
    labels, X = trajectories_from_estimates([])
    assert labels.size == 0 and X.shape == (0, 0, 0)
    # a scan with no estimate (a tracker's state array of shape (0, d)) leaves its step absent
    gap = [run[0], TrackEstimates(1.0, np.zeros(0, np.int64), np.zeros((0, 4))), run[2]]
    labels, X = trajectories_from_estimates(gap, components=[0, 1])
    assert labels.tolist() == [1, 4] and np.isnan(X[:, 1]).all() and X[0, 2].tolist() == [2.0, 0.0]


def test_cost_matrices_are_validated_and_match_the_base_metric():
    X = np.array([[[0.0], [NAN]]])
    Y = np.array([[[3.0], [1.0]]])
    D = trajectory_cost_matrices(X, Y, c=2.0, p=2)
    np.testing.assert_array_equal(D[0], [[4.0, 2.0], [2.0, 0.0]])  # far pair: c^p; unassigned: c^p/2
    np.testing.assert_array_equal(D[1], [[2.0, 0.0], [2.0, 0.0]])  # estimate absent
    with pytest.raises(ValueError, match="c must be a finite number > 0"):
        trajectory_cost_matrices(X, Y, c=-1.0)
    with pytest.raises(TypeError, match=r"X must be an \(n, T, d\) array of numbers"):
        trajectory_gospa([[["a"]]], Y, c=1.0)


def test_a_case_where_the_lp_is_a_strict_relaxation():
    """Found by a random search (3000 cases of 2–4 trajectories a side, 2–6 steps: the LP optimum was
    fractional 8 times, strictly below the assignment metric once — this case). The LP value stays
    a metric (the paper's result) but is then a lower bound: 36.0 against 36.5 (p-th powers)."""
    X = np.array([[2.0, 2.0, 2.0, 1.0], [0.0, 2.0, 3.0, 2.0], [NAN, 0.0, 0.0, NAN]])[..., None]
    Y = np.array([[NAN, 1.0, NAN, 0.0], [NAN, NAN, 0.0, 3.0], [1.0, NAN, NAN, NAN], [NAN, 3.0, 0.0, NAN]])[..., None]
    kw = dict(c=3.0, p=2, gamma=2.0)
    oracle = brute_force(X, Y, kw["c"], kw["p"], kw["gamma"], dp=True)
    lp, milp = trajectory_gospa(X, Y, **kw), trajectory_gospa(X, Y, **kw, integral=True)
    assert oracle == pytest.approx(36.5, abs=1e-9)
    assert milp.value**2 == pytest.approx(oracle, abs=1e-7) and milp.integral
    assert lp.value**2 == pytest.approx(36.0, abs=1e-7) and not lp.integral


def test_dynamic_programme_equals_enumeration():
    rng = np.random.default_rng(9)
    for _ in range(10):
        X, Y = random_trajectories(rng, 2, 3), random_trajectories(rng, 2, 3)
        assert brute_force(X, Y, 2.0, 1.0, 0.8, dp=True) == pytest.approx(brute_force(X, Y, 2.0, 1.0, 0.8), abs=1e-12)


# --- cases where a near-miss of the definitions gives another number ---

def test_no_time_steps_gives_zero_everywhere():
    # T = 0 (trajectories over no step, d = 2): nothing to score; every field zero, weights (0, 3, 2)
    r = trajectory_gospa(np.zeros((2, 0, 2)), np.zeros((1, 0, 2)), c=1.0)
    assert (r.value, r.localisation, r.missed, r.false, r.switches, r.n_missed, r.n_false, r.n_switches) == (
        0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    assert r.integral is True and r.weights.shape == (0, 3, 2)


def test_empty_sets_keep_their_time_steps():
    # (0, 5, 2) against (0, 5, 2): five steps with nothing in them; [] against [] has no step
    assert trajectory_cost_matrices(np.zeros((0, 5, 2)), np.zeros((0, 5, 2)), c=1.0).shape == (5, 1, 1)
    assert trajectory_cost_matrices([], [], c=1.0).shape == (0, 1, 1)
    # an empty set of another dimension takes the other's: (0, 3, 2) estimates against one 1-D truth over three
    # steps, present at all three: three missed steps, c / 2 = 2 each (p = 1)
    Y = np.array([[[0.0], [1.0], [2.0]]])
    for empty in (np.zeros((0, 3, 2)), [], np.zeros((0, 0, 0))):
        r = trajectory_gospa(empty, Y, c=4.0, p=1)
        assert (r.value, r.n_missed, r.n_false) == (6.0, 3.0, 0.0)
        # and the other way round: three false steps
        r = trajectory_gospa(Y, empty, c=4.0, p=1)
        assert (r.value, r.n_missed, r.n_false) == (6.0, 0.0, 3.0)
        assert r.weights.shape == (3, 2, 1)


def test_a_pair_at_exactly_the_cut_off_is_missed_plus_false():
    # one truth at 0, one estimate 1 away at step 0 and exactly c = 2 away at step 1 (p = 1, gamma = 10):
    # keeping the assignment costs 1 + 2 = 3; ending it costs 1 + (1 + 1) + gamma / 2 = 8. At step 1 the pair
    # costs c^p = 2, reported (as GOSPA does) as one missed plus one false, c / 2 each, not as localisation
    r = trajectory_gospa([[[1.0], [2.0]]], [[[0.0], [0.0]]], c=2.0, p=1, gamma=10.0)
    assert r.value == pytest.approx(3.0, abs=1e-9)
    assert (r.localisation, r.missed, r.false, r.switches) == pytest.approx((1.0, 1.0, 1.0, 0.0), abs=1e-9)
    assert (r.n_missed, r.n_false) == pytest.approx((1.0, 1.0), abs=1e-9)


def test_a_switch_over_two_steps():
    # truths at 0 and 10 over two steps; one estimate at 0 then at 10 (c = 20, p = 1, gamma = 1). Following
    # both truths: localisation 0, truth 2 missed at step 0 and truth 1 at step 1 (10 each), one full switch
    # (gamma = 1): 21. Staying on truth 1: 10 + truth 2 missed twice (20) = 30.
    r = trajectory_gospa([[[0.0], [10.0]]], [[[0.0], [0.0]], [[10.0], [10.0]]], c=20.0, p=1, gamma=1.0)
    assert r.value == pytest.approx(21.0, abs=1e-9)
    assert (r.switches, r.n_switches, r.n_missed, r.n_false) == pytest.approx((1.0, 1.0, 2.0, 0.0), abs=1e-9)


def test_false_steps_are_counted():
    # one truth over two steps, two estimates: one on it, one 50 away (c = 4, p = 1): two false steps
    r = trajectory_gospa([[[0.0], [0.0]], [[50.0], [50.0]]], [[[0.0], [0.0]]], c=4.0, p=1)
    assert (r.value, r.false, r.n_false, r.n_missed) == pytest.approx((4.0, 4.0, 2.0, 0.0), abs=1e-9)


def test_order_defaults_to_one():
    # one truth, one estimate 3 and then 4 away, c = 10: p = 1 gives 3 + 4 = 7 (p = 2 would give
    # sqrt(9 + 16) = 5)
    X, Y = [[[3.0], [4.0]]], [[[0.0], [0.0]]]
    assert trajectory_gospa(X, Y, c=10.0).value == pytest.approx(7.0, abs=1e-9)
    D = trajectory_cost_matrices(X, Y, c=10.0)
    assert D[:, 0, 0].tolist() == [3.0, 4.0]  # p = 1: the distances themselves, not their squares


def test_type_errors_name_the_offending_type():
    with pytest.raises(TypeError, match=r"^p must be a real number in \[1, inf\), got str$"):
        trajectory_gospa(np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), c=1.0, p="2")
    with pytest.raises(TypeError, match=r"^integral must be a bool, got int$"):
        trajectory_gospa(np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), c=1.0, integral=1)
    with pytest.raises(TypeError, match=r"^X must be an \(n, T, d\) array of numbers \(NaN where absent\), got list "
                                        r"that NumPy cannot convert"):
        trajectory_gospa([[[0.0], [0.0, 1.0]]], np.zeros((1, 2, 1)), c=1.0)
    with pytest.raises(ValueError, match=r"^X\[0, 1\] is partly NaN"):
        trajectory_gospa([[[0.0, 0.0], [NAN, 1.0]]], np.zeros((1, 2, 2)), c=1.0)
    with pytest.raises(ValueError, match=r"^Y\[0, 0\] is partly NaN"):
        trajectory_gospa(np.zeros((1, 2, 2)), [[[NAN, 0.0], [0.0, 1.0]]], c=1.0)


def test_estimates_without_components_and_odd_shapes():
    from hypotrack.protocol import TrackEstimates

    # no components: every state component kept
    run = [TrackEstimates(0.0, np.array([3]), np.array([[0.0, 1.0]])),
           TrackEstimates(1.0, np.array([5, 3]), np.array([[9.0, 0.0], [0.5, 1.0]]))]
    labels, X = trajectories_from_estimates(run)
    assert labels.tolist() == [3, 5]
    np.testing.assert_array_equal(X[0], [[0.0, 1.0], [0.5, 1.0]])
    assert np.isnan(X[1, 0]).all() and X[1, 1].tolist() == [9.0, 0.0]
    # one label with its state given flat (d,), and labels as whole-valued floats: int64 labels
    labels, X = trajectories_from_estimates([TrackEstimates(0.0, np.array([3.0]), np.array([0.0, 1.0]))])
    assert labels.dtype == np.int64 and labels.tolist() == [3] and X.tolist() == [[[0.0, 1.0]]]
    # a step without estimates given as a flat empty array leaves its step absent
    gap = [run[0], TrackEstimates(1.0, np.zeros(0, np.int64), np.zeros(0))]
    labels, X = trajectories_from_estimates(gap)
    assert labels.tolist() == [3] and X[0, 0].tolist() == [0.0, 1.0] and np.isnan(X[0, 1]).all()
    # only empty steps: no trajectory, the width of the components asked for
    labels, X = trajectories_from_estimates([gap[1], gap[1]], components=[0, 1])
    assert labels.dtype == np.int64 and X.shape == (0, 2, 2)
    assert trajectories_from_estimates([])[0].dtype == np.int64
    # steps of two different dimensions (2 and 3), in any order
    mixed = [run[0], TrackEstimates(1.0, np.array([3]), np.array([[0.0, 1.0, 2.0]]))]
    with pytest.raises(ValueError, match=r"^estimates must have states of one dimension, got \[2, 3\]$"):
        trajectories_from_estimates(mixed)
    with pytest.raises(ValueError, match=r"^estimates must have states of one dimension, got \[2, 3\]$"):
        trajectories_from_estimates(mixed[::-1])


def test_weights_keep_the_fixed_entries_at_zero():
    """The program fixes W[∅, ∅] = 0 and the pairs never both present and closer than c at W = 0
    (module docstring): the weights returned are exactly 0 there, and every weight lies in [0, 1].
    Freeing those entries leaves the value unchanged but lets the solver return another optimal vertex
    with weight on a far pair (it did in about one case in five of these)."""
    rng = np.random.default_rng(5)
    for _ in range(60):
        nx, ny, T = int(rng.integers(1, 4)), int(rng.integers(1, 4)), int(rng.integers(2, 6))
        X, Y = random_trajectories(rng, nx, T, spread=6.0), random_trajectories(rng, ny, T, spread=6.0)
        c = 1.5
        W = trajectory_gospa(X, Y, c=c, gamma=1.0).weights
        D = trajectory_cost_matrices(X, Y, c)
        ex, ey = ~np.isnan(X[..., 0]).T, ~np.isnan(Y[..., 0]).T
        active = (ex[:, :, None] & ey[:, None, :] & (D[:, :nx, :ny] < c)).any(axis=0)
        assert np.all(W[:, nx, ny] == 0.0)
        assert np.all(W[:, :nx, :ny][:, ~active] == 0.0)
        assert np.all((W >= 0.0) & (W <= 1.0))


def test_zero_dimensional_states():
    from hypotrack.protocol import TrackEstimates

    # states with no component, (m, 0): trajectories (n, T, 0) that exist wherever their label does
    labels, X = trajectories_from_estimates([TrackEstimates(0.0, np.array([3]), np.zeros((1, 0))),
                                             TrackEstimates(1.0, np.array([3, 4]), np.zeros((2, 0)))])
    assert labels.tolist() == [3, 4] and X.shape == (2, 2, 0)

"""Loopy belief propagation marginals (Williams & Lau 2014) against enumeration, the full
sum-product algorithm, the one-track closed form, and on a large sparse problem.

Measured here (seeds fixed below) and asserted with a margin:

* on graphs without cycles (one return shared by two tracks, chains, random forests) LBP equals
  the enumerated marginals to 1e-12 — BP is exact on trees;
* on the smallest loopy problems (3 tracks × 3 returns, every pair gated, log weights N(0, 1)),
  the largest error of a marginal over 300 draws is 0.079 (mean of the per-problem maxima 0.021);
  asserted: < 0.12 and mean < 0.04;
* on a 200-track, 300-return sparse problem (tracks and returns on a line, ~4 returns per gate,
  807 gated pairs, P_D = 0.9), LBP converges in 36 passes to 1e-10 and differs from the exact
  marginals by at most 0.050; asserted: < 100 passes and < 0.1.
"""

import itertools

import numpy as np
import pandas as pd
import pytest

from hypotrack.association.lbp import LbpMarginals, lbp_benchmark, lbp_marginals, random_line_problem
from hypotrack.association.marginals import jpda_marginals


def brute_force(lw):
    """Marginals by enumerating every feasible joint event: each track missed or one gated
    return, no return used twice; event weight Π_i w_i(a_i)."""
    n, m1 = lw.shape
    options = [[c for c in range(m1) if np.isfinite(lw[i, c])] for i in range(n)]
    beta = np.zeros((n, m1))
    total = 0.0
    for a in itertools.product(*options):
        used = [c for c in a if c > 0]
        if len(used) != len(set(used)):
            continue
        w = np.exp(sum(lw[i, c] for i, c in enumerate(a)))
        total += w
        for i, c in enumerate(a):
            beta[i, c] += w
    return beta / total


def full_sum_product(lw, iterations=2000):
    """The textbook SPA on the pairwise model with vector messages: a_i ∈ {0..m}, b_j ∈ {0..n},
    ψ_ij(a_i, b_j) = [(a_i = j) == (b_j = i)]. Same schedule (tracks, then returns); returns the
    track beliefs. An independent check of the simplified scalar messages."""
    n, m1 = lw.shape
    m = m1 - 1
    w = np.exp(lw - lw.max(axis=1, keepdims=True))
    psi = np.zeros((n, m, m1, n + 1))  # psi[i, j, a_i, b_j]
    for i in range(n):
        for j in range(m):
            for a in range(m1):
                for b in range(n + 1):
                    psi[i, j, a, b] = float((a == 1 + j) == (b == 1 + i))
    to_track = np.ones((m, n, m1))  # message from return j to track i, over a_i
    to_ret = np.ones((n, m, n + 1))  # message from track i to return j, over b_j
    for _ in range(iterations):
        for i in range(n):
            for j in range(m):
                prod = w[i] * np.prod([to_track[k, i] for k in range(m) if k != j], axis=0)
                msg = prod @ psi[i, j]
                to_ret[i, j] = msg / msg.sum()
        for j in range(m):
            for i in range(n):
                prod = np.prod([to_ret[k, j] for k in range(n) if k != i], axis=0)
                msg = psi[i, j] @ prod
                to_track[j, i] = msg / msg.sum()
    belief = w * np.prod(to_track, axis=0)
    return belief / belief.sum(axis=1, keepdims=True)


def forest_problem(rng, n, m):
    """Random log weights whose gating graph (tracks – returns) has no cycle."""
    lw = np.full((n, m + 1), -np.inf)
    lw[:, 0] = rng.normal(size=n)
    # Union–find over the n + m nodes: add random edges that join two components.
    parent = list(range(n + m))

    def root(u):
        while parent[u] != u:
            u = parent[u]
        return u

    for _ in range(3 * (n + m)):
        i, j = int(rng.integers(n)), int(rng.integers(m))
        ri, rj = root(i), root(n + j)
        if ri != rj and rng.random() < 0.7:
            parent[ri] = rj
            lw[i, 1 + j] = rng.normal() * 2
    return lw


def test_one_track_is_the_pdaf_softmax_by_hand():
    # w = (missed 0.1, returns 0.6, 0.3): β = w / 1.0, no other track so ν ≡ 1 after one pass.
    r = lbp_marginals(np.log([[0.1, 0.6, 0.3]]))
    np.testing.assert_allclose(r.beta, [[0.1, 0.6, 0.3]], rtol=1e-14)
    assert r.iterations == 1 and r.change == 0.0
    # A gated-out return gets 0 and the rest renormalise: (2, 0, 6) / 8.
    r = lbp_marginals([[np.log(2.0), -np.inf, np.log(6.0)]])
    np.testing.assert_allclose(r.beta, [[0.25, 0.0, 0.75]], rtol=1e-14)


def test_two_tracks_one_return_by_hand():
    """Events: none (1·2), track 0 (3·2), track 1 (1·5): P(t0 ↔ r) = 6/13, P(t1 ↔ r) = 5/13."""
    lw = np.log([[1.0, 3.0], [2.0, 5.0]])
    r = lbp_marginals(lw)
    np.testing.assert_allclose(r.beta, [[7 / 13, 6 / 13], [8 / 13, 5 / 13]], rtol=0, atol=1e-15)


def test_exact_on_chains():
    """Track k gates returns k and k+1: a path graph, so LBP is exact."""
    rng = np.random.default_rng(5)
    for n in range(2, 7):
        lw = np.full((n, n + 2), -np.inf)
        lw[:, 0] = rng.normal(size=n)
        for k in range(n):
            lw[k, 1 + k] = rng.normal() * 2
            lw[k, 2 + k] = rng.normal() * 2
        r = lbp_marginals(lw, tol=1e-14)
        assert r.change < 1e-14
        np.testing.assert_allclose(r.beta, brute_force(lw), rtol=0, atol=1e-12)


def test_exact_on_random_forests():
    rng = np.random.default_rng(11)
    shared = 0
    for _ in range(150):
        n, m = int(rng.integers(1, 6)), int(rng.integers(1, 6))
        lw = forest_problem(rng, n, m)
        r = lbp_marginals(lw, tol=1e-14)
        np.testing.assert_allclose(r.beta, brute_force(lw), rtol=0, atol=1e-12)
        np.testing.assert_allclose(r.beta, jpda_marginals(lw), rtol=0, atol=1e-12)
        shared += int((np.isfinite(lw[:, 1:]).sum(axis=0) > 1).any())
    assert shared > 60  # most problems do have returns shared by several tracks


def test_loopy_error_is_small_and_constraints_hold():
    rng = np.random.default_rng(3)
    errors = []
    for _ in range(300):
        lw = rng.normal(size=(3, 4))
        r = lbp_marginals(lw)
        assert r.change < 1e-10
        np.testing.assert_allclose(r.beta.sum(axis=1), 1.0, rtol=0, atol=1e-14)
        assert (r.beta[:, 1:].sum(axis=0) <= 1 + 1e-9).all()  # a return is used at most once
        exact = jpda_marginals(lw)
        errors.append(np.abs(r.beta - exact).max())
    errors = np.array(errors)
    assert errors.max() < 0.12, errors.max()  # measured 0.079
    assert errors.mean() < 0.04, errors.mean()  # measured 0.021
    assert errors.max() > 1e-3  # the loopy graph really is approximated (not secretly exact)


def test_scalar_messages_equal_the_full_sum_product():
    """Williams & Lau's simplified messages reach the fixed point of the textbook SPA."""
    rng = np.random.default_rng(8)
    for n, m in ((2, 2), (3, 3), (3, 2), (2, 4)):
        lw = rng.normal(size=(n, m + 1))
        lw[:, 1:][rng.random((n, m)) < 0.2] = -np.inf
        np.testing.assert_allclose(lbp_marginals(lw).beta, full_sum_product(lw, iterations=300), atol=1e-8)


def test_empty_cases():
    r = lbp_marginals(np.zeros((0, 4)))
    assert r.beta.shape == (0, 4) and r.iterations == 0
    r = lbp_marginals(np.zeros((3, 1)))  # no returns: every track missed
    np.testing.assert_array_equal(r.beta, np.ones((3, 1)))
    lw = [[0.0, np.log(2.0), -np.inf], [0.0, -np.inf, -np.inf]]  # track 1 gates nothing
    np.testing.assert_allclose(lbp_marginals(lw).beta, [[1 / 3, 2 / 3, 0.0], [1.0, 0.0, 0.0]], atol=1e-15)


def test_weights_of_any_range_stay_finite():
    """Log-likelihood ratios of ±800 (exp() would overflow) give the limit marginals."""
    lw = np.array([[0.0, 800.0, 0.0], [0.0, 800.0, 790.0]])
    r = lbp_marginals(lw)
    assert np.isfinite(r.beta).all()
    np.testing.assert_allclose(r.beta, brute_force(lw - lw.max(axis=1, keepdims=True)), atol=1e-12)
    lw = np.array([[0.0, -800.0], [0.0, -800.0]])
    np.testing.assert_allclose(lbp_marginals(lw).beta, [[1.0, 0.0], [1.0, 0.0]], atol=1e-300)


def test_row_constants_cancel():
    rng = np.random.default_rng(2)
    lw = rng.normal(size=(4, 5))
    shifted = lw + rng.normal(size=(4, 1)) * 100
    np.testing.assert_allclose(lbp_marginals(shifted).beta, lbp_marginals(lw).beta, atol=1e-12)


@pytest.mark.parametrize(
    "lw, kwargs, match",
    [
        (np.zeros(3), {}, r"log_weights must have shape \(n, m \+ 1\)"),
        (np.zeros((2, 0)), {}, r"log_weights must have shape"),
        (np.array([[0.0, np.nan]]), {}, "NaN"),
        (np.array([[0.0, np.inf]]), {}, r"\+inf"),
        (np.array([[-np.inf, 0.0]]), {}, r"log_weights\[:, 0\] \(missed\) must be finite"),
        (np.zeros((1, 2)), {"tol": 0.0}, "tol must be a finite number > 0"),
        (np.zeros((1, 2)), {"tol": np.nan}, "tol must be a finite number > 0"),
        (np.zeros((1, 2)), {"max_iter": 0}, r"max_iter must be an integer in \[1, inf\]"),
    ],
)
def test_bad_inputs_are_named(lw, kwargs, match):
    with pytest.raises(ValueError, match=match):
        lbp_marginals(lw, **kwargs)


def test_max_iter_must_be_an_integer():
    with pytest.raises(TypeError, match="max_iter must be an integer"):
        lbp_marginals(np.zeros((1, 2)), max_iter=2.5)


def test_max_iter_stops_early_and_reports_the_change():
    lw = np.random.default_rng(1).normal(size=(3, 4)) * 2
    r = lbp_marginals(lw, max_iter=2)
    assert r.iterations == 2 and r.change > 1e-10
    full = lbp_marginals(lw)
    assert full.iterations > 2 and full.change < 1e-10


def test_large_sparse_problem_converges_close_to_exact():
    rng = np.random.default_rng(0)
    lw = random_line_problem(rng, 200, 300, gated_per_track=4.0)
    pairs = int(np.isfinite(lw[:, 1:]).sum())
    r = lbp_marginals(lw)
    exact = jpda_marginals(lw)  # the frontier stays small along a line, so exact is affordable
    err = np.abs(r.beta - exact).max()
    assert 600 < pairs < 1000  # ~4 returns per gate (measured: 807)
    assert r.change < 1e-10 and r.iterations < 100, (r.iterations, r.change)  # measured: 36 passes
    assert err < 0.1, err  # measured: 0.050
    assert (r.beta[:, 1:].sum(axis=0) <= 1 + 1e-9).all()


def test_benchmark_table():
    """The benchmark's table has its columns and a consistent count of pairs (timings are not tested)."""
    df = lbp_benchmark(((20, 30), (40, 60)), repeats=1, passes=3, seed=5)
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == ["n", "m", "gated_pairs", "iterations", "change", "seconds",
                                "seconds_per_pass", "seconds_per_pass_per_pair"]
    rng = np.random.default_rng(5)
    for row, (n, m) in zip(df.itertuples(), ((20, 30), (40, 60))):
        lw = random_line_problem(rng, n, m)  # the benchmark's problems, drawn in the same order
        assert row.gated_pairs == np.isfinite(lw[:, 1:]).sum()
        assert row.iterations == lbp_marginals(lw).iterations and row.change < 1e-10
    assert (df.seconds_per_pass > 0).all() and (df.seconds > 0).all()
    np.testing.assert_allclose(df.seconds_per_pass_per_pair, df.seconds_per_pass / df.gated_pairs)
    with pytest.raises(ValueError, match=r"passes must be an integer in \[1, inf\]"):
        lbp_benchmark(((5, 5),), passes=0)


def test_result_unpacks():
    beta, iterations, change = lbp_marginals(np.zeros((2, 3)))
    assert isinstance(lbp_marginals(np.zeros((2, 3))), LbpMarginals)
    assert beta.shape == (2, 3) and iterations >= 1 and change >= 0


def test_unassigned_weights_equal_shifted_track_weights_and_enumeration():
    """A return left unassigned with weight u_j: events weigh Π_i w_i(a_i) Π_{j unassigned} u_j."""
    rng = np.random.default_rng(13)
    for _ in range(30):
        n, m = int(rng.integers(1, 4)), int(rng.integers(1, 4))
        lw = rng.normal(size=(n, m + 1))
        lw[:, 1:][rng.random((n, m)) < 0.3] = -np.inf
        lu = rng.normal(size=m)
        r = lbp_marginals(lw, log_unassigned=lu)
        shifted = lw.copy()
        shifted[:, 1:] -= lu
        np.testing.assert_array_equal(r.beta, lbp_marginals(shifted).beta)
        # Against enumeration with the unassigned weights written out.
        options = [[c for c in range(m + 1) if np.isfinite(lw[i, c])] for i in range(n)]
        beta, total = np.zeros((n, m + 1)), 0.0
        for a in itertools.product(*options):
            used = [c for c in a if c > 0]
            if len(used) != len(set(used)):
                continue
            w = np.exp(sum(lw[i, c] for i, c in enumerate(a)) + sum(lu[j] for j in range(m) if j + 1 not in used))
            total += w
            for i, c in enumerate(a):
                beta[i, c] += w
        exact = beta / total
        np.testing.assert_allclose(jpda_marginals(shifted), exact, atol=1e-12)
        if n == 1 or m == 1:  # tree-shaped: LBP exact
            np.testing.assert_allclose(r.beta, exact, atol=1e-12)
    with pytest.raises(ValueError, match=r"log_unassigned must have shape \(m,\) = \(2,\)"):
        lbp_marginals(np.zeros((1, 3)), log_unassigned=[0.0])
    with pytest.raises(ValueError, match="log_unassigned must be finite"):
        lbp_marginals(np.zeros((1, 3)), log_unassigned=[0.0, -np.inf])

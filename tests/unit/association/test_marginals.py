"""Exact JPDA marginals (EHM recursion) against exhaustive enumeration and closed forms."""

import math

import numpy as np
import pytest
from scipy.special import logsumexp

from hypotrack.association import enumerate_associations
from hypotrack.association.marginals import MarginalsBudgetError, jpda_marginals, track_order


def brute_force(lw):
    """Marginals and log normaliser by enumerating every joint event (the oracle)."""
    n, m1 = lw.shape
    m = m1 - 1
    allowed = np.isfinite(lw[:, 1:]).T  # (m, n) validation matrix
    events = enumerate_associations(n, m, allowed=allowed).astype(np.int64)  # (E, m): track or -1
    # Column chosen by each track in each event: 1 + return index, or 0 (missed).
    choice = np.zeros((len(events), n), dtype=np.int64)
    e_idx, r_idx = np.nonzero(events >= 0)
    choice[e_idx, events[e_idx, r_idx]] = 1 + r_idx
    logw = lw[np.arange(n)[None, :], choice].sum(axis=1)
    log_total = logsumexp(logw)
    if not np.isfinite(log_total):
        return np.zeros((n, m1)), log_total
    p = np.exp(logw - log_total)
    beta = np.zeros((n, m1))
    for t in range(n):
        np.add.at(beta[t], choice[:, t], p)
    return beta, log_total


def random_problem(rng, n, m, density=0.5, scale=3.0):
    lw = rng.normal(size=(n, m + 1)) * scale
    lw[:, 1:][rng.random((n, m)) >= density] = -np.inf
    return lw


def test_matches_enumeration_on_random_small_clusters():
    rng = np.random.default_rng(2024)
    checked = 0
    for _ in range(400):
        n, m = int(rng.integers(1, 7)), int(rng.integers(0, 7))
        lw = random_problem(rng, n, m, density=rng.uniform(0.2, 1.0))
        beta_bf, total_bf = brute_force(lw)
        beta, total = jpda_marginals(lw, return_log_total=True)
        np.testing.assert_allclose(beta, beta_bf, rtol=0, atol=1e-12)
        assert total == pytest.approx(total_bf, abs=1e-10)
        checked += 1
    assert checked == 400


def test_matches_enumeration_with_zero_missed_weight():
    """P_D = 1 with P_G → 1 makes 'missed' impossible for some tracks; events must then detect them."""
    rng = np.random.default_rng(7)
    n_feasible = 0
    for _ in range(200):
        n, m = int(rng.integers(1, 5)), int(rng.integers(1, 6))
        lw = random_problem(rng, n, m, density=0.7)
        lw[rng.random(n) < 0.5, 0] = -np.inf
        if not np.isfinite(lw).any(axis=1).all():
            with pytest.raises(ValueError, match="finite"):
                jpda_marginals(lw)
            continue
        _, total_bf = brute_force(lw)
        if not np.isfinite(total_bf):
            with pytest.raises(ValueError, match="no feasible"):
                jpda_marginals(lw)
            continue
        n_feasible += 1
        np.testing.assert_allclose(jpda_marginals(lw), brute_force(lw)[0], atol=1e-12)
    assert n_feasible > 50


def test_lecture_example_clusters_are_independent():
    """Lecture 004 validation matrix: T1 gates y3; T2 gates y3, y4; T3 gates y1; y2 in no gate.

    Marginals of the joint problem equal those of the clusters {T1, T2} and {T3} solved apart.
    """
    rng = np.random.default_rng(3)
    valid = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], bool)  # (returns, tracks)
    lw = np.where(valid.T, rng.normal(size=(3, 4)), -np.inf)
    lw = np.concatenate([rng.normal(size=(3, 1)), lw], axis=1)
    beta = jpda_marginals(lw)
    b12 = jpda_marginals(lw[:2])
    b3 = jpda_marginals(lw[2:])
    np.testing.assert_allclose(beta[:2], b12, atol=1e-14)
    np.testing.assert_allclose(beta[2:], b3, atol=1e-14)
    assert np.all(beta[:, 2] == 0)  # y2 gated by nobody
    np.testing.assert_allclose(beta, brute_force(lw)[0], atol=1e-14)


def symmetric_total(n, m, r):
    """Σ_k C(n,k) C(m,k) k! r^k: every track gates every return with weight r, missed weight 1."""
    return sum(math.comb(n, k) * math.comb(m, k) * math.factorial(k) * r**k for k in range(min(n, m) + 1))


@pytest.mark.parametrize("n, m", [(12, 12), (16, 14), (9, 17)])
def test_fully_connected_cluster_matches_closed_form(n, m):
    """Beyond enumeration (A(16, 14) ≈ 2e13 events): exchangeable tracks have a closed form.

    P(track missed) = Z(n−1, m) / Z(n, m) and P(track ↔ return) = r Z(n−1, m−1) / Z(n, m).
    """
    r = 0.37
    lw = np.full((n, m + 1), np.log(r))
    lw[:, 0] = 0.0
    beta, log_total = jpda_marginals(lw, return_log_total=True)
    Z = symmetric_total(n, m, r)
    assert log_total == pytest.approx(math.log(Z), rel=1e-12)
    np.testing.assert_allclose(beta[:, 0], symmetric_total(n - 1, m, r) / Z, rtol=1e-10)
    np.testing.assert_allclose(beta[:, 1:], r * symmetric_total(n - 1, m - 1, r) / Z, rtol=1e-10)


def test_long_chain_is_linear_and_exact():
    """300 tracks in a line, each sharing a return with its neighbours: ~1e100s of events, small frontier.

    Cross-checked against a transfer-matrix recursion written independently here.
    """
    rng = np.random.default_rng(11)
    n = 300
    # Return j (0..n) lies between tracks j-1 and j; track t may take return t or t+1.
    lw = np.full((n, n + 2), -np.inf)
    lw[:, 0] = rng.normal(size=n)
    lw[np.arange(n), 1 + np.arange(n)] = rng.normal(size=n)
    lw[np.arange(n), 2 + np.arange(n)] = rng.normal(size=n)
    beta, log_total = jpda_marginals(lw, return_log_total=True)

    # Forward/backward over "is return t+1 taken by track t" (a 2-state chain), in log space.
    w_miss, w_left, w_right = lw[:, 0], lw[np.arange(n), 1 + np.arange(n)], lw[np.arange(n), 2 + np.arange(n)]
    f = np.full((n + 1, 2), -np.inf)  # f[t, s]: tracks < t decided, s = return t taken by track t-1
    f[0, 0] = 0.0
    for t in range(n):
        free_left = f[t, 0]
        f[t + 1, 0] = np.logaddexp(logsumexp([f[t, 0], f[t, 1]]) + w_miss[t], free_left + w_left[t])
        f[t + 1, 1] = logsumexp([f[t, 0], f[t, 1]]) + w_right[t]
    assert log_total == pytest.approx(logsumexp(f[n]), rel=1e-12)
    b = np.full((n + 1, 2), -np.inf)
    b[n] = 0.0
    for t in range(n - 1, -1, -1):
        for s in (0, 1):
            opts = [w_miss[t] + b[t + 1, 0], w_right[t] + b[t + 1, 1]]
            if s == 0:
                opts.append(w_left[t] + b[t + 1, 0])
            b[t, s] = logsumexp(opts)
    Z = logsumexp(f[n])
    p_miss = np.exp(logsumexp(f[:-1], axis=1) + w_miss + b[1:, 0] - Z)
    p_left = np.exp(f[:-1, 0] + w_left + b[1:, 0] - Z)
    p_right = np.exp(logsumexp(f[:-1], axis=1) + w_right + b[1:, 1] - Z)
    np.testing.assert_allclose(beta[:, 0], p_miss, atol=1e-12)
    np.testing.assert_allclose(beta[np.arange(n), 1 + np.arange(n)], p_left, atol=1e-12)
    np.testing.assert_allclose(beta[np.arange(n), 2 + np.arange(n)], p_right, atol=1e-12)


def test_invariant_to_track_and_return_order():
    rng = np.random.default_rng(5)
    lw = random_problem(rng, 9, 11, density=0.35)
    beta = jpda_marginals(lw)
    pt, pr = rng.permutation(9), rng.permutation(11)
    lw2 = np.concatenate([lw[pt][:, :1], lw[pt][:, 1:][:, pr]], axis=1)
    beta2 = jpda_marginals(lw2)
    np.testing.assert_allclose(beta2[:, 0], beta[pt, 0], atol=1e-13)
    np.testing.assert_allclose(beta2[:, 1:], beta[pt][:, 1:][:, pr], atol=1e-13)


def test_extreme_log_weights_do_not_overflow():
    """Products of many large likelihood ratios overflow doubles; the recursion rescales."""
    rng = np.random.default_rng(9)
    lw = random_problem(rng, 6, 6, density=0.8) * 150.0
    lw[:, 0] = rng.normal(size=6) * 150.0
    beta_bf, total_bf = brute_force(lw)
    beta, total = jpda_marginals(lw, return_log_total=True)
    assert np.isfinite(beta).all()
    np.testing.assert_allclose(beta, beta_bf, atol=1e-12)
    assert total == pytest.approx(total_bf, rel=1e-12)


def test_rows_and_columns_are_probabilities():
    rng = np.random.default_rng(13)
    beta = jpda_marginals(random_problem(rng, 30, 40, density=0.08))
    np.testing.assert_allclose(beta.sum(axis=1), 1.0, atol=1e-12)
    assert np.all(beta >= 0) and np.all(beta[:, 1:].sum(axis=0) <= 1 + 1e-12)


def test_track_order_is_a_permutation_grouping_components():
    valid = np.zeros((6, 5), bool)
    valid[[0, 3], 0] = True
    valid[[3, 5], 1] = True
    valid[[1, 2], 2] = True
    order = track_order(valid)
    assert sorted(order.tolist()) == list(range(6))
    pos = {t: i for i, t in enumerate(order)}
    # Connected tracks {0, 3, 5} and {1, 2} are contiguous in the order.
    assert max(pos[t] for t in (0, 3, 5)) - min(pos[t] for t in (0, 3, 5)) == 2
    assert abs(pos[1] - pos[2]) == 1


def test_empty_and_trivial_inputs():
    assert jpda_marginals(np.zeros((0, 4))).shape == (0, 4)
    np.testing.assert_array_equal(jpda_marginals(np.zeros((3, 1))), np.ones((3, 1)))
    beta = jpda_marginals(np.log([[0.5, 0.5]]))
    np.testing.assert_allclose(beta, [[0.5, 0.5]])


def test_bad_input():
    with pytest.raises(ValueError, match="shape"):
        jpda_marginals(np.zeros(3))
    with pytest.raises(ValueError, match="NaN"):
        jpda_marginals(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match=r"\+inf"):
        jpda_marginals(np.array([[0.0, np.inf]]))
    with pytest.raises(ValueError, match="finite"):
        jpda_marginals(np.array([[-np.inf, -np.inf]]))


def test_wide_frontier_beyond_one_machine_word():
    """Two tracks sharing 150 returns: 150 returns in flight at once (three 64-bit words per node)."""
    rng = np.random.default_rng(17)
    lw = rng.normal(size=(2, 151))
    beta_bf, total_bf = brute_force(lw)
    beta, total = jpda_marginals(lw, return_log_total=True)
    np.testing.assert_allclose(beta, beta_bf, atol=1e-12)
    assert total == pytest.approx(total_bf, rel=1e-12)


def test_budget_error_instead_of_exhausting_memory():
    """A fully connected 40 x 40 cluster needs ~2^40 nodes: refused quickly, naming the budget."""
    with pytest.raises(MarginalsBudgetError, match="max_nodes"):
        jpda_marginals(np.zeros((40, 41)), max_nodes=100_000)
    with pytest.raises(ValueError, match="max_nodes"):
        jpda_marginals(np.zeros((2, 3)), max_nodes=0)


def test_no_tracks_total_is_the_empty_product():
    beta, log_total = jpda_marginals(np.zeros((0, 4)), return_log_total=True)
    assert beta.shape == (0, 4) and log_total == 0.0  # one (empty) joint event of weight 1


def test_smallest_budgets_are_accepted():
    """max_nodes = 1 is a valid budget (too small for any track: the root and one child), refused by
    the recursion, not by the argument check; one track with no return needs a single edge."""
    with pytest.raises(MarginalsBudgetError):
        jpda_marginals(np.zeros((1, 1)), max_nodes=1)
    np.testing.assert_array_equal(jpda_marginals(np.zeros((1, 1)), max_edges=1), [[1.0]])


def test_integer_and_rational_log_weights_read_as_floats():
    """Two tracks, one shared return, all log-weights 0: events {} {T1} {T2}, so each track takes
    the return with probability 1/3."""
    from fractions import Fraction

    expected = np.array([[2 / 3, 1 / 3], [2 / 3, 1 / 3]])
    np.testing.assert_allclose(jpda_marginals([[0, 0], [0, 0]]), expected, rtol=1e-15)
    rational = [[Fraction(0), Fraction(0)], [Fraction(0), Fraction(0)]]
    np.testing.assert_allclose(jpda_marginals(rational), expected, rtol=1e-15)


def test_messages_say_what_is_wrong():
    with pytest.raises(ValueError, match=r"^log_weights must not contain NaN or \+inf \(use -inf for gated-out "
                                         r"pairs\)$"):
        jpda_marginals(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match="^every track needs at least one option with finite log weight$"):
        jpda_marginals(np.array([[0.0, 0.0], [-np.inf, -np.inf]]))
    with pytest.raises(ValueError, match=r"^no feasible joint association event \(some track can be neither "
                                         r"missed nor detected\)$"):
        jpda_marginals(np.array([[-np.inf, 0.0], [-np.inf, 0.0]]))  # both must take the one return
    for name in ("max_nodes", "max_edges"):
        with pytest.raises(ValueError, match=rf"^{name} must be an integer in \[1, inf\], got 0$"):
            jpda_marginals(np.zeros((2, 3)), **{name: 0})
    with pytest.raises(MarginalsBudgetError, match=(
            r"^cluster of 40 tracks and 40 returns is too large for exact JPDA marginals within "
            r"max_nodes=100,000 and max_edges=10,000,000; raise the budget, gate more tightly or use an "
            r"approximation$")):
        jpda_marginals(np.zeros((40, 41)), max_nodes=100_000)

"""Cardinality tracking (document 003 §4): class weights, K rule, classical null solution, scenario."""

import itertools
import math

import numpy as np
import pytest

from hypotrack.scenarios.cardinality import simulate_cardinality
from hypotrack.trackers.cardinality import (
    CardinalityTracker,
    ClassicalCountMHT,
    CountModel,
    count_objective,
    exact_count_dp,
    k_rule,
    tetris_extract,
    track_log_score,
)


def count_labelled_hypotheses(r, d, b):
    """Brute force: labelled assignments of r returns to d given tracks, b births, f false alarms."""
    n = 0
    for labels in itertools.product(range(d + 2), repeat=r):  # 0..d-1 tracks, d birth, d+1 false alarm
        tracks = [x for x in labels if x < d]
        if len(tracks) == d and len(set(tracks)) == d and labels.count(d) == b:
            n += 1
    return n


@pytest.mark.parametrize("r,d,b", [(3, 1, 1), (4, 2, 1), (4, 0, 2), (5, 2, 2), (3, 0, 0), (4, 3, 1)])
def test_class_weight_counts_the_labelled_hypotheses(r, d, b):
    """Eq. 4.8's multiplicative weight r!/(b! f!) is the number of TO-MHT hypotheses in the class."""
    model = CountModel(p_d=0.7, p_chi=0.1, lambda_b=1.0, lambda_fa=2.0)
    chi, d_, b_ = [0, 0], [0, d], [d, b]  # scan 0: d births detected; scan 1: the counts under test
    r_seq = [d, r]
    w = count_objective(r_seq, chi, d_, b_, model) - count_objective(r_seq, chi, d_, b_, model, equivalence_class=False)
    # scan 0's class holds one labelled hypothesis (d returns, all births): d!/(d! 0!) = 1
    assert count_labelled_hypotheses(d, 0, d) == 1
    assert math.exp(w) == pytest.approx(count_labelled_hypotheses(r, d, b))


@pytest.mark.parametrize("p_d,K", [(0.95, 1), (0.9, 1), (0.8, 2), (0.7, 3), (0.5, 6), (1.0, 0)])
def test_k_rule_table(p_d, K):
    """Eq. 4.10 with p_χ = 0.01, λ_b = 1 (reconstruction §3.3 table)."""
    assert k_rule(p_d, 0.01, 1.0) == K
    if p_d < 1:  # K is the largest gap whose bridging beats splitting (join/split ratio >= 1)
        ratio = lambda g: (1 - 0.01) ** (g + 1) * (1 - p_d) ** g / (1.0 * 0.01)  # noqa: E731
        assert ratio(K) >= 1 and ratio(K + 1) < 1


def test_k_rule_zero_when_no_gap_qualifies():
    assert k_rule(0.9, 0.5, 1.0) == 0  # λ_b p_χ = 0.5 > (1 − p_χ) already at g = 0


def test_track_score_is_the_class_objective_of_one_track():
    """Eq. 4.11 times the measurement values equals J of the single-track count sequence."""
    model = CountModel(p_d=0.8, p_chi=0.02, lambda_b=0.5, lambda_fa=4.0)
    r = np.array([0, 2, 1, 0, 3, 1, 0, 0])
    # one track born at scan 1, detected at scans 1, 2, 4, missed at 3, dies before scan 6
    chi = [0, 0, 0, 0, 0, 0, 1, 0]
    d = [0, 0, 1, 0, 1, 0, 0, 0]
    b = [0, 1, 0, 0, 0, 0, 0, 0]
    J = count_objective(r, chi, d, b, model)
    # track spans scans 1..5 (N = 5) with M = 3 detections and one more live scan (5) missed
    N, M = 5, 3
    ell = track_log_score(N, M, model, starts_at_data_start=False, reaches_data_end=False)
    ell += sum(math.log(r[k] / model.lambda_fa) for k in (1, 2, 4))
    assert J == pytest.approx(ell)


def test_classical_mht_returns_the_null_solution_in_the_fig_4_2_setting():
    """λ_fa = 10: every track's likelihood ratio is < 1, so the MAP hypothesis has no tracks."""
    real = simulate_cardinality(n_scans=250, p_chi=0.01, lambda_b=1.0, p_d=0.9, lambda_fa=10.0, rng=11)
    mht = ClassicalCountMHT(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=10.0, max_alive=2 * int(real.r.max()))
    for rk in real.r:
        mht.step(int(rk))
    assert np.all(mht.estimates() == 0)
    tracker = CardinalityTracker(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=10.0)
    for rk in real.r:
        tracker.step(int(rk))
    n_hat = tracker.estimates()
    # the class MAP tracks most of the ≈100 targets (it underestimates: long tracks, §4)
    assert 0.6 * real.n_true.mean() < n_hat.mean() < real.n_true.mean()
    assert np.abs(n_hat - real.n_true).mean() < 0.2 * real.n_true.mean()


def test_classical_mht_is_not_always_null():
    """With rare false alarms the classical MAP does hold tracks (the null result is not built in)."""
    model = CountModel(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=0.05)
    real = simulate_cardinality(n_scans=40, p_chi=0.01, lambda_b=1.0, p_d=0.9, lambda_fa=0.05, rng=2)
    sol = exact_count_dp(real.r, model, equivalence_class=False, max_alive=2 * int(real.r.max()))
    assert sol.n.mean() > 0.8 * real.n_true.mean()


def test_tracker_surface_matches_batch_extraction_and_handles_empty_data():
    model = dict(p_d=0.85, p_chi=0.02, lambda_b=1.0, lambda_fa=5.0)
    tracker = CardinalityTracker(**model)
    assert tracker.estimates().shape == (0,)
    real = simulate_cardinality(n_scans=50, p_chi=0.02, lambda_b=1.0, p_d=0.85, lambda_fa=5.0, rng=4)
    for rk in real.r:
        tracker.step(int(rk))
    batch = tetris_extract(real.r, CountModel(**model))
    np.testing.assert_array_equal(tracker.estimates(), batch.n)
    assert len(tracker.tracks()) == len(batch.tracks)
    zeros = np.zeros(10, dtype=int)
    assert np.all(tetris_extract(zeros, CountModel(**model)).n == 0)
    assert exact_count_dp(zeros, CountModel(**model)).J == 0.0
    assert exact_count_dp([], CountModel(**model)).n.shape == (0,)


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(p_d=0.0, p_chi=0.01, lambda_b=1.0, lambda_fa=1.0), "p_d"),
        (dict(p_d=0.9, p_chi=1.0, lambda_b=1.0, lambda_fa=1.0), "p_chi"),
        (dict(p_d=0.9, p_chi=0.01, lambda_b=-1.0, lambda_fa=1.0), "lambda_b"),
        (dict(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=0.0), "lambda_fa"),
    ],
)
def test_bad_parameters_are_rejected(kwargs, match):
    with pytest.raises(ValueError, match=match):
        CountModel(**kwargs)


def test_bad_counts_are_rejected():
    model = CountModel(0.9, 0.01, 1.0, 10.0)
    with pytest.raises(ValueError, match="non-negative integers"):
        tetris_extract([1, -1, 2], model)
    with pytest.raises(ValueError, match="non-negative integers"):
        exact_count_dp([1, 1.5], model)
    with pytest.raises(ValueError, match="infeasible"):
        count_objective([1, 1], [1, 0], [0, 0], [0, 0], model)
    with pytest.raises(ValueError, match="r_k"):
        CardinalityTracker(0.9, 0.01, 1.0, 10.0).step(-2)


def test_scenario_statistics():
    """Steady-state population λ_b/p_χ, detections Binomial(n, p_d), false alarms Poisson(λ_fa)."""
    runs = [simulate_cardinality(n_scans=60, p_chi=0.05, lambda_b=2.0, p_d=0.7, lambda_fa=3.0, rng=s) for s in range(300)]
    n = np.array([r.n_true for r in runs], dtype=float)
    det = np.array([r.n_detected for r in runs], dtype=float)
    fa = np.array([r.n_false for r in runs], dtype=float)
    # steady state mean 40 at every scan; the per-run average has std ≈ 40**0.5 / sqrt(300)
    assert n.mean() == pytest.approx(40.0, abs=5 * np.sqrt(40 / 300))
    assert det.sum() / n.sum() == pytest.approx(0.7, abs=0.005)
    assert fa.mean() == pytest.approx(3.0, abs=5 * np.sqrt(3.0 / fa.size))
    empty = simulate_cardinality(n_scans=5, p_chi=0.05, lambda_b=0.0, p_d=0.7, lambda_fa=0.0, rng=0, start="empty")
    assert np.all(empty.n_true == 0) and np.all(empty.r == 0)


def test_monte_carlo_driver_and_summary():
    """Per-run errors pool into the table; the row-DP gap is never negative (DP is the optimum)."""
    from hypotrack.experiments.cardinality.run import (
        cardinality_monte_carlo,
        monte_carlo_table,
        summarise_cardinality,
    )

    params = dict(n_scans=40, p_chi=0.05, lambda_b=1.0, p_d=0.9, lambda_fa=3.0)
    res = cardinality_monte_carlo(n_runs=6, seed=5, **params)
    assert np.all(res["J_gap_row_dp"] >= -1e-9) and np.all(res["J_gap_group"] >= -1e-9)
    errors, optimality = summarise_cardinality(monte_carlo_table(res))
    e = errors.set_index("method")
    assert e.loc["cardinality_tracker", "mean_abs_error"] == pytest.approx(res["mean_abs_error"]["cardinality_tracker"].mean())
    assert e.loc["classical_mht", "n_runs"] == 6
    o = optimality.set_index("variant")
    assert o.loc["cardinality_tracker", "worst_gap"] == pytest.approx(res["J_gap_row_dp"].max())
    again = cardinality_monte_carlo(n_runs=6, seed=5, **params)
    np.testing.assert_array_equal(again["mean_n_true"], res["mean_n_true"])  # seeded: reproducible

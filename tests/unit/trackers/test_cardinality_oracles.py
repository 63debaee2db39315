"""Cardinality tracking against independent oracles: the objective written out term by term,
exhaustive search over every feasible count sequence, and hand-worked Tetris extractions."""

import math

import numpy as np
import pytest

from hypotrack.trackers.cardinality import (
    CardinalityTracker,
    ClassicalCountMHT,
    CountModel,
    Track,
    alive_from_counts,
    check_counts,
    count_objective,
    counts_from_tracks,
    exact_count_dp,
    k_rule,
    tetris_extract,
    track_log_score,
)

MODELS = [
    CountModel(p_d=0.7, p_chi=0.2, lambda_b=0.6, lambda_fa=1.5),
    CountModel(p_d=0.9, p_chi=0.05, lambda_b=1.0, lambda_fa=0.3),
    CountModel(p_d=1.0, p_chi=0.3, lambda_b=0.8, lambda_fa=0.7),
    CountModel(p_d=0.5, p_chi=0.4, lambda_b=2.0, lambda_fa=4.0),
]


def reference_objective(r, chi, d, b, m: CountModel, equivalence_class=True):
    """J written from the module docstring, one scan at a time, with plain math (no library code)."""
    tau, J = 0, 0.0
    for k in range(len(r)):
        f = r[k] - d[k] - b[k]
        surv = tau - chi[k]
        mu = m.lambda_b / m.p_chi if k == 0 else m.lambda_b
        misses = surv - d[k]
        term = (d[k] + b[k]) * math.log(m.p_d / m.lambda_fa) + b[k] * math.log(mu)
        if misses:
            term += misses * math.log(1 - m.p_d) if m.p_d < 1 else -math.inf
        term += chi[k] * math.log(m.p_chi) + surv * math.log(1 - m.p_chi)
        if equivalence_class:
            term += math.log(math.factorial(r[k]) / (math.factorial(b[k]) * math.factorial(f)))
        J += term
        tau = surv + b[k]
    return J


def feasible_sequences(r, cap=None):
    """Every (chi, d, b) sequence with chi <= tau, d <= tau - chi, d + b <= r (and tau <= cap)."""

    def rec(k, tau):
        if k == len(r):
            yield (), (), ()
            return
        for chi in range(tau + 1):
            for d in range(tau - chi + 1):
                for b in range(r[k] - d + 1):
                    nxt = tau - chi + b
                    if cap is not None and nxt > cap:
                        continue
                    for c2, d2, b2 in rec(k + 1, nxt):
                        yield (chi,) + c2, (d,) + d2, (b,) + b2

    yield from rec(0, 0)


@pytest.mark.parametrize("r", [[2, 3, 1], [1, 0, 2, 1], [3, 1, 2], [0, 2, 2, 0]])
@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("ec", [True, False])
def test_exact_dp_is_the_exhaustive_maximum(r, model, ec):
    """The DP optimum equals the best of all feasible count sequences, and its path scores J."""
    best = max(reference_objective(r, *s, model, ec) for s in feasible_sequences(r))
    sol = exact_count_dp(r, model, equivalence_class=ec)
    assert sol.J == pytest.approx(best, abs=1e-9)
    assert reference_objective(r, sol.chi, sol.d, sol.b, model, ec) == pytest.approx(sol.J, abs=1e-9)
    np.testing.assert_array_equal(sol.f, np.asarray(r) - sol.d - sol.b)
    np.testing.assert_array_equal(sol.n, np.cumsum(sol.b - sol.chi))
    assert not sol.cap_reached


@pytest.mark.parametrize("cap", [0, 1, 2])
def test_capped_dp_is_the_exhaustive_maximum_under_the_cap(cap):
    model = CountModel(p_d=0.9, p_chi=0.05, lambda_b=1.0, lambda_fa=0.3)
    r = [2, 3, 3, 1]
    best = max(reference_objective(r, *s, model) for s in feasible_sequences(r, cap=cap))
    sol = exact_count_dp(r, model, max_alive=cap)
    assert sol.J == pytest.approx(best, abs=1e-9)
    assert sol.n.max(initial=0) <= cap
    assert sol.cap_reached  # the optimal path touches the cap (rare false alarms: 2 targets unconstrained)
    assert exact_count_dp(r, model).n.max() == 2
    assert not exact_count_dp(r, model, max_alive=3).cap_reached
    assert not exact_count_dp(r, model, max_alive=50).cap_reached


def test_count_objective_equals_the_term_by_term_sum_on_every_feasible_sequence():
    r = [2, 1, 2]
    seqs = list(feasible_sequences(r))
    assert len(seqs) > 100
    for model in MODELS:
        for ec in (True, False):
            for s in seqs[::7]:
                assert count_objective(r, *s, model, equivalence_class=ec) == pytest.approx(
                    reference_objective(r, *s, model, ec), abs=1e-9
                )


@pytest.mark.parametrize(
    "chi,d,b",
    [([0, 2, 0], [0, 0, 0], [1, 0, 0]),  # two terminations, one target
     ([0, 0, 0], [0, 2, 0], [1, 0, 0]),  # two detections, one survivor
     ([0, 0, 0], [0, 1, 0], [1, 2, 0])],  # three returns explained, two measured
)
def test_infeasible_counts_name_the_scan(chi, d, b):
    with pytest.raises(ValueError, match="infeasible counts at scan 1"):
        count_objective([1, 2, 0], chi, d, b, MODELS[0])


def test_count_objective_rejects_unequal_lengths_and_bad_counts():
    with pytest.raises(ValueError, match="^r, chi, d and b must have the same length$"):
        count_objective([1, 1], [0, 0], [0, 0], [0], MODELS[0])
    with pytest.raises(ValueError, match="^r, chi, d and b must have the same length$"):
        count_objective([1, 1], [0], [0, 0], [0, 0], MODELS[0])
    with pytest.raises(ValueError, match="r must be a 1-D sequence of counts"):
        check_counts([[1, 2]])
    with pytest.raises(ValueError, match="d must hold non-negative integers"):
        count_objective([1], [0], [0.5], [0], MODELS[0])
    np.testing.assert_array_equal(check_counts([0.0, 3.0]), [0, 3])
    assert check_counts([2.0]).dtype == np.int64


@pytest.mark.parametrize("start,end", [(True, True), (True, False), (False, True), (False, False)])
def test_track_score_is_eq_4_11(start, end):
    """L = λ_b p_χ p_d^M (1 − p_d)^(N−M) (1 − p_χ)^(N−1); λ_b/p_χ at the data start; no p_χ at its end."""
    m = CountModel(p_d=0.8, p_chi=0.1, lambda_b=0.5, lambda_fa=2.0)
    N, M = 5, 3
    L = (0.5 / 0.1 if start else 0.5) * 0.8**M * 0.2 ** (N - M) * 0.9 ** (N - 1) * (1 if end else 0.1)
    got = track_log_score(N, M, m, starts_at_data_start=start, reaches_data_end=end)
    assert got == pytest.approx(math.log(L), rel=1e-12)


def test_track_score_with_certain_detection_and_its_bounds():
    m = CountModel(p_d=1.0, p_chi=0.2, lambda_b=0.5, lambda_fa=2.0)
    got = track_log_score(3, 3, m, starts_at_data_start=False, reaches_data_end=False)
    assert got == pytest.approx(math.log(0.5 * 0.2 * 0.8**2))
    assert track_log_score(1, 1, m, starts_at_data_start=False, reaches_data_end=True) == pytest.approx(math.log(0.5))
    assert track_log_score(2, 1, m, starts_at_data_start=False, reaches_data_end=True) == -math.inf
    with pytest.raises(ValueError, match=r"^n_meas must be an integer in \[1, 2\]"):
        track_log_score(2, 3, m, starts_at_data_start=False, reaches_data_end=True)
    with pytest.raises(ValueError, match=r"^n_scans must be an integer in \[1, inf\]"):
        track_log_score(0, 1, m, starts_at_data_start=False, reaches_data_end=True)
    with pytest.raises(ValueError, match=r"^n_meas must be an integer in \[1, 2\]"):
        track_log_score(2, 0, m, starts_at_data_start=False, reaches_data_end=True)


def test_k_rule_boundary_is_inclusive_and_needs_two_survival_factors():
    # λ_b p_χ equal to (1 − p_d)(1 − p_χ)² exactly: g = 1 qualifies (>=), g = 2 does not.
    p_d, p_chi = 0.5, 0.5
    lam = (1 - p_d) * (1 - p_chi) ** 2 / p_chi  # 0.25
    assert k_rule(p_d, p_chi, lam) == 1
    assert k_rule(p_d, p_chi, lam * 1.01) == 0
    assert k_rule(0.5, 0.1, 1.0) == 2  # 0.25 · 0.9³ = 0.182 >= 0.1 > 0.125 · 0.9⁴ = 0.082
    assert k_rule(0.9, 0.5, 0.4) == 0  # 0.1 · 0.25 = 0.025 < 0.2: only g = 0 qualifies


def model_tetris():
    return CountModel(p_d=0.9, p_chi=0.1, lambda_b=0.2, lambda_fa=0.5)


def test_tetris_one_row_without_gaps_is_one_track():
    """r = 1 1 1 1: one track from the data start to its end, ℓ = ln(λ_b/p_χ) + 4 ln p_d + 3 ln(1−p_χ) + 4 ln(1/λ_fa)."""
    m = model_tetris()
    res = tetris_extract([1, 1, 1, 1], m)
    ell = math.log(0.2 / 0.1) + 4 * math.log(0.9) + 3 * math.log(0.9) + 4 * math.log(1 / 0.5)
    assert res.tracks == [Track(1, 0, 3, (0, 1, 2, 3), pytest.approx(ell))]
    assert res.J == pytest.approx(ell)
    np.testing.assert_array_equal(res.n, [1, 1, 1, 1])
    assert res.K == k_rule(0.9, 0.1, 0.2) == 1  # 0.1 · 0.9² = 0.081 >= 0.02 > 0.01 · 0.9³


def test_tetris_bridges_a_gap_and_splits_beyond_k():
    m = CountModel(p_d=0.9, p_chi=0.1, lambda_b=0.2, lambda_fa=0.05)  # K = 1
    res = tetris_extract([0, 1, 0, 1], m)
    # born at scan 1 (not the data start), missed at 2, reaches the end
    ell = math.log(0.2) + 2 * math.log(0.9) + math.log(0.1) + 2 * math.log(0.9) + 2 * math.log(20.0)
    assert [(t.start, t.end, t.scans) for t in res.tracks] == [(1, 3, (1, 3))]
    assert res.J == pytest.approx(ell)
    np.testing.assert_array_equal(res.n, [0, 1, 1, 1])
    # two empty scans exceed K: the pieces are never joined, each decided alone
    far = tetris_extract([1, 1, 0, 0, 1, 1], m)
    assert [(t.start, t.end) for t in far.tracks] == [(0, 1), (4, 5)]


def test_tetris_second_row_pays_the_birth_coupling_and_the_reduced_value():
    """r = 2 2: row 2 explains (r − 1)/λ_fa per return and shares its birth scan with row 1 (1/2!)."""
    m = model_tetris()
    res = tetris_extract([2, 2], m)
    row1 = math.log(0.2 / 0.1) + 2 * math.log(0.9) + math.log(0.9) + 2 * math.log(2 / 0.5)
    row2 = math.log(0.2 / 0.1) - math.log(2) + 2 * math.log(0.9) + math.log(0.9) + 2 * math.log(1 / 0.5)
    assert [(t.row, t.start, t.end) for t in res.tracks] == [(1, 0, 1), (2, 0, 1)]
    assert [t.log_score for t in res.tracks] == pytest.approx([row1, row2])
    assert res.J == pytest.approx(row1 + row2)
    assert res.J == pytest.approx(reference_objective([2, 2], [0, 0], [0, 2], [2, 0], m))


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("variant", ["row_dp", "group"])
def test_tetris_score_is_the_class_objective_of_its_counts(seed, variant):
    """Σ ℓ of the extracted tracks = J of their count sequence (reconstruction §3.4), ≤ the exact optimum."""
    rng = np.random.default_rng(seed)
    m = MODELS[seed % 2]
    r = rng.poisson(2.0, size=9)
    res = tetris_extract(r, m, variant=variant)
    chi, d, b = counts_from_tracks(res.tracks, len(r))
    assert res.J == pytest.approx(reference_objective(r, chi, d, b, m), abs=1e-9)
    assert res.J <= exact_count_dp(r, m).J + 1e-9
    np.testing.assert_array_equal(res.n, alive_from_counts(chi, b))
    for t in res.tracks:
        assert r[list(t.scans)].min() >= t.row and t.scans[0] == t.start and t.scans[-1] == t.end


def test_counts_from_tracks_by_hand():
    tracks = [Track(1, 0, 2, (0, 2), 0.0), Track(2, 1, 4, (1, 3, 4), 0.0), Track(1, 3, 3, (3,), 0.0)]
    chi, d, b = counts_from_tracks(tracks, 5)
    np.testing.assert_array_equal(b, [1, 1, 0, 1, 0])
    np.testing.assert_array_equal(d, [0, 0, 1, 1, 1])
    np.testing.assert_array_equal(chi, [0, 0, 0, 1, 1])  # tracks ending at 2 and 3 terminate at 3 and 4; 4 is the end
    assert [a.dtype for a in (chi, d, b)] == [np.int64] * 3
    with pytest.raises(ValueError, match=r"^n_scans must be an integer in \[0, inf\]"):
        counts_from_tracks(tracks, -1)
    assert [a.shape for a in counts_from_tracks([], 0)] == [(0,)] * 3  # no scans, no tracks


def test_count_trackers_by_hand_and_bad_options():
    tr = CardinalityTracker(0.9, 0.1, 0.2, 0.5)
    for rk in (1, 1, 1, 1):
        tr.step(rk)
    np.testing.assert_array_equal(tr.counts, [1, 1, 1, 1])
    np.testing.assert_array_equal(tr.estimates(), [1, 1, 1, 1])
    assert [(t.start, t.end) for t in tr.tracks()] == [(0, 3)]
    tr.step(0)  # the cache is re-solved after a new scan
    np.testing.assert_array_equal(tr.estimates(), tetris_extract([1, 1, 1, 1, 0], tr.model).n)
    group = CardinalityTracker(0.66, 0.2, 1.0, 0.55, variant="group")
    for rk in (1, 1, 1, 1, 1, 0, 1, 1):
        group.step(rk)
    assert [(t.start, t.end) for t in group.tracks()] == [(0, 7)]  # row_dp: (0, 0) and (7, 7)
    np.testing.assert_array_equal(group.estimates(), [1] * 8)
    assert group.estimates().dtype == np.int64
    with pytest.raises(ValueError, match="variant"):
        CardinalityTracker(0.9, 0.1, 0.2, 0.5, variant="rows")
    with pytest.raises(ValueError, match="variant"):
        tetris_extract([1], model_tetris(), variant="rows")
    mht = ClassicalCountMHT(0.9, 0.05, 1.0, 0.3, max_alive=1)
    for rk in (2, 3, 3, 1):
        mht.step(rk)
    assert mht.max_alive == 1
    np.testing.assert_array_equal(mht.estimates(), exact_count_dp([2, 3, 3, 1], mht.model, equivalence_class=False, max_alive=1).n)
    assert mht.estimates().max() == 1
    with pytest.raises(ValueError, match="max_alive"):
        ClassicalCountMHT(0.9, 0.05, 1.0, 0.3, max_alive=-1)
    assert ClassicalCountMHT(0.9, 0.05, 1.0, 0.3).max_alive is None


def reference_row_score(ks, a, i, m: CountModel, T):
    """Row-1 track over returns ks[a..i] (one return per scan): Eq. 4.11 times 1/λ_fa per return."""
    start, end, M = ks[a], ks[i], i - a + 1
    N = end - start + 1
    v = math.log(m.lambda_b / m.p_chi if start == 0 else m.lambda_b)
    v += M * math.log(m.p_d) + (N - M) * (math.log(1 - m.p_d) if N > M else 0.0) + (N - 1) * math.log(1 - m.p_chi)
    return v + (math.log(m.p_chi) if end < T - 1 else 0.0) + M * math.log(1 / m.lambda_fa)


def best_disjoint_intervals(ks, m, T):
    """Exhaustive: the best set of disjoint runs of consecutive returns (each a track, the rest false alarms)."""
    best = (0.0, [])

    def rec(pos, acc, chosen):
        nonlocal best
        if pos >= len(ks):
            if acc > best[0] + 1e-12:
                best = (acc, chosen)
            return
        rec(pos + 1, acc, chosen)
        for i in range(pos, len(ks)):
            rec(i + 1, acc + reference_row_score(ks, pos, i, m, T), chosen + [(int(ks[pos]), int(ks[i]))])

    rec(0, 0.0, [])
    return best


@pytest.mark.parametrize("seed", range(4))
def test_single_row_extraction_is_the_exhaustive_best_per_group(seed):
    """r ∈ {0, 1}: row_dp = the best disjoint tracks of each K-group; group = the whole group iff ℓ > 0."""
    rng = np.random.default_rng(seed)
    n_split = 0
    for _ in range(12):
        m = CountModel(*rng.uniform([0.3, 0.05, 0.2, 0.1], [0.9, 0.4, 2.0, 1.5]))
        r = (rng.random(8) < 0.6).astype(np.int64)
        T, K = len(r), k_rule(m.p_d, m.p_chi, m.lambda_b)
        present = np.flatnonzero(r)
        groups = np.split(present, np.flatnonzero(np.diff(present) - 1 > K) + 1) if len(present) else []
        want_dp, want_group, J_dp, J_group = [], [], 0.0, 0.0
        for ks in groups:
            J, chosen = best_disjoint_intervals(ks, m, T)
            want_dp += chosen
            J_dp += J
            whole = reference_row_score(ks, 0, len(ks) - 1, m, T)
            if whole > 0:
                want_group.append((int(ks[0]), int(ks[-1])))
                J_group += whole
        dp, group = tetris_extract(r, m), tetris_extract(r, m, variant="group")
        assert [(t.start, t.end) for t in dp.tracks] == want_dp
        assert dp.J == pytest.approx(J_dp, abs=1e-9)
        assert [(t.start, t.end) for t in group.tracks] == want_group
        assert group.J == pytest.approx(J_group, abs=1e-9)
        n_split += want_dp != want_group
    assert n_split >= 2  # the two variants really differ on these draws


def test_runs_beyond_k_stay_apart_even_when_joining_would_score_higher():
    """K = 2 (p_d = 0.5, p_χ = 0.1, λ_b = 1): a gap of 3 misses splits both rows, although joining row 2
    would avoid its second birth's 1/2! coupling and beat the split (the exact DP is higher)."""
    m = CountModel(0.5, 0.1, 1.0, 0.1)
    r = [2, 2, 0, 0, 0, 2, 2]
    res = tetris_extract(r, m)
    assert res.K == 2
    assert [(t.row, t.start, t.end) for t in res.tracks] == [(1, 0, 1), (1, 5, 6), (2, 0, 1), (2, 5, 6)]
    assert res.J < exact_count_dp(r, m).J - 0.1
    assert res.n.dtype == np.int64


def test_a_zero_score_track_is_not_extracted():
    """p_d = 1, λ_b = p_χ, λ_fa = 1: a one-scan track at the only scan scores ℓ = 0 exactly; kept only if ℓ > 0."""
    m = CountModel(1.0, 0.5, 0.5, 1.0)
    assert track_log_score(1, 1, m, starts_at_data_start=True, reaches_data_end=True) == 0.0
    for variant in ("row_dp", "group"):
        res = tetris_extract([1], m, variant=variant)
        assert res.tracks == [] and res.J == 0.0
    for variant in ("row_dp", "group"):  # no returns at all: no rows to process
        res = tetris_extract([0, 0, 0], m, variant=variant)
        assert res.tracks == [] and res.n.tolist() == [0, 0, 0]


@pytest.mark.parametrize("name,args", [("chi", ([0.5, 0], [0, 0], [1, 0])), ("b", ([0, 0], [0, 0], [-1, 0]))])
def test_count_objective_names_the_bad_sequence(name, args):
    with pytest.raises(ValueError, match=f"^{name} must hold non-negative integers"):
        count_objective([1, 1], *args, MODELS[0])


def test_detections_bounded_by_survivors_after_terminations():
    """τ = 2, χ = 1 leaves one survivor: two detections are infeasible."""
    with pytest.raises(ValueError, match="infeasible counts at scan 1"):
        count_objective([2, 2], [0, 1], [0, 2], [2, 0], MODELS[0])


def test_vanishing_detection_probability_does_not_overflow():
    """p_d = 1e-310: ln(p_d / (λ_fa (1 − p_d))) ≈ −714 (e^714 overflows), so no survivor is worth detecting."""
    m = CountModel(1e-310, 0.2, 0.5, 1.0)
    sol = exact_count_dp([1, 2, 1], m)
    assert np.all(sol.d == 0) and np.isfinite(sol.J)
    assert sol.J == pytest.approx(max(reference_objective([1, 2, 1], *s, m) for s in feasible_sequences([1, 2, 1])))


def test_exact_dp_rejects_a_negative_cap():
    with pytest.raises(ValueError, match=r"max_alive must be an integer in \[0, inf\]"):
        exact_count_dp([1, 2], MODELS[0], max_alive=-1)


def test_empty_data_and_integer_solutions():
    sol = exact_count_dp([], MODELS[0])
    assert sol.J == 0.0 and not sol.cap_reached
    for a in (sol.chi, sol.d, sol.b, sol.f, sol.n):
        assert a.shape == (0,)
    sol = exact_count_dp([2, 0, 3], MODELS[1])
    for a in (sol.chi, sol.d, sol.b, sol.f, sol.n):
        assert a.dtype == np.int64


@pytest.mark.parametrize("r", [[0, 0, 2, 2], [0, 0, 0, 2]])
def test_cap_reached_late_in_the_data(r):
    """The optimal path meets the cap only after the first scan (or only at the last): still reported."""
    model = CountModel(p_d=0.9, p_chi=0.05, lambda_b=1.0, lambda_fa=0.3)
    sol = exact_count_dp(r, model, max_alive=1)
    assert sol.n.max() == 1 and sol.cap_reached


def test_cap_not_reached_by_the_null_solution():
    model = CountModel(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=10.0)
    sol = exact_count_dp([1, 2, 1, 0], model, equivalence_class=False, max_alive=1)
    assert np.all(sol.n == 0) and sol.J == 0.0 and not sol.cap_reached


@pytest.mark.parametrize("model,r,want", [
    # adjacent one-scan tracks in one row (a track ends where the next begins)
    (CountModel(0.93, 0.45, 2.5, 0.75), [2, 1, 1, 2], [(1, 0, 0), (1, 1, 1), (1, 2, 2), (1, 3, 3), (2, 0, 0), (2, 3, 3)]),
    # a lower-row track ending before its group does: the next scan's return stays for the rows above
    (CountModel(0.45, 0.36, 2.15, 0.33), [4, 3, 4], [(1, 0, 0), (1, 1, 1), (1, 2, 2), (2, 0, 2), (3, 0, 2), (4, 2, 2)]),
])
def test_multi_row_extractions(model, r, want):
    res = tetris_extract(r, model)
    assert [(t.row, t.start, t.end) for t in res.tracks] == want
    chi, d, b = counts_from_tracks(res.tracks, len(r))
    assert res.J == pytest.approx(reference_objective(r, chi, d, b, model), abs=1e-9)


@pytest.mark.parametrize("model", MODELS + [CountModel(0.5, 0.3, 20.0, 2.0), CountModel(0.6, 0.1, 1.0, 0.5)])
@pytest.mark.parametrize("ec", [True, False])
def test_best_detections_maximise_the_scan_term(model, ec):
    """For every (r, s, b): the chosen d maximises the scan term over 0 ≤ d ≤ min(s, r − b) (brute force)."""
    from hypotrack.trackers.cardinality import _best_detections

    for r in range(6):
        s = np.arange(6)[:, None]
        b = np.arange(r + 1)[None, :]
        d = _best_detections(model, r, s, b, ec)
        for si in range(6):
            for bi in range(r + 1):
                def term(dd):
                    return reference_objective([si, r], [0, 0], [0, dd], [si, bi], model, ec)

                best = max(term(dd) for dd in range(min(si, r - bi) + 1))
                assert 0 <= d[si, bi] <= min(si, r - bi)
                assert term(int(d[si, bi])) == pytest.approx(best, abs=1e-9)


def test_capped_dp_path_scores_its_j_and_a_full_cap_is_not_binding():
    model = CountModel(p_d=0.9, p_chi=0.05, lambda_b=1.0, lambda_fa=0.3)
    for cap in (1, 2):
        sol = exact_count_dp([2, 3, 3, 1], model, max_alive=cap)
        assert reference_objective([2, 3, 3, 1], sol.chi, sol.d, sol.b, model) == pytest.approx(sol.J, abs=1e-9)
    births = CountModel(p_d=0.9, p_chi=0.05, lambda_b=5.0, lambda_fa=10.0)
    sol = exact_count_dp([2], births)  # both returns are births: the live count reaches Σ r
    assert sol.n.tolist() == [2] and not sol.cap_reached


def test_count_model_stores_validated_floats_and_names_bad_parameters():
    m = CountModel(1, 0.5, 2, 3)
    assert [type(v) for v in (m.p_d, m.p_chi, m.lambda_b, m.lambda_fa)] == [float] * 4
    assert set(vars(m)) == {"p_d", "p_chi", "lambda_b", "lambda_fa"}
    for kwargs, msg in [(dict(p_d=0.0), r"^p_d must lie in \(0, 1\]"), (dict(p_chi=1.0), r"^p_chi must lie in \(0, 1\)"),
                        (dict(lambda_b=0.0), "^lambda_b must be a finite number > 0"),
                        (dict(lambda_fa=-1.0), "^lambda_fa must be a finite number > 0")]:
        with pytest.raises(ValueError, match=msg):
            CountModel(**{**dict(p_d=0.9, p_chi=0.1, lambda_b=1.0, lambda_fa=1.0), **kwargs})
    with pytest.raises(ValueError, match="^r must be finite"):
        check_counts([1.0, np.nan])


def test_certain_detection_scores_without_warnings():
    """p_d = 1: 0 · ln(1 − p_d) is taken as 0 without a RuntimeWarning."""
    import warnings

    m = CountModel(1.0, 0.2, 1.0, 0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        J = count_objective([1, 1], [0, 0], [0, 1], [1, 0], m)
        exact_count_dp([1, 1, 2], m)
    assert J == pytest.approx(reference_objective([1, 1], [0, 0], [0, 1], [1, 0], m))


@pytest.mark.parametrize("model,r,cap", [
    (CountModel(0.81, 0.38, 2.6, 2.2), [2, 4, 0], 1),  # at the cap, one target terminates
    (CountModel(0.64, 0.19, 1.0, 2.24), [3, 2], None),  # λ_fa (1 − p_d) > p_d: some survivors go undetected
    (CountModel(0.59, 0.11, 1.7, 1.9), [2, 2, 5, 1], None),
])
def test_exact_dp_on_cases_with_partial_detection_and_a_binding_cap(model, r, cap):
    best = max(reference_objective(r, *s, model) for s in feasible_sequences(r, cap=cap))
    sol = exact_count_dp(r, model, max_alive=cap)
    assert sol.J == pytest.approx(best, abs=1e-9)
    assert reference_objective(r, sol.chi, sol.d, sol.b, model) == pytest.approx(sol.J, abs=1e-9)

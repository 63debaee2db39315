"""The GLMB benchmark's scenario, metrics and summary on hand-checked cases."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.experiments.glmb_benchmark.run import (
    DiscreteWhiteNoiseAcceleration,
    benchmark_model,
    make_tracker,
    ospa_parts,
    run_tracker,
    simulate_scans,
    truth_states,
)
from hypotrack.experiments.glmb_benchmark.summary import summary_table

CFG = dict(sigma_r=10.0, half_width=1000.0, p_D=0.98, clutter_rate=30.0, sigma_v=5.0, p_S=0.99, r_birth=0.03,
           birth_means=[[0.1, 0.1, 0, 0], [400, -600, 0, 0]], birth_std=10.0, n_scans=6)


def test_discrete_white_noise_acceleration_q_by_hand():
    Q = DiscreteWhiteNoiseAcceleration(5.0).Q(2.0)
    # G = [T²/2; T] per axis: var x = 25 * 4 = 100, cov(x, vx) = 25 * 2 * 2 = 100, var vx = 25 * 4 = 100
    np.testing.assert_allclose(Q[[0, 0, 2], [0, 2, 2]], [100.0, 100.0, 100.0])
    assert Q[0, 1] == 0.0 and Q[0, 3] == 0.0


def test_truth_births_deaths_and_noiseless_motion():
    rows = [[1, 3, 0.0, 0.0, 1.0, -2.0], [2, 10, 5.0, 5.0, 0.0, 1.0]]
    truth = truth_states(rows, 4)
    assert [len(x) for x, _ in truth] == [1, 2, 1, 1]  # object 0 dies at scan 3, object 1 born at 2
    np.testing.assert_allclose(truth[1][0][0], [1.0, -2.0, 1.0, -2.0])  # one scan after its birth
    np.testing.assert_allclose(truth[3][0][0], [5.0, 7.0, 0.0, 1.0])
    np.testing.assert_array_equal(truth[3][1], [1])


def test_ospa_parts_by_hand():
    X = np.array([[0.0, 0.0], [10.0, 0.0]])
    Y = np.array([[3.0, 4.0]])
    total, loc, card = ospa_parts(X, Y, 100.0)
    assert card == pytest.approx(50.0)  # c |n - m| / max(n, m)
    assert loc == pytest.approx(2.5)  # distance 5 of the one pair, divided by 2
    assert total == pytest.approx(52.5)
    assert ospa_parts(np.zeros((0, 2)), np.zeros((0, 2)), 100.0) == (0.0, 0.0, 0.0)


def test_glmb_tracks_the_two_objects_and_summary_has_standard_errors():
    model = benchmark_model(CFG)
    truth = truth_states([[1, 101, 0.0, 0.0, 5.0, 0.0], [1, 101, 400.0, -600.0, 0.0, 5.0]], 6)
    parts = []
    for run in range(2):
        scans = simulate_scans(model, truth, np.random.default_rng(run))
        tr = make_tracker("glmb", model, {"max_hypotheses": 10, "n_sweeps": 20, "gate_probability": 0.9999999}, run)
        df = run_tracker(tr, scans, truth, 100.0)
        parts.append(df.assign(tracker="glmb", run=run))
    per_scan = pd.concat(parts)
    assert (per_scan.n_est.iloc[-3:] == 2).all()  # both birth terms picked the objects up
    summary, timing = summary_table(per_scan)
    assert summary.loc[0, "n_runs"] == 2 and np.isfinite(summary.loc[0, "ospa_se"])
    assert summary.loc[0, "ospa_mean"] < 30.0


def test_unknown_tracker_kind_is_refused():
    with pytest.raises(ValueError, match="tracker kind"):
        make_tracker("phd", benchmark_model(CFG), {"max_hypotheses": 5}, 0)


def test_stonesoup_gmphd_peer_follows_the_gm_phd_update_by_hand():
    """One return exactly at a birth mean, then an empty scan (Vo & Ma 2006 Eqs. 20-21)."""
    model = benchmark_model(CFG)
    peer = make_tracker("gmphd", model, {}, 0)
    post = peer.step(np.array([[0.1, 0.1]]))
    # birth term 1 predicts the return with N(z; Hm, HPH' + R) = 1 / (2 pi (100 + 100)); term 2 is gated out
    q = 1.0 / (2 * np.pi * 200.0)
    kappa = 30.0 / 2000.0**2
    w = 0.98 * 0.03 * q / (kappa + 0.98 * 0.03 * q)
    # Stone Soup's PHDUpdater drops the undetected part of the birth intensity: the mass is the one update
    assert post.expected_number == pytest.approx(w, rel=1e-9)
    assert w > 0.5 and post.map_estimate.means.shape == (1, 4)
    np.testing.assert_allclose(post.map_estimate.means[0], [0.1, 0.1, 0.0, 0.0], atol=1e-9)
    post = peer.step(np.zeros((0, 2)))
    assert post.expected_number == pytest.approx(0.99 * 0.02 * w, rel=1e-9)  # p_S (1 - p_D) w, missed
    assert post.map_estimate.means.shape == (0, 4)  # below the 0.5 extraction threshold


def test_peer_is_labelled_in_the_summary():
    from hypotrack.experiments.glmb_benchmark.run import implementation_labels, legend_labels

    legend = legend_labels({"a": {"kind": "rfisst", "completion_rounds": 0}, "b": {"kind": "rfisst"},
                            "phd": {"kind": "gmphd"}})
    assert legend == {"a": "a (R-FISST, chain alone)", "b": "b (R-FISST + completion)",
                      "phd": "phd (Stone Soup GM-PHD, peer implementation)"}

    labels = implementation_labels({"glmb": {"kind": "glmb"}, "phd": {"kind": "gmphd"}})
    assert labels == {"glmb": "hypotrack engine", "phd": "Stone Soup GM-PHD, peer implementation"}
    per_scan = pd.DataFrame({"tracker": ["glmb", "phd"] * 2, "run": [0, 0, 1, 1], "scan": 1, "ospa": [1.0, 3.0, 2.0, 5.0],
                             "ospa_loc": 0.0, "ospa_card": 0.0, "n_est": [1, 2, 1, 1], "n_true": 1, "time_s": 0.1})
    summary, _ = summary_table(per_scan, labels)
    assert list(summary.implementation) == ["hypotrack engine", "Stone Soup GM-PHD, peer implementation"]
    assert list(summary.ospa_mean) == [1.5, 4.0] and list(summary.card_err_mean) == [0.0, 0.5]


# ---------------------------------------------------------------- Vo's conventions (gen_truth, extraction, truncation)

VO_TRUTH = [  # the demo's 12 objects, [t_birth, t_death, x, y, vx, vy] (the demo's state order is x, vx, y, vy)
    [1, 70, 0.0, 0.0, 0.0, -10.0], [1, 101, 400.0, -600.0, -10.0, 5.0], [1, 70, -800.0, -200.0, 20.0, -5.0],
    [20, 101, 400.0, -600.0, -7.0, -4.0], [20, 101, 400.0, -600.0, -2.5, 10.0], [20, 101, 0.0, 0.0, 7.5, -5.0],
    [40, 101, -800.0, -200.0, 12.0, 7.0], [40, 101, -200.0, 800.0, 15.0, -10.0],
    [60, 101, -800.0, -200.0, 3.0, 15.0], [60, 101, -200.0, 800.0, -3.0, -15.0],
    [80, 101, 0.0, 0.0, -20.0, -15.0], [80, 101, -200.0, 800.0, 15.0, -5.0],
]


def test_gen_truth_first_scan_is_one_step_past_x_start_and_death_scan_is_included():
    import yaml
    from pathlib import Path

    cfg = yaml.safe_load((Path(__file__).parents[4] / "workflows/config/default.yaml").read_text())["glmb_benchmark"]
    assert cfg["truth"] == VO_TRUTH and cfg["truth_convention"] == "gen_truth"
    truth = truth_states(VO_TRUTH, 100, convention="gen_truth")
    # numbers present, by hand: 3 from scan 1, +3 at 20, +2 at 40, +2 at 60, objects 1 and 3 last seen at 70
    # (tdeath inclusive), +2 at 80, everyone else through scan 100 (tdeath = K + 1 clipped to K)
    expected = [3] * 19 + [6] * 20 + [8] * 20 + [10] * 11 + [8] * 9 + [10] * 21
    assert [len(x) for x, _ in truth] == expected
    assert 0 in truth[69][1] and 2 in truth[69][1] and 0 not in truth[70][1] and 2 not in truth[70][1]
    for i, row in enumerate(VO_TRUTH):
        k = int(row[0])
        x, ids = truth[k - 1]
        first = x[list(ids).index(i)]
        # first scan: F x_start = x_start + v T (T = 1 s), never the birth mean itself
        np.testing.assert_allclose(first, [row[2] + row[4], row[3] + row[5], row[4], row[5]])
    x, ids = truth[99]
    np.testing.assert_allclose(x[list(ids).index(1)][:2], [400.0 - 10.0 * 100, -600.0 + 5.0 * 100])  # F^100 x_start
    old = truth_states(VO_TRUTH, 100, convention="birth_mean")
    assert len(old[69][0]) == 8 and np.allclose(old[0][0][0], [0.0, 0.0, 0.0, -10.0])  # the earlier reading
    with pytest.raises(ValueError, match="truth convention"):
        truth_states(VO_TRUTH, 5, convention="vo")


def test_map_cardinality_extraction_differs_from_the_heaviest_hypothesis_by_hand():
    from hypotrack.experiments.glmb_benchmark.reference import heaviest_index, map_cardinality_index

    # weights 0.40 (two objects), 0.35 and 0.25 (one object each): the heaviest holds two objects, but
    # P(N = 1) = 0.60 > P(N = 2) = 0.40, so the demo takes N = 1 and the heaviest of those, index 1
    lw = np.log([0.40, 0.35, 0.25])
    n = [2, 1, 1]
    assert heaviest_index(lw, n) == 0
    assert map_cardinality_index(lw, n) == 1
    # when the heaviest holds the MAP cardinality the two agree
    assert map_cardinality_index(np.log([0.5, 0.3, 0.2]), [2, 2, 1]) == 0
    # unnormalised log-weights give the same choice
    assert map_cardinality_index(lw - 700.0, n) == 1
    with pytest.raises(ValueError, match="n_objects"):
        map_cardinality_index(lw, [1, 2])


def test_sqrt_allocation_by_hand():
    from hypotrack.experiments.glmb_benchmark.reference import sqrt_allocation

    # sqrt w = 0.8, 0.4, 0.4, 0.2 (sum 1.8): 1000 * 0.8 / 1.8 = 444.4, 222.2, 222.2, 111.1
    np.testing.assert_array_equal(sqrt_allocation(np.log([0.64, 0.16, 0.16, 0.04]), 1000), [444, 222, 222, 111])
    np.testing.assert_array_equal(sqrt_allocation(np.log([0.5, 0.5]), 3), [2, 2])  # 1.5 rounds away from zero
    with pytest.raises(ValueError, match="total_samples"):
        sqrt_allocation([0.0], 0)


def test_sqrt_allocation_filter_on_one_parent_is_the_gibbs_preset_with_total_minus_one_sweeps():
    """From the empty prior there is one parent: it gets every sample (the start and total - 1 sweeps)."""
    model = benchmark_model(CFG)
    truth = truth_states([[1, 101, 0.0, 0.0, 5.0, 0.0]], 2, convention="gen_truth")
    Z = simulate_scans(model, truth, np.random.default_rng(3))[0]
    ref = make_tracker("glmb", model, {"max_hypotheses": 50, "sample_allocation": "sqrt_weight", "total_samples": 40,
                                       "gate_probability": 0.9999999}, 7)
    peer = make_tracker("glmb", model, {"max_hypotheses": 50, "n_sweeps": 39, "gate_probability": 0.9999999}, 7)
    a, b = ref.step(Z), peer.step(Z)
    np.testing.assert_array_equal(a.log_weights, b.log_weights)
    assert len(a.log_weights) > 1
    ref.step(simulate_scans(model, truth, np.random.default_rng(4))[1])  # several parents: runs, weights normalised
    assert np.exp(ref.log_weights).sum() == pytest.approx(1.0)
    with pytest.raises(ValueError, match="total_samples"):
        make_tracker("glmb", model, {"max_hypotheses": 5, "sample_allocation": "sqrt_weight"}, 0)
    with pytest.raises(ValueError, match="sample_allocation"):
        make_tracker("glmb", model, {"max_hypotheses": 5, "sample_allocation": "sqrt", "total_samples": 5}, 0)


def test_blind_control_sees_no_return_and_run_tracker_reports_both_extractions():
    model = benchmark_model(CFG)
    truth = truth_states([[1, 101, 0.0, 0.0, 5.0, 0.0], [1, 101, 400.0, -600.0, 0.0, 5.0]], 6, convention="gen_truth")
    scans = simulate_scans(model, truth, np.random.default_rng(0))
    blind = make_tracker("blind", model, {"max_hypotheses": 10, "n_sweeps": 20, "gate_probability": 0.9999999}, 0)
    df = run_tracker(blind, scans, truth, 100.0)
    assert (df.n_est == 0).all() and (df.n_est_mc == 0).all() and (df.ospa == 100.0).all()
    tr = make_tracker("glmb", model, {"max_hypotheses": 10, "n_sweeps": 20, "gate_probability": 0.9999999}, 0)
    df = run_tracker(tr, scans, truth, 100.0)
    assert {"ospa_mc", "ospa_loc_mc", "ospa_card_mc", "n_est_mc"} <= set(df.columns)
    assert (df.n_est_mc.iloc[-3:] == 2).all()


def _per_scan(tracker, n_true, n_est, runs=1):
    rows = []
    for r in range(runs):
        for k, (t, e) in enumerate(zip(n_true, n_est), start=1):
            rows.append({"tracker": tracker, "run": r, "scan": k, "n_true": t, "n_est": e, "n_est_mc": e})
    return pd.DataFrame(rows)


def test_follow_score_by_hand_and_the_control_decides_the_status():
    from hypotrack.experiments.glmb_benchmark.summary import follow_claims, follow_score

    n_true = [1, 1, 2, 2, 2, 2]
    # lag 2: changes at scans 1 and 3, windows {1, 2} and {3, 4}; outside {5, 6}
    good = _per_scan("good", n_true, [0, 1, 1, 2, 2, 1])  # |error| 0 and 1 outside: mean 0.5; window ends 2, 4: gaps 0
    assert follow_score(good, "good", 2) == (0.5, 0.0)
    slow = _per_scan("slow", n_true, [0, 0, 1, 1, 2, 2])  # outside exact, but scan 2 and 4 still one short
    assert follow_score(slow, "slow", 2) == (0.0, 1.0)
    blind = _per_scan("blind", n_true, [0] * 6)
    perfect = _per_scan("perfect", n_true, n_true)
    per_scan = pd.concat([slow, blind, perfect])
    rows = follow_claims(per_scan, {"perfect": "map_cardinality", "slow": "heaviest"}, "blind", 2, 0.1)
    assert [c.status for c in rows] == ["qualitative", "not reproduced"]
    assert rows[0].control.endswith("-> fails") and rows[0].key == "FollowsPerfect"
    # a control that passes too leaves the check without power: uninformative
    rows = follow_claims(per_scan, {"perfect": "heaviest"}, "perfect", 2, 0.1)
    assert rows[0].status == "uninformative"


def _diag_per_scan(name="diag_reference", runs=(0, 1)):
    """Two runs of 14 scans with two objects throughout (lag 2: window {1, 2}, outside 3..14): run 0 misses
    truth row 1 on scans 5..9 (a spell of 5 ≥ 2 × lag) and counts one too many on scan 13; run 1 one too
    many on scan 4."""
    est = {0: [0, 2, 2, 2, 1, 1, 1, 1, 1, 2, 3, 2, 2, 2], 1: [0, 2, 2, 3] + [2] * 10}
    rows = []
    for r in runs:
        for k, e in enumerate(est[r % 2], start=1):
            missed = "1" if e == 1 else ""
            rows.append({"tracker": name, "run": r, "scan": k, "n_true": 2, "n_est": e, "n_est_mc": e,
                         "missed": missed, "missed_mc": missed})
    return pd.DataFrame(rows)


TRUTH_ROWS = [[1, 101, 0.0, 0.0, 0.0, 0.0], [1, 101, 0.0, 0.0, 3.0, 4.0]]


def test_follow_diagnosis_by_hand():
    from hypotrack.experiments.glmb_benchmark.summary import diagnosis_note, follow_diagnosis, follow_score

    per_scan = _diag_per_scan()
    d = follow_diagnosis(per_scan, "diag_reference", 2, "map_cardinality", TRUTH_ROWS)
    # outside errors: run 0 |−1| × 5 + |+1| = 6 of 12 scans, run 1 one of 12: mean 7/24, per-run 1/2 and 1/12
    assert d["outside"] == pytest.approx(7 / 24) == follow_score(per_scan, "diag_reference", 2, "map_cardinality")[0]
    assert d["se"] == pytest.approx(abs(0.5 - 1 / 12) / 2)  # sd of two values |a − b|/√2, over √2
    assert d["n_runs"] == 2 and d["spell_runs"] == 1 and d["undercount_spells"] == 1
    assert d["spell_share"] == pytest.approx(5 / 7) and d["flicker"] == pytest.approx(2 / 24)
    assert d["spell_after"] == [1]
    assert d["lost"] == 1 and d["lost_birth"] == 1 and d["lost_speed"] == pytest.approx(5.0)
    note = diagnosis_note(d, 0.1, 10.0)
    assert "0.292 ± 0.208 (s.e. over 2 runs)" in note and "71 % of the error" in note
    assert "missed most in them: born at scan 1, moving at 5 m/s against the birth prior's velocity s.d. of 10 m/s" in note
    # without the missed column the object is not named
    assert "lost" not in follow_diagnosis(per_scan.drop(columns=["missed", "missed_mc"]), "diag_reference", 2)
    with pytest.raises(ValueError, match="lag"):
        follow_diagnosis(per_scan, "diag_reference", 0)


def test_failing_follow_row_names_its_cause_from_the_diagnosis():
    from hypotrack.experiments.glmb_benchmark.summary import follow_claims

    blind = _per_scan("blind", [2] * 14, [0] * 14)
    # two runs: 0.292 ± 0.208 against 0.1, the Monte Carlo interval straddles the threshold: the runs cannot
    # decide, so the row is inconclusive (the ledger's Monte Carlo rule), not 'not reproduced'
    rows = follow_claims(pd.concat([_diag_per_scan(), blind]), {"diag_reference": "map_cardinality"}, "blind", 2,
                         0.1, truth_rows=TRUTH_ROWS)
    assert rows[0].status == "inconclusive" and rows[0].cause == "too few runs"
    assert "diagnosis: 0.292 ± 0.208" in rows[0].note
    # forty runs of the same two patterns: s.e. 0.034, so 0.292 is > 3 s.e. above 0.1; the reference settings'
    # failing stays open, a budget-truncated filter's is its truncation (project choice)
    many = _diag_per_scan(runs=range(40))
    rows = follow_claims(pd.concat([many, blind]), {"diag_reference": "map_cardinality"}, "blind", 2, 0.1)
    assert rows[0].status == "not reproduced" and rows[0].cause == ""
    rows = follow_claims(pd.concat([many.assign(tracker="diag"), blind]), {"diag": "map_cardinality"}, "blind", 2, 0.1)
    assert rows[0].cause == "project choice"


def test_missed_objects_by_hand():
    from hypotrack.experiments.glmb_benchmark.run import missed_objects

    pos = np.array([[0.0, 0.0], [500.0, 0.0], [0.0, 150.0]])
    assert missed_objects([[10.0, 0.0]], pos, [3, 7, 9], 100.0) == "7 9"
    assert missed_objects(np.zeros((0, 2)), pos, [3, 7, 9], 100.0) == "3 7 9"
    assert missed_objects([[0.0, 60.0], [500.0, 99.0]], pos, [3, 7, 9], 100.0) == ""

"""Negative controls of the cardinality, generation_time, swaps, sht and belief_space rows.

Each reproduced or qualitative row names a control built to break what its claim is about; the
control must fail the row's check, and a control that also passes demotes the row to
*uninformative*. These tests pin the controls' values on hand-computed inputs and the wiring of
the statuses.
"""

import numpy as np
import pandas as pd
import pytest

from hypotrack.reporting.verdict import parse_control


# ---------------------------------------------------------------- cardinality: the trivial estimators
def test_trivial_count_estimators_on_a_hand_sequence():
    from hypotrack.trackers.cardinality import CountModel, constant_count_estimate, per_scan_count_estimate

    model = CountModel(p_d=0.9, p_chi=0.01, lambda_b=1.0, lambda_fa=10.0)
    # lambda_b / p_chi = 1 / 0.01 = 100 at every scan, whatever the data
    np.testing.assert_allclose(constant_count_estimate(4, model), [100.0] * 4)
    # (r - 10) / 0.9: 19 -> 10, 28 -> 20, 10 -> 0; 5 -> -5.6 clipped to 0
    np.testing.assert_allclose(per_scan_count_estimate([10, 19, 5, 28], model), [0.0, 10.0, 0.0, 20.0])
    assert constant_count_estimate(0, model).shape == (0,)
    with pytest.raises(ValueError, match="non-negative integers"):
        per_scan_count_estimate([3, -1], model)
    with pytest.raises(ValueError, match="n_scans"):
        constant_count_estimate(-1, model)


def test_summary_pairs_errors_run_by_run():
    from hypotrack.experiments.cardinality.run import summarise_cardinality

    rows = []
    # two runs; tracker errors 10 and 12, constant 8 and 9, true mean 100 in both
    for run, (trk, const) in enumerate(((10.0, 8.0), (12.0, 9.0))):
        rows.append(dict(run=run, method="cardinality_tracker", mean_abs_error=trk, mean_n=100 - trk, mean_n_true=100.0,
                         J_gap=0.5 * run, J_opt=-1000.0, cap_reached=False))
        rows.append(dict(run=run, method="constant_prior", mean_abs_error=const, mean_n=100.0, mean_n_true=100.0,
                         J_gap=np.nan, J_opt=-1000.0, cap_reached=False))
    errors, optimality = summarise_cardinality(pd.DataFrame(rows))
    e = errors.set_index("method")
    # paired excess over the tracker: -2 and -3 -> mean -2.5, sd 0.7071, s.e. 0.5
    assert e.loc["constant_prior", "excess_error"] == pytest.approx(-2.5)
    assert e.loc["constant_prior", "excess_error_se"] == pytest.approx(0.5)
    assert e.loc["cardinality_tracker", "excess_error"] == 0 and e.loc["cardinality_tracker", "excess_error_se"] == 0
    # bias n-hat - n: -10 and -12 -> mean -11, s.e. 1
    assert e.loc["cardinality_tracker", "bias"] == pytest.approx(-11.0)
    assert e.loc["cardinality_tracker", "bias_se"] == pytest.approx(1.0)
    o = optimality.set_index("variant").loc["cardinality_tracker"]
    assert o["worst_gap"] == 0.5 and o["worst_relative_gap"] == pytest.approx(5e-4) and o["mean_J_opt"] == -1000


def _errors(tracker=11.7, constant=8.7, per_scan=3.9, classical=100.0, se=0.4, n=100):
    """An error table as summarise_cardinality writes it (excess errors paired against the tracker)."""
    methods = {"classical_mht": (classical, -100.0), "cardinality_tracker": (tracker, -11.5),
               "exact_class_map": (tracker, -11.5), "constant_prior": (constant, 0.1), "per_scan": (per_scan, 0.02)}
    return pd.DataFrame([dict(method=m, mean_abs_error=err, std_error=se, mean_n=100 + bias, mean_n_true=100.0,
                              n_runs=n, bias=bias, bias_se=0.1, excess_error=err - tracker,
                              excess_error_se=0.0 if m == "cardinality_tracker" else se)
                         for m, (err, bias) in methods.items()])


OPTIMALITY = pd.DataFrame(dict(variant=["cardinality_tracker"], fraction_at_optimum=[0.25], worst_gap=[0.8],
                               worst_relative_gap=[2.3e-5], mean_J_opt=[3.4e4], n_runs=[100]))
CFG = {"p_d": 0.9, "lambda_b": 1.0, "p_chi": 0.01, "control_lambda_fa": 0.1}


def test_cardinality_rows_and_their_controls():
    from hypotrack.experiments.cardinality.claims import cardinality_claims

    fig42 = pd.DataFrame(dict(classical_mht=[0, 0, 0]))
    low_clutter = pd.DataFrame(dict(classical_mht=[90, 101, 97]))
    rows = {c.key: c for c in cardinality_claims(_errors(), OPTIMALITY, fig42, CFG, control=low_clutter)}
    # the classical MHT's null solution, and the same MHT at low clutter returning tracks (the control fails)
    assert rows["classical_no_tracks"].status == "reproduced"
    assert parse_control(rows["classical_no_tracks"].control) == (
        "the same classical MHT at λ_fa = 0.1 false alarms per scan (low clutter)", "max n̂ = 101", False)
    # "vastly outperforms": the constant 100 also beats half of the classical MHT's error -> uninformative
    assert rows["tracker_error"].status == "uninformative" and parse_control(rows["tracker_error"].control)[2]
    # the power test: tracker 11.7 vs constant 8.7 and per-scan 3.9 -> not reproduced; the null estimate fails it too
    beats = rows["tracker_beats_trivial"]
    assert beats.status == "not reproduced" and not parse_control(beats.control)[2]
    assert beats.reproduced == "tracker − constant 3 ± 0.4; tracker − per-scan 7.8 ± 0.4"
    # underestimates: -11.5 ± 0.1 is below 0 by > 3 s.e.; the per-scan estimate's 0.02 ± 0.1 is not
    assert rows["underestimates"].status == "reproduced" and not parse_control(rows["underestimates"].control)[2]
    # the trivial estimators' errors are extension rows with n, mean and s.e.
    assert rows["per_scan_error"].status == "extension" and rows["per_scan_error"].mean == "3.9"
    # Tetris: this project's reconstruction, an extension with the relative gap
    tet = rows["tetris_optimal"]
    assert tet.status == "extension" and "reconstruction" in tet.note and "(≤ 2.3×10⁻⁵ relative)" in tet.reproduced and "3.4×10⁴" in tet.reproduced


def test_cardinality_power_test_passes_for_a_good_tracker_and_the_control_can_pass():
    from hypotrack.experiments.cardinality.claims import cardinality_claims

    good = _errors(tracker=2.0)
    rows = {c.key: c for c in cardinality_claims(good, OPTIMALITY, pd.DataFrame(dict(classical_mht=[0])), CFG,
                                                 control=pd.DataFrame(dict(classical_mht=[0, 0])))}
    assert rows["tracker_beats_trivial"].status == "qualitative"
    # a low-clutter control that also returns no tracks: the check cannot tell, so the row is uninformative
    assert rows["classical_no_tracks"].status == "uninformative"
    # a constant estimator far off (error 60, above half of 100) fails "vastly outperforms": the row keeps its verdict
    rows = {c.key: c for c in cardinality_claims(_errors(constant=60.0), OPTIMALITY,
                                                 pd.DataFrame(dict(classical_mht=[0])), CFG,
                                                 control=pd.DataFrame(dict(classical_mht=[5])))}
    assert rows["tracker_error"].status == "reproduced"


# ---------------------------------------------------------------- generation_time: one linear assignment
def test_linear_assignment_event_is_the_best_summed_score_by_brute_force():
    from hypotrack.association import iter_association_chunks
    from hypotrack.experiments.generation_time.difficulty import difficulty_problem, linear_assignment_event

    for difficulty, M, seed in (("1sigma", 4, 2), ("2sigma", 5, 7), ("paper", 4, 1)):
        p = difficulty_problem(difficulty, M, seed).problem
        target, clutter = p.target_scores, p.option_scores[:, 0]

        def total(event):
            return sum(target[i, j] if j >= 0 else clutter[i] for i, j in enumerate(event))

        best = max((total(ev) for chunk in iter_association_chunks(p.n_exclusive, p.n_returns, allowed=p.allowed)
                    for ev in chunk), default=0.0)
        assert total(linear_assignment_event(p)) == pytest.approx(best, abs=1e-9)


def test_reach_rows_are_uninformative_when_one_assignment_finds_the_truth():
    from hypotrack.experiments.generation_time.difficulty import OUTCOME_COLUMNS, difficulty_claims

    base = {c: 0 for c in OUTCOME_COLUMNS}
    rows = []
    for i, (logA, lsa, found) in enumerate(((2.0, True, True), (20.0, False, True), (34.0, True, True),
                                            (40.0, False, False))):
        for method in ("chain", "chain_completion"):
            rows.append(dict(base, difficulty="paper", method=method, run="ok", log10_hypotheses=logA, n_objects=i + 2,
                             n_returns=i + 2, problem=0, truth_found=found, map_found=True, truth_is_map=True,
                             truth_rank_exact=1, lsa_is_truth=lsa))
    params = {"n_problems": 1, "reference_k": 10}
    claims = {c.key: c for c in difficulty_claims(pd.DataFrame(rows), params)[0]}
    reach = claims["diffChainReachPaper"]
    # reach 1e34 >= 1e33, but the linear assignment misses one problem up to 1e33: the control fails
    assert reach.status == "reproduced" and reach.reproduced == "1e34"
    assert parse_control(reach.control) == ("one maximum-likelihood linear assignment (no search)",
                                            "equals the truth on 1 of 2 problems up to 1e33", False)
    hard = claims["diffChainHardPaper"]
    assert hard.reproduced == "1 of 1 problems up to 1e33" and hard.status == "reproduced"
    assert "missed the truth on 2 of 4 problems" in hard.note
    # every problem solved by the assignment: the reach row is uninformative and the hard row undecided
    easy = pd.DataFrame(rows).assign(lsa_is_truth=True)
    claims = {c.key: c for c in difficulty_claims(easy, params)[0]}
    assert claims["diffChainReachPaper"].status == "uninformative"
    assert claims["diffChainHardPaper"].status == "inconclusive"


def test_sweep_rows_carry_their_controls():
    from hypotrack.experiments.generation_time.claims import generation_time_claims, generation_time_timing_claims

    rows = []
    for method in ("homht", "rfisst", "homht_kbest"):
        for n in range(2, 41):
            rows.append({"method": method, "n_objects": n, "n_returns": n, "log10_hypotheses": float(n),
                         "seconds": (1e-6 * 10.0 ** n if method == "homht" else 0.01) if method != "homht" or n < 9
                         else float("nan"), "broken": method == "homht" and n >= 9, "truth_found": True,
                         "lsa_is_truth": True})
    table = pd.DataFrame(rows)
    params = {"exhaustive_max_events": 1e8, "control_max_events": 1e5, "mcmc_steps": 1000, "keep": 100,
              "control_time_factor": 100.0}
    c = {x.key: x for x in generation_time_claims(table, params)}
    # the break is the configured budget: a consistency check; a budget of 1e5 refuses at 1e6, far from 1e8
    assert c["exhaustive_break"].status == "consistency check"
    assert parse_control(c["exhaustive_break"].control)[1:] == ("first refusal at A = 1e+06", False)
    assert c["rfisst_reach"].status == "uninformative"
    t = {x.key: x for x in generation_time_timing_claims(table, params)}
    # R-FISST's 0.01 s: exhaustive is slower from A = 1e5; a chain 100 times longer (1 s) only from 1e7
    assert t["crossover"].status == "qualitative"
    assert parse_control(t["crossover"].control)[1:] == ("A = 1e+07", False)


# ---------------------------------------------------------------- swaps
def test_swap_controls():
    from hypotrack.experiments.swaps.claims import swap_claims
    from hypotrack.experiments.swaps.run import summarise_swaps, swap_shard

    table = swap_shard([0.0, 10.0, 30.0], n_sensors=30, sigma=10.0, n_runs=1500, seed=3)
    curves, rates = summarise_swaps(table)
    rows = swap_claims(curves, rates, distance=10.0, n_sensors=30)
    assert [r.status for r in rows] == ["reproduced"] * 4
    controls = [parse_control(r.control) for r in rows]
    # with the returns labelled by their true target, any swap only adds error: minimum at 0 swaps
    assert controls[0][1] == "minimum at 0 swaps" and not controls[0][2]
    assert controls[1][1] == "peak at 0 swaps" and not controls[1][2]
    assert controls[2][1] == "rate 0" and controls[3][1] == "rate 0.5"
    assert not any(c[2] for c in controls)
    # the control's draws come from other streams: the main columns do not depend on it
    again = swap_shard([0.0, 10.0, 30.0], n_sensors=30, sigma=10.0, n_runs=1500, seed=3)
    pd.testing.assert_frame_equal(table, again)


# ---------------------------------------------------------------- sht
def _curves(jpda_lag, gnn_lag, se=0.5):
    rows = []
    for method, lag in (("jpda", jpda_lag), ("gnn", gnn_lag)):
        for scan, truth in enumerate((20.0, 5.0, 1.0, 5.0, 20.0)):
            after = scan >= 2
            rows.append(dict(method=method, scan=scan, truth_separation=truth,
                             separation=truth - (lag if after and scan == 3 else 0.0), separation_se=se))
    return pd.DataFrame(rows)


def test_sht_controls():
    from hypotrack.experiments.sht.claims import sht_claims
    from hypotrack.experiments.sht.run import LECTURE_VALIDATION, lecture_summary

    _, clusters = lecture_summary(LECTURE_VALIDATION)
    summary = pd.DataFrame(columns=["method"])
    rows = sht_claims(clusters, _curves(7.5, 0.9), summary, min_lag=5.0)
    # a gate that validates every pair puts the three tracks in one cluster: the control fails
    assert rows[0].status == "reproduced"
    assert parse_control(rows[0].control) == ("a broken gate that validates every return for every track",
                                              "{T1, T2, T3}", False)
    assert rows[1].status == "qualitative" and parse_control(rows[1].control)[1:] == ("lag 0.9 ± 0.5 m", False)
    # GNN lagging as much as JPDA: the check cannot tell a coalescing tracker -> uninformative
    assert sht_claims(clusters, _curves(7.5, 7.0), summary, min_lag=5.0)[1].status == "uninformative"
    # a lag within 3 s.e. is no coalescence
    assert sht_claims(clusters, _curves(7.5, 0.9, se=3.0), summary, min_lag=5.0)[1].status == "not reproduced"


# ---------------------------------------------------------------- belief_space: the oracle with a known defect
def test_oracle_without_missed_detection_factors_is_rejected():
    from hypotrack.experiments.belief_space import fisst_oracle as fo
    from hypotrack.experiments.belief_space.oracle import _oracle_scene, random_scene

    cfg = {"pixel_size": 1000.0, "measurement_std": 1.0, "max_objects": 2, "max_returns": 2, "p_D": 0.9,
           "clutter_rate": 2.0, "alpha": 0.1, "p_survive": 0.95, "q": 0.1}
    scene = random_scene(cfg, np.random.default_rng(0), (2, 2))
    good = fo.fisst_children(_oracle_scene(cfg, scene, births=True))
    bad = fo.fisst_children(_oracle_scene(cfg, scene, births=True), defect="no_missed_detection")
    assert good.keys() == bad.keys()
    # the undetected-birth ratio is (1 - p_D) alpha = 0.01 with the factor, alpha = 0.1 without
    np.testing.assert_allclose(fo.undetected_birth_ratios(good), 0.01, rtol=1e-12)
    np.testing.assert_allclose(fo.undetected_birth_ratios(bad), 0.1, rtol=1e-12)
    # a child with k undetected objects differs by k ln(1 - p_D) between the two
    diff = {k: bad[k] - good[k] for k in good}
    for (a, kind, _arg), d in diff.items():
        missed = (2 - (1 if kind == fo.DEATH else 0)) - len({x for x in a if 0 <= x < 2})
        missed += kind == fo.UNDETECTED_BIRTH
        assert d == pytest.approx(-missed * np.log(0.1), abs=1e-9)
    reid_good = fo.reid_children(_oracle_scene(cfg, scene, births=False))
    reid_bad = fo.reid_children(_oracle_scene(cfg, scene, births=False), defect="no_missed_detection")
    for a, _, _ in reid_good:
        missed = 2 - len({x for x in a if 0 <= x < 2})
        assert reid_bad[a, 0, -1] - reid_good[a, 0, -1] == pytest.approx(-missed * np.log(0.1), abs=1e-9)
    with pytest.raises(ValueError, match="defect"):
        fo.fisst_children(_oracle_scene(cfg, scene, births=True), defect="typo")


def test_oracle_claims_wire_their_controls():
    from hypotrack.experiments.belief_space.oracle import oracle_claims

    table = pd.DataFrame(dict(n_objects=[2], n_returns=[2], fisst_same_children=[True], fisst_max_abs_dlogp=[1e-13],
                              fisst_abs_dlog_normaliser=[1e-13], reid_same_children=[True], reid_max_abs_dlogp=[1e-13],
                              oracle_fisst_vs_reid_max_abs_dlogp=[1e-13], eq39_pairs=[3], eq39_oracle_rel_dev=[1e-14],
                              eq39_engine_vs_oracle_rel_dev=[1e-14], control_fisst_max_abs_dlogp=[2.3],
                              control_reid_max_abs_dlogp=[2.3], control_eq39_rel_dev=[9.0]))
    rows = oracle_claims(table, 1e-9)
    assert [r.status for r in rows] == ["reproduced"] * 3
    assert [parse_control(r.control)[1] for r in rows] == ["max |d log p| = 2.3", "max |d log p| = 2.3",
                                                           "max rel. deviation 9"]
    # a control that also passes (deviation within tolerance) makes the rows uninformative
    same = table.assign(control_fisst_max_abs_dlogp=1e-12, control_reid_max_abs_dlogp=1e-12, control_eq39_rel_dev=0.0)
    assert [r.status for r in oracle_claims(same, 1e-9)] == ["uninformative"] * 3

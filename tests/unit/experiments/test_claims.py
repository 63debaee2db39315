"""Ledger rows of sht and the benchmarks: the decision follows the measured tables."""

import pandas as pd

from hypotrack.experiments.generation_time.claims import throughput_claims
from hypotrack.experiments.perf_sht.claims import perf_sht_claims
from hypotrack.experiments.sht.claims import sht_claims
from hypotrack.experiments.sht.run import lecture_summary


def _curves(jpda_lag, gnn_lag):
    rows = []
    for method, lag in (("gnn", gnn_lag), ("jpda", jpda_lag)):
        for scan, truth in enumerate([20.0, 10.0, 0.0, 10.0, 20.0]):
            rows.append(dict(method=method, scan=scan, truth_separation=truth,
                             separation=max(truth - (lag if scan > 2 else 0.0), 0.0), separation_se=0.5))
    return pd.DataFrame(rows)


def _summary():
    return pd.DataFrame(dict(method=["gnn", "jpda"], mospa_targets=[5.0, 4.6], mospa_targets_se=[0.2, 0.3],
                             track_loss=[0.3, 0.2], track_loss_se=[0.05, 0.04], n_runs=[10, 10]))


def test_sht_claims_from_the_lecture_example_and_coalescence():
    _, clusters = lecture_summary()  # computed from the lecture's validation matrix
    claims = sht_claims(clusters, _curves(jpda_lag=7.0, gnn_lag=1.0), _summary(), min_lag=5.0)
    assert [c.status for c in claims] == ["reproduced", "qualitative"] + ["extension"] * 4
    assert [c.evidence for c in claims[:2]] == ["published number", "measurement"]
    jpda_loss = claims[5]
    assert (jpda_loss.key, jpda_loss.n, jpda_loss.mean, jpda_loss.se, jpda_loss.z) == ("jpda_track_loss", "10", "0.2",
                                                                                       "0.04", "")
    assert "7.0 ± 0.5 m" in claims[1].reproduced and "GNN" in claims[1].control and "1.0 ± 0.5 m" in claims[1].control
    wrong = pd.DataFrame(dict(cluster=[1], tracks=["T1 T2 T3"], returns=["y1 y3 y4"]))
    assert sht_claims(wrong, _curves(1.0, 7.0), _summary(), min_lag=5.0)[0].status == "not reproduced"
    assert sht_claims(wrong, _curves(1.0, 7.0), _summary(), min_lag=5.0)[1].status == "not reproduced"


def test_perf_claims_report_measured_ranges():
    speedups = pd.DataFrame(dict(algorithm=["gnn", "gnn", "jpda"], peer=["G", "G", "E"], n_targets=[12, 24, 4],
                                 speedup=[41.2, 90.6, 10.4], goal=[30, 30, 10]))
    largest = pd.DataFrame(dict(algorithm=["gnn", "gnn"], implementation=["G", "hypotrack"],
                                largest_cluster_tracks=[128, 867]))
    claims = perf_sht_claims(speedups, largest)
    assert claims[0].reproduced == "41x to 91x" and claims[1].reproduced == "10x to 10x"
    assert claims[2].reproduced == "G: 128; hypotrack: 867"
    floor = pd.DataFrame(dict(algorithm=["gnn", "gnn"], peer=["numpy_scipy_gnn"] * 2, n_targets=[12, 24],
                              speedup=[0.5, 0.8], hypotrack_over_peer=[2.0, 1.25], goal=[1 / 1.5] * 2,
                              goal_met=[False, True]))
    f = perf_sht_claims(floor, largest.iloc[:0])[0]
    assert (f.published, f.reproduced, f.key) == ("<= 1.5x", "1.25x to 2.00x", "GnnFloor")
    assert f.note.startswith("target not met")
    table = pd.DataFrame(dict(benchmark=["mcmc"], label=["m"], variant=["paper"], per_second=[9.8e6],
                              target_per_second=[1e6], meets_target=[True], peak_bytes=[None]))
    assert throughput_claims(table)[0].reproduced == "9.80e+06 proposals/s"
    assert throughput_claims(table)[0].key == "mcmc_paper"
    # two exhaustive sizes: the largest keeps the plain key, the smaller its rank (never a config value)
    two = pd.DataFrame(dict(benchmark=["exhaustive"] * 2, label=["a", "b"], variant=["all"] * 2, n_objects=[9, 8],
                            per_second=[1.7e7, 1.8e7], target_per_second=[5e6] * 2, meets_target=[True] * 2,
                            peak_bytes=[None] * 2))
    assert [c.key for c in throughput_claims(two)] == ["exhaustive_all", "exhaustive_all_size1"]


def test_swap_claims_follow_the_curves():
    from hypotrack.experiments.swaps.claims import swap_claims

    swaps = list(range(8))
    rms = [2.6, 2.2, 1.9, 1.7, 1.6, 1.7, 1.9, 2.1]  # minimum at 4 swaps
    curves = pd.DataFrame(dict(distance=10.0, swaps=swaps, rms=rms, log_prob_class=[-9 + abs(i - 5) * -1 for i in swaps],
                               log_prob_single=[-float(i) for i in swaps], rms_labelled=[1.0 + i for i in swaps],
                               n_runs=100))
    rates = pd.DataFrame(dict(distance=[0.0, 10.0, 30.0], rms_optimal_rate=[0.5, 0.13, 0.0],
                              class_optimal_rate=[0.5, 0.2, 0.0]))
    claims = swap_claims(curves, rates, distance=10.0, n_sensors=30)
    assert [c.reproduced for c in claims[:2]] == ["4", "5"]
    assert all(c.status == "reproduced" for c in claims)
    assert [c.control.split(": ")[1] for c in claims] == ["minimum at 0 swaps -> fails", "peak at 0 swaps -> fails",
                                                         "rate 0 -> fails", "rate 0.5 -> fails"]
    shifted = curves.assign(rms=[1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.4])  # minimum at 0 swaps
    assert swap_claims(shifted, rates.assign(rms_optimal_rate=[0.3, 0.1, 0.03]), distance=10.0,
                       n_sensors=30)[0].status == "not reproduced"
    bad_rates = swap_claims(curves, rates.assign(rms_optimal_rate=[0.3, 0.1, 0.03]), distance=10.0, n_sensors=30)
    assert [c.status for c in bad_rates[2:]] == ["not reproduced", "not reproduced"]


def test_cardinality_claims_need_a_significant_difference():
    from hypotrack.experiments.cardinality.claims import cardinality_claims

    methods = ["classical_mht", "cardinality_tracker", "exact_class_map", "constant_prior", "per_scan"]
    errors = pd.DataFrame(dict(method=methods, mean_abs_error=[100.0, 11.7, 11.7, 60.0, 3.9],
                               std_error=[3.0, 4.0, 4.0, 1.0, 0.1], mean_n=[0.0, 95.0, 95.0, 100.0, 100.0],
                               mean_n_true=[100.0] * 5, n_runs=[50] * 5, bias=[-100.0, -5.0, -5.0, 0.0, 0.0],
                               bias_se=[0.1] * 5, excess_error=[88.3, 0.0, 0.0, 48.3, -7.8],
                               excess_error_se=[3.0, 0.0, 0.0, 1.0, 0.1]))
    optimality = pd.DataFrame(dict(variant=["cardinality_tracker"], fraction_at_optimum=[0.25], worst_gap=[5.5],
                                   worst_relative_gap=[1.6e-4], mean_J_opt=[3.4e4], n_runs=[50]))
    fig42 = pd.DataFrame(dict(classical_mht=[0, 0, 0]))
    cfg = {"p_d": 0.9, "lambda_b": 1.0, "p_chi": 0.01, "control_lambda_fa": 0.1}
    control = pd.DataFrame(dict(classical_mht=[3, 5]))
    claims = {c.key: c for c in cardinality_claims(errors, optimality, fig42, cfg, control=control)}
    assert [claims[k].status for k in ("classical_no_tracks", "tracker_error", "underestimates", "tetris_optimal")] \
        == ["reproduced", "reproduced", "reproduced", "extension"]
    # difference 88.3, s.e. of the difference hypot(3, 4) = 5 -> 17.7 s.e.
    assert claims["tracker_error"].note.startswith("50 runs; difference 88.3 = 17.7 s.e.")
    assert claims["tetris_optimal"].evidence == "independent oracle"
    # the same means with s.e. 20 and 25 (difference 2.8 s.e. of hypot = 32.0) are not a significant difference
    noisy = errors.assign(std_error=[20.0, 25.0, 25.0, 1.0, 0.1])
    assert {c.key: c for c in cardinality_claims(noisy, optimality, fig42, cfg, control=control)}[
        "tracker_error"].status == "not reproduced"
    assert cardinality_claims(errors, optimality, pd.DataFrame(dict(classical_mht=[0, 2])), cfg,
                              control=control)[0].status == "not reproduced"
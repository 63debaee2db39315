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

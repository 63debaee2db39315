"""The Williams-2015 experiment: its truth and returns, GOSPA scoring, shards' determinism, the reference's
record and its glue (the Octave run itself: tests/crosscheck/test_williams2015_reference.py)."""

import json

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.williams2015.reference import (export_scans, reference_estimates, scenario_prelude,
                                                          scenario_signature)
from hypotrack.experiments.williams2015.run import run_shard, score_estimates, tracker_seed, truth_for
from hypotrack.experiments.williams2015.scenario import draw_truth, scenario, simulate_scans, truth_at
from hypotrack.experiments.williams2015.summary import curves, summary_table


def _cfg(**over):
    cfg = yaml.safe_load(open("workflows/config/default.yaml"))["williams2015"]
    cfg.update(over)
    return cfg


def test_truth_meets_at_the_midpoint_and_the_first_object_dies_there():
    m = scenario(_cfg(n_steps=21, q=1e-12))  # q ~ 0: noiseless constant velocity both ways from the mid-point
    X = draw_truth(m, np.random.default_rng(0))
    assert X.shape == (4, 21, 4) and m.midpoint == 11
    assert np.isnan(X[0, 10:]).all() and not np.isnan(X[0, :10]).any() and not np.isnan(X[1:]).any()
    mid = X[1:, 10]
    for k in (0, 5, 20):
        np.testing.assert_allclose(X[1:, k, :2], mid[:, :2] + (k - 10) * mid[:, 2:], atol=1e-4)
    # the objects start within a few sqrt(0.1) of (150, 150) at the mid-point
    assert np.all(np.abs(mid[:, :2] - 150) < 2)


def test_returns_and_gospa_by_hand():
    m = scenario(_cfg(n_steps=5, p_D=1.0, clutter_rate=1e-9))
    X = draw_truth(m, np.random.default_rng(1))
    scans = simulate_scans(m, X, np.random.default_rng(2))
    assert [len(Z) for Z in scans] == [4, 4, 3, 3, 3]  # p_D = 1, no clutter; the first object gone at step 3
    # step 3 (index 2): three objects; estimates: one 3 m off, one 4 m off, one 20 m off (beyond c), one spurious
    x, _ = truth_at(X, 2)
    est = np.array([x[0, :2] + [3, 0], x[1, :2] + [0, 4], x[2, :2] + [20, 0], [0.0, 0.0]])
    row = score_estimates([np.zeros((0, 2)), np.zeros((0, 2)), est], X[:, :3], c=10.0, p=2.0).iloc[2]
    assert (row.n_true, row.n_est, row.n_missed, row.n_false) == (3, 4, 1, 2)
    assert row.gospa_loc == pytest.approx(9 + 16)
    assert row.gospa_missed == pytest.approx(50) and row.gospa_false == pytest.approx(100)
    assert row.gospa == pytest.approx(np.sqrt(25 + 150))


def _small_cfg(trackers):
    return _cfg(n_steps=11, trackers=trackers)


GNN = {"kind": "gnn", "m_of_n": [2, 3], "initial_velocity_std": 1.0}
GLMB = {"kind": "glmb", "max_hypotheses": 5, "n_sweeps": 20, "gate_probability": 0.999}


def test_shards_are_deterministic_independent_of_sharding_and_of_other_trackers():
    a, ra = run_shard(_small_cfg({"gnn": GNN, "glmb": GLMB}), 7, 0, 2)
    b, rb = run_shard(_small_cfg({"glmb": GLMB}), 7, 1, 1)
    cols = [c for c in a.columns if c != "time_s"]
    pd.testing.assert_frame_equal(a[(a.run == 1) & (a.tracker == "glmb")][cols].reset_index(drop=True),
                                  b[cols].reset_index(drop=True))
    pd.testing.assert_frame_equal(ra[(ra.run == 1) & (ra.tracker == "glmb")].reset_index(drop=True), rb)
    assert set(a.run) == {0, 1} and len(a) == 2 * 2 * 11
    assert tracker_seed(7, 1, "glmb").entropy != tracker_seed(7, 1, "gnn").entropy
    # trajectory GOSPA's parts add up to its p-th power
    np.testing.assert_allclose(ra.tgospa**2, ra.tgospa_loc + ra.tgospa_missed + ra.tgospa_false + ra.tgospa_switches)


def test_summary_means_errors_and_rms():
    per_scan = pd.DataFrame({"tracker": "t", "run": [0, 0, 1, 1], "scan": [1, 2, 1, 2], "gospa": [1.0, 3.0, 2.0, 4.0],
                             "gospa_loc": [1.0, 9.0, 4.0, 16.0], "gospa_missed": 0.0, "gospa_false": 0.0,
                             "n_missed": 0, "n_false": 0, "n_est": 1, "n_true": 1, "time_s": 0.1})
    per_run = pd.DataFrame({"tracker": "t", "run": [0, 1], "tgospa": [5.0, 7.0], "n_switches": [1.0, 0.0]})
    s, _ = summary_table(per_scan, per_run, settled_after=1)
    r = s.iloc[0]
    assert r.gospa_settled_mean == pytest.approx(3.5)  # step 2 only: 3 and 4
    assert r.gospa_mean == pytest.approx(2.5) and r.gospa_se == pytest.approx(0.5)  # run means 2 and 3
    assert r.rms_gospa == pytest.approx(np.sqrt((1 + 9 + 4 + 16) / 4))
    assert r.tgospa_mean == 6.0 and r.tgospa_se == pytest.approx(1.0)
    c = curves(per_scan)
    assert c.rms_gospa.tolist() == pytest.approx([np.sqrt(2.5), np.sqrt(12.5)])


def test_prelude_in_the_reference_order_and_scans_exported(tmp_path):
    m = scenario(_cfg())
    pre = scenario_prelude(m, 3.0)
    assert pre["birth_mean"].tolist() == [100.0, 0.0, 100.0, 0.0]
    assert np.diag(pre["birth_cov"]).tolist() == [150.0**2, 1.0, 150.0**2, 1.0]
    assert (pre["side"], pre["clutter_rate"], pre["n_steps"]) == (300.0, 10.0, 81)
    scans = {0: [np.array([[1.0, 2.0]]), np.zeros((0, 2)), np.array([[1 / 3, 2.5], [4.0, 5.0]])]}
    df = export_scans(scans, tmp_path / "s.csv")
    back = pd.read_csv(tmp_path / "s.csv")
    assert back.scan.tolist() == [1, 3, 3] and back.x.iloc[1] == 1 / 3  # full precision, empty scan absent
    assert len(df) == 3


def test_record_must_match_the_scenario(tmp_path):
    cfg = _cfg()
    cfg["reference"] = {**cfg["reference"], "mtt_dir": "", "tcl_dir": "", "record": str(tmp_path / "rec.csv")}
    pd.DataFrame({"run": [0], "scan": [1], "x": [1.0], "y": [2.0]}).to_csv(tmp_path / "rec.csv", index=False)
    pd.DataFrame({"run": [0, 1, 2], "scan": [1, 1, 1], "cpu_s": [0.1] * 3}).to_csv(tmp_path / "rec_timing.csv", index=False)
    (tmp_path / "rec_config.json").write_text(json.dumps(scenario_signature(cfg, 5)))
    est, times, source = reference_estimates(cfg, 5, "driver.m")
    assert source == "record" and len(est) == 1 and times.run.tolist() == [0, 1, 2]
    with pytest.raises(ValueError, match=r"another scenario or seed \(differs in \['seed'\]\)"):
        reference_estimates(cfg, 6, "driver.m")
    with pytest.raises(ValueError, match=r"differs in \['p_D'\]"):
        reference_estimates({**cfg, "p_D": 0.8}, 5, "driver.m")
    cfg["reference"]["n_runs"] = 4
    with pytest.raises(ValueError, match="reference.n_runs may be at most 3"):
        reference_estimates(cfg, 5, "driver.m")


def test_bad_settings_name_the_parameter():
    with pytest.raises(ValueError, match="n_steps must be odd"):
        scenario(_cfg(n_steps=80))
    with pytest.raises(ValueError, match="p_D"):
        scenario(_cfg(p_D=1.5))
    with pytest.raises(ValueError, match="birth.weight"):
        scenario(_cfg(birth={"weight": 0.0, "mean": [0, 0, 0, 0], "std": [1, 1, 1, 1]}))


def test_truth_from_the_master_seed():
    _, a = truth_for(_cfg(), 3)
    _, b = truth_for(_cfg(), 3)
    _, c = truth_for(_cfg(), 4)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(np.nan_to_num(a), np.nan_to_num(c))


def test_reference_comparison_scores_the_reference_like_the_trackers():
    """A 'reference' whose estimates are the true positions scores 0 at every step; a tracker with every object
    3 m off in x (no other pairing is cheaper: Σ|x_π(i) − x_i + s|² = Σ|x_π(i) − x_i|² + n s²) scores 3√n
    (p = 2): 6 at the first two steps, 3√3 after the first object's death; compared on the same runs only
    (run 5 of the tracker is left out)."""
    from hypotrack.experiments.williams2015.compare import REFERENCE_NAME, reference_claims, reference_comparison

    cfg = _cfg(n_steps=5)
    _, X = truth_for(cfg, 11)
    est = pd.DataFrame([(r, k + 1, j, *x[:2]) for r in (0, 1) for k in range(5)
                        for x, j in zip(*truth_at(X, k))], columns=["run", "scan", "label", "x", "y"])
    times = pd.DataFrame([(r, k, 0.5) for r in (0, 1) for k in range(1, 6)], columns=["run", "scan", "cpu_s"])
    rows, per_run = [], []
    for r in (0, 1, 5):
        off = [truth_at(X, k)[0][:, :2] + [3.0, 0.0] for k in range(5)]
        df = score_estimates(off, X, 10.0, 2.0).assign(tracker="t", run=r, time_s=0.01)
        rows.append(df)
        per_run.append({"run": r, "tracker": "t", "tgospa": 7.0 + r, "n_switches": 1.0})
    table, timing = reference_comparison({**cfg, "settled_after": 2}, 11, pd.concat(rows), est, times,
                                         pd.DataFrame(per_run))
    ref, t = table.set_index("tracker").loc[REFERENCE_NAME], table.set_index("tracker").loc["t"]
    assert ref.gospa_mean == 0 and ref.n_runs == 2 and ref.runs == "0 1"
    # the reference's tracks carry the truth's labels: trajectory GOSPA 0, no switch; the tracker's on runs 0 and 1
    assert (ref.tgospa_mean, ref.n_switches_mean, t.tgospa_mean) == (0.0, 0.0, 7.5)
    assert t.gospa_mean == pytest.approx((2 * 6 + 3 * 3 * np.sqrt(3)) / 5) and t.n_runs == 2
    assert t.gospa_settled_mean == pytest.approx(3 * np.sqrt(3))
    assert timing.set_index("tracker").time_per_scan_s.to_dict() == pytest.approx({REFERENCE_NAME: 0.5, "t": 0.01})
    claim = reference_claims(table)[0]
    assert claim.key == "GospaPmbmReference" and claim.status == "extension" and claim.evidence == "peer implementation"

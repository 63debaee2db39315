"""The ssa_breakup experiment: pass segmentation, ratios and summaries by hand, and a small end-to-end run."""

import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_breakup.jobs import density, score_tracker
from hypotrack.experiments.ssa_breakup.run import pass_ends
from hypotrack.experiments.ssa_breakup.scorecard import predict
from hypotrack.experiments.ssa_breakup.summary import (AMBIGUITY_TRACKERS, RATIO_TRACKERS, cross_tag_ratios, density_table,
                                                       scorecard_summary)
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.scenarios.tables import truth_table

from pathlib import Path

CONFIG = Path(__file__).resolve().parents[4] / "workflows" / "config" / "default.yaml"


def test_pass_ends_by_hand():
    # object 7 in view at 0, 10, 20 s then 700, 710 s (a gap of 680 s > 300 s: two passes); object 8 at 10 s
    t = [0.0, 10.0, 20.0, 700.0, 710.0, 10.0]
    s = [0, 1, 2, 70, 71, 1]
    tab = truth_table(s, t, [7, 7, 7, 7, 7, 8], np.ones((6, 6)), [True] * 6)
    p = pass_ends(tab)
    assert p[["target", "pass_no", "first_scan", "last_scan"]].to_numpy().tolist() == [
        [7, 0, 0, 2], [7, 1, 70, 71], [8, 0, 1, 1]]
    assert p["t_first"].tolist() == [0.0, 700.0, 10.0]


def test_predict_is_the_ekf():
    motion = J2Orbit3D(q=1e-9)
    x = np.array([7000.0, 0, 0, 0, 7.5, 0.1])
    P = np.diag([0.25, 0.25, 0.25, 1e-6, 1e-6, 1e-6])
    xp, Pp = predict(motion, x, P, 600.0)
    m, Phi = motion.transition(x[None], 600.0)
    assert xp == pytest.approx(m[0])
    assert Pp == pytest.approx(Phi[0] @ P @ Phi[0].T + motion.Q(600.0))
    assert np.allclose(Pp, Pp.T) and np.all(np.linalg.eigvalsh(Pp) > 0)


@pytest.fixture(scope="module")
def small_cfg():
    full = yaml.safe_load(CONFIG.read_text())
    cfg = copy.deepcopy(full["ssa_breakup"])
    cfg.update(seeds=[5], scenarios=["breakup", "catalogue"], control={"n_objects": 300, "n_scans": 30})
    cfg["event"]["lc_min_m"] = 0.2  # 78 fragments
    cfg["window"] = {"obs_start_s": 7200.0, "obs_end_s": 8400.0}  # the cloud's first pass over the site
    return cfg, full["ssa_catalogue"]


def test_small_run_end_to_end(small_cfg):
    cfg, cat = small_cfg
    cards = score_tracker("gnn", cfg, cat)
    assert cards["scenario"].tolist() == ["breakup", "catalogue"]
    b = cards.iloc[0]
    assert 70 <= b["n_objects"] <= 78  # 6 x 0.2^-1.6 = 78 drawn, those re-entering within the revolution removed
    assert b["object_returns"] > 100
    parts = b[["correct_per_1e4", "cross_tags_per_1e4", "orphan_per_1e4", "uncorrelated_per_1e4"]].sum()
    assert parts == pytest.approx(1e4)
    causes = b[["xtag_newborn_per_1e4", "xtag_own_label_per_1e4", "xtag_carried_label_per_1e4", "xtag_elsewhere_per_1e4"]]
    assert causes.sum() == pytest.approx(b["cross_tags_per_1e4"])  # every cross-tag has one cause
    assert b["id_switches"] == int(b["id_switches"]) >= 0
    assert 0.0 <= b["first_return_own"] <= 1.0
    assert 0.0 <= b["completeness"] <= 1.0
    again = score_tracker("gnn", cfg, cat)
    pd.testing.assert_frame_equal(cards.drop(columns="cpu_s"), again.drop(columns="cpu_s"))
    rows, dist = density(cfg, cat)
    assert rows["scenario"].tolist() == ["breakup", "catalogue"]
    assert rows.iloc[0]["nn_median_km"] < rows.iloc[1]["nn_median_km"]  # the cloud is denser than the catalogue


def test_batched_prediction_is_predict_row_by_row():
    motion = J2Orbit3D(q=1e-9)
    X = np.array([[7000.0, 0, 0, 0, 7.5, 0.1], [0, 7100.0, 0, -7.4, 0, 0.5]])
    P = np.broadcast_to(np.diag([0.25, 0.25, 0.25, 1e-6, 1e-6, 1e-6]), (2, 6, 6))
    dt = np.array([600.0, 1800.0])
    Xp, Phi = motion.transition_each(X, dt)
    Pp = Phi @ P @ np.swapaxes(Phi, 1, 2) + motion.Q_each(dt)
    for i in range(2):
        x1, P1 = predict(motion, X[i], P[i], dt[i])
        assert Xp[i] == pytest.approx(x1)
        assert Pp[i] == pytest.approx(P1, rel=1e-9, abs=1e-15)


def test_every_claim_row_is_placed_in_the_extension_group():
    from hypotrack.experiments.ssa_breakup.summary import breakup_claims

    doc = yaml.safe_load((CONFIG.parents[2] / "src" / "hypotrack" / "reporting" / "document_claims.yaml").read_text())
    placed = {r for g in doc["extensions"] if g["id"] == "extension.breakup" for r in g["rows"]}
    # the default's factored trackers also report their ambiguity outputs (rows <name>_amb of the same runs)
    names = ["glmb", "glmb_murty", "homht_kbest", "rfisst", "gnn", "jpda", *AMBIGUITY_TRACKERS]
    cards = pd.DataFrame([dict(scenario=s, tracker=t, seed=k, cross_tags_per_1e4=float(k), completeness=0.5,
                               duplicate_per_1000=1.0, false_per_1000=1.0, nn_in_gate_share=0.5, reacquisitions=3.0,
                               id_switches_per_1e4=float(k), catalogue_cross_tags_per_1e4=3.0 * k)
                          for s in ("breakup", "catalogue") for t in names for k in (1, 2)])
    acc, _ = scorecard_summary(cards)
    dens = density_table([dict(scenario=s, seed=1, n_pairs=3, nn_median_km=1.0, gate_km=2.0, share_in_gate=0.5,
                               share_in_5_gates=1.0) for s in ("breakup", "catalogue")])
    ratios = pd.concat([cross_tag_ratios(cards, "gnn", (*RATIO_TRACKERS, *AMBIGUITY_TRACKERS), column=c)
                        for c in ("cross_tags_per_1e4", "id_switches_per_1e4", "catalogue_cross_tags_per_1e4")])
    rows = breakup_claims(acc, ratios, dens)
    keys = {f"ssa_breakup/{c.key}" for c in rows}
    # per scenario: cross-tags of the 10 outputs, the cross-tag, identity-switch and catalogue cross-tag ratios of the
    # 8 compared with GNN, the two density rows and the two re-acquisition gates
    assert len(keys) == len(rows) == 2 * (10 + 8 + 8 + 8 + 1 + 1)
    assert keys == placed  # every tracker runs in the default: every row is placed
    assert {c.status for c in rows} == {"extension"}


def test_radar_frame_option_end_to_end(small_cfg):
    """``radar.measurement: rae_rate`` with ``model.birth: admissible``: the config validates, the scans are
    (ρ, az, el, ρ̇), every tracker runs in the sensor frame (same scorecard twice), GNN keeps the known fragments
    of the cloud's first pass, and the options are refused where they cannot apply."""
    from hypotrack.config import validate_config
    from hypotrack.experiments.ssa_breakup.run import build
    from hypotrack.experiments.ssa_catalogue.run import make_motion, make_problem, make_radar, tracker_sensor
    from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor

    cfg, cat = small_cfg
    cfg = copy.deepcopy(cfg)
    cfg["scenarios"] = ["breakup", "catalogue"]
    cfg["radar"].update(measurement="rae_rate", sigma_range_km=0.03, sigma_angle_deg=0.05, sigma_range_rate_km_s=0.01)
    cfg["model"]["birth"] = "admissible"
    # the catalogue's process noise, with which the thresholds below were set (one pass of 78 fragments: with the
    # cloud's tuned 1e-12, 39 of them are within 5 km at their next pass against 41 with 1e-9)
    cfg["model"]["process_noise_q"] = 1e-9
    full = yaml.safe_load(CONFIG.read_text())
    full["ssa_breakup"] = {**full["ssa_breakup"], "radar": cfg["radar"], "model": cfg["model"]}
    schema = Path(__file__).resolve().parents[4] / "workflows" / "config" / "schema"
    validate_config(copy.deepcopy(full), schema)
    bad = copy.deepcopy(full)
    bad["ssa_breakup"]["model"]["birth"] = "two_point"
    with pytest.raises(Exception, match="two_point|birth"):
        validate_config(bad, schema)
    radar = make_radar(cfg)
    assert radar.measurement == "rae_rate" and np.sqrt(np.diag(radar.R))[3] == pytest.approx(0.01)
    assert isinstance(tracker_sensor(radar), RadarTrackerSensor)
    _, _, sc, _ = build("breakup", cfg, cat, 5)
    assert [c for c in sc.scans.columns if c.startswith("z_")] == ["z_0", "z_1", "z_2", "z_3"]
    _, _, ctrl, _ = build("catalogue", cfg, cat, 5)  # the control: the catalogue's site, this radar's measurement
    assert ctrl.sensors[0].measurement == "rae_rate" and ctrl.sensors[0].site.lat_deg == cat["radar"]["lat_deg"]
    cards = score_tracker("gnn", cfg, cat)
    assert cards["scenario"].tolist() == ["breakup", "catalogue"]
    b = cards.iloc[0]
    assert b["object_returns"] > 100
    assert b["cross_tags_per_1e4"] < 100 and b["completeness"] > 0.5
    assert cards.iloc[1]["cross_tags"] == 0  # the sparse catalogue: no cross-tag
    pd.testing.assert_frame_equal(cards.drop(columns="cpu_s"), score_tracker("gnn", cfg, cat).drop(columns="cpu_s"))
    enu = copy.deepcopy(small_cfg[0])
    enu["radar"]["measurement"], enu["model"]["birth"] = "enu", "admissible"
    with pytest.raises(ValueError, match="admissible needs the documented radar"):
        make_problem(enu, tracker_sensor(make_radar(enu)), make_motion(enu), np.zeros((0, 6)), np.zeros((0, 6, 6)),
                     np.zeros(0, np.int64))
    with pytest.raises(ValueError, match="radar.measurement must be"):
        make_radar({**cfg, "radar": {**cfg["radar"], "measurement": "rae"}})


def test_sensor_frame_correlation_by_hand():
    """Returns correlate with the estimate of smallest ``νᵀ R⁻¹ ν`` within the χ²₄(0.999) = 18.47 gate: a return 2σ
    from track A in azimuth across the ±π wrap goes to A, one 4σ in range from B to B (d² = 16), one far off both to
    none, one 4.5σ off (d² = 20.25) to none."""
    from hypotrack.experiments.ssa_breakup.run import correlate_in_sensor_frame
    from hypotrack.models.measurement import ExtendedMeasurement

    class _Identity(ExtendedMeasurement):  # h(x) = x (a 4-state "radar" so that S = P + R is known by hand)
        wrapped = (1,)
        ndim_state = 4
        R = np.diag([1.0, 0.01, 0.01, 1.0])  # σ = 1, 0.1, 0.1, 1

        def h(self, x):
            return np.array(x, dtype=float)

        def jacobian(self, x):
            return np.broadcast_to(np.eye(4), (len(x), 4, 4)).copy()

    m = _Identity()
    X = np.array([[100.0, np.pi - 0.05, 0.3, 0.0], [200.0, 0.0, 0.3, 0.0]])
    Z = np.array([[100.0, -np.pi + 0.15, 0.3, 0.0],   # Δaz = +0.2 across the wrap: d² = 4
                  [204.0, 0.0, 0.3, 0.0],              # 4σ in range: d² = 16
                  [150.0, 0.0, 0.3, 0.0]])            # 50σ off both
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, Z, [7, 9], X, 0.999), [7, 9, -1])
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, Z[:0], [7, 9], X, 0.999), np.zeros(0, int))
    Z2 = np.array([[100.0, np.pi - 0.05, 0.3, 4.5]])  # d² = 4.5² = 20.25 > 18.47: outside the gate
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, Z2, [7, 9], X, 0.999), [-1])


def test_sensor_frame_correlation_is_one_to_one():
    """A neighbour's return nearer an estimate than its own object's return is not charged to that estimate too:
    estimates A (az 0) and B (az 0.3), σ_az = 0.1. Return zA at az 0.2 (d² 4 to A, 1 to B) and zB at az 0.3 (9 to A,
    0 to B): nearest-estimate correlation gives both to B; the one-to-one assignment costs 4 + 0 against 1 + 9 and
    gives zA to A, zB to B. Alone, zA goes to B (its nearest); of three returns about A alone (d² 0.25, 1, 4) only
    the nearest is correlated; a return outside every gate never is, even when an estimate is free."""
    from hypotrack.experiments.ssa_breakup.run import correlate_in_sensor_frame
    from hypotrack.models.measurement import ExtendedMeasurement

    class _Identity(ExtendedMeasurement):
        wrapped = (1,)
        ndim_state = 4
        R = np.diag([1.0, 0.01, 0.01, 1.0])

        def h(self, x):
            return np.array(x, dtype=float)

        def jacobian(self, x):
            return np.broadcast_to(np.eye(4), (len(x), 4, 4)).copy()

    m = _Identity()
    X = np.array([[100.0, 0.0, 0.3, 0.0], [100.0, 0.3, 0.3, 0.0]])
    zA, zB = [100.0, 0.2, 0.3, 0.0], [100.0, 0.3, 0.3, 0.0]
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, np.array([zA, zB]), [7, 9], X, 0.999), [7, 9])
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, np.array([zB, zA]), [7, 9], X, 0.999), [9, 7])
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, np.array([zA]), [7, 9], X, 0.999), [9])
    Z3 = np.array([[100.0, -0.1, 0.3, 0.0], [100.0, 0.0, 0.3, 0.5], [100.0, 0.0, 0.3, -2.0]])  # d² 1, 0.25, 4 to A
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, Z3, [7], X[:1], 0.999), [-1, 7, -1])
    far = np.array([[100.0, 0.0, 0.3, 0.1], [100.0, 1.5, 0.3, 0.0]])  # the second: 12σ from B, outside every gate
    np.testing.assert_array_equal(correlate_in_sensor_frame(m, far, [7, 9], X, 0.999), [7, -1])


def test_ambiguity_output_from_the_same_run(small_cfg):
    """A factored tracker's run records its MAP labels' marginals; its ambiguity output is scored from that run (one
    tracker run: the tracks' columns equal), p_min = 0 reports the MAP itself, and the sweep's row at the
    configured p_min is the output row's identity columns. GNN has no marginals: no output row, no sweep."""
    from hypotrack.experiments.ssa_breakup.jobs import score_tracker_outputs
    from hypotrack.experiments.ssa_breakup.run import build, run_scored
    from hypotrack.experiments.ssa_breakup.scorecard import identity_row

    cfg, cat = small_cfg
    cfg = copy.deepcopy(cfg)
    cfg.update(scenarios=["breakup"], ambiguity={"mode": "withhold", "p_min": 0.9, "p_min_sweep": [0.5, 0.9]},
               window={"obs_start_s": 7200.0, "obs_end_s": 7800.0})  # half the pass: two runs of the tracker
    cards, sweep = score_tracker_outputs("glmb_murty", cfg, cat)
    assert cards["tracker"].tolist() == ["glmb_murty", "glmb_murty_amb"]
    same = ["n_objects", "object_returns", "completeness", "reacquisitions", "reacq_within_km", "gospa_loc_per_object",
            "false_per_1000", "duplicate_per_1000"]
    same = [c for c in same if c in cards]
    pd.testing.assert_frame_equal(cards.iloc[[0]][same].reset_index(drop=True), cards.iloc[[1]][same].reset_index(drop=True))
    assert sweep[["mode", "p_min"]].values.tolist() == [["fresh", 0.5], ["fresh", 0.9], ["withhold", 0.5],
                                                          ["withhold", 0.9]]
    assert set(sweep["tracker"]) == {"glmb_murty_amb"}
    at = sweep[(sweep["p_min"] == 0.9) & (sweep["mode"] == "withhold")].iloc[0]
    assert at["cross_tags_per_1e4"] == cards.iloc[1]["cross_tags_per_1e4"]
    assert at["id_switches"] == cards.iloc[1]["id_switches"]
    assert at["uncorrelated_per_1e4"] == cards.iloc[1]["uncorrelated_per_1e4"]
    scen = build("breakup", cfg, cat, 5)
    run = run_scored("glmb_murty", cfg, scen, 5, count_hypotheses=False)
    m = run.marginals
    # one row per MAP label and scan; those in view are the scan's estimates
    in_view = m[m["in_view"]].groupby("scan").size().reindex(run.per_scan["scan"], fill_value=0)
    assert in_view.tolist() == run.per_scan["n_estimates"].tolist()
    assert ((m["p"] > 0) & (m["p"] <= 1)).all() and m["in_view"].dtype == bool
    zero = run.with_output(0.0, "withhold")
    assert zero.returns["label"].tolist() == run.returns["label"].tolist()
    assert identity_row(zero)["cross_tags"] == cards.iloc[0]["cross_tags"]
    g_cards, g_sweep = score_tracker_outputs("gnn", cfg, cat)
    assert g_cards["tracker"].tolist() == ["gnn"] and g_sweep.empty

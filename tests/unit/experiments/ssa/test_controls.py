"""The SSA negative controls (hypotrack.experiments.ssa.controls): the blind tracker and the control wiring."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments import ssa as st
from hypotrack.models.orbit import MU_EARTH, TwoBodyOrbit
from hypotrack.reporting.ledger import Claim
from hypotrack.scenarios.ssa import params_from_config, simulate_ssa

ROOT = Path(__file__).resolve().parents[4]


def test_blind_prediction_of_a_circular_orbit_is_the_rotated_position():
    # r = 7000 km circular: after k steps of dt the object is at angle k·ω·dt, ω = sqrt(μ/r³)
    r, dt, k = 7000.0, 60.0, 5
    v = np.sqrt(MU_EARTH / r)
    X, C = st.blind_predictions(TwoBodyOrbit(q=0.0), [[r, 0.0, 0.0, v]], [np.eye(4)], np.full(k, dt))
    angle = np.sqrt(MU_EARTH / r**3) * dt * np.arange(k + 1)
    assert X.shape == (k + 1, 1, 4) and C.shape == (k + 1, 1, 4, 4)
    np.testing.assert_allclose(X[:, 0, 0], r * np.cos(angle), atol=1e-6)
    np.testing.assert_allclose(X[:, 0, 1], r * np.sin(angle), atol=1e-6)
    np.testing.assert_allclose(X[:, 0, 2:], v * np.c_[-np.sin(angle), np.cos(angle)], atol=1e-9)
    np.testing.assert_array_equal(C[0, 0], np.eye(4))


class _ConstantVelocity:
    """x' = F x, F = [[I, dt I], [0, I]], Q = q I (a hand-checkable EKF prediction)."""

    q = 0.5

    def transition(self, x, dt):
        F = np.block([[np.eye(2), dt * np.eye(2)], [np.zeros((2, 2)), np.eye(2)]])
        return x @ F.T, np.broadcast_to(F, (len(x), 4, 4))

    def Q(self, dt):
        return self.q * np.eye(4)


def test_blind_prediction_covariance_is_phi_p_phi_t_plus_q():
    P0 = np.diag([1.0, 2.0, 3.0, 4.0])
    X, C = st.blind_predictions(_ConstantVelocity(), [[0.0, 0.0, 1.0, -2.0]], [P0], [2.0, 2.0])
    np.testing.assert_allclose(X[2, 0], [4.0, -8.0, 1.0, -2.0])
    # dt = 2. Step 1: var(x) = 1 + dt²·3 + q = 13.5, cov(x, vx) = dt·3 = 6, var(vx) = 3.5.
    # Step 2: var(x) = 13.5 + 2·dt·6 + dt²·3.5 + q = 52
    assert C[1, 0, 0, 0] == pytest.approx(1 + 4 * 3 + 0.5) and C[1, 0, 0, 2] == pytest.approx(6.0)
    assert C[2, 0, 0, 0] == pytest.approx(13.5 + 2 * 2 * 6 + 4 * 3.5 + 0.5)
    assert C[2, 0, 3, 3] == pytest.approx(4 + 0.5 + 0.5)
    with pytest.raises(ValueError, match="dts"):
        st.blind_predictions(_ConstantVelocity(), [[0.0, 0.0, 1.0, -2.0]], [P0], [-1.0])
    with pytest.raises(ValueError, match="covs"):
        st.blind_predictions(_ConstantVelocity(), [[0.0, 0.0, 1.0, -2.0]], [np.eye(3)], [1.0])


def _scenario(n_scans=8):
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    config["ssa"]["n_scans"] = n_scans
    return simulate_ssa(params_from_config(config["ssa"], "ssa15"), 3)


def test_blind_run_holds_the_predicted_initial_hypothesis_and_never_a_birth():
    sc = _scenario()
    run = st.blind_run(sc, snapshots=[0, 4])
    X, C = st.blind_predictions(sc.motion, sc.prior_means, sc.prior_covs, np.diff(sc.times))
    est = run.map_estimates[run.map_estimates["scan"] == 7]
    np.testing.assert_array_equal(est["label"], sc.prior_ids)
    np.testing.assert_allclose(est[["state_0", "state_1", "state_2", "state_3"]], X[7])
    np.testing.assert_allclose(est["cov_0_1"], C[7, :, 0, 1])
    n = len(sc.prior_ids)
    assert (run.summary["expected_number"] == n).all() and (run.summary["n_children"] == 0).all()
    assert run.cardinality["probability"].eq(1.0).all() and run.cardinality["n_objects"].eq(n).all()
    assert run.weights["scan"].tolist() == [0, 4] and run.weights["weight"].eq(1.0).all()
    assert run.summary["n_returns"].sum() == len(sc.scans)


def _matched(bad_scans, n_scans=5):
    rows = []
    for k in range(n_scans):
        status = "incorrect" if k in bad_scans else "correct"
        rows.append({"scan": k, "role": "estimate", "id": 0, "status": status})
        rows.append({"scan": k, "role": "truth", "id": 0, "status": "tracked" if status == "correct" else "missed"})
    return pd.DataFrame(rows)


def test_every_scan_verdict_counts_scans_with_a_red_star_and_leaves_scan_0_out():
    metrics = pd.DataFrame({"scan": range(5), "ospa_in_view": [9.0, 1.0, 1.0, 1.0, 3.0]})
    text, ok = st.every_scan_verdict(_matched({0, 2}), metrics, tolerance=0.25)
    assert text.startswith("25.0 % of 4 scans (1)") and "in-view OSPA 1.5 km" in text and ok
    assert not st.every_scan_verdict(_matched({0, 2}), metrics, tolerance=0.2)[1]
    # the accuracy bound: mean in-view OSPA 1.5 km over scans 1-4 against one return's RMS error
    assert not st.every_scan_verdict(_matched(set()), metrics, tolerance=0.0, max_ospa_km=1.41)[1]
    assert st.every_scan_verdict(_matched(set()), metrics, tolerance=0.0, max_ospa_km=1.5)[1]
    e = st.scan_errors(_matched({3}))
    assert e["clean"].tolist() == [True, True, True, False, True] and e.loc[3, "missed"] == 1
    with pytest.raises(ValueError, match="tolerance"):
        st.every_scan_verdict(_matched(set()), metrics, tolerance=1.5)
    with pytest.raises(ValueError, match="max_ospa_km"):
        st.every_scan_verdict(_matched(set()), metrics, tolerance=0.1, max_ospa_km=0.0)


def _claim(key, status, value="v"):
    return Claim("ssa50", f"item {key}", "000 Fig. 11", "1", value, "+/- 0.1", status, key=key)


def test_attach_controls_demotes_a_row_whose_control_also_passes():
    claims = [_claim("A", "reproduced"), _claim("B", "qualitative"), _claim("C", "not reproduced"),
              _claim("", "extension")]
    control = [_claim("A", "reproduced", "45"), _claim("B", "not reproduced", "45 -> 45"),
               _claim("C", "reproduced", "0")]
    a, b, c, d = st.attach_controls(claims, control)
    assert a.status == "uninformative" and a.control == f"{st.BLIND_LABEL}: 45 -> also passes"
    assert b.status == "qualitative" and b.control == f"{st.BLIND_LABEL}: 45 → 45 -> fails"
    assert c.status == "not reproduced" and c.control.endswith("-> also passes")  # only passing rows are demoted
    assert d == claims[3]
    only_b = st.attach_controls(claims, control, keys=["B"])
    assert only_b[0] == claims[0] and only_b[1].control


def test_ssa50_rows_a_blind_tracker_passes_are_uninformative_on_a_real_scenario():
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    config["ssa"]["n_scans"] = 30
    sc = simulate_ssa(params_from_config(config["ssa"], "ssa50"), 5)
    sec = config["ssa50"]
    K = len(sc.times)
    snaps = st.snapshot_scans(K, sec["weight_snapshots"])
    run, metrics, matched, births = st.evaluate_blind(sec, sc, snapshots=snaps)
    kw = dict(estimate_scans=st.snapshot_scans(K, sec["estimate_snapshots"]), n_scans=K,
              error_bound_probability=sec["error_bound_probability"])
    blind = {c.key: c for c in st.ssa50_claims(metrics, run.cardinality, run.weights, matched, births, **kw)}
    # E[N] = 45 before the first birth and all weight on the initial hypothesis: the blind tracker passes both
    assert blind["ExpectedStart"].status == "reproduced" and blind["InitialWeight"].status == "reproduced"
    # births: never tracked, E[N] stays 45, the MAP cardinality never moves, one hypothesis
    for key in ("ExpectedEnd", "PEnd", "SingleFile", "BirthsTracked", "HypothesesVary"):
        assert blind[key].status == "not reproduced", key
    # the same checks on the blind tracker's tables, attached to its own rows, demote exactly the two passing ones
    own = {c.key: c for c in st.attach_controls(list(blind.values()), blind)}
    assert own["ExpectedStart"].status == own["InitialWeight"].status == "uninformative"
    assert own["SingleFile"].status == "not reproduced"


def test_clutter_ignoring_engine_takes_the_clutter_density_a_million_times_too_small():
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    config["ssa"]["n_scans"] = 40
    sc = simulate_ssa(params_from_config(config["ssa"], "ssa50"), 5)
    defect = st.clutter_ignoring(sc)
    assert sc.sensor.clutter.density / defect.sensor.clutter.density == pytest.approx(1e6, rel=1e-9)
    assert defect.sensor.detection == sc.sensor.detection and defect.scans is sc.scans
    with pytest.raises(ValueError, match="factor"):
        st.clutter_ignoring(sc, 0.5)
    # the control runs up to the scan before the first birth, and there holds more objects than the 45 known:
    # clutter returns became births (the check "E[N] = 45 before the first birth" must fail on it)
    settings = st.TrackerSettings(kind="rfisst", max_hypotheses=3, n_steps=300, completion_rounds=0)
    run = st.clutter_control_run(sc, settings, np.random.default_rng(0))
    first = int(sc.first_in_view_scan[sc.birth_ids].min())
    assert run.summary["scan"].tolist() == list(range(first))
    n_clutter = int((sc.scans[sc.scans["scan"].between(1, first - 1)]["origin"] == -1).sum())
    assert n_clutter > 0
    e = run.summary.set_index("scan")["expected_number"]
    claim = st.expected_start_claim(e, 45, first, 39)
    assert e.iloc[-1] > 45.5 and claim.status == "not reproduced"

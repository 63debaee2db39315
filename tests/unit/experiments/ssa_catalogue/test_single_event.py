"""Document 000's single-event population through the factored engine
(:mod:`hypotrack.experiments.ssa_catalogue.single_event`): the per-scan comparison on a scene
computed by hand, the negative control on ssa50 (α = β = 0: no event, nothing to detect), the
summary on a hand-made table, the ledger rows and macros, and bad settings."""

import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.config import ConfigError, validate_config
from hypotrack.experiments.ssa_catalogue.single_event import (
    SingleEventSettings,
    against_floor,
    compare_runs,
    pair_summary,
    single_event_claims,
    single_event_comparison,
    single_event_macros,
)
from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    FactoredFilter,
    FISSTPoissonWeights,
    HypothesisFilter,
    SingleEventPopulation,
)
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor
from hypotrack.scenarios.ssa import scenario_from_config

P_D = 0.85
VIEW = Box([-10.0, -10.0], [10.0, 10.0])
SENSOR = position_sensor(0.3, P_D, VIEW, 1.0, Box([-20.0, -20.0], [20.0, 20.0]))


def _config():
    with open("workflows/config/default.yaml") as fh:
        return yaml.safe_load(fh)


def _two_objects(beta, seed):
    """Two objects far apart in view, deaths only (α = 0), exhaustive children: no sampling."""
    pop = SingleEventPopulation(SingleEventBirthDeath(0.0, beta, 1),
                                birth_densities=(UniformBirthDensity(VIEW, np.eye(2) * 0.05),))
    return HypothesisFilter(ConstantVelocity(q=0.02), SENSOR, FISSTPoissonWeights(), ExhaustiveGenerator(),
                            population=pop, max_hypotheses=10**6, gate_probability=0.99, seed=seed,
                            means=[[-3.0, 0.0, 1.0, 0.0], [9.0, -5.0, 0.0, 0.0]],
                            covs=np.repeat(np.diag([0.5, 0.5, 0.05, 0.05])[None], 2, axis=0))


def test_comparison_of_one_empty_scan_by_hand():
    """One scan without returns. Unfactored (one event for the scene): P(2) = (1 − 2β)(1 − p_D) /
    ((1 − 2β)(1 − p_D) + 2β), P(1) the rest. Factored (one event per object's group): each object
    alive with q = (1 − β)(1 − p_D) / ((1 − β)(1 − p_D) + β), independently. The reseeded run is
    exhaustive too, so the floor is 0."""
    beta = 0.05
    filters = {"unfactored": _two_objects(beta, 0), "factored": FactoredFilter.from_filter(_two_objects(beta, 0)),
               "reseeded": _two_objects(beta, 1)}
    per_scan, cpu = compare_runs(filters, [(0.0, np.zeros((0, 2))), (1.0, np.zeros((0, 2)))], [2, 2])
    miss = 1 - P_D
    p2 = (1 - 2 * beta) * miss / ((1 - 2 * beta) * miss + 2 * beta)
    q = (1 - beta) * miss / ((1 - beta) * miss + beta)
    (r,) = per_scan.to_dict("records")
    tv = 0.5 * ((1 - q) ** 2 + abs(1 - p2 - 2 * q * (1 - q)) + abs(p2 - q * q))
    assert r["tv_factoring"] == pytest.approx(tv, abs=1e-12) and r["tv_factoring"] == pytest.approx(0.0675, abs=1e-4)
    assert r["tv_chain_noise"] == pytest.approx(0.0, abs=1e-12)
    assert r["tv_factoring_reseeded"] == pytest.approx(tv, abs=1e-12)  # the reseeded run is the unfactored one
    assert r["expected_number_unfactored"] == pytest.approx(1 + p2, abs=1e-12)
    assert r["expected_number_factored"] == pytest.approx(2 * q, abs=1e-12)
    assert r["p_true_unfactored"] == pytest.approx(p2, abs=1e-12) and r["p_true_factored"] == pytest.approx(q * q, abs=1e-12)
    # both MAP hypotheses keep the two objects (p2 ≈ 0.57, q ≈ 0.74 > 1/2)
    assert (r["map_n_unfactored"], r["map_n_factored"], r["map_same_n_factoring"]) == (2, 2, True)
    assert (r["scan"], r["n_returns"], r["n_true"], r["groups"]) == (1, 0, 2, 2)
    assert set(cpu) == {"unfactored", "factored", "reseeded"}


def test_no_events_on_ssa50_nothing_to_detect():
    """Negative control on document 000's scenario (its first 5 scans, 200 proposals): with α = β = 0
    the population has no event, so every run holds the 45 known objects with probability 1 — TV 0
    (to rounding: the factored cardinality is a convolution) and E[N] = 45 at every scan, although
    the factored run keeps about one group per object."""
    cfg = _config()
    cfg["ssa50"]["population"].update(alpha=0.0, beta=0.0)
    per_scan, _ = single_event_comparison(scenario_from_config(cfg, "ssa50"), SingleEventSettings(n_steps=200, n_scans=6),
                                          cfg["ssa50"], cfg["seed"])
    assert per_scan["scan"].tolist() == [1, 2, 3, 4, 5] and (per_scan["n_true"] == 45).all()
    for pair in ("factoring", "factoring_reseeded", "chain_noise"):
        assert per_scan[f"tv_{pair}"].abs().max() < 1e-12 and per_scan[f"map_same_n_{pair}"].all()
    for run in ("unfactored", "factored", "reseeded"):
        np.testing.assert_allclose(per_scan[f"expected_number_{run}"], 45.0, rtol=0, atol=1e-9)
        np.testing.assert_allclose(per_scan[f"p_true_{run}"], 1.0, rtol=0, atol=1e-12)
        assert (per_scan[f"map_n_{run}"] == 45).all()
    # the comparison is of a factored posterior: (nearly) one group per object, not one group
    assert per_scan["groups"].min() >= 44 and per_scan["largest_group"].max() <= 2


def _hand_frame():
    return pd.DataFrame({
        "scan": [1, 2, 3], "n_true": [45, 45, 46],
        "expected_number_unfactored": [45.0, 45.5, 46.0],
        "expected_number_factored": [45.1, 45.2, 46.3],
        "expected_number_reseeded": [45.0, 45.6, 45.9],
        "p_true_unfactored": [1.0, 0.5, 0.8], "p_true_factored": [0.9, 0.6, 0.7], "p_true_reseeded": [1.0, 0.4, 0.85],
        "tv_factoring": [0.1, 0.3, 0.2], "tv_factoring_reseeded": [0.05, 0.2, 0.02], "tv_chain_noise": [0.0, 0.1, 0.05],
        "map_same_n_factoring": [True, False, True], "map_same_n_factoring_reseeded": [True, True, False],
        "map_same_n_chain_noise": [True, True, True],
        "groups": [40, 42, 44], "largest_group": [3, 5, 4]})


def test_summary_on_a_hand_made_table():
    s = pair_summary(_hand_frame()).set_index("pair")
    f, r, c = s.loc["factoring"], s.loc["factoring_reseeded"], s.loc["chain_noise"]
    assert f.tv_mean == pytest.approx(0.2) and f.tv_max == 0.3 and f.tv_max_scan == 2 and f.tv_final == 0.2
    assert f.abs_den_mean == pytest.approx((0.1 + 0.3 + 0.3) / 3) and f.den_final == pytest.approx(0.3)
    assert f.map_same_n_share == pytest.approx(2 / 3) and f.p_true_final == 0.7 and f.p_true_final_reference == 0.8
    # factored − reseeded: 0.1, −0.4, 0.4
    assert r.tv_mean == pytest.approx(0.09) and r.tv_max == 0.2 and r.tv_max_scan == 2 and r.tv_final == 0.02
    assert r.abs_den_mean == pytest.approx(0.3) and r.den_final == pytest.approx(0.4) and r.map_same_n_share == pytest.approx(2 / 3)
    assert r.p_true_final == 0.7 and r.p_true_final_reference == 0.85
    assert c.tv_mean == pytest.approx(0.05) and c.tv_max == 0.1 and c.tv_final == 0.05
    assert c.abs_den_mean == pytest.approx(0.2 / 3) and c.den_final == pytest.approx(-0.1) and c.map_same_n_share == 1.0
    assert [(x.run, x.reference) for x in (f, r, c)] == [("factored", "unfactored"), ("factored", "reseeded"),
                                                         ("reseeded", "unfactored")]
    assert f.n_scans == 3


@pytest.mark.parametrize("effect, floor, word", [
    ((0.2, 0.09), 0.05, "about as large as"),  # 0.09 < 2 × 0.05: one factored pair does not exceed the floor twice
    ((0.2, 0.11), 0.05, "larger than"),
    ((0.02, 0.04), 0.1, "smaller than"),
    ((0.02, 0.06), 0.1, "about as large as"),
    ((0.29, 0.05), 0.29, "about as large as"),  # a wandering unfactored chain: the floor and one pair both large
])
def test_against_floor_needs_a_factor_of_two_in_both_factored_pairs(effect, floor, word):
    summary = pd.DataFrame({"pair": ["factoring", "factoring_reseeded", "chain_noise"], "tv_mean": [*effect, floor]})
    assert against_floor(summary) == word


def test_claims_and_macros_quote_effect_and_floor():
    frame = _hand_frame()
    summary = pair_summary(frame)
    settings = SingleEventSettings()
    tv, en = single_event_claims(summary, frame, settings, h_inf=100)
    assert tv.reproduced == "TV mean 0.2 (max 0.3) and 0.09 (max 0.2) vs chain-seed floor 0.05 (max 0.1)"
    assert en.reproduced == "mean |ΔE[N]| 0.23 and 0.3 vs chain-seed floor 0.067"
    for row in (tv, en):
        assert (row.status, row.evidence, row.experiment) == ("extension", "measurement", "ssa_catalogue")
        assert "3 scans" in row.note and "H_inf = 100 per group" in row.note and "count term" in row.note
    assert "last scan TV 0.2 and 0.02 (floor 0.05)" in tv.note and "largest 5 objects" in tv.note
    assert "effect about as large as the floor" in tv.note
    assert "66.7 % and 66.7 % of scans (floor 100 %)" in en.note and "0.700 factored, 0.800 unfactored, 0.850 reseeded" in en.note
    m = single_event_macros(summary, frame, settings)
    assert m == {"SingleEventScans": 3, "SingleEventGateMiss": "1e-09", "SingleEventGroupsMean": "42",
                 "SingleEventLargestGroup": 5, "SingleEventTvMean": "0.2", "SingleEventTvMax": "0.3",
                 "SingleEventTvFinal": "0.2", "SingleEventDenMean": "0.23", "SingleEventMapSame": "66.7",
                 "SingleEventFloorTvMean": "0.05", "SingleEventFloorTvMax": "0.1", "SingleEventFloorTvFinal": "0.05",
                 "SingleEventReseededTvMean": "0.09", "SingleEventReseededTvMax": "0.2",
                 "SingleEventReseededTvFinal": "0.02", "SingleEventReseededDenMean": "0.3",
                 "SingleEventReseededMapSame": "66.7",
                 "SingleEventFloorDenMean": "0.067", "SingleEventFloorMapSame": "100",
                 "SingleEventAgainstFloor": "about as large as", "SingleEventFloorFactor": "2"}


@pytest.mark.parametrize("kw, message", [({"split": "sometimes"}, "split"), ({"gate_probability": 1.0}, "gate_probability"),
                                         ({"n_steps": 0}, "n_steps"), ({"n_scans": 1}, "n_scans")])
def test_bad_settings_name_the_parameter(kw, message):
    with pytest.raises(ValueError, match=message):
        SingleEventSettings(**kw)


def test_tracker_must_be_rfisst_with_births_and_deaths():
    ssa50 = _config()["ssa50"]
    settings = SingleEventSettings(n_steps=123, gate_probability=0.99)
    t = settings.tracker_settings(ssa50)
    assert (t.kind, t.n_steps, t.gate_probability, t.completion_rounds, t.beta) == ("rfisst", 123, 0.99, 0, 1e-4)
    with pytest.raises(ValueError, match="R-FISST"):
        SingleEventSettings(tracker="glmb").tracker_settings(ssa50)
    with pytest.raises(ValueError, match="unknown tracker"):
        SingleEventSettings(tracker="nope").tracker_settings(ssa50)


def test_config_validation_names_the_bad_single_event_key():
    cfg = copy.deepcopy(_config())
    cfg["ssa_catalogue"]["single_event"]["split"] = "sometimes"
    with pytest.raises(ConfigError, match=r"ssa_catalogue\.single_event\.split"):
        validate_config(cfg, "workflows/config/schema")

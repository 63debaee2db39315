"""A preset registered here, and nowhere else, reaches every experiment's tracker construction and the
Stone Soup adapter: the registry is the one way trackers are built.

Two kinds are registered for the test: ``test_chain`` (engine family: R-FISST's chain with its own
option ``chain_length``) and ``test_nn`` (single family: GNN on Stone Soup's Mahalanobis criterion).
Each experiment that builds trackers of a family is run for one scan with the new kind; the option
is checked to have reached the tracker, and the scan to have used the returns.
"""

from __future__ import annotations

import copy
import datetime

import numpy as np
import pytest
import yaml

from hypotrack.experiments import ssa as st
from hypotrack.experiments.glmb_benchmark import run as gb
from hypotrack.experiments.sht import run as sht
from hypotrack.experiments.ssa_catalogue import run as cat
from hypotrack.hypotheses import HypothesisFilter, presets
from hypotrack.hypotheses.factored import FactoredFilter
from hypotrack.registry import engine_options, register, unregister
from hypotrack.scenarios.cluttered import crossing_targets
from hypotrack.scenarios.ssa import SSAParams, prior_table, simulate_ssa
from hypotrack.trackers import ScanModel, SingleHypothesisTracker

CONFIG = yaml.safe_load(open("workflows/config/default.yaml"))
built = []


def _chain(problem, *, seed, population, chain_length, **common):
    built.append(("test_chain", problem))
    return presets.rfisst(problem.motion, problem.sensor, n_steps=chain_length, completion_rounds=0,
                          population=problem.event_population() if population else None,
                          **engine_options(problem, seed, common))


def _nn(problem, *, seed, gate_probability, max_misses, min_clutter_rate, **unused):
    built.append(("test_nn", problem))
    s = problem.sensor
    model = ScanModel(s.measurement.H, s.measurement.R, s.detection.p_D, gate_probability,
                      max(s.clutter.rate, min_clutter_rate, 1e-9) / s.clutter.region.area, 0.0)
    return SingleHypothesisTracker(problem.motion, model, association="gnn", gnn_score="mahalanobis",
                                   max_misses=max_misses, in_view=problem.in_view)


@pytest.fixture(autouse=True)
def registered():
    built.clear()
    register("test_chain", _chain, family="engine",
             options={"chain_length": {"type": "integer", "minimum": 1, "default": 60}})
    register("test_nn", _nn, family="single")
    yield
    unregister("test_chain")
    unregister("test_nn")


def test_ssa_experiments():
    params = SSAParams(n_objects=5, n_known=4, n_scans=3)
    sim = simulate_ssa(params, 3)
    scenario = st.scenario_from_tables(params, sim.truth, sim.scans, prior_table(sim))
    section = {"max_hypotheses": 5, "gate_probability": None, "population": {"alpha": 1e-3, "n_birth_regions": 2},
               "trackers": {"mine": {"kind": "test_chain", "chain_length": 40}}}
    tracker = st.make_tracker(scenario, st.TrackerSettings.from_config(section, "mine"), 1)
    assert isinstance(tracker, HypothesisFilter) and tracker.generator.n_steps == 40
    assert tracker.max_hypotheses == 5 and built[-1][1].births.n_birth_regions == 2
    t, Z = scenario.scan_list()[1]
    post = tracker.step(Z, t)
    assert tracker.time == t and np.isclose(post.weights.sum(), 1.0)
    assert post.map_estimate.n_objects >= 4  # the known objects, each updated with its return
    with pytest.raises(ValueError, match="hypothesis engine"):
        st.TrackerSettings("test_nn")


def test_catalogue_experiment_factored_and_single():
    cfg = copy.deepcopy(CONFIG["ssa_catalogue"])
    cfg.pop("tuning", None)  # scan 0 at the catalogue's epoch, where the scene below holds
    cfg = cat.peer_config(cfg)  # the ENU stand-in radar (a fixed H, which the test kinds' scan model reads)
    cfg["model"] = {k: v for k, v in cfg["model"].items() if k not in ("birth", "plausibility")}
    cfg.update(n_scans=2, trackers={
        "mine": {"kind": "test_chain", "chain_length": 30, "max_hypotheses": 4, "gate_probability": 0.999,
                 "factored": {"lazy": True, "min_weight": 0.001, "gate_out_of_view": False}},
        "mine_nn": {"kind": "test_nn", "gate_probability": 0.999}})
    per_scan, assign, _ = cat.run_tracker("mine", cfg, 100, 0)  # two objects in view at scans 0 and 1
    assert len(per_scan) == 2 and per_scan["n_groups"].notna().all()
    assert (per_scan["n_estimates"] == per_scan["n_in_view"]).all() and (per_scan["gospa_km"] < 2.0).all()
    problem = built[-1][1]
    assert built[-1][0] == "test_chain" and problem.adaptive_birth() is not None
    per_scan, _, _ = cat.run_tracker("mine_nn", cfg, 100, 0)
    assert len(per_scan) == 2 and per_scan["n_groups"].isna().all() and built[-1][0] == "test_nn"
    assert (per_scan["n_estimates"] == per_scan["n_in_view"]).all() and (per_scan["gospa_km"] < 2.0).all()
    tracker = cat.make_tracker("mine", cfg, problem, 0)
    assert isinstance(tracker, FactoredFilter)


def test_glmb_benchmark():
    cfg = CONFIG["glmb_benchmark"]
    model = gb.benchmark_model(cfg)
    truth = gb.truth_states(cfg["truth"], 2, convention="gen_truth")
    scans = gb.simulate_scans(model, truth, np.random.default_rng(0))
    tracker = gb.make_tracker("test_chain", model, {"chain_length": 25, "max_hypotheses": 5, "run_every": 1}, 3)
    assert tracker.generator.n_steps == 25 and type(built[-1][1].births).__name__ == "LabeledMultiBernoulliPopulation"
    df = gb.run_tracker(tracker, scans[:1], truth[:1], 100.0)
    assert len(df) == 1 and df["expected_number"].iloc[0] > 0  # births from the four labeled terms


def test_sht_experiment():
    scenario = crossing_targets(2, crossing_angle_deg=40.0, clutter_rate=1.0, n_scans=3, rng=2)
    per_scan, lost, _ = sht.run_crossing(CONFIG["sht"], "test_nn", scenario)
    assert built[-1][0] == "test_nn" and len(per_scan) == 2 and lost == 0


@pytest.mark.parametrize("kind", ["test_chain", "test_nn"])
def test_stonesoup_adapter(kind):
    pytest.importorskip("stonesoup")
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.types.detection import Detection
    from stonesoup.types.state import GaussianState

    from hypotrack.interop.stonesoup import HypotrackTracker

    t0 = datetime.datetime(2026, 1, 1)
    mm = LinearGaussian(4, (0, 2), np.eye(2))
    tracker = HypotrackTracker(
        transition_model=CombinedLinearGaussianTransitionModel([ConstantVelocity(0.1), ConstantVelocity(0.1)]),
        measurement_model=mm, algorithm=kind, detection_probability=0.9, clutter_rate=1.0,
        clutter_region=[[-50, 50], [-50, 50]],
        initial_states=[GaussianState(np.array([[0.0], [1.0], [0.0], [0.0]]), np.eye(4), timestamp=t0)],
        options={"chain_length": 30, "seed": 1} if kind == "test_chain" else {})
    time, tracks = tracker.update_tracker(t0 + datetime.timedelta(seconds=1),
                                          {Detection(np.array([[1.1], [0.1]]), timestamp=t0 + datetime.timedelta(
                                              seconds=1), measurement_model=mm)})
    assert built[-1][0] == kind and len(tracks) == 1
    state = next(iter(tracks)).state
    assert abs(state.state_vector[0, 0] - 1.1) < 0.6  # updated towards the return

"""The radar and the fence fused in the catalogue's trackers (hypotrack.experiments.ssa_catalogue.fused)."""

import copy

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.fused import (SENSOR_SETS, TABLE_COLUMNS, fused_table, fused_tracker,
                                                       fusion_claims, fusion_macros, make_fence)
from hypotrack.experiments.ssa_catalogue.run import initial_tracks, make_motion, make_problem, make_radar
from hypotrack.hypotheses.factored.multisensor import MultiSensorFactored
from hypotrack.registry import TrackerSpec, build
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, attributable_to_state
from hypotrack.trackers.multisensor import MultiSensorSHT

THETA = 1.0  # GMST (rad) of the scan


def _cfg():
    with open("workflows/config/default.yaml") as fh:
        cfg = yaml.safe_load(fh)["ssa_catalogue"]
    cfg = copy.deepcopy(cfg)
    cfg["radar"].pop("snr")  # constant p_D: the update is the subject here
    cfg["fusion"]["fence"]["snr"] = False
    cfg["model"]["birth"] = "one_point"
    cfg["model"]["plausibility"] = False  # one-point newborns are mostly unbound: the test would refuse them all
    return cfg


def _scene():
    """One known object in the fence's view (1,500 km at azimuth 30°, elevation 21.5° from Kwajalein, a LEO speed
    across the line of sight), out of the radar's (45° N, 0° E)."""
    cfg = _cfg()
    radar, fence = RadarTrackerSensor(make_radar(cfg)).at(THETA), RadarTrackerSensor(make_fence(cfg)).at(THETA)
    x = attributable_to_state(np.array([1500.0, np.deg2rad(30.0), np.deg2rad(21.5), -1.0, 0.0035, 0.002]),
                              fence.radar.site, THETA)[0].real
    assert fence.detection.in_view(x[None])[0] and not radar.detection.in_view(x[None])[0]
    P0 = np.diag([1.0, 1.0, 1.0, 1e-4, 1e-4, 1e-4])
    rng = np.random.default_rng(3)
    x0 = x + rng.standard_normal(6) * np.sqrt(np.diag(P0))
    z = fence.h(x[None])[0] + np.array([0.02, 2e-4, -3e-4, 0.005])
    return cfg, radar, fence, x0, P0, z


class _Sc:
    """The parts of a scenario :func:`fused_tracker` reads: the known object's state at scan 0."""

    def __init__(self, x0, P0):
        self.catalogue = pd.DataFrame(dict(norad=[7]))
        self._x = x0

    def states(self, times):
        return self._x[None, None], np.ones((1, 1), bool)


@pytest.mark.parametrize("name", ["glmb", "gnn"])
def test_the_fences_return_updates_the_track_with_the_fences_model(name):
    """The radar's scan (no return: the object is out of its view) then the fence's at the same instant (zero
    interval): the track is the fence's EKF update of the prior — its own measurement model (site, frame, R) —
    and not the radar's."""
    cfg, radar, fence, x0, P0, z = _scene()
    cfg["init_position_std_km"], cfg["init_velocity_std_km_s"] = 1.0, 0.01
    tsensors = [radar, fence]
    scenario = ({}, np.zeros(0, np.int64), _Sc(x0, P0), 0)
    tracker = fused_tracker(name, cfg, scenario, tsensors, seed=1)
    assert isinstance(tracker, MultiSensorFactored if name == "glmb" else MultiSensorSHT)
    # the prior the tracker started from: initial_tracks adds a seeded error; read it back
    if name == "gnn":
        x_prior, P_prior = tracker.x[0].copy(), tracker.P[0].copy()
    else:
        st = tracker.posterior().map_estimate
        x_prior, P_prior = st.means[0].copy(), st.covs[0].copy()
    tracker.step(np.zeros((0, 4)), 0.0, sensor=0)
    tracker.step(z[None], 0.0, sensor=1)
    if name == "gnn":
        x, P = tracker.x[0], tracker.P[0]
    else:
        est = tracker.posterior().map_estimate
        assert len(est.labels) == 1
        x, P = est.means[0], est.covs[0]
    want_x, want_P = fence.measurement.update(x_prior[None], P_prior[None], z[None])
    np.testing.assert_allclose(x, want_x[0], rtol=0, atol=1e-6)
    # GNN's own EKF update (gnn_update: the gain from its gated S) and the measurement model's agree to ~2e-6 relative
    # on this ill-conditioned S (30 m in range, ~1 km across the beam); the radar's model is 100s of km away
    np.testing.assert_allclose(P, want_P[0], rtol=1e-8 if name == "glmb" else 1e-5, atol=1e-12)
    wrong_x, _ = radar.measurement.update(x_prior[None], P_prior[None], z[None])
    assert np.linalg.norm(wrong_x[0][:3] - x[:3]) > 100.0  # the radar's model would put it elsewhere


def _hand_wrapped(name, cfg, scenario, tsensors, seed):
    """The fused tracker wrapped by hand, as the experiment did before the registry built it: one registry tracker
    per sensor's problem, the engine's joined with each problem's adaptive births and the ``factored`` options."""
    objects, unknown, sc, init_seed = scenario
    motion = make_motion(cfg)
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    problems = [make_problem(cfg, t, motion, means, covs, labels) for t in tsensors]
    own = dict(cfg["trackers"][name])
    factored = own.pop("factored", None)
    trackers = [build(TrackerSpec.from_config(own), p, seed=seed) for p in problems]
    if factored is None:
        return MultiSensorSHT.from_trackers(trackers)
    # adaptive births for a preset with a population and no births seeded at the returns (HOMHT's population, with
    # the model's survival, holds only its deaths)
    births = [p.adaptive_birth() if t.population is not None and not t.weights.seeded_births else None
              for p, t in zip(problems, trackers)]
    return MultiSensorFactored.from_filters(trackers, births, **factored)


@pytest.mark.parametrize("name", ["glmb", "homht_kbest", "rfisst", "gnn", "jpda"])
def test_the_registry_builds_the_hand_wrapped_tracker(name):
    """The catalogue's sensors (the radar, the fence; sensor-frame EKF, admissible-region births of each one's own
    returns, the fence's return at a zero interval after the radar's empty scan, then an empty instant): the tracker
    the registry builds is the hand-wrapped one, bit for bit (engine) or track for track (GNN/JPDA)."""
    cfg, radar, fence, x0, P0, z = _scene()
    cfg["model"]["birth"] = "admissible"
    scenario = ({}, np.zeros(0, np.int64), _Sc(x0, P0), 0)
    reg = fused_tracker(name, cfg, scenario, [radar, fence], seed=1)
    hand = _hand_wrapped(name, cfg, scenario, [radar, fence], seed=1)
    clutter = fence.h(x0[None])[0] + np.array([40.0, 0.01, 0.004, 0.3])  # a second return: a birth candidate
    for t, s, Z in ((0.0, 0, np.zeros((0, 4))), (0.0, 1, np.vstack([z, clutter])), (10.0, 0, np.zeros((0, 4))),
                    (10.0, 1, np.zeros((0, 4)))):
        reg.step(Z, t, sensor=s)
        hand.step(Z, t, sensor=s)
        if isinstance(reg, MultiSensorFactored):
            assert reg.same_posterior(hand)
        else:
            for a, b in ((reg.ids, hand.ids), (reg.x, hand.x), (reg.P, hand.P), (reg.initiator.x, hand.initiator.x)):
                np.testing.assert_array_equal(a, b)
    assert len(reg.estimates()) >= 1


def _rows():
    base = {c: 0.0 for c in TABLE_COLUMNS}
    rows = []
    for t in ("glmb", "gnn"):
        for s, comp, real, g in (("radar", 0.2, 1.0, 0.5), ("radar+fence", 0.25, 0.9, 0.4)):
            rows.append({**base, "tracker": t, "sensors": s, "fence_returns": 100 if s != "radar" else 0,
                         "n_objects": 300, "n_scans": 720, "completeness": comp, "realism_95": real,
                         "gospa_per_object_km": g, "reacquisitions": 4, "reacq_within_km": 0.5,
                         "time_to_orbit_unknown_s": float("nan"), "unknown_with_orbit": 0})
    return rows[::-1]


def test_table_claims_and_macros_on_a_fabricated_table():
    t = fused_table(_rows())
    assert list(t["tracker"]) == ["gnn", "gnn", "glmb", "glmb"] and list(t["sensors"]) == list(SENSOR_SETS) * 2
    claims = fusion_claims(t)
    keys = [c.key for c in claims]
    assert keys == [f"fusion_{f}_{n}" for n in ("gnn", "glmb") for f in ("completeness", "realism", "gospa")]
    assert claims[0].reproduced == "0.25" and "radar alone 0.2 " in claims[0].note and claims[0].status == "extension"
    m = fusion_macros(t)
    assert m["FusionCompletenessglmbFused"] == "0.25" and m["FusionCompletenessglmbRadar"] == "0.2"
    assert m["FusionTimeToOrbitgnnFused"] == "n/a" and m["FusionFenceReturns"] == 100 and m["FusionReacqgnnRadar"] == 4


def test_fusion_needs_the_documented_radar():
    cfg = _cfg()
    cfg["radar"]["measurement"] = "enu"
    with pytest.raises(ValueError, match="radar.measurement: rae_rate"):
        make_fence(cfg)

"""The catalogue model's optional physics through the registry-built trackers: a never-confirmed track decays
out in a hand-computed number of scans while a confirmed one out of view for an orbit stays; with
``plausibility: true`` a hypothesis holding an unphysical track is pruned and GNN deletes such a track."""

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from hypotrack.config import ConfigError, validate_config
from hypotrack.experiments.ssa_catalogue.physics import model_survival, model_validity
from hypotrack.experiments.ssa_catalogue.run import make_motion, make_problem, make_radar, make_tracker, peer_config
from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue.tracking import TrackerSensor

ROOT = Path(__file__).resolve().parents[4]
OMEGA_E = 7.2921159e-5  # rad/s


def _cfg(**model):
    with open(ROOT / "workflows" / "config" / "default.yaml") as fh:
        cfg = copy.deepcopy(yaml.safe_load(fh)["ssa_catalogue"])
    cfg = peer_config(cfg)  # the ENU stand-in radar with a constant p_D: these are tests of the model block
    cfg["model"] = {k: v for k, v in cfg["model"].items() if k not in ("birth", "plausibility")}
    cfg["model"].update(model)
    return cfg


# Two objects on the far side of the Earth from the radar (45 N, 0 E; TEME = Earth-fixed at theta = 0):
# a catalogued one on a circular 622-km polar orbit (confirmed: velocity std 0.5 m/s) and a one-point
# birth left by a false return (zero velocity, 8 km/s std: tentative).
V_CIRC = np.sqrt(398600.4418 / 7000.0)
CONFIRMED = np.array([-7000.0, 0, 0, 0, 0, V_CIRC])
TENTATIVE = np.array([-6900.0, 0, 1000.0, 0, 0, 0])
P_CONF = np.diag([0.25, 0.25, 0.25, 2.5e-7, 2.5e-7, 2.5e-7])
P_TENT = np.diag([1.0, 1.0, 1.0, 64.0, 64.0, 64.0])


def _run(cfg, name, means, covs, n_scans):
    tsensor = TrackerSensor(make_radar(cfg))
    problem = make_problem(cfg, tsensor, make_motion(cfg), means, covs, np.arange(len(means)))
    tracker = make_tracker(name, cfg, problem, seed=0)
    out = []
    for k in range(1, n_scans + 1):
        t = 10.0 * k
        tsensor.at(OMEGA_E * t)
        post = tracker.step(np.zeros((0, 3)), t)
        out.append(post)
    return tracker, out


def test_never_confirmed_track_decays_out_in_hand_computed_scans():
    """p_tentative = 0.5, min_weight = 0.001: existence 0.5^k, pruned once 0.5^k < 0.001, i.e. at k = 10
    (0.5^9 = 0.00195 stays); the confirmed object's existence stays 1 (p_confirmed = 1)."""
    cfg = _cfg(unconfirmed_decay={"p_tentative": 0.5, "velocity_std_km_s": 1.0})
    tracker, posts = _run(cfg, "glmb", np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]), 11)
    for k, post in enumerate(posts, start=1):
        expected = 1.0 + (0.5**k if k <= 9 else 0.0)
        assert post.expected_number == pytest.approx(expected, rel=1e-9), k
    assert tracker.estimates().labels.tolist() == [0]


def test_confirmed_object_out_of_view_for_an_orbit_survives():
    cfg = _cfg(unconfirmed_decay={"p_tentative": 0.5, "velocity_std_km_s": 1.0})
    period_scans = int(np.ceil(2 * np.pi * np.sqrt(7000.0**3 / 398600.4418) / 10.0))  # 5,828 s: 583 scans
    assert period_scans == 583
    tracker, posts = _run(cfg, "glmb", CONFIRMED[None], P_CONF[None], period_scans)
    assert all(p.expected_number == 1.0 for p in posts)
    assert tracker.estimates().labels.tolist() == [0]
    # and the covariance stayed "confirmed" (largest velocity std below 1 km/s) all along
    assert model_survival(cfg["model"])(tracker.estimates().x, np.stack([P_CONF])).tolist() == [1.0]


def test_without_decay_the_false_entry_stays():
    tracker, posts = _run(_cfg(unconfirmed_decay=None), "glmb", np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]),
                          11)
    assert [p.expected_number for p in posts] == [2.0] * 11


def test_plausibility_prunes_the_hypotheses_holding_an_unphysical_track():
    """With decay the tentative, unphysical track's hypotheses are {held: 0.5, died: 0.5} after one scan;
    ``plausibility: true`` gives the first weight 0, so the posterior holds the catalogued object alone."""
    assert plausible_orbits(CONFIRMED) and not plausible_orbits(TENTATIVE)
    decay = {"p_tentative": 0.5, "velocity_std_km_s": 1.0}
    _, off = _run(_cfg(unconfirmed_decay=decay), "glmb", np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]), 1)
    assert off[0].expected_number == pytest.approx(1.5, rel=1e-12)
    tracker, on = _run(_cfg(unconfirmed_decay=decay, plausibility=True), "glmb",
                       np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]), 1)
    assert on[0].expected_number == 1.0
    assert tracker.estimates().labels.tolist() == [0]


def test_plausibility_deletes_an_unphysical_gnn_track():
    tracker, _ = _run(_cfg(plausibility=True), "gnn", np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]), 1)
    assert tracker.estimates().labels.tolist() == [0]
    kept, _ = _run(_cfg(), "gnn", np.stack([CONFIRMED, TENTATIVE]), np.stack([P_CONF, P_TENT]), 1)
    assert kept.estimates().labels.tolist() == [0, 1]


def test_model_options_checked():
    assert model_survival({}) is None and model_validity({}) is None
    assert model_validity({"plausibility": True}) is plausible_orbits
    with pytest.raises(ValueError, match="model.unconfirmed_decay"):
        model_survival({"unconfirmed_decay": {"p_tentative": 0.5}})
    with pytest.raises(ValueError, match="p_tentative"):
        model_survival({"unconfirmed_decay": {"p_tentative": 1.5, "velocity_std_km_s": 1.0}})
    with pytest.raises(ValueError, match="model.plausibility"):
        model_validity({"plausibility": "yes"})


def test_schema_takes_the_options():
    with open(ROOT / "workflows" / "config" / "default.yaml") as fh:
        config = yaml.safe_load(fh)
    schemas = ROOT / "workflows" / "config" / "schema"
    for section in ("ssa_catalogue", "ssa_breakup"):
        good = copy.deepcopy(config)
        good[section]["model"].update(unconfirmed_decay={"p_tentative": 0.5, "velocity_std_km_s": 1.0},
                                      plausibility=True)
        validate_config(good, schemas)
        bad = copy.deepcopy(config)
        bad[section]["model"]["unconfirmed_decay"] = {"p_tentative": 1.5, "velocity_std_km_s": 1.0}
        with pytest.raises(ConfigError, match="unconfirmed_decay"):
            validate_config(bad, schemas)


def test_snr_config_reaches_truth_and_trackers():
    from hypotrack.experiments.ssa_catalogue.run import build_scenario, run_tracker
    from hypotrack.scenarios.catalogue.snr import SnrModel

    snr = {"wavelength_m": 0.69, "ref_diameter_m": 0.1, "ref_range_km": 1500.0, "ref_p_D": 0.5, "p_fa": 1e-6}
    with open(ROOT / "workflows" / "config" / "default.yaml") as fh:
        config = yaml.safe_load(fh)
    config["ssa_catalogue"]["radar"]["snr"] = snr
    validate_config(config, ROOT / "workflows" / "config" / "schema")
    cfg = _cfg()  # the ENU stand-in (a linear TrackerSensor below) ...
    cfg["radar"] = dict(cfg["radar"], snr=snr)  # ... with this SNR detection
    cfg["n_scans"] = 30
    constant = {k: v for k, v in cfg["radar"].items() if k != "snr"}  # the radar's constant p_D
    assert make_radar(cfg).snr == SnrModel(**snr) and make_radar({**cfg, "radar": constant}).snr is None
    objects, unknown, sc, init_seed = build_scenario(cfg, 300, 1)
    plain = build_scenario({**cfg, "radar": constant}, 300, 1)[2]
    assert sc.n_in_view.sum() == plain.n_in_view.sum()  # same truth
    assert not sc.scans[["z_0", "z_1", "z_2"]].equals(plain.scans[["z_0", "z_1", "z_2"]])  # other detections
    per_scan, _, _ = run_tracker("glmb", cfg, 300, 1, scenario=(objects, unknown, sc, init_seed))
    assert len(per_scan) == 30
    # the trackers' detection: the marginal over the sizes with the config's debris share (0.5 by default)
    from hypotrack.experiments.ssa_catalogue.physics import attach_tracker_snr
    from hypotrack.scenarios.catalogue.snr import SizeModel, SnrTrackerDetection
    from hypotrack.scenarios.catalogue.tracking import TrackerSensor

    det = attach_tracker_snr(cfg, TrackerSensor(make_radar(cfg))).detection
    ref = SnrTrackerDetection(TrackerSensor(make_radar(cfg)), SnrModel(**snr), SizeModel(debris_share=0.5))
    assert det.sizes.debris_share == cfg["debris_share"] == 0.5 and np.array_equal(det.table, ref.table)
    plain = {**cfg, "radar": constant}
    assert not hasattr(attach_tracker_snr(plain, TrackerSensor(make_radar(plain))).detection, "p_D_of")

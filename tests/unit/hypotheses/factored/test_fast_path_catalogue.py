"""The fast path on catalogue-like scans (the real catalogue, N = 400, the default configuration's radar,
J2 EKF and δ-GLMB / HOMHT k-best trackers): stepped both ways, every component's weights and moments agree
to 1e-12 at every scan, through births, groups that die, lone birth terms and objects out of view; and the
single-hypothesis prior the registry hands over goes to the lane as the exact split would put it."""

import numpy as np
import pytest

from hypotrack.experiments.ssa_catalogue.run import make_tracker, peer_config
from hypotrack.hypotheses import FactoredFilter, LabeledMultiBernoulliPopulation, glmb
from hypotrack.hypotheses.factored_groups import factorise
from hypotrack.hypotheses.factored.lane import one_hypothesis_lane
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models.motion import ConstantVelocity
from scenes import catalogue_scene, default_catalogue_config, position_sensor

N_SCANS = 40


@pytest.fixture(scope="module", params=["enu", "rae_rate"])
def catalogue(request):
    """The default section's scans with its documented radar (sensor-frame EKF, admissible births) or with the
    ENU stand-in (a fixed H: one-point births)."""
    cfg = default_catalogue_config(N_SCANS)
    # the shortcuts counted below are the silent population's (quiet groups dropped, lone tracks of r = 1); the
    # decaying one's Bernoulli lane and its fast path: test_bernoulli_lane.py
    cfg["model"] = {k: v for k, v in cfg["model"].items() if k != "unconfirmed_decay"}
    if request.param == "enu":
        cfg = peer_config(cfg)
        cfg["model"] = {k: v for k, v in cfg["model"].items() if k not in ("birth", "plausibility")}
    scene = catalogue_scene(cfg, 400, snr=False)
    return cfg, scene.problem(), [(t, Z) for t, Z, _ in scene.scans], len(scene.labels)


@pytest.mark.parametrize("name", ["glmb", "homht_kbest"])
def test_every_component_agrees_with_the_general_path(catalogue, name):
    cfg, problem, scans, n_known = catalogue
    general, fast = (make_tracker(name, cfg, problem, 1, fast_path=on) for on in (False, True))
    label0 = fast.next_label
    linear = getattr(problem.sensor.measurement, "H", None) is not None
    seen = dict(n_fast_path=0, n_fast_quiet=0, n_fast_born=0, out_of_view=0, dropped=0)
    for t, Z in scans:
        before = general.n_objects_held
        general.step(Z, t)
        fast.step(Z, t)
        ga, gb = general.groups, fast.groups  # every component, the lane's predicted to the scan
        assert len(ga) == len(gb) and general.next_label == fast.next_label
        for s, u in zip(ga, gb):
            np.testing.assert_allclose(s.log_w, u.log_w, rtol=0, atol=1e-12)
            np.testing.assert_array_equal(s.store.labels, u.store.labels)
            np.testing.assert_allclose(s.store.means, u.store.means, rtol=0, atol=1e-12)
            np.testing.assert_allclose(s.store.covs, u.store.covs, rtol=0, atol=1e-12)
            assert all(np.array_equal(x, y) for x, y in zip(s.tracks, u.tracks))
        if linear:  # and bit for bit, as held, with a fixed H (the sensor frame's batched EKF rounds differently)
            assert general.same_posterior(fast)
        st = fast.last_stats
        for k in ("n_fast_path", "n_fast_quiet", "n_fast_born"):
            seen[k] += st[k]
        seen["out_of_view"] += general.n_objects_held - st["n_predicted"] > 0
        seen["dropped"] += general.n_objects_held < before + (general.next_label - label0)
    # the run holds what the check is for: lone tracks, objects out of view, births, groups that died
    # (HOMHT's admissible-region seeded births, one child per component, too: :mod:`...factored.fast_mixture`)
    assert seen["n_fast_path"] > 0 and seen["out_of_view"] == N_SCANS
    assert fast.next_label > label0 and seen["dropped"] > 0
    if linear:  # and the shortcuts; in the sensor frame the admissible births' wide gates reach most returns,
        # so few lone tracks are left (measured: 3 lone-track steps in 40 scans against 70 with the stand-in)
        assert seen["n_fast_path"] > N_SCANS and seen["n_fast_quiet"] > 0
        assert (seen["n_fast_born"] > 0) == (name == "glmb")  # HOMHT's births are seeded at returns: no terms


def test_a_one_hypothesis_prior_goes_to_the_lane_as_the_exact_split_puts_it():
    """Five objects with shuffled labels, one hypothesis: the lane is the split's singletons in its order
    (by label), moment for moment; a prior of two hypotheses is not one."""
    rng = np.random.default_rng(3)
    labels = np.array([40, 7, 19, 3, 25])
    means = rng.normal(size=(5, 4)) * 50
    covs = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 5, axis=0) * rng.uniform(1, 2, size=(5, 1, 1))
    f = glmb(ConstantVelocity(q=0.01), position_sensor(R=0.5, p_D=0.9, clutter_rate=1.0), means=means, covs=covs,
             labels=labels, n_sweeps=10, max_hypotheses=5,
             population=LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0))
    ff = FactoredFilter.from_filter(f)
    state = f.state
    _, parts = factorise(state, np.searchsorted(state.labels, state.store.labels))
    lane = ff.state().lane.store
    np.testing.assert_array_equal(lane.labels, [3, 7, 19, 25, 40])
    np.testing.assert_array_equal(lane.labels, np.concatenate([p.store.labels for p in parts]))
    np.testing.assert_array_equal(lane.means, np.concatenate([p.store.means for p in parts]))
    np.testing.assert_array_equal(lane.covs, np.concatenate([p.store.covs for p in parts]))
    assert len(ff.state().groups) == 0
    two = FilterState(state.store, np.log([0.5, 0.5]), [state.tracks[0], state.tracks[0][:4]], [(), ()])
    assert one_hypothesis_lane(two) is None
    store = TrackStore(state.store.means, state.store.covs, np.array([3, 3, 19, 25, 40]))
    assert one_hypothesis_lane(FilterState(store, np.zeros(1), [np.arange(5)], [()])) is None  # labels repeat

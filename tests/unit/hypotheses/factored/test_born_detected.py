"""A lone birth term with its one return, born detected (:mod:`hypotrack.hypotheses.factored.born_detected`): the
posterior of the general path, with and without a validity test, and only for the components whose general step
keeps the detected child alone (not two returns in the term's gate, not a track competing with the term, not a
return so far out that "not born" keeps more than ``min_weight``)."""

import numpy as np
import pytest
import yaml

import hypotrack.hypotheses.factored.engine as engine_module
from hypotrack.experiments.ssa_catalogue.run import initial_tracks, make_motion, make_problem, make_tracker, tracker_sensor
from hypotrack.experiments.ssa_catalogue.scale import clone_scenario
from hypotrack.hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation, glmb
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredFilter
from hypotrack.hypotheses.factored.born_detected import takes_born_detected
from hypotrack.hypotheses.factored.fast_path import MARGIN, FastRule
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import H_POSITION, observed_scans, position_sensor

VIEW = Box([-500.0, -500.0], [500.0, 500.0])
SENSOR = position_sensor(R=0.5, p_D=0.85, view=VIEW, clutter_rate=5.0)
MOTION = ConstantVelocity(q=0.01)
GRID = np.arange(-400.0, 401.0, 80.0)
TRUTH = np.array([[x, y, 0.5, -0.3] for x in GRID for y in GRID])  # 121 objects, 80 apart
KNOWN = np.arange(len(TRUTH)) % 7 != 3  # every seventh object unknown: born from the data

def _assert_same(a, b):
    """Every group's weights, labels, tracks and moments (to 1e-12), the next label and the stored state."""
    ga, gb = a.groups, b.groups
    assert len(ga) == len(gb) and a.next_label == b.next_label
    for s, t in zip(ga, gb):
        np.testing.assert_allclose(s.log_w, t.log_w, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(s.store.labels, t.store.labels)
        np.testing.assert_allclose(s.store.means, t.store.means, rtol=0, atol=1e-12)
        np.testing.assert_allclose(s.store.covs, t.store.covs, rtol=0, atol=1e-12)
        assert all(np.array_equal(x, y) for x, y in zip(s.tracks, t.tracks))
    assert a.same_posterior(b)  # bit for bit, lazy lane and groups as held


# terms: T1 with one return close by (born detected); T2 with two returns in its gate; T3 with a track at its
# place and one return; T4 with one return far out in its gate (d² ≈ 13 against the gate's 13.8)
_TERMS = np.array([[-300.0, 0.0], [-150.0, 0.0], [150.0, 0.0], [0.0, 300.0]])
_Z = np.array([[-300.2, 0.1], [-150.3, 0.0], [-149.6, 0.2], [150.1, -0.2], [7.6, 300.0]])
_TRACK = np.array([[150.0, 0.0, 0.0, 0.0]])


def _hand(fast, validity=None, min_weight=1e-3):
    terms = [GaussianBirthTerm(np.array([*x, 0.0, 0.0]), np.diag([4.0, 4.0, 1.0, 1.0]), H_POSITION,
                               SENSOR.measurement.R, gate_probability=0.999) for x in _TERMS]
    f = glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation(terms, r_birth=0.5, p_survive=1.0),
             n_sweeps=50, max_hypotheses=20, gate_probability=0.999, seed=0, means=_TRACK, validity=validity,
             covs=np.diag([0.5, 0.5, 0.01, 0.01])[None])
    return FactoredFilter.from_filter(f, min_weight=min_weight, fast_path=fast)


def _step_both(**kw):
    general, fast = _hand(False, **kw), _hand(True, **kw)
    general.step(_Z, 0.0)
    fast.step(_Z, 0.0)
    _assert_same(general, fast)
    return general, fast


def test_only_the_term_with_its_lone_close_return_is_born_detected():
    general, fast = _step_both()
    st, gst = fast.last_stats, general.last_stats
    assert st["n_fast_born_detected"] == 1 and gst["n_fast_born_detected"] == 0
    assert st["n_jobs"] == gst["n_jobs"] - 1 == 3  # T2's, T3's and T4's components: the general path
    # components in order of their first node: T3's (the track's) used label 1; T1's step labels 2 (detected, kept)
    # and 3 (undetected, pruned); T2's step counts from 4
    labels = np.concatenate([s.store.labels for s in fast.groups])
    assert 1 in labels and 2 in labels and 3 not in labels and labels[labels > 2].min() == 4
    # T1's newborn: the term's Kalman update with its return (S = 4 + 0.5 per axis), weight 1
    born = [s for s in fast.groups if s.store.labels.tolist() == [2]]
    assert len(born) == 1 and born[0].log_w.tolist() == [0.0]
    np.testing.assert_allclose(born[0].store.means[0, :2], _TERMS[0] + 4.0 / 4.5 * (_Z[0] - _TERMS[0]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diag(born[0].store.covs[0])[:2], 4.0 - 16.0 / 4.5, rtol=0, atol=1e-12)
    # T4's far return: "not born" keeps more than min_weight, beside born detected and undetected
    t4 = [s for s in fast.groups if np.all(s.store.means[:, 1] == 300.0)]
    assert len(t4) == 1 and sorted(len(t) for t in t4[0].tracks) == [0, 1, 1]


def test_an_invalid_prior_uses_one_label_and_an_invalid_update_sends_the_term_to_the_general_path():
    def prior_fails(means):  # T1's prior sits exactly at the term's mean; its update does not
        return ~((means[:, 0] == -300.0) & (means[:, 1] == 0.0))

    general, fast = _step_both(validity=prior_fails)
    assert fast.last_stats["n_fast_born_detected"] == 1
    labels = np.concatenate([s.store.labels for s in fast.groups])  # T1's undetected child not kept: no label
    assert 2 in labels and labels[labels > 2].min() == 3

    def update_fails(means):
        return ~((means[:, 0] > -300.25) & (means[:, 0] < -300.1))

    general, fast = _step_both(validity=update_fails)
    assert fast.last_stats["n_fast_born_detected"] == 0 and fast.last_stats["n_jobs"] == general.last_stats["n_jobs"]


def test_the_rule_by_hand():
    """r_B = 0.5, p_D = 0.9, κ = 10⁻³, ℓ = log 0.05: detected 22.5, undetected 0.05, not born 0.5 (relative);
    against the detected child alone "not born" weighs 0.5 / 23 = 0.02174 and undetected 0.05 / 22.55 = 0.00222."""
    def rule(min_weight):
        return FastRule(float(np.log(1e-3)), np.zeros(1), 0, float(np.log(min_weight) + np.log1p(-MARGIN)), 0.9)

    ll = float(np.log(0.05))
    assert takes_born_detected(rule(0.0218), 0.5, ll)
    assert not takes_born_detected(rule(0.0217), 0.5, ll)  # "not born" kept: the general path
    assert not takes_born_detected(rule(0.5), 0.5, -np.inf)  # outside the gate
    assert not takes_born_detected(rule(0.5), 1.0, ll)  # a sure birth: no "not born" child
    # a heavier term existence makes "not born" lighter: 0.1 / (0.9 · 0.9 · 0.05 / 10⁻³ + 0.1) = 0.00246
    assert takes_born_detected(rule(0.0025), 0.9, ll) and not takes_born_detected(rule(0.0024), 0.9, ll)


@pytest.mark.parametrize("lazy", [False, True])
def test_a_scene_with_births_from_the_data_is_the_general_path(lazy):
    """121 objects, 17 unknown, born from the data through adaptive birth terms of ``r_B = 0.5``: every scan's
    posterior is the general path's, and terms were born detected (the check is not vacuous)."""
    scans, _ = observed_scans(TRUTH, MOTION, SENSOR, 10, seed=5)
    rng = np.random.default_rng(1)
    means = TRUTH[KNOWN] + rng.normal(size=(KNOWN.sum(), 4)) * [1.0, 1.0, 0.3, 0.3]
    covs = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], KNOWN.sum(), axis=0)

    def make(fast):
        f = glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0), n_sweeps=50,
                 dt=1.0, max_hypotheses=20, gate_probability=0.999, seed=3, means=means, covs=covs)
        birth = AdaptiveBirth(position_std=0.0, velocity_std=2.0, r_birth=0.5, gate_probability=0.999)
        return FactoredFilter.from_filter(f, adaptive_birth=birth, min_weight=1e-3, fast_path=fast, lazy=lazy,
                                          gate_out_of_view=not lazy)

    general, fast = make(False), make(True)
    n = 0
    for k, Z in enumerate(scans):
        general.step(Z, float(k + 1))
        fast.step(Z, float(k + 1))
        _assert_same(general, fast)
        n += fast.last_stats["n_fast_born_detected"]
    assert n > 0


@pytest.mark.parametrize("start_after_s", [0.0, 5700.0])
def test_the_catalogue_is_the_same_both_ways(monkeypatch, start_after_s):
    """The scale harness's catalogue (N = 3000 clones, the default radar, admissible-region births, the decaying
    population's Bernoulli lane), from the priors' epoch and in the steady state: stepped with and without the
    closed form, the posterior (lane and groups as held) and the labels are the same bit for bit at every scan."""
    off = [False]
    real = engine_module.born_detected_applies
    monkeypatch.setattr(engine_module, "born_detected_applies", lambda *a: False if off[0] else real(*a))
    with open("workflows/config/default.yaml") as fh:
        cfg = yaml.safe_load(fh)["ssa_catalogue"]
    s, seed = cfg["scale"], 20261122
    _, unknown, sc, init_seed = clone_scenario(cfg, 3000, seed, n_scans=40, chunk=s["chunk"], start_after_s=start_after_s)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed, at=-start_after_s)
    problem = make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels)
    general, fast = (make_tracker("glmb", cfg, problem, seed, **(s.get("factored") or {})) for _ in range(2))
    n = 0
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        Zt = tsensor.returns(Z)
        off[0] = True
        general.step(Zt, float(t_k) + start_after_s)
        off[0] = False
        fast.step(Zt, float(t_k) + start_after_s)
        assert general.next_label == fast.next_label and general.same_posterior(fast)
        assert general.last_stats["n_fast_born_detected"] == 0
        n += fast.last_stats["n_fast_born_detected"]
    assert n > 0

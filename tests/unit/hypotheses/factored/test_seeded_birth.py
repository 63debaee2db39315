"""A return in no gate under HOMHT's seeded births stepped without the engine (:mod:`...factored.seeded_birth`):

* on toy mixtures, the closed form against the engine's step from the empty hypothesis
  (:meth:`HypothesisFilter.advance`) bit for bit — weights, keys, tracks, labels, moments, the light entries' NaN —
  and against the weights by hand (clutter ``λ_C``, component ``c`` ``λ_B w_c``, normalised), through components
  the validity test fails, a cap that drops children, and the cases it leaves to the general step (a tie at the
  top, a sampled cap, another generator);
* the admissible region's covariances mapped for a scan's returns in one call
  (:meth:`SeededAdmissibleBirth.map_covariances`) against one call per return, bit for bit;
* the default catalogue configuration stepped with the closed form and without it (the general step): the same
  posterior bit for bit at every scan, the closed form taking lone returns.
"""

import numpy as np
import pytest
from scenes import catalogue_scene, default_catalogue_config, position_sensor

import hypotrack.hypotheses.factored.engine as engine_module
from hypotrack.experiments.ssa_catalogue.run import make_tracker
from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay, homht_kbest
from hypotrack.hypotheses.factored.lane import empty_state
from hypotrack.hypotheses.factored.planner import ObjectIds
from hypotrack.hypotheses.factored.seeded_birth import lone_seeded_applies, lone_seeded_plan, lone_seeded_step
from hypotrack.hypotheses.scan_context import ScanContext
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
LAM_B, CLUTTER = 0.5 / VIEW.area, 1.0
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))


class ToyMixture:
    """``components(z)``: weights ``w`` and means ``z`` plus offsets, identity-scaled covariances (index ``c``)."""

    def __init__(self, w, offsets):
        self.w, self.offsets = np.asarray(w, float), np.asarray(offsets, float)

    def components(self, z):
        K = len(self.w)
        means = np.column_stack([z[0] + self.offsets, np.full(K, z[1]), np.zeros(K), np.zeros(K)])
        return self.w.copy(), means, np.array([np.eye(4) * (1.0 + c) for c in range(K)])


def _engine(density, max_hypotheses=20, cap="top", validity=None, k=20, lam_b=LAM_B):
    pop = BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=DECAY)
    return homht_kbest(ConstantVelocity(0.01), position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=CLUTTER), k=k,
                       birth_intensity=lam_b, birth_density=density, population=pop, max_hypotheses=max_hypotheses,
                       cap=cap, validity=validity, seed=0)


def _general_plan(engine, z):
    """The general plan of a lone return's component (:func:`~...factored.planner.touched_plan`'s, no member)."""
    state = empty_state(4)
    pred = state.store
    ctx = ScanContext(Z=np.atleast_2d(z), loglik=np.zeros((1, 0)), allowed=np.zeros((1, 0), bool),
                      p_detect=np.zeros(0), birth_loglik=np.zeros((1, 0)), p_detect_birth=engine.p_D,
                      clutter_rate=CLUTTER, clutter_volume=VIEW.area, p_survive=np.zeros(0))
    return ("touched", state, pred, ctx, np.zeros(0, np.int64))


def _both(engine, z, min_weight=0.0, label=100):
    general = _general_plan(engine, z)
    want = engine.advance(general[1].with_next_label(label), general[2], general[3],
                          min(min_weight, 1.0 / engine.max_hypotheses) * (1 - 1e-9))
    plan = lone_seeded_plan(engine, general, min_weight)
    if plan is None:
        return want, None
    stats = dict(n_touched=0, n_fast_seeded=0, mass_retained_min=1.0)
    objects = ObjectIds()
    new, parts, used = lone_seeded_step(plan, engine, label, objects, stats, 4)
    assert used == want.n_new_labels and stats["n_fast_seeded"] == 1 and len(parts) == len(new.store)
    assert stats["mass_retained_min"] == min(1.0, want.stats["mass_retained"])
    return want, new


def _assert_same(want, new):
    g = want.state.with_next_label(0)
    np.testing.assert_array_equal(new.log_w, g.log_w)
    assert [t.tolist() for t in new.tracks] == [t.tolist() for t in g.tracks] and new.keys == g.keys
    np.testing.assert_array_equal(new.store.labels, g.store.labels)
    np.testing.assert_array_equal(new.store.means, g.store.means)  # (NaN where both leave a light entry)
    np.testing.assert_array_equal(new.store.covs, g.store.covs)
    assert new.next_label == 0


def test_the_closed_form_is_the_engine_s_step_and_the_weights_by_hand():
    w = np.array([0.5, 0.3, 0.15, 0.05])
    density = ToyMixture(w, [0.0, 1.0, -70.0, 2.0])
    engine = _engine(density, validity=lambda m: m[:, 0] > -50)  # component 2's mean fails the test
    assert lone_seeded_applies(engine, rule=object())
    want, new = _both(engine, np.array([10.0, 5.0]))
    _assert_same(want, new)
    kids = np.r_[CLUTTER / VIEW.area, LAM_B * w[[0, 1, 3]]]
    order = np.argsort(-kids, kind="stable")
    np.testing.assert_allclose(np.exp(new.log_w), (kids / kids.sum())[order], rtol=1e-12)
    assert len(new.store) == 3 and new.store.labels.tolist() == [100, 101, 102]
    np.testing.assert_array_equal(new.store.means[:, 0], 10.0 + np.array([0.0, 1.0, 2.0])[np.argsort(order[order > 0])])


@pytest.mark.parametrize("min_weight", [0.0, 0.05])
def test_a_cap_that_drops_children_and_light_entries(min_weight):
    density = ToyMixture([0.4, 0.3, 0.2, 0.06, 0.04], [0.0, 1.0, 2.0, 3.0, 4.0])
    for max_h in (3, 20):
        want, new = _both(_engine(density, max_hypotheses=max_h), np.array([0.0, 0.0]), min_weight)
        _assert_same(want, new)
    if min_weight:
        assert np.isnan(new.store.means).any()  # the light components: no moments, as the engine leaves them


def test_it_leaves_the_general_step_what_is_not_its_case():
    tie = ToyMixture([0.5, 0.5], [0.0, 1.0])  # two equal components heavier than clutter: the solver's order
    engine = _engine(tie, lam_b=20 * LAM_B)
    assert 20 * LAM_B * 0.5 > CLUTTER / VIEW.area
    assert lone_seeded_plan(engine, _general_plan(engine, np.zeros(2)), 0.0) is None
    want, new = _both(engine, np.zeros(2))
    assert new is None and len(want.state.log_w) == 3  # the general step: clutter and both components
    density = ToyMixture([0.6, 0.4], [0.0, 1.0])
    _assert_same(*_both(_engine(density, lam_b=20 * LAM_B), np.zeros(2)))  # no tie: the closed form
    assert not lone_seeded_applies(_engine(density, cap="sample"), rule=object())
    assert not lone_seeded_applies(_engine(density), rule=None)  # the fast path off
    assert not lone_seeded_applies(_engine(UniformBirthDensity(VIEW, np.eye(2) * 4.0)), rule=object())  # one Gaussian


@pytest.fixture(scope="module")
def catalogue():
    cfg = default_catalogue_config(40)
    assert cfg["model"]["birth"] == "admissible"
    scene = catalogue_scene(cfg, 300)
    return cfg, scene.problem, scene.sensor, scene.scans


def test_the_covariances_mapped_at_once_are_those_mapped_one_by_one(catalogue):
    cfg, problem, tsensor, scans = catalogue
    t, Z, theta = next((t, Z, th) for t, Z, th in scans if len(Z) > 5)
    tsensor.at(theta)
    one, batch = (make_tracker("homht_kbest", cfg, problem(), 1).engine.weights.birth_density for _ in range(2))
    assert one is not batch
    for d in (one, batch):
        d.prime(Z)
    assert batch.map_covariances(Z) == len({z.tobytes() for z in Z if len(one.component_weights(z)[0])}) > 5
    assert batch.map_covariances(Z) == 0  # mapped once
    for z in Z:
        a, b = one.components(z), batch.components(z)
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)


def test_homht_with_lone_returns_in_closed_form_is_the_general_engine(catalogue, monkeypatch):
    cfg, problem, tsensor, scans = catalogue
    general, fast = (make_tracker("homht_kbest", cfg, problem(), 1) for _ in range(2))
    applies = engine_module.lone_seeded_applies
    n_seeded = 0
    for t, Z, theta in scans:
        tsensor.at(theta)
        monkeypatch.setattr(engine_module, "lone_seeded_applies", lambda *a: False)  # the general step
        general.step(Z, t)
        monkeypatch.setattr(engine_module, "lone_seeded_applies", applies)
        fast.step(Z, t)
        assert general.same_posterior(fast) and general.next_label == fast.next_label
        assert general.state().objects == fast.state().objects
        n_seeded += fast.last_stats["n_fast_seeded"]
        assert general.last_stats["n_fast_seeded"] == 0
        for k in ("n_touched", "mass_retained_min", "n_kalman_updates", "n_duplicates_merged"):
            assert general.last_stats[k] == fast.last_stats[k], k
        assert general.last_stats["n_jobs"] - fast.last_stats["n_jobs"] == fast.last_stats["n_fast_seeded"]
    assert n_seeded > 20 and fast.next_label > len(problem().labels)

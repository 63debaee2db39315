"""The factored engine's fast path (``fast_path``): the posterior of the general path, component for
component, and only the components whose general step keeps the detected child alone."""

import numpy as np
import pytest

from hypotrack.hypotheses import (BinomialPopulation, GaussianBirthTerm, LabeledMultiBernoulliPopulation, fisst_kbest,
                                  glmb, homht_kbest, rfisst)
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredFilter, FactoredOptions
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from hypotrack.registry import SpecError, TrackerSpec
from scenes import H_POSITION, observed_scans, position_sensor

VIEW = Box([-500.0, -500.0], [500.0, 500.0])
SENSOR = position_sensor(R=0.5, p_D=0.85, view=VIEW, clutter_rate=5.0)
MOTION = ConstantVelocity(q=0.01)
GRID = np.arange(-400.0, 401.0, 80.0)
TRUTH = np.array([[x, y, 0.5, -0.3] for x in GRID for y in GRID])  # 121 objects, 80 apart
KNOWN = np.arange(len(TRUTH)) % 7 != 3  # every seventh object unknown: born from the data
BIRTH = AdaptiveBirth(position_std=0.0, velocity_std=2.0, r_birth=0.01, gate_probability=0.999)


def _prior(seed=1):
    rng = np.random.default_rng(seed)
    means = TRUTH[KNOWN] + rng.normal(size=(KNOWN.sum(), 4)) * [1.0, 1.0, 0.3, 0.3]
    return means, np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], KNOWN.sum(), axis=0)


def _moving(means):
    """A validity test: a track must move; a newborn at rest (a seeded birth, a birth term's prior) fails it."""
    return np.hypot(means[:, 2], means[:, 3]) > 1e-3


def _factored(kind, fast, min_weight=0.001, validity=None, **kw):
    means, covs = _prior()
    common = dict(dt=1.0, max_hypotheses=20, gate_probability=0.999, seed=3, means=means, covs=covs,
                  validity=validity)
    birth = BIRTH
    if kind == "glmb":
        f = glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0),
                 n_sweeps=50, **common)
    elif kind == "homht_kbest":  # Reid's births seeded at the returns (a birth child uses a label)
        f = homht_kbest(MOTION, SENSOR, birth_intensity=0.5 / VIEW.area,
                        birth_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0), **common)
        birth = None
    elif kind == "fisst_kbest":
        f = fisst_kbest(MOTION, SENSOR, population=BinomialPopulation([], alpha=0.01, p_survive=1.0), **common)
    else:
        f = rfisst(MOTION, SENSOR, n_steps=200, population=BinomialPopulation([], alpha=0.01, p_survive=1.0), **common)
    return FactoredFilter.from_filter(f, adaptive_birth=birth, min_weight=min_weight, fast_path=fast, **kw)


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


@pytest.mark.parametrize("kind", ["glmb", "homht_kbest", "rfisst", "fisst_kbest"])
@pytest.mark.parametrize("lazy, min_weight", [(False, 0.001), (True, 0.001), (True, 0.002)])
def test_fast_path_posterior_is_the_general_one(kind, lazy, min_weight):
    """121 objects in a linear-Gaussian scene (17 unknown, born from the data), clutter, misses, 12 scans:
    with the fast path every scan's posterior is the general path's, and the fast path took most of the
    touched components (the check has power: it is not vacuous). With ``min_weight = 0.002`` above a
    birth term's born-undetected weight (``r_B (1 − p_D) = 0.0015``) the lone birth terms are dropped too."""
    scans, _ = observed_scans(TRUTH, MOTION, SENSOR, 12, seed=5)
    general = _factored(kind, False, min_weight, lazy=lazy, gate_out_of_view=not lazy)
    fast = _factored(kind, True, min_weight, lazy=lazy, gate_out_of_view=not lazy)
    n_fast = n_touched = n_births = 0
    for k, Z in enumerate(scans):
        general.step(Z, float(k + 1))
        fast.step(Z, float(k + 1))
        _assert_same(general, fast)
        assert general.last_stats["n_fast_path"] == 0
        assert fast.last_stats["n_touched"] == general.last_stats["n_touched"]
        assert fast.last_stats["n_kalman_updates"] == general.last_stats["n_kalman_updates"]
        st = fast.last_stats
        assert st["n_jobs"] == (general.last_stats["n_jobs"] - st["n_fast_path"] - st["n_fast_clutter"] - st["n_fast_births"]
                                - st["n_fast_quiet"] - st["n_fast_born"])
        n_births += st["n_fast_births"]
        n_fast += fast.last_stats["n_fast_path"]
        n_touched += fast.last_stats["n_touched"]
    assert n_fast > 0.7 * n_touched
    assert (n_births > 0) == (kind != "homht_kbest" and min_weight > 0.0015)
    assert general.n_objects_held > KNOWN.sum()  # unknown objects were born (births ran beside the fast path)


@pytest.mark.parametrize("kind", ["glmb", "homht_kbest"])
def test_fast_path_with_a_validity_test_is_the_general_path(kind):
    """With the engine's validity test (here: a track must move) the children holding a newborn at rest
    are not kept: HOMHT's seeded birth children use no label (and no object is born), a birth term's
    undetected prior fails and the term is dropped whatever its weight (min_weight 0.001 < r_B (1 − p_D));
    the posterior is still the general path's."""
    scans, _ = observed_scans(TRUTH, MOTION, SENSOR, 8, seed=5)
    general, fast = _factored(kind, False, validity=_moving), _factored(kind, True, validity=_moving)
    n_births = 0
    for k, Z in enumerate(scans):
        general.step(Z, float(k + 1))
        fast.step(Z, float(k + 1))
        _assert_same(general, fast)
        assert fast.last_stats["n_fast_path"] > 0
        n_births += fast.last_stats["n_fast_births"]
    assert (n_births > 0) == (kind == "glmb")
    if kind == "homht_kbest":
        assert general.next_label == KNOWN.sum()  # no birth child was kept: no label used


def test_fast_path_takes_nothing_without_min_weight():
    """With ``min_weight = 0`` the general path keeps every alternative child: nothing is exact to take."""
    scans, _ = observed_scans(TRUTH, MOTION, SENSOR, 3, seed=5)
    general, fast = _factored("glmb", False, min_weight=0.0), _factored("glmb", True, min_weight=0.0)
    for k, Z in enumerate(scans):
        general.step(Z, float(k + 1))
        fast.step(Z, float(k + 1))
        assert fast.last_stats["n_fast_path"] == 0
    _assert_same(general, fast)


# A hand scene: A alone with one return (the fast path's case); B with two returns in its gate;
# C and D sharing one return; E with a birth term competing for its return; F alone with one return
# far out in its gate (its missed child keeps more than min_weight).
_X = np.array([[-300.0, 0, 0, 0], [-150.0, 0, 0, 0], [0.0, 0, 0, 0], [0.0, 1.0, 0, 0], [150.0, 0, 0, 0],
               [300.0, 0, 0, 0]])
_Z = np.array([[-300.2, 0.1], [-150.3, 0.0], [-149.6, 0.2], [0.1, 0.5], [150.1, -0.2], [300.0, 2.9],
               [-450.0, 450.0]])  # the last: clutter in no gate


def _hand(fast, min_weight=1e-4, birth_at=(150.0, 0.0), validity=None):
    term = GaussianBirthTerm(np.array([*birth_at, 0.0, 0.0]), np.diag([4.0, 4.0, 1.0, 1.0]), H_POSITION,
                             SENSOR.measurement.R, gate_probability=0.999)
    f = glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation([term], r_birth=0.01, p_survive=1.0),
             n_sweeps=50, max_hypotheses=20, gate_probability=0.999, seed=0, means=_X, validity=validity,
             covs=np.repeat(np.diag([0.5, 0.5, 0.01, 0.01])[None], len(_X), axis=0))
    return FactoredFilter.from_filter(f, min_weight=min_weight, fast_path=fast)


def test_only_a_lone_track_with_a_lone_return_takes_the_fast_path():
    general, fast = _hand(False), _hand(True)
    general.step(_Z, 0.0)
    fast.step(_Z, 0.0)
    _assert_same(general, fast)
    st = fast.last_stats
    # A and the clutter return in no gate take the fast path; B, C+D, E with the term and F the general one
    assert st["n_fast_path"] == 1 and st["n_fast_clutter"] == 1 and st["n_touched"] == 6 and st["n_jobs"] == 4
    assert general.last_stats["n_touched"] == 6 and general.last_stats["n_jobs"] == 6
    by_label = {tuple(np.unique(s.store.labels).tolist()): s for s in fast.groups}
    assert len(by_label[(5,)].log_w) == 2  # F kept its missed child: a group of two hypotheses
    # the fast path's own result: A's Joseph update with its return, alone
    a = by_label[(0,)]
    assert len(a.log_w) == 1 and a.log_w[0] == 0.0
    S = 0.5 + 0.5  # H P Hᵀ + R on each axis (P diagonal, no velocity coupling at a zero interval)
    np.testing.assert_allclose(a.store.means[0, :2], _X[0, :2] + 0.5 / S * (_Z[0] - _X[0, :2]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diag(a.store.covs[0])[:2], 0.5 - 0.5**2 / S, rtol=0, atol=1e-12)


def test_an_invalid_update_sends_the_lone_track_to_the_general_path():
    """A's update (x ≈ −300.1) fails the validity test, its prediction (x = −300) passes: the general step
    keeps the missed child alone, so the fast path may not take A."""
    def validity(means):
        return ~((means[:, 0] > -300.15) & (means[:, 0] < -300.05))

    general, fast = _hand(False, validity=validity), _hand(True, validity=validity)
    general.step(_Z, 0.0)
    fast.step(_Z, 0.0)
    _assert_same(general, fast)
    assert fast.last_stats["n_fast_path"] == 0
    (a,) = [s for s in fast.groups if s.store.labels.tolist() == [0]]
    np.testing.assert_array_equal(a.store.means[0], _X[0])  # only predicted (a zero interval: as it was)


def test_a_heavier_threshold_sends_the_lone_track_to_the_general_path():
    """min_weight above A's missed child: the general path keeps both children, so the fast path may not take it."""
    fast = _hand(True, min_weight=1e-300)
    fast.step(_Z, 0.0)
    assert fast.last_stats["n_fast_path"] == 0
    assert len({tuple(np.unique(s.store.labels).tolist()): s for s in fast.groups}[(0,)].log_w) == 2


def test_the_flag_is_off_by_default_and_a_bad_value_is_refused_naming_it():
    assert FactoredOptions().fast_path is False
    with pytest.raises(TypeError, match=r"^fast_path must be True or False, got 'yes'$"):
        FactoredOptions(fast_path="yes")
    with pytest.raises(TypeError, match=r"^fast_path must be True or False, got 1$"):
        _hand(1)
    spec = TrackerSpec.from_config({"kind": "glmb", "factored": {"fast_path": True}})
    assert spec.options["factored"]["fast_path"] is True
    with pytest.raises(SpecError, match=r"'x\.factored\.fast_path'"):
        TrackerSpec.from_config({"kind": "glmb", "factored": {"fast_path": "on"}}, "x")


def test_fast_path_with_a_pool_holds_the_serial_general_posterior():
    """The fast path's components keep their random streams' places: with two workers (threads) the
    posterior is still the serial general path's, bit for bit."""
    scans, _ = observed_scans(TRUTH, MOTION, SENSOR, 6, seed=5)
    general, fast = _factored("glmb", False), _factored("glmb", True, workers=2, parallel="thread")
    try:
        for k, Z in enumerate(scans):
            general.step(Z, float(k + 1))
            fast.step(Z, float(k + 1))
            _assert_same(general, fast)
            assert fast.last_stats["n_fast_path"] > 0
    finally:
        fast.close()


def _far_term(fast, validity=None, min_weight=1e-4):
    """The hand scene with its birth term at (450, −450): far from every return, a lone birth term each scan."""
    return _hand(fast, min_weight=min_weight, birth_at=(450.0, -450.0), validity=validity)


def test_lone_birth_terms_and_dying_quiet_groups_take_the_fast_path_exactly():
    """r_B = 0.01, p_D = 0.85: a lone term's "born undetected" child weighs 0.01 · 0.15 = 0.0015 against
    0.99, normalised 0.00151 > min_weight = 1e-4, so both are kept: every scan's term is stepped from
    the template (one engine step of such a term). Its group is then quiet (in view, no return): after one
    miss the born child weighs 0.0015 · 0.15 / 0.99 ≈ 2.3e-4 > 1e-4 (kept, the general step), after
    two 3.4e-5 < 1e-4: the group keeps no object and the fast path drops it without a step."""
    general, fast = _far_term(False), _far_term(True)
    expected = [(1, 0), (1, 0), (1, 1)]  # (n_fast_born, n_fast_quiet) per scan
    for k, (n_born, n_quiet) in enumerate(expected):
        general.step(_Z, float(k))
        fast.step(_Z, float(k))
        _assert_same(general, fast)
        assert (fast.last_stats["n_fast_born"], fast.last_stats["n_fast_quiet"]) == (n_born, n_quiet)
        assert general.last_stats["n_fast_born"] == general.last_stats["n_fast_quiet"] == 0
        assert fast.last_stats["n_jobs"] == general.last_stats["n_jobs"] - n_born - n_quiet - fast.last_stats["n_fast_path"] \
            - fast.last_stats["n_fast_clutter"] - fast.last_stats["n_fast_births"]
    # the newest term's group, from the template: the two hand weights and the term's prior under a new label
    born = [s for s in fast.groups if len(s.log_w) == 2 and len(s.store) == 1 and s.store.labels[0] >= len(_X)]
    assert len(born) == 2  # scans 2 and 3's (scan 1's died at scan 3)
    older, newest = sorted(born, key=lambda s: s.store.labels[0])
    for s, w_born in ((newest, 0.0015), (older, 0.0015 * 0.15)):  # the older one missed once
        np.testing.assert_allclose(s.log_w, np.log([0.99, w_born]) - np.log(0.99 + w_born), rtol=0, atol=1e-12)
        np.testing.assert_array_equal(s.store.means[0][:2], [450.0, -450.0])  # at rest: it stays
    np.testing.assert_array_equal(newest.store.covs[0], np.diag([4.0, 4.0, 1.0, 1.0]))  # the term's prior


def test_with_a_validity_test_lone_terms_and_quiet_groups_take_the_general_path():
    """A validity test could reject a child before the normalisation: the closed forms are not used."""
    def validity(means):
        return np.abs(means[:, 0]) < 1e6  # passes everything; its presence alone decides

    general, fast = _far_term(False, validity=validity), _far_term(True, validity=validity)
    plain = _far_term(True)
    for k in range(3):
        for f in (general, fast, plain):
            f.step(_Z, float(k))
        _assert_same(general, fast)
        assert fast.last_stats["n_fast_born"] == fast.last_stats["n_fast_quiet"] == 0
        # the lone tracks, tested and valid, take the fast path as without the test
        assert fast.last_stats["n_fast_path"] == plain.last_stats["n_fast_path"] >= 2  # A and E at least


def test_a_heavy_born_child_or_a_light_one_is_not_a_template_step():
    """min_weight 0.002 above the born child's 0.00151: the lone term is dropped (n_fast_births), never
    stepped from a template; min_weight 0 keeps every child: the fast path is off for all of it."""
    fast = _far_term(True, min_weight=0.002)
    for k in range(3):
        fast.step(_Z, float(k))
        assert fast.last_stats["n_fast_births"] == 1 and fast.last_stats["n_fast_born"] == 0
    fast = _far_term(True, min_weight=0.0)
    for k in range(3):
        fast.step(_Z, float(k))
        assert fast.last_stats["n_fast_born"] == fast.last_stats["n_fast_quiet"] == 0

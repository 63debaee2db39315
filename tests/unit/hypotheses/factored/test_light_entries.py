"""The engine step's moments left out for the entries the factored engine's pruning drops, and the seeded moments
asked once per return:

* :func:`~hypotrack.hypotheses.children.heavy_entries` on masses by hand (an entry held by several hypotheses sums
  their weights; the bound is ``>=``);
* HOMHT k-best on the default catalogue configuration (admissible-region births, the plausibility test, the decaying
  survival, 3,000 objects) stepped with the light entries left out and with every entry's moments (the path before):
  bit for bit the same posterior at every scan (:meth:`FactoredFilter.same_posterior`), the run leaving out moments
  of newborn components and of updates the pruning then drops;
* :func:`~hypotrack.hypotheses.seeded.seeded_moments` against :func:`seeded_state` pair by pair (mixture and
  one-Gaussian densities, with and without covariances) and its error for a component a return does not have;
* Reid's option scores computed once per scan context: the same numbers as a fresh model's, read-only, not shared
  between two models.
"""

import copy

import numpy as np
import pytest
from scenes import catalogue_scene, default_catalogue_config

from hypotrack.experiments.ssa_catalogue.run import make_tracker
from hypotrack.hypotheses import children as children_mod
from hypotrack.hypotheses import filter as filter_mod
from hypotrack.hypotheses.children import heavy_entries
from hypotrack.hypotheses.scan_context import ScanContext
from hypotrack.hypotheses.seeded import seeded_moments, seeded_state
from hypotrack.hypotheses.weights import ReidWeights
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box


class ToyMixture:
    """``components(z)``: the mixture stored under ``int(z[0])`` (test_fast_mixture.py's)."""

    def __init__(self, table):
        self.table = table

    def components(self, z):
        w, x = self.table[int(z[0])]
        return w.copy(), x.copy(), np.repeat(np.eye(2)[None], len(w), axis=0) * (1.0 + np.arange(len(w)))[:, None, None]


def test_heavy_entries_sum_the_weights_of_the_hypotheses_holding_them():
    # entry 0 in hypotheses 0 and 2 (0.6 + 0.0004), entry 1 in 0 and 1 (0.6 + 0.3995), entry 2 in 2 alone (0.0004),
    # entry 3 in 3 alone (0.0001), entry 4 in none
    w = np.array([0.6, 0.3995, 0.0004, 0.0001])
    lists = [np.array([0, 1]), np.array([1]), np.array([0, 2]), np.array([3])]
    need = heavy_entries(lists, np.log(w), 5, 1e-3)
    np.testing.assert_array_equal(need, [True, True, False, False, False])
    # the bound is inclusive: an entry of mass exactly the bound keeps its moments
    assert heavy_entries([np.array([0]), np.array([1])], np.log([0.5, 0.5]), 2, 0.5).tolist() == [True, True]
    assert heavy_entries(lists, np.log(w), 5, 0.0).all() and heavy_entries(lists, np.log(w), 5, -1.0).all()
    assert heavy_entries([], np.zeros(0), 0, 1e-3).shape == (0,)
    assert heavy_entries([np.zeros(0, np.int64)], np.zeros(1), 2, 1e-3).tolist() == [False, False]


N_SCANS = 30


@pytest.fixture(scope="module")
def decaying_catalogue():
    """The default section as it is (admissible births, plausibility, the decaying survival), 3,000 objects
    (test_fast_mixture.py's scene, ten times as dense: steps whose children the pruning drops)."""
    cfg = default_catalogue_config(N_SCANS)
    assert "unconfirmed_decay" in cfg["model"] and cfg["model"]["birth"] == "admissible"
    scene = catalogue_scene(cfg, 3000)
    return cfg, scene.problem(), scene.sensor, scene.scans


def _states(problem, cfg, tsensor, scans, every_entry: bool, counts: dict):
    """The factored posterior after each scan; ``every_entry``: every new store entry's moments computed."""
    real = children_mod.heavy_entries

    def counted(lists, log_w, n_entries, light):
        need = real(lists, log_w, n_entries, light)
        counts["entries"] += n_entries
        counts["light"] += int(np.sum(~need))
        return np.ones(n_entries, dtype=bool) if every_entry else need

    filter_mod.heavy_entries = counted
    try:
        tracker = make_tracker("homht_kbest", cfg, problem, 1, fast_path=True)
        out = []
        for t, Z, theta in scans[:N_SCANS]:
            tsensor.at(theta)
            tracker.step(Z, t)
            out.append(copy.deepcopy(tracker.state()))
        return out, tracker
    finally:
        filter_mod.heavy_entries = real


def test_leaving_out_the_light_entries_changes_no_bit_of_the_posterior(decaying_catalogue):
    cfg, problem, tsensor, scans = decaying_catalogue
    counts_all, counts_light = {"entries": 0, "light": 0}, {"entries": 0, "light": 0}
    before, _ = _states(problem, cfg, tsensor, scans, True, counts_all)
    after, tracker = _states(problem, cfg, tsensor, scans, False, counts_light)
    assert len(before) == len(after) == N_SCANS
    for k, (a, b) in enumerate(zip(before, after)):
        assert a.same_as(b), f"scan {k}: the posteriors differ"
        for s in b.groups.states:  # nothing left without moments survives the pruning
            assert np.isfinite(s.store.means).all() and np.isfinite(s.store.covs).all()
    # the check is not empty: many of the steps' entries were light (newborn components, unlikely updates)
    assert counts_light["entries"] == counts_all["entries"] > 300
    assert counts_light["light"] > 0.15 * counts_light["entries"]
    assert tracker.next_label > len(problem.labels)  # births took labels


def test_the_light_entries_are_only_in_hypotheses_the_pruning_drops():
    """One engine step with ``light`` against the same step without it: the same hypotheses, keys and labels,
    the entries of mass below ``light`` NaN and every hypothesis holding one below ``min_weight``."""
    from scenes import position_sensor

    from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay, homht_kbest
    from hypotrack.hypotheses.factored.planner import prune
    from hypotrack.hypotheses.tracks import TrackStore
    from hypotrack.models import ConstantVelocity

    view = Box([-100.0, -100.0], [100.0, 100.0])
    decay = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))
    means = np.array([[0.0, 0.0, 1.0, 0.0], [3.0, 0.0, -1.0, 0.0]])
    covs = np.array([np.diag([0.5, 0.5, 0.04, 0.04])] * 2)
    engine = homht_kbest(ConstantVelocity(0.01), position_sensor(R=0.25, p_D=0.8, view=view, clutter_rate=1.0), k=20,
                         birth_intensity=0.5 / view.area, birth_density=UniformBirthDensity(view, np.eye(2) * 4.0),
                         population=BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=decay),
                         max_hypotheses=20, seed=0, means=means, covs=covs)
    state = engine._state
    pred = engine.predict(state.store, 1.0)
    ctx = engine.scan_context(pred, np.array([[1.0, 0.1], [2.2, -0.1], [60.0, 60.0]]))
    full = engine.advance(state, pred, ctx).state
    light = 1e-3 * (1 - 1e-9)
    part = engine.advance(state, pred, ctx, light).state
    assert part.keys == full.keys and [t.tolist() for t in part.tracks] == [t.tolist() for t in full.tracks]
    np.testing.assert_array_equal(part.log_w, full.log_w)
    np.testing.assert_array_equal(part.store.labels, full.store.labels)
    w = np.exp(full.log_w)
    mass = np.zeros(len(full.store))
    for h, t in enumerate(full.tracks):
        mass[t] += w[h]
    skipped = mass < light
    assert skipped.any() and (~skipped).any()
    assert np.isnan(part.store.means[skipped]).all() and np.isnan(part.store.covs[skipped]).all()
    np.testing.assert_array_equal(part.store.means[~skipped], full.store.means[~skipped])
    np.testing.assert_array_equal(part.store.covs[~skipped], full.store.covs[~skipped])
    kept_full, kept_part = prune(full, 1e-3), prune(part, 1e-3)
    assert kept_full.same_as(kept_part)
    assert all(w[h] < 1e-3 for h, t in enumerate(full.tracks) if skipped[t].any())
    assert isinstance(kept_part.store, TrackStore) and np.isfinite(kept_part.store.covs).all()


class OneGaussian:
    """A one-Gaussian seeded density: the return's position, unit velocity spread."""

    def initial_state(self, z, R):
        return np.r_[z, 0.0, 0.0], np.diag(np.r_[np.diag(R), 1.0, 1.0])


def test_seeded_moments_are_seeded_state_pair_by_pair():
    density = ToyMixture({0: (np.array([0.25, 0.75]), np.array([[1.0, 2.0], [3.0, 4.0]])),
                          1: (np.array([0.5, 0.2, 0.3]), np.array([[5.0, 6.0], [-7.0, 8.0], [9.0, 1.0]]))})
    Z, R = np.array([[1.0, 0.0], [0.0, 0.0]]), np.eye(2)
    returns, comps = np.array([0, 1, 0, 1, 0]), np.array([2, 0, 0, 1, 1])
    means, covs = seeded_moments(density, Z, R, returns, comps, 2)
    for q, (r, c) in enumerate(zip(returns, comps)):
        m, P = seeded_state(density, Z[r], R, int(c))
        np.testing.assert_array_equal(means[q], m)
        np.testing.assert_array_equal(covs[q], P)
    np.testing.assert_array_equal(means[[0, 1, 3]], [[9.0, 1.0], [1.0, 2.0], [3.0, 4.0]])
    only, none = seeded_moments(density, Z, R, returns, comps, 2, covariances=False)
    assert none is None
    np.testing.assert_array_equal(only, means)
    with pytest.raises(ValueError, match=r"component must lie in \[0, 1\] for this return, got 2"):
        seeded_moments(density, Z, R, np.array([1]), np.array([2]), 2)
    gauss = OneGaussian()
    m1, P1 = seeded_moments(gauss, Z, 0.25 * np.eye(2), np.array([1, 0]), np.array([0, 0]), 4)
    np.testing.assert_array_equal(m1, [[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(P1[1], np.diag([0.25, 0.25, 1.0, 1.0]))
    with pytest.raises(ValueError, match="one seeded option"):
        seeded_moments(gauss, Z, R, np.array([0]), np.array([1]), 4)
    empty_m, empty_c = seeded_moments(density, Z, R, np.zeros(0, np.int64), np.zeros(0, np.int64), 2)
    assert empty_m.shape == (0, 2) and empty_c.shape == (0, 2, 2)


def test_reid_option_scores_once_per_context():
    density = ToyMixture({0: (np.array([0.25, 0.75]), np.zeros((2, 2))), 1: (np.array([1.0]), np.zeros((1, 2)))})
    Z = np.array([[1.0, 0.0], [0.0, 0.0], [1.0, 5.0]])
    ctx = ScanContext(Z=Z, loglik=np.zeros((3, 0)), allowed=np.zeros((3, 0), bool), p_detect=np.zeros(0),
                      birth_loglik=np.zeros((3, 0)), p_detect_birth=0.9, clutter_rate=2.0, clutter_volume=100.0)
    w = ReidWeights(birth_intensity=0.01, birth_density=density)
    first = w.option_scores(ctx)
    want = np.array([[np.log(0.02), np.log(0.01), -np.inf], [np.log(0.02), np.log(0.0025), np.log(0.0075)],
                     [np.log(0.02), np.log(0.01), -np.inf]])
    np.testing.assert_allclose(first, want, rtol=1e-15)
    assert w.option_scores(ctx) is first and not first.flags.writeable
    other = ReidWeights(birth_intensity=0.02, birth_density=density)
    np.testing.assert_allclose(other.option_scores(ctx)[:, 1:2], want[:, 1:2] + np.log(2), rtol=1e-15)
    assert w.option_scores(ctx) is not first  # the context holds the last model's; asked again, recomputed
    np.testing.assert_array_equal(w.option_scores(ctx), first)
    fresh = ScanContext(Z=Z, loglik=np.zeros((3, 0)), allowed=np.zeros((3, 0), bool), p_detect=np.zeros(0),
                        birth_loglik=np.zeros((3, 0)), p_detect_birth=0.9, clutter_rate=2.0, clutter_volume=100.0)
    np.testing.assert_array_equal(ReidWeights(birth_intensity=0.01, birth_density=density).option_scores(fresh), first)

"""HypothesisFilter: edge cases, shared tracks, capping, posterior summaries, bad input."""

import numpy as np
import pytest
from scipy import stats
from scipy.special import logsumexp

from hypotrack.association import EnumerationBudgetError
from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    HFISSTWeights,
    HypothesisFilter,
    ReidWeights,
    hfisst,
    homht,
    homht_kbest,
    rfisst,
)
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.hypotheses.population_events import BinomialPopulation
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, Sensor
from scenes import HALVES, REGION, position_sensor, single_event_population
from scenes import THREE_COVS as P0
from scenes import THREE_MEANS as X0

MOTION = ConstantVelocity(0.05)


def sensor(p_D=0.9, rate=1.0, region=REGION):
    return position_sensor(0.5, p_D, region, rate)


def observe(X, rng, s=None):
    return (s or sensor()).observe(X, rng)[0]


def population(alpha=1e-3, beta=1e-3):
    return single_event_population(alpha, beta, 2, HALVES, np.eye(2) * 4.0)


def run(f, n_scans=4, seed=0, X=X0):
    rng = np.random.default_rng(seed)
    F = MOTION.F(1.0)
    for _ in range(n_scans):
        X = X @ F.T
        post = f.step(observe(X, rng))
    return post, X


@pytest.mark.parametrize("preset", [hfisst, rfisst, homht, homht_kbest])
def test_presets_track_three_objects(preset):
    f = preset(MOTION, sensor(), max_hypotheses=20, means=X0, covs=P0, seed=1)
    post, X = run(f)
    assert post.log_weights[0] == pytest.approx(max(post.log_weights))
    assert logsumexp(post.log_weights) == pytest.approx(0.0, abs=1e-12)
    assert post.cardinality.sum() == pytest.approx(1.0)
    assert post.expected_number == pytest.approx(np.dot(np.arange(len(post.cardinality)), post.cardinality))
    est = f.estimates()
    assert est.x.shape == (3, 4) and est.P.shape == (3, 4, 4) and est.time == f.time
    assert np.max(np.abs(est.x[:, :2] - X[:, :2])) < 3.0


def test_zero_objects_and_births():
    """A zero-object parent: children are all-clutter or one birth; a persistent object is born."""
    f = hfisst(MOTION, sensor(p_D=0.95, rate=0.2), population=population(alpha=0.02), max_hypotheses=50, seed=0)
    assert f.posterior().expected_number == 0.0
    rng = np.random.default_rng(3)
    X = np.array([[20.0, 20.0, 0.0, 0.0]])
    for _ in range(6):
        f.step(observe(X, rng, sensor(p_D=0.95, rate=0.2)))
    post = f.posterior()
    assert post.cardinality[1] > 0.9
    assert np.linalg.norm(post.map_estimate.means[0, :2] - X[0, :2]) < 2.0


def test_empty_scans():
    f = hfisst(MOTION, sensor(), population=population(), max_hypotheses=30, means=X0, covs=P0)
    P_before = f.store.covs.copy()
    post = f.step(np.zeros((0, 2)))
    assert f.last_stats["n_kalman_updates"] == 0
    # every object missed: the heaviest hypothesis keeps all three, predicted (covariance grew)
    assert post.map_estimate.n_objects == 3
    assert np.all(np.trace(post.map_estimate.covs, axis1=1, axis2=2) > np.trace(P_before, axis1=1, axis2=2))
    # children: the all-missed association, its undetected-birth twins and a death per object
    assert f.last_stats["n_association_children"] == 1
    assert f.last_stats["n_twin_children"] == 2 + 3
    f.step([])  # an empty list is an empty scan too


def test_all_clutter_scan_with_gating():
    f = homht(MOTION, sensor(), gate_probability=0.99, max_hypotheses=30, means=X0, covs=P0)
    far = np.array([[45.0, 45.0], [-45.0, 40.0], [40.0, -45.0]])
    f.step(far)
    assert f.last_stats["n_association_children"] == 1  # gated: only the all-clutter event
    np.testing.assert_array_equal(f.last_kept.events, -np.ones((1, 3)))
    assert f.last_stats["n_kalman_updates"] == 0


def test_more_than_100_returns():
    """m = 120: R-FISST copes; exhaustive H-FISST refuses, naming its budget."""
    rng = np.random.default_rng(5)
    Z = np.vstack([observe(X0 @ MOTION.F(1.0).T, rng), REGION.sample_uniform(120, rng)])
    f = rfisst(MOTION, sensor(rate=120.0), n_steps=20_000, max_hypotheses=10, means=X0, covs=P0, seed=2)
    post = f.step(Z)
    assert np.all(np.isfinite(post.log_weights))
    g = hfisst(MOTION, sensor(rate=120.0), max_events=10**6, max_hypotheses=10, means=X0, covs=P0)
    with pytest.raises(EnumerationBudgetError, match="max_events"):
        g.step(Z)


def test_weight_underflow_kept_in_log_space():
    """Every child weighs < exp(-745) (0 in floating point): log space keeps the posterior."""
    huge = Box([-1e150, -1e150], [1e150, 1e150])
    s = sensor(region=huge)
    f = homht(MOTION, s, max_hypotheses=50, means=X0, covs=P0)
    Z = np.array([[1e140, 1e140], [-1e140, 3e139], [2e139, -1e140], [1.0, 0.0]])
    children = f.expand(Z)
    assert np.all(children.log_weights < -745) and np.all(np.exp(children.log_weights) == 0.0)
    post = f.step(Z)
    assert np.all(np.isfinite(post.log_weights))
    assert np.exp(post.log_weights).sum() == pytest.approx(1.0)
    assert post.weights[0] > 0.5  # the return at (1, 0) goes to the object at the origin


def test_tracks_updated_once_per_pair():
    f = hfisst(MOTION, sensor(), max_hypotheses=200, means=X0, covs=P0)
    rng = np.random.default_rng(7)
    X = X0 @ MOTION.F(1.0).T
    f.step(observe(X, rng))
    old_lists = f.track_lists
    X = X @ MOTION.F(1.0).T
    f.step(observe(X, rng))
    kept = f.last_kept
    updates, all_pairs, n_refs = set(), set(), 0
    for p, ev in zip(kept.parent, kept.events):
        tr = old_lists[p]
        ret = {int(ev[i]): int(i) for i in np.flatnonzero(ev >= 0)}
        all_pairs |= {(tr[j], ret.get(j, -1)) for j in range(len(tr))}
        updates |= {(tr[j], r) for j, r in ret.items()}
        n_refs += len(tr)
    assert f.last_stats["n_kalman_updates"] == len(updates)
    assert len(f.store) == len(all_pairs)  # one track per distinct (track, return) pair
    assert len(f.store) < n_refs  # ... shared by the hypotheses that hold it


def test_sampled_cap_is_seeded_and_normalised():
    def final(seed):
        f = hfisst(MOTION, sensor(p_D=0.7, rate=4.0), cap="sample", max_hypotheses=8, means=X0, covs=P0, seed=seed)
        run(f, n_scans=3, seed=11)
        return f

    a, b, c = final(1), final(1), final(2)
    np.testing.assert_array_equal(a.log_weights, b.log_weights)
    assert len(a.log_weights) == 8
    assert logsumexp(a.log_weights) == pytest.approx(0.0, abs=1e-12)
    top = hfisst(MOTION, sensor(p_D=0.7, rate=4.0), max_hypotheses=8, means=X0, covs=P0)
    run(top, n_scans=3, seed=11)
    assert set(a.lineage_keys) != set(top.lineage_keys)
    assert set(a.lineage_keys) != set(c.lineage_keys)


def test_bad_input():
    s = sensor()
    with pytest.raises(ValueError, match="p_D"):
        hfisst(MOTION, sensor(p_D=1.0))
    with pytest.raises(ValueError, match="max_hypotheses"):
        hfisst(MOTION, s, max_hypotheses=0)
    with pytest.raises(ValueError, match="cap"):
        hfisst(MOTION, s, cap="best")
    with pytest.raises(ValueError, match="gate_probability"):
        hfisst(MOTION, s, gate_probability=1.5)
    with pytest.raises(ValueError, match="dt"):
        hfisst(MOTION, s, dt=0.0)
    with pytest.raises(ValueError, match="clutter"):
        hfisst(MOTION, Sensor(LinearPositionSensor(np.eye(2), 4), DetectionModel(0.9)))
    with pytest.raises(TypeError, match="weights"):
        HypothesisFilter(MOTION, s, "hfisst", ExhaustiveGenerator())
    with pytest.raises(ValueError, match="covs"):
        hfisst(MOTION, s, means=X0)
    with pytest.raises(ValueError, match="seeded births"):
        HypothesisFilter(MOTION, s, ReidWeights(1e-3, UniformBirthDensity(REGION, np.eye(2))), ExhaustiveGenerator(),
                         population=population())
    f = hfisst(MOTION, s, means=X0, covs=P0)
    with pytest.raises(ValueError, match="Z"):
        f.step(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match="Z"):
        f.step(np.zeros((3, 3)))
    assert isinstance(f.weights, HFISSTWeights)


def test_parent_with_underflowing_weight_keeps_its_children():
    """A hypothesis of normalised weight ~e^-1400 (0.0 in linear space) survives and has
    children with finite log-weights (its lineage is traceable through lineage_keys)."""
    huge = Box([-1e150, -1e150], [1e150, 1e150])  # log g = -log V = -690.8 per clutter return
    s = position_sensor(0.01, 0.9, huge, 1.0)
    X = X0[:2]
    f = homht(MOTION, s, max_hypotheses=1000, means=X, covs=P0[:2])
    Z = (X @ MOTION.F(1.0).T)[:, :2]
    f.step(Z)
    lw = f.log_weights
    tiny = np.flatnonzero(np.isfinite(lw) & (lw < -1000))
    assert len(tiny) and np.all(np.exp(lw[tiny]) == 0.0)
    tiny_keys = {f.lineage_keys[i] for i in tiny}
    f.step((X @ MOTION.F(2.0).T)[:, :2])
    descendants = [i for i, key in enumerate(f.lineage_keys) if key[0] in tiny_keys]
    assert descendants and np.all(np.isfinite(f.log_weights[descendants]))
    assert np.all(f.log_weights[descendants] < -1000)
    assert logsumexp(f.log_weights) == pytest.approx(0.0, abs=1e-12)


def test_binomial_survival_death_twins():
    """Seed 001 Eq. 59: a child with one object dead weighs (1 - p_s) / (p_s (1 - p_D)) times
    its twin in which that object is alive but missed (any object may die, in view or not)."""
    from hypotrack.hypotheses.population_events import BinomialPopulation
    from hypotrack.hypotheses import ChildSet

    p_s, p_D = 0.97, 0.9
    f = hfisst(MOTION, sensor(p_D=p_D), population=BinomialPopulation((), alpha=0.0, p_survive=p_s),
               max_hypotheses=10**5, means=X0, covs=P0)
    Z = (X0 @ MOTION.F(1.0).T)[:2, :2]
    ch = f.expand(Z)
    base = {ev.tobytes(): w for ev, k, w in zip(ch.events, ch.kind, ch.log_weights) if k == ChildSet.ASSOCIATION}
    deaths = [(ev, a, w) for ev, k, a, w in zip(ch.events, ch.kind, ch.arg, ch.log_weights) if k == ChildSet.DEATH]
    assert len(deaths) > 10
    for ev, dead, w in deaths:
        assert dead not in ev  # only a missed object can have died
        assert w - base[ev.tobytes()] == pytest.approx(np.log((1 - p_s) / (p_s * (1 - p_D))), abs=1e-12)


def _hand_scene(population_model):
    """One object in view at the origin, one out of view (x = 60), one return near the first;
    the view is REGION (V = 100 × 100), the birth region is the whole view."""
    view_sensor = position_sensor(0.5, 0.8, REGION, 1.0)
    X = np.array([[0.0, 0.0, 1.0, 0.0], [60.0, 0.0, 0.0, 0.0]])
    P = np.repeat(np.diag([1.0, 1.0, 0.2, 0.2])[None], 2, axis=0)
    f = hfisst(MOTION, view_sensor, population=population_model, max_hypotheses=50, means=X, covs=P)
    z = np.array([1.3, -0.2])
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    H = np.hstack([np.eye(2), np.zeros((2, 2))])
    S = H @ (F @ P[0] @ F.T + Q) @ H.T + np.eye(2) * 0.5
    log_n = stats.multivariate_normal(H @ F @ X[0], S).logpdf(z)  # N(z; H x̂⁻, S) of the object in view
    return f, z[None], log_n


def _children_by_key(children):
    return {(int(k), int(a), tuple(e)): lw
            for k, a, e, lw in zip(children.kind, children.arg, children.events.tolist(), children.log_weights)}


def test_single_event_children_weighed_by_hand():
    """Seed 000 Eq. 8 × Eq. 30 child by child. Only the object in view counts in
    M_d (P(no event) = 1 − α − 1·β, not 1 − α − 2β) and only it may die; the out-of-view object
    has p_D = 0 (missed with probability 1). Columns: 0 object in view, 1 out of view, 2 birth."""
    alpha, beta, p_D, V = 0.01, 0.05, 0.8, 100.0 * 100.0
    pop = single_event_population(alpha, beta, 1, (REGION,), np.eye(2) * 4.0)
    f, Z, log_n = _hand_scene(pop)
    p_none = np.log(1 - alpha - beta)
    a_detect = p_none + np.log(p_D) + log_n  # −log(C(1,1) 1!) = 0
    a_clutter = p_none + np.log(1 - p_D) + np.log(1 / V)
    a_birth = np.log(alpha) + np.log(p_D) - np.log(V) + np.log(1 - p_D)  # born and detected; object missed
    expected = {
        (0, -1, (0,)): a_detect,
        (0, -1, (-1,)): a_clutter,
        (0, -1, (2,)): a_birth,
        (1, 0, (0,)): a_detect + np.log(alpha) - p_none + np.log(1 - p_D),  # undetected birth
        (1, 0, (-1,)): a_clutter + np.log(alpha) - p_none + np.log(1 - p_D),
        (2, 0, (-1,)): np.log(beta) + np.log(1 / V),  # object 0 died; the return is clutter
    }
    got = _children_by_key(f.expand(Z))
    assert got.keys() == expected.keys()
    for key, lw in expected.items():
        assert got[key] == pytest.approx(lw, abs=1e-10), key
    post = f.step(Z)
    w = np.array(list(expected.values()))
    np.testing.assert_allclose(np.sort(post.log_weights), np.sort(w - logsumexp(w)), atol=1e-10)
    # cardinality: 1 object after a death, 3 after a birth (detected or not), 2 otherwise
    card = {1: w[5], 2: np.logaddexp(w[0], w[1]), 3: np.logaddexp.reduce(w[2:5])}
    for n, lw in card.items():
        assert post.cardinality[n] == pytest.approx(np.exp(lw - logsumexp(w)), abs=1e-12)


def test_binomial_children_weighed_by_hand():
    """Seed 001's binomial model: every object may die (in view or not), the death ratio is
    (1 − p_s)/p_s, and the out-of-view object's twin keeps its weight factor 1 − 0 = 1."""
    alpha, p_s, p_D, V = 0.02, 0.9, 0.8, 100.0 * 100.0
    pop = BinomialPopulation([UniformBirthDensity(REGION, np.eye(2) * 4.0)], alpha=alpha, p_survive=p_s)
    f, Z, log_n = _hand_scene(pop)
    base = np.log(1 - alpha) + 2 * np.log(p_s)  # no birth in the one pixel, both survive
    a_detect = base + np.log(p_D) + log_n
    a_clutter = base + np.log(1 - p_D) - np.log(V)
    a_birth = np.log(alpha) + 2 * np.log(p_s) + np.log(p_D) - np.log(V) + np.log(1 - p_D)
    death = np.log((1 - p_s) / p_s)
    birth = np.log(alpha / (1 - alpha)) + np.log(1 - p_D)
    expected = {
        (0, -1, (0,)): a_detect, (0, -1, (-1,)): a_clutter, (0, -1, (2,)): a_birth,
        (1, 0, (0,)): a_detect + birth, (1, 0, (-1,)): a_clutter + birth,
        (2, 1, (0,)): a_detect + death, (2, 1, (-1,)): a_clutter + death, (2, 1, (2,)): a_birth + death,
        (2, 0, (-1,)): a_clutter + death - np.log(1 - p_D),
        (2, 0, (2,)): a_birth + death - np.log(1 - p_D),
    }
    got = _children_by_key(f.expand(Z))
    assert got.keys() == expected.keys()
    for key, lw in expected.items():
        assert got[key] == pytest.approx(lw, abs=1e-10), key

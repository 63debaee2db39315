"""Identical hypotheses merged (every filter), and the factored engine on hand-checked cases.

Duplicates: a δ-GLMB scene with two objects, survival p_S and no returns, where the posterior is
a product of two Bernoullis and every weight is a closed form in ``x = p_S (1 − p_D)`` and
``y = 1 − p_S``; then a run whose duplicates are counted independently (distinct exact pair
sets among all children of :meth:`HypothesisFilter.expand`).

Factored engine: the group algebra (product, factorisation with KL / L1 by hand), the
posterior summary, which groups a scan touches, how birth terms are coupled, all-or-nothing
steps, and H-FISST's count term (not separable) by hand. The equality with the unfactored
engine is in ``tests/crosscheck/test_equivalence_factored.py``.
"""

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.special import logsumexp

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    FactoredFilter,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    ReidWeights,
    TrackStore,
    glmb,
    glmb_murty,
    hfisst,
    homht,
)
from hypotrack.hypotheses import duplicates as dup_mod
from hypotrack.hypotheses.duplicates import child_hashes, child_pairs, merge_duplicates
from hypotrack.hypotheses.factored_groups import GroupState, components, factorise, product, restrict_population
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, FieldOfView
from scenes import position_sensor

R = np.eye(2) * 0.5
P_D, P_S, R_B = 0.8, 0.9, 0.2
MOTION = ConstantVelocity(q=0.05)
VIEW = Box([-10.0, -10.0], [10.0, 10.0])
SENSOR = position_sensor(R, P_D, VIEW, 1.5, Box([-20.0, -20.0], [20.0, 20.0]))
H = SENSOR.measurement.H
X0 = np.array([[0.0, 0.0, 1.0, 0.5], [5.0, 2.0, -0.5, 0.6], [-6.0, -4.0, 0.3, 0.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 3, axis=0)
BIRTH_MEAN, BIRTH_COV = np.array([-5.0, 6.0, 0.0, 0.0]), np.diag([2.0, 2.0, 0.5, 0.5])
EMPTY = np.zeros((0, 2))


def lmb(p_s=P_S, births=True, gate=None):
    terms = [GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R, gate_probability=gate)] if births else []
    return LabeledMultiBernoulliPopulation(terms, r_birth=R_B, p_survive=p_s)


def glmb_filter(population, n=2, **kw):
    kw.setdefault("max_hypotheses", 10**6)
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True, population=population,
                            means=X0[:n], covs=P0[:n], seed=0, **kw)


# ---------------------------------------------------------------- duplicates
def test_two_parents_same_child_merged_weight_is_logsumexp_by_hand():
    """Scan 2 without returns: parent {a, b} whose b dies and parent {a} (b died at scan 1) both
    give {a missed twice}; the merged weight is the log-sum-exp of the two copies and equals the
    closed form P(a alive) P(b dead) of two independent Bernoullis."""
    f = glmb_filter(lmb(births=False))
    f.step(EMPTY)
    assert f.last_stats["n_duplicates_merged"] == 0  # one parent: no two children alike
    children = f.expand(EMPTY)  # 4 + 2 + 2 + 1 children of the parents {a,b}, {a}, {b}, {}
    assert len(children) == 9
    by_set = {}
    for c in range(len(children)):
        key = frozenset(child_pairs(children, c, f.track_lists[children.parent[c]], 0))
        by_set.setdefault(key, []).append(float(children.log_weights[c]))
    assert sorted(len(v) for v in by_set.values()) == [1, 2, 2, 4]  # {a,b}; {a}; {b}; {}
    a_track = int(np.flatnonzero(f.store.labels == 0)[0])  # object a after scan 1 (label 0)
    copies = by_set[frozenset({(a_track, -1)})]
    norm = logsumexp(children.log_weights)
    f.step(EMPTY)
    assert f.last_stats["n_duplicates_merged"] == 5 and len(f.log_weights) == 4
    x, y = P_S * (1 - P_D), 1 - P_S
    alive = x * x / (x * x + y + x * y)  # P(object alive after 2 scans | missed twice)
    want = {(): (1 - alive) ** 2, (0,): alive * (1 - alive), (1,): alive * (1 - alive), (0, 1): alive**2}
    for lw, t in zip(f.log_weights, f.track_lists):
        labels = tuple(sorted(f.store.labels[t].tolist()))
        assert np.exp(lw) == pytest.approx(want[labels], rel=1e-12)
        if labels == (0,):
            assert len(copies) == 2 and lw == pytest.approx(logsumexp(copies) - norm, abs=1e-12)


def test_merge_keeps_heaviest_member_and_moves_its_key():
    f = glmb_filter(lmb(births=False))
    f.step(EMPTY)
    children = f.expand(EMPTY)
    keys = children.log_weights + np.arange(len(children)) * 0.01  # distinct 'Gumbel' offsets
    merged, mkeys, n = merge_duplicates(children, keys, f.track_lists, 0)
    assert n == 5 and len(merged) == 4
    for c in range(len(merged)):
        pairs = frozenset(child_pairs(merged, c, f.track_lists[merged.parent[c]], 0))
        copies = [i for i in range(len(children))
                  if frozenset(child_pairs(children, i, f.track_lists[children.parent[i]], 0)) == pairs]
        rep = copies[int(np.argmax(children.log_weights[copies]))]
        assert merged.parent[c] == children.parent[rep] and merged.arg[c] == children.arg[rep]
        assert merged.log_weights[c] == pytest.approx(logsumexp(children.log_weights[copies]), abs=1e-13)
        assert mkeys[c] - merged.log_weights[c] == pytest.approx(keys[rep] - children.log_weights[rep], abs=1e-12)


def test_merge_refuses_keys_of_the_wrong_length():
    """Keys too short or too long were taken, each child paired with some other child's key."""
    f = glmb_filter(lmb(births=False))
    f.step(EMPTY)
    children = f.expand(EMPTY)
    E = len(children)
    for keys in (children.log_weights[:-1], np.append(children.log_weights, 0.0), children.log_weights[:, None]):
        with pytest.raises(ValueError, match=rf"keys must have shape \({E},\), one cap key per child"):
            merge_duplicates(children, keys, f.track_lists, 0)


def test_hash_collisions_cannot_merge_different_hypotheses(monkeypatch):
    """Every child given the same hash: the exact pair sets still decide (same result)."""
    f = glmb_filter(lmb(births=False))
    f.step(EMPTY)
    children = f.expand(EMPTY)
    want, _, n_want = merge_duplicates(children, children.log_weights, f.track_lists, 0)
    monkeypatch.setattr(dup_mod, "child_hashes", lambda ch, *a, **k: np.zeros(len(ch), dtype=np.uint64))
    got, _, n_got = dup_mod.merge_duplicates(children, children.log_weights, f.track_lists, 0)
    assert n_got == n_want == 5
    np.testing.assert_allclose(np.sort(got.log_weights), np.sort(want.log_weights), atol=1e-13)


def test_hashes_are_order_free_and_separate_distinct_sets():
    f = glmb_filter(lmb(births=False))
    f.step(EMPTY)
    children = f.expand(EMPTY)
    h = child_hashes(children, f.track_lists, 0)
    sets = [frozenset(child_pairs(children, c, f.track_lists[children.parent[c]], 0)) for c in range(len(children))]
    for i in range(len(sets)):
        for j in range(len(sets)):
            assert (h[i] == h[j]) == (sets[i] == sets[j])


def test_glmb_run_duplicates_counted_independently_and_posterior_unchanged():
    """Two scans with returns, a birth term, deaths: the engine's count of merged children equals
    (all children) − (distinct exact pair sets), and the merged posterior puts on each distinct
    hypothesis the summed weight of its copies."""
    scans = [np.array([[1.1, 0.4], [4.4, 2.7], [-4.8, 6.3]]), np.array([[2.0, 1.1], [-5.1, 5.9]])]
    f = glmb_filter(lmb())
    f.step(scans[0])
    children = f.expand(scans[1])
    groups = {}
    for c in range(len(children)):
        key = frozenset(child_pairs(children, c, f.track_lists[children.parent[c]], 1))
        groups.setdefault(key, []).append(float(children.log_weights[c]))
    f.step(scans[1])
    n_dup = len(children) - len(groups)
    assert n_dup > 1000  # most GLMB death children are copies: the merge matters
    assert f.last_stats["n_duplicates_merged"] == n_dup
    assert len(f.log_weights) == len(groups)
    norm = logsumexp(children.log_weights)
    want = np.sort([logsumexp(v) - norm for v in groups.values()])
    np.testing.assert_allclose(np.sort(f.log_weights), want, atol=1e-10)


def test_no_deaths_no_duplicates_and_no_hashing(monkeypatch):
    """p_S = 1 and no birth term: no child has a death, so no two can coincide and the merge
    returns before hashing anything."""
    f = glmb_filter(lmb(p_s=1.0, births=False), n=3)
    f.step(np.array([[1.1, 0.4], [4.4, 2.7]]))
    monkeypatch.setattr(dup_mod, "child_hashes", lambda *a, **k: pytest.fail("hashed without deaths"))
    f.step(np.array([[2.0, 1.1], [4.0, 3.1]]))
    assert f.last_stats["n_duplicates_merged"] == 0


def test_birth_gate_bad_input_and_effect():
    with pytest.raises(ValueError, match="gate_probability"):
        GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R, gate_probability=1.0)
    term = GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R, gate_probability=0.99)
    open_term = GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R)
    Z = np.array([[-5.0, 6.0], [-5.0 + 2.5 * 2.0, 6.0], [-5.0 + 3.5 * 2.0, 6.0]])  # S = 2.5 I: d² = 0, 10, 19.6
    ll, ll_open = term.loglik(Z), open_term.loglik(Z)
    # χ²₂ 99 % quantile = −2 log 0.01 = 9.21: only the first return is inside the gate
    assert np.isfinite(ll[0]) and ll[0] == ll_open[0] and np.all(np.isneginf(ll[1:])) and np.all(np.isfinite(ll_open))


# ---------------------------------------------------------------- factored engine: parts
def _state(weights, tracks, means):
    """A GroupState with 1-D-ish tracks: ``means`` (n, 4), unit covariances, labels by row."""
    means = np.asarray(means, dtype=float)
    store = TrackStore(means, np.repeat(np.eye(4)[None], len(means), axis=0), np.arange(len(means)))
    lw = np.log(np.asarray(weights, dtype=float))
    return GroupState(store, lw - logsumexp(lw), [np.asarray(t, dtype=np.int64) for t in tracks],
                      [("h", i) for i in range(len(weights))])


def _pt(x):
    return [x, 0.0, 0.0, 0.0]


A = _state([0.7, 0.3], [[0], [1]], [_pt(0.0), _pt(1.0)])  # object 0: two tracks
B = _state([0.5, 0.3, 0.2], [[0], [1], []], [_pt(10.0), _pt(11.0)])  # object 1: two tracks or absent


def test_product_weights_tracks_and_top_cap_by_hand():
    joint, used = product([A, B], 100)
    assert len(joint.log_w) == 6 and len(joint.store) == 4 and used.tolist() == [0, 1, 2, 3]
    got = {tuple(joint.store.means[t, 0].tolist()): np.exp(lw) for lw, t in zip(joint.log_w, joint.tracks)}
    want = {(a, b) if b is not None else (a,): wa * wb
            for a, wa in ((0.0, 0.7), (1.0, 0.3)) for b, wb in ((10.0, 0.5), (11.0, 0.3), (None, 0.2))}
    assert got.keys() == want.keys()
    for k in want:
        assert got[k] == pytest.approx(want[k], abs=1e-14)
    top, used = product([A, B], 2)  # 0.35, 0.21 (renormalised); tracks of the rest compacted away
    np.testing.assert_allclose(np.exp(top.log_w), [0.35 / 0.56, 0.21 / 0.56], atol=1e-14)
    assert used.tolist() == [0, 2, 3] and len(top.store) == 3
    # capping after each factor is exact for the top cap: three factors against the full product
    C = _state([0.6, 0.4], [[0], [1]], [_pt(20.0), _pt(21.0)])
    full, _ = product([A, B, C], 100)
    capped, _ = product([A, B, C], 5)
    np.testing.assert_allclose(capped.log_w, np.sort(full.log_w)[::-1][:5] - logsumexp(np.sort(full.log_w)[::-1][:5]),
                               atol=1e-13)


def test_product_sample_cap_is_seeded():
    a, _ = product([A, B], 3, "sample", np.random.default_rng(1))
    b, _ = product([A, B], 3, "sample", np.random.default_rng(1))
    assert len(a.log_w) == 3 and a.keys == b.keys
    assert logsumexp(a.log_w) == pytest.approx(0.0, abs=1e-13)


def test_factorise_exact_product_recovers_the_factors():
    joint, _ = product([A, B], 100)
    record, (pa, pb) = factorise(joint, np.array([0, 0, 1, 1]))  # A's two tracks, then B's
    assert record.exact and record.kl < 1e-15 and record.l1 < 1e-15 and record.n_parts == (2, 3)
    np.testing.assert_allclose(np.exp(pa.log_w), [0.7, 0.3], atol=1e-14)
    np.testing.assert_allclose(np.exp(pb.log_w), [0.5, 0.3, 0.2], atol=1e-14)
    assert pb.tracks[2].size == 0  # "object 1 absent" is a hypothesis of its part


def test_factorise_non_product_marginals_kl_l1_by_hand():
    """P(a1, b1) = 0.5, P(a2, b2) = 0.3, P(a1, b2) = 0.2: marginals a (0.7, 0.3), b (0.5, 0.5);
    Q = (0.35, 0.15, 0.35) on P's support and 0.15 on (a2, b1), which P lacks."""
    st = _state([0.5, 0.3, 0.2], [[0, 2], [1, 3], [0, 3]], [_pt(0.0), _pt(1.0), _pt(10.0), _pt(11.0)])
    record, (pa, pb) = factorise(st, np.array([0, 0, 1, 1]))
    kl = 0.5 * np.log(0.5 / 0.35) + 0.3 * np.log(0.3 / 0.15) + 0.2 * np.log(0.2 / 0.35)
    assert not record.exact and record.n_joint == 3 and record.n_parts == (2, 2)
    assert record.kl == pytest.approx(kl, abs=1e-14) and record.l1 == pytest.approx(0.6, abs=1e-14)
    np.testing.assert_allclose(np.exp(pa.log_w), [0.7, 0.3], atol=1e-14)
    np.testing.assert_allclose(np.exp(pb.log_w), [0.5, 0.5], atol=1e-14)


def test_components_of_the_bipartite_graph():
    # nodes 0, 1, 2; returns 0, 1, 2: node 0 - r0 - node 1 ; node 2 - r2 ; r1 alone
    n, lab = components(3, 3, [0, 1, 2], [0, 0, 2])
    assert n == 3 and lab[0] == lab[1] == lab[3] and lab[2] == lab[5] and lab[4] not in (lab[0], lab[2])
    # numbered by smallest vertex, as scipy numbers them: node 2 is alone before r1 (vertex 4)
    assert lab.tolist() == [0, 0, 1, 0, 2, 1]


@pytest.mark.parametrize("size", [(12, 9, 14), (150, 140, 180)])  # a few dozen and hundreds of vertices
def test_components_equal_scipy_labels_on_random_graphs(size):
    """The union–find gives scipy's ``connected_components`` labels (numbered by smallest vertex),
    on graphs with isolated nodes, isolated returns and repeated edges."""
    rng = np.random.default_rng(7)
    n_nodes, n_ret, n_edges = size
    for _ in range(200):
        e = int(rng.integers(0, n_edges))
        node, ret = rng.integers(0, n_nodes, e), rng.integers(0, n_ret, e)
        n = n_nodes + n_ret
        g = coo_matrix((np.ones(e, dtype=np.int8), (node, ret + n_nodes)), shape=(n, n))
        want = connected_components(g, directed=False)
        got = components(n_nodes, n_ret, node, ret)
        assert got[0] == want[0]
        np.testing.assert_array_equal(got[1], want[1])


def test_restrict_population_keeps_the_chosen_terms():
    t0 = GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R)
    t1 = GaussianBirthTerm(BIRTH_MEAN + 1.0, BIRTH_COV, H, R)
    pop = LabeledMultiBernoulliPopulation([t0, t1], r_birth=[0.1, 0.3], p_survive=0.9)
    sub = restrict_population(pop, [1])
    assert sub.n_birth_regions == 1 and sub.birth_densities[0] is t1 and sub.r_birth.tolist() == [0.3]
    assert pop.n_birth_regions == 2 and pop.r_birth.tolist() == [0.1, 0.3]  # unchanged
    assert restrict_population(pop, [0, 1]) is pop and restrict_population(None, []) is None


# ---------------------------------------------------------------- factored engine: behaviour
F1 = MOTION.F(1.0)
FAR = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 8.0, 1.0, 0.0]])  # never in each other's gates


def _homht_far(**kw):
    return FactoredFilter.from_filter(homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000, gate_probability=0.99, means=FAR,
                                            covs=P0[:2], seed=0), **kw)


def test_bad_input():
    f = homht(MOTION, SENSOR, merge_duplicates=True, means=FAR, covs=P0[:2])
    with pytest.raises(ValueError, match="split"):
        FactoredFilter.from_filter(f, split="always")
    with pytest.raises(ValueError, match="births"):
        FactoredFilter.from_filter(f, births="none")
    with pytest.raises(ValueError, match="factor_tol"):
        FactoredFilter.from_filter(f, factor_tol=0.0)
    with pytest.raises(ValueError, match="min_weight"):
        FactoredFilter.from_filter(f, min_weight=1.0)
    with pytest.raises(ValueError, match="allowed: split"):
        FactoredFilter.from_filter(f, cap="top")
    with pytest.raises(TypeError, match="HypothesisFilter"):
        FactoredFilter.from_filter("homht")
    with pytest.raises(ValueError, match="max_hypotheses"):
        FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), max_hypotheses=0)
    with pytest.raises(ValueError, match="covs"):
        FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=FAR)
    with pytest.raises(ValueError, match="labels must be distinct"):
        FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=FAR, covs=P0[:2], labels=[3, 3])
    ff = _homht_far()
    with pytest.raises(ValueError, match="limit"):
        ff.joint_hypotheses(limit=0)
    with pytest.raises(ValueError, match="Z"):
        ff.step(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="n_top"):
        ff.posterior(n_top=0)


def test_untouched_group_only_predicts_when_exact():
    """HOMHT: object b has no return in its gate; its single hypothesis is only predicted
    (Kalman prediction by hand); object a is updated."""
    ff = _homht_far()
    ff.step(np.array([[1.2, 0.1]]))
    assert ff.last_stats["n_predict_only"] == 1 and ff.last_stats["n_touched"] == 1
    (b,) = [g for g in ff.groups if g.labels.tolist() == [1]]
    np.testing.assert_allclose(b.store.means[0], F1 @ FAR[1], atol=1e-12)
    np.testing.assert_allclose(b.store.covs[0], F1 @ P0[1] @ F1.T + MOTION.Q(1.0), atol=1e-12)
    assert ff.posterior().cardinality.tolist() == [0.0, 0.0, 1.0]


def test_untouched_group_with_deaths_takes_an_empty_scan_step():
    """GLMB: a scan without returns still multiplies each hypothesis by p_S (1 − p_D) or
    (1 − p_S): the object's existence becomes x / (x + y)."""
    ff = FactoredFilter.from_filter(glmb_filter(lmb(births=False), n=1))
    ff.step(EMPTY)
    assert ff.last_stats["n_predict_only"] == 0
    x, y = P_S * (1 - P_D), 1 - P_S
    np.testing.assert_allclose(ff.posterior().cardinality, [y / (x + y), x / (x + y)], atol=1e-12)


def test_step_is_all_or_nothing():
    """The merged a + b problem exceeds the enumeration budget after c's group was already
    stepped: groups, labels, scan index, statistics and the random state are restored."""
    X = np.array([[20.0, 20.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 6.0, 1.0, 0.0]])  # c, a, b
    f = homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000, gate_probability=0.99, means=X, covs=P0, max_events=6, seed=0)
    ff = FactoredFilter.from_filter(f)
    ff.step(np.array([[20.0, 20.1], [1.0, 0.0], [1.0, 6.0]]))
    assert ff.last_stats["n_groups"] == 3
    before = (ff.groups, ff.scan_index, len(ff.stats_history), ff.rng.bit_generator.state, ff.next_label)
    with pytest.raises(ValueError, match="budget|max_events"):
        ff.step(np.array([[20.0, 20.1], [2.0, 2.9], [2.0, 3.0], [2.0, 3.1]]))  # a + b merge: 13 events
    after = (ff.groups, ff.scan_index, len(ff.stats_history), ff.rng.bit_generator.state, ff.next_label)
    assert len(before[0]) == len(after[0]) == 3 and before[1:] == after[1:]
    for x, y in zip(before[0], after[0]):  # the same hypotheses, weights and tracks as before the failed step
        assert np.array_equal(x.log_w, y.log_w) and np.array_equal(x.store.labels, y.store.labels)
        assert np.array_equal(x.store.means, y.store.means) and np.array_equal(x.store.covs, y.store.covs)
        assert all(np.array_equal(s, t) for s, t in zip(x.tracks, y.tracks))
    ff.step(np.array([[20.0, 20.1], [2.0, 0.0], [2.0, 6.0]]))  # a retry with a lighter scan works
    assert ff.scan_index == 2 and ff.last_stats["n_merges"] == 0


def test_from_filter_leaves_the_filter_alone_and_splits_exactly():
    f = homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000, gate_probability=0.99, means=FAR, covs=P0[:2], seed=0)
    f.step(np.array([[1.1, 0.0], [1.0, 8.1], [5.0, 4.0]]))  # one return each, one clutter
    state = (f.log_weights, f.rng.bit_generator.state)
    ff = FactoredFilter.from_filter(f)
    assert len(f.log_weights) == 4 and ff.n_joint_hypotheses == 4
    assert [len(g.log_w) for g in ff.groups] == [2, 2]  # the joint of 4 was a product of 2 × 2
    ff.step(np.zeros((0, 2)))
    np.testing.assert_array_equal(f.log_weights, state[0])
    assert f.rng.bit_generator.state == state[1]
    coupled = homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000, gate_probability=0.99, means=FAR[:1], covs=P0[:1])
    coupled.initialise(np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 1.0, 0.0]]), P0[:2])
    coupled.step(np.array([[1.0, 0.5]]))  # one return between the two: a joint that is no product
    assert len(FactoredFilter.from_filter(coupled).groups) == 1


def _birth_scene(births, min_weight=0.0):
    """Object a just below the birth term; one return in both a's gate and the birth gate."""
    pop = lmb(gate=0.99)
    f = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True, population=pop, max_hypotheses=1000,
                         gate_probability=0.99, means=[[-5.0, 4.5, 0.0, 0.0]], covs=P0[:1], seed=0)
    ff = FactoredFilter.from_filter(f, births=births, min_weight=min_weight)
    ff.step(np.array([[-5.0, 5.5]]))
    return ff


def test_births_coupled_merges_the_birth_term_with_the_group_it_shares_a_return_with():
    ff = _birth_scene("coupled")
    (g,) = ff.groups
    # a, the newborn detected at the return, the newborn undetected: one group
    assert len(g.labels) == 3 and ff.last_stats["n_splits"] == 0
    born_at_return = np.isclose(g.store.means[:, 1], 5.5, atol=0.5) & (g.store.labels > 0) & \
        (np.trace(g.store.covs, axis1=1, axis2=2) < np.trace(BIRTH_COV))
    assert born_at_return.any()


def test_births_free_offers_only_ungated_returns_to_birth_and_min_weight_prunes():
    ff = _birth_scene("free")
    assert sorted(len(g.labels) for g in ff.groups) == [1, 1]
    (u,) = [g for g in ff.groups if g.labels[0] != 0]
    np.testing.assert_allclose(u.store.means[0], BIRTH_MEAN, atol=1e-12)  # born undetected only
    w = R_B * (1 - P_D)
    np.testing.assert_allclose(np.sort(np.exp(u.log_w)), [w / (w + 1 - R_B), (1 - R_B) / (w + 1 - R_B)], atol=1e-12)
    pruned = _birth_scene("free", min_weight=0.1)  # the undetected birth (0.048) is dropped
    assert [g.labels.tolist() for g in pruned.groups] == [[0]]


def test_newborn_labels_of_one_birth_term_stay_one_object():
    """A birth term gating two returns yields three newborn labels (born at either return, born
    undetected) — one object: a scan later, split='marginal' on a group without returns must
    not split them (which would let two of them coexist)."""
    pop = lmb(gate=0.99)
    f = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True, population=pop, max_hypotheses=1000,
                         gate_probability=0.99, seed=0)
    ff = FactoredFilter.from_filter(f, split="marginal")
    ff.step(np.array([[-5.5, 6.0], [-4.5, 6.0]]))
    (g,) = ff.groups
    assert len(g.labels) == 3
    ff.step(EMPTY)
    assert ff.last_stats["n_splits"] == 0
    (g,) = [h for h in ff.groups if len(h.labels) == 3]  # (plus this scan's undetected-birth group)
    # not born, or born once: never two of the three newborn labels together
    assert sorted(len(t) for t in g.tracks) == [0, 1, 1, 1]


def test_posterior_convolves_cardinalities_and_unites_maps():
    ff = _homht_far()
    ff.step(np.array([[1.1, 0.0], [1.0, 8.1], [5.0, 4.0]]))
    post = ff.posterior()
    assert post.n_groups == 2
    c0, c1 = (p.cardinality for p in post.groups)
    np.testing.assert_allclose(post.cardinality, np.convolve(c0, c1), atol=1e-15)
    assert post.map_estimate.log_weight == pytest.approx(sum(p.map_estimate.log_weight for p in post.groups))
    joint = ff.joint_hypotheses()
    assert joint[0].weight == pytest.approx(post.map_estimate.weight, abs=1e-14)
    np.testing.assert_allclose(np.sort(joint[0].means[:, 1]), np.sort(ff.estimates().x[:, 1]), atol=1e-14)
    assert [s["n_groups"] for s in ff.stats_history] == [2] and ff.stats_history[0]["largest_group"] == 1


def test_hfisst_count_term_is_not_separable_by_hand():
    """H-FISST's −log(m!/(m − n)!) counts the whole scan's returns. Two objects, one return each
    (in no other gate): unfactored, 'both detected', 'one detected' carry −log 2 (m = 2, n = 2 or
    1) and 'both missed' 0; factored, each group has m = 1 and every count term is 0. So the odds
    'both missed' : 'both detected' are twice as large unfactored."""
    Z = np.array([[1.3, 0.0], [1.0, 8.3]])
    u = hfisst(MOTION, SENSOR, merge_duplicates=True, gate_probability=0.99, means=FAR, covs=P0[:2])
    ff = FactoredFilter.from_filter(hfisst(MOTION, SENSOR, merge_duplicates=True, gate_probability=0.99, means=FAR, covs=P0[:2]))
    u.step(Z)
    ff.step(Z)
    pred = FAR @ F1.T

    def odds(items):
        w = {}
        for weight, means in items:
            missed = tuple(bool(np.allclose(m, p)) for m, p in zip(sorted(means.tolist()), sorted(pred.tolist())))
            w[missed] = weight
        return w[(True, True)] / w[(False, False)]

    odds_u = odds([(np.exp(lw), u.store.means[t]) for lw, t in zip(u.log_weights, u.track_lists)])
    odds_f = odds([(e.weight, e.means) for e in ff.joint_hypotheses()])
    assert odds_u == pytest.approx(2 * odds_f, rel=1e-10)


@pytest.mark.parametrize("preset", ["glmb", "glmb_murty"])
def test_sampling_and_ranking_generators_run_per_group(preset):
    """The glmb (Gibbs) and glmb_murty presets, factored: after one scan each group's hypotheses
    are among the exhaustive factored filter's, with the same weight ratios (exact weights of
    the children found), and the heaviest is the same."""
    pop = lmb(gate=0.99)
    Z = np.array([[1.1, 0.4], [0.8, 0.9], [-5.2, 6.1], [6.0, -4.0]])
    opts = dict(population=pop, max_hypotheses=1000, gate_probability=0.99, means=X0[:2], covs=P0[:2], seed=3)
    make = {"glmb": lambda: glmb(MOTION, SENSOR, merge_duplicates=True, n_sweeps=3, **opts),
            "glmb_murty": lambda: glmb_murty(MOTION, SENSOR, merge_duplicates=True, k=2, **opts)}[preset]
    # split='never': a split's marginal weights would sum over whichever children were found
    ff = FactoredFilter.from_filter(make(), split="never")
    ex = FactoredFilter.from_filter(HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True, **opts),
                                    split="never")
    ff.step(Z)
    ex.step(Z)

    def table(g):
        keys = [tuple(np.round(np.r_[g.store.means[j], g.store.covs[j].ravel()], 9)) for j in range(len(g.store))]
        return {frozenset(keys[j] for j in t): lw for lw, t in zip(g.log_w, g.tracks)}

    assert len(ff.groups) == len(ex.groups) == 3  # the same gates: the same groups, in the same order
    found = total = 0
    for gf, ge in zip(ff.groups, ex.groups):
        t, exact = table(gf), table(ge)
        assert t.keys() <= exact.keys()
        best = max(t, key=t.get)
        assert best == max(exact, key=exact.get)
        for k in t:
            assert t[k] - t[best] == pytest.approx(exact[k] - exact[best], abs=1e-9)
        found, total = found + len(t), total + len(exact)
    assert found < total  # the generators did not find every child (k = 2, 3 sweeps)


def _lazy_scene(lazy):
    """Three objects under HOMHT (no population events; alternatives below 1 % pruned): a starts
    out of view (x > 10), enters at scan 3 (x = 10, on the edge) and is detected at scan 4; b and c
    stay in view and share a return at scan 3."""
    X = np.array([[13.0, 0.0, -1.0, 0.0], [0.0, -2.0, 0.0, 0.0], [0.0, 2.0, 0.0, 0.0]])
    f = homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000, gate_probability=0.99, means=X,
              covs=P0, seed=0)
    ff = FactoredFilter.from_filter(f, lazy=lazy, min_weight=0.01)
    scans = [np.array([[0.1, -2.0], [0.0, 2.1]]), np.array([[0.0, -1.9], [0.1, 2.0]]), np.array([[0.0, 0.0]]),
             np.array([[9.1, 0.0], [-0.1, -2.1], [0.0, 2.0]]), np.zeros((0, 2)), np.array([[7.1, 0.1], [0.1, -2.0]])]
    stats = []
    for Z in scans:
        ff.step(Z)
        stats.append(dict(ff.last_stats))
    return ff, stats


def test_singletons_live_in_the_lane_and_lazy_prediction_is_exact_for_a_linear_model():
    """The singletons are one batched lane (an object nothing disturbed is one Gaussian); with
    ``lazy=True`` an object out of view is not predicted until it may be seen, and for a
    constant-velocity model one prediction over k scans is k predictions (F(kΔ) = F(Δ)ᵏ and the
    exactly discretised Q composes), so the posterior is the eager one."""
    eager, se = _lazy_scene(False)
    lazy, sl = _lazy_scene(True)
    # a (label 0) is out of view at scans 1–2: the lazy filter predicts one track fewer then
    assert [e["n_predicted"] - x["n_predicted"] for e, x in zip(se, sl)] == [1, 1, 0, 0, 0, 0]
    assert se[0]["n_singletons"] == 3 and se[0]["n_groups"] == 3  # every object alone, in the lane
    assert se[2]["n_merges"] == 1 and se[2]["n_singletons"] == 1  # b and c merged: a is the lane
    ge, gl = eager.groups, lazy.groups  # the lazy lane is predicted to the current scan here
    assert [g.labels.tolist() for g in ge] == [g.labels.tolist() for g in gl]
    for a, b in zip(ge, gl):
        np.testing.assert_allclose(a.log_w, b.log_w, atol=1e-12)
        np.testing.assert_allclose(a.store.means, b.store.means, atol=1e-9)
        np.testing.assert_allclose(a.store.covs, b.store.covs, atol=1e-9)
    # by hand: a's track after its update at scan 4 (one Kalman update of the prior predicted 4 scans),
    # predicted over the empty scan 5 and updated at scan 6
    x, P = np.array([13.0, 0.0, -1.0, 0.0]), P0[0]
    for k, z in ((4.0, [9.1, 0.0]), (2.0, [7.1, 0.1])):
        F = MOTION.F(k)
        x, P = F @ x, F @ P @ F.T + MOTION.Q(k)
        S = H @ P @ H.T + R
        K = P @ H.T @ np.linalg.inv(S)
        x, P = x + K @ (np.asarray(z) - H @ x), (np.eye(4) - K @ H) @ P
    (a0,) = [g for g in gl if 0 in g.labels.tolist()]
    (j,) = a0.tracks[int(np.argmax(a0.log_w))]
    np.testing.assert_allclose(a0.store.means[j], x, atol=1e-9)
    np.testing.assert_allclose(a0.store.covs[j], P, atol=1e-9)


# an annulus: an object crossing the middle leaves the view and comes back
RING = position_sensor(R, P_D, FieldOfView(0.0, 360.0, 3.0, 20.0), 1.5, Box([-20.0, -20.0], [20.0, 20.0]))


def _ring_scene(lazy):
    """GLMB, two objects that always exist (labeled multi-Bernoulli, no births, p_S = 1): a crosses the
    ring's hole (x = −6 + t: in view at scans 1–3, out at 4–8, back at 9), b sits in view at (0, 8).
    Two returns near each at scan 1 leave both a group of two hypotheses (either return; missed is pruned),
    so b's group is stepped while a's waits.
    A track out of view gates nothing (the catalogue's setting), so both filters form the same groups."""
    X = np.array([[-6.0, 0.0, 1.0, 0.0], [0.0, 8.0, 0.0, 0.0]])
    f = HypothesisFilter(MOTION, RING, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True,
                         population=LabeledMultiBernoulliPopulation([], r_birth=R_B, p_survive=1.0),
                         max_hypotheses=1000, gate_probability=0.99, means=X, covs=P0[:2], seed=0)
    ff = FactoredFilter.from_filter(f, lazy=lazy, min_weight=0.01, gate_out_of_view=False)
    b = np.array([[0.1, 8.0]])
    scans = [np.array([[-5.3, 0.2], [-4.8, -0.3], [0.5, 8.4], [-0.3, 7.7]]), EMPTY] + [b] * 7 + [np.array([[4.1, 0.1], [0.0, 7.9]]),
                                                                            np.array([[5.0, 0.0]])]
    out = []
    for Z in scans:
        ff.step(Z)
        out.append((dict(ff.last_stats), ff.groups, ff.map_means()))
    return ff, out


def test_lazy_groups_out_of_view_wait_and_are_exact_for_a_linear_model():
    """A multi-hypothesis group whose tracks are all out of view is left unpredicted (``lazy``): not
    scored, not stepped, its means advanced; when a track may be seen again it is predicted over its whole
    gap. For the constant-velocity model that is the eager posterior at every scan (weights, means,
    covariances), read while asleep (``groups``, ``map_means``) and after it wakes."""
    _, eager = _ring_scene(False)
    _, lazy = _ring_scene(True)
    asleep = [st.get("n_asleep", 0) for st, _, _ in lazy]
    # a's two tracks straddle the ring's edge at scans 3 and 9 (one in view, one not): the group is awake then
    assert asleep == [0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0]
    assert [st.get("n_asleep", 0) for st, _, _ in eager] == [0] * 11
    n_a = [len(g.store) for g in eager[5][1] if 0 in g.labels.tolist()]
    assert n_a == [2]  # a: two hypotheses, one track each
    assert [e[0]["n_predicted"] - x[0]["n_predicted"] for e, x in zip(eager, lazy)] == [0, 0, 0] + [2] * 5 + [0] * 3
    for (_, ge, (le, me)), (_, gl, (ll, ml)) in zip(eager, lazy):
        assert sorted(g.labels.tolist() for g in ge) == sorted(g.labels.tolist() for g in gl)
        for a in ge:
            (b,) = [g for g in gl if g.labels.tolist() == a.labels.tolist()]
            np.testing.assert_allclose(b.log_w, a.log_w, atol=1e-12)
            np.testing.assert_allclose(b.store.means, a.store.means, atol=1e-9)
            np.testing.assert_allclose(b.store.covs, a.store.covs, atol=1e-9)
        assert sorted(le.tolist()) == sorted(ll.tolist())
        np.testing.assert_allclose(ml[np.argsort(ll)], me[np.argsort(le)], atol=1e-9)
    # by hand while asleep (scan 7): a's MAP mean is the scan-3 mean moved 4 scans at its velocity
    (a3,) = [g for g in lazy[2][1] if g.labels.tolist() == [0]]
    (a7,) = [g for g in lazy[6][1] if g.labels.tolist() == [0]]
    j3, j7 = (g.tracks[int(np.argmax(g.log_w))][0] for g in (a3, a7))
    np.testing.assert_allclose(a7.store.means[j7], MOTION.F(4.0) @ a3.store.means[j3], atol=1e-12)
    np.testing.assert_allclose(a7.store.covs[j7], MOTION.F(4.0) @ a3.store.covs[j3] @ MOTION.F(4.0).T + MOTION.Q(4.0),
                               atol=1e-12)


def test_map_means_are_the_map_estimate_without_predicting_the_lane():
    """``map_means`` gives the labels and means of ``posterior().map_estimate`` — the lazy lane's
    means advanced one scan at a time (equal to its one prediction over the gap for the
    constant-velocity model) — and, at scans 1–2, the out-of-view object a where its true motion
    (x = 13 − t) puts it, which a lane whose means were not advanced (x = 13) would fail."""
    for lazy in (False, True):
        ff, _ = _lazy_scene(lazy)
        est = ff.posterior().map_estimate
        labels, means = ff.map_means()
        order, want = np.argsort(labels), np.argsort(est.labels)
        assert labels[order].tolist() == est.labels[want].tolist() == [0, 1, 2]
        np.testing.assert_allclose(means[order], est.means[want], atol=1e-12)
        est = ff.estimates()
        np.testing.assert_allclose(est.x, means)
        assert est.labels.tolist() == labels.tolist() and est.P is None and est.time == ff.time == ff.scan_index * 1.0
    ff = FactoredFilter.from_filter(homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=1000,
                                          gate_probability=0.99, means=np.array([[13.0, 0.0, -1.0, 0.0]]),
                                          covs=P0[:1], seed=0), lazy=True)
    for k in (1, 2):
        ff.step(np.zeros((0, 2)))
        assert ff.last_stats["n_predicted"] == 0  # out of view (x > 10): never predicted in full
        labels, means = ff.map_means()
        np.testing.assert_allclose(means, [[13.0 - k, 0.0, -1.0, 0.0]], atol=1e-12)
    ff.step(np.zeros((0, 2)))  # x = 10: on the edge, in view, predicted in full over its 3-scan gap
    assert ff.last_stats["n_predicted"] == 1
    # a failed step leaves the lane (and its means) as they were
    before = ff.map_means()[1].copy()
    with pytest.raises(ValueError):
        ff.step(np.array([[np.nan, 0.0]]))
    np.testing.assert_array_equal(ff.map_means()[1], before)

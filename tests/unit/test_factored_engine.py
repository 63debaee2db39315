"""Identical hypotheses merged (every filter), and the factored engine on hand-checked cases.

Duplicates: a δ-GLMB scene with two objects, survival p_S and no returns, where the posterior is
a product of two Bernoullis and every weight is a closed form in ``x = p_S (1 − p_D)`` and
``y = 1 − p_S``; then a run whose duplicates are counted independently (distinct exact pair
sets among all children of :meth:`HypothesisFilter.expand`).
"""

import numpy as np
import pytest
from scipy.special import logsumexp

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
)
from hypotrack.hypotheses import duplicates as dup_mod
from hypotrack.hypotheses.duplicates import child_hashes, child_pairs, merge_duplicates
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

R = np.eye(2) * 0.5
P_D, P_S, R_B = 0.8, 0.9, 0.2
MOTION = ConstantVelocity(q=0.05)
VIEW = Box([-10.0, -10.0], [10.0, 10.0])
SENSOR = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)), DetectionModel(P_D, VIEW),
                PoissonClutter(1.5, Box([-20.0, -20.0], [20.0, 20.0])))
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
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=population,
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

"""A parent's children on a one-return scan on Python floats (:mod:`hypotrack.hypotheses.one_return_children`), and
the few-children duplicate merge by pair sets (:func:`hypotrack.hypotheses.duplicates.merge_few`).

Oracle: the general path of :meth:`HypothesisFilter.children_of` (taken by making :func:`applies` decline) and
:func:`merge_duplicates` (hashes, then pair sets). On random parents — 0 to 4 objects, some out of view (``p_D = 0``),
per-track survival (some ``p_S = 1``: no death twin) or one ``p_S``, Reid's seeded births or none, no
population, ``keep`` below and above the number of children — the children (events, kinds, arguments,
log-weights, parents), keys, counts and masses must be identical bit for bit, and whole steps' posteriors too.
A hand-computed parent fixes the death twins' weights and order.
"""

import numpy as np
import pytest

import hypotrack.hypotheses.filter as filter_mod
from hypotrack.hypotheses import ChildSet, HypothesisFilter, homht_kbest
from hypotrack.hypotheses.duplicates import FEW, child_pairs, merge_duplicates, merge_few, pairs_function
from hypotrack.hypotheses.one_return_children import applies
from hypotrack.hypotheses.population_events import BinomialPopulation
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from scenes import HALVES, REGION, position_sensor, single_event_population

MOTION = ConstantVelocity(0.05)


class _Decay:
    """Per-track survival: tracks with a wide x variance are tentative (``p_S = 0.7``), the others sure (1)."""

    def __call__(self, means, covs):
        return np.where(np.asarray(covs)[:, 0, 0] > 2.0, 0.7, 1.0)


def _filter(kind, k=4, p_D=0.8):
    sensor = position_sensor(0.5, p_D, REGION, 2.0)
    seeded = dict(birth_intensity=1e-4, birth_density=UniformBirthDensity(REGION, np.eye(2) * 4.0))
    if kind == "survival":
        return homht_kbest(MOTION, sensor, k=k, max_hypotheses=k, **seeded,
                           population=BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=_Decay()))
    if kind == "binomial":
        return homht_kbest(MOTION, sensor, k=k, max_hypotheses=k, population=BinomialPopulation([], p_survive=0.9))
    if kind == "poisson_survival":  # a survival probability below 1 for the sure tracks too
        return homht_kbest(MOTION, sensor, k=k, max_hypotheses=k, population=BinomialPopulation(
            [], p_survive=0.95, poisson_limit=True, survival=lambda m, c: np.where(np.asarray(c)[:, 0, 0] > 2.0, 0.6, 0.97)))
    return homht_kbest(MOTION, sensor, k=k, max_hypotheses=k, **seeded)


def _scene(rng, n_tracks, n_parents):
    """Predicted tracks (a few at x = 70: out of view) and parents holding random subsets of them."""
    means = np.column_stack([rng.uniform(-8, 8, n_tracks), rng.uniform(-8, 8, n_tracks), rng.normal(size=(n_tracks, 2))])
    means[rng.random(n_tracks) < 0.25, 0] = 70.0
    covs = np.stack([np.diag([rng.choice([1.0, 4.0]), 1.0, 0.2, 0.2]) for _ in range(n_tracks)])
    tracks = [np.sort(rng.choice(n_tracks, size=int(rng.integers(0, min(4, n_tracks) + 1)), replace=False))
              for _ in range(n_parents)]
    lw = rng.normal(size=n_parents)
    lw -= np.logaddexp.reduce(lw)
    store = TrackStore(means, covs, np.arange(n_tracks, dtype=np.int64))
    return FilterState(store, lw, [t.astype(np.int64) for t in tracks], [(i,) for i in range(n_parents)], n_tracks)


def _general(f, *args, **kw):
    orig = filter_mod.applies
    filter_mod.applies = lambda *a: False
    try:
        return f.children_of(*args, **kw)
    finally:
        filter_mod.applies = orig


def _same_children(a, b):
    for field in ("parent", "events", "kind", "arg", "log_weights"):
        x, y = getattr(a[0], field), getattr(b[0], field)
        assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), field
    assert a[1].tobytes() == b[1].tobytes()
    assert a[2] == b[2] and a[4] == b[4]
    assert np.float64(a[3]).tobytes() == np.float64(b[3]).tobytes()


def test_hand_computed_death_twins():
    # one parent holding a sure track (p_S = 1: no twin) and a tentative one (p_S = 0.7), both in view
    f = _filter("survival", k=10)
    store = TrackStore(np.array([[0.0, 0.0, 0.0, 0.0], [5.0, 0.0, 0.0, 0.0]]),
                       np.stack([np.diag([1.0, 1.0, 0.2, 0.2]), np.diag([4.0, 1.0, 0.2, 0.2])]), np.array([0, 1]))
    state = FilterState(store, np.zeros(1), [np.array([0, 1])], [()], 2)
    ctx = f.scan_context(store, np.array([[0.2, 0.1]]))
    cs, keys, n_gen, _, n_twins = f.children_of(ctx, state, 0, 10, None)
    assoc = cs.kind == ChildSet.ASSOCIATION
    events = cs.events[assoc, 0].tolist()
    assert n_twins == int(np.sum(~assoc)) and n_gen == int(assoc.sum())
    # each twin: the tentative object (1) dies in an association child not detecting it; weight × (1 − p_S)/(p_S (1 − p_D))
    lw = dict(zip(events, cs.log_weights[assoc].tolist()))
    twins = [(int(e), float(w)) for e, w, a in zip(cs.events[~assoc, 0], cs.log_weights[~assoc], cs.arg[~assoc])
             if a == 1]
    assert len(twins) == n_twins == len([e for e in events if e != 1])
    for e, w in twins:
        assert w == pytest.approx(lw[e] + np.log(0.3 / 0.7) - np.log(0.2), abs=1e-12)
    assert keys.tolist() == cs.log_weights.tolist()
    # nothing trimmed (keep 10): the association children in Murty's order, heaviest first, then the twins
    assert cs.kind.tolist() == [0] * n_gen + [2] * n_twins
    assert list(cs.log_weights[assoc]) == sorted(cs.log_weights[assoc], reverse=True)
    assert events[0] == 0  # the return on the sure track it lies next to


@pytest.mark.parametrize("kind", ["survival", "binomial", "poisson_survival", "none"])
@pytest.mark.parametrize("seed", range(4))
def test_children_equal_to_the_general_path(kind, seed):
    _compare(kind, seed)


@pytest.mark.parametrize("kind", ["survival", "binomial"])
def test_children_equal_in_chunks(kind, monkeypatch):
    # the general path reduces and trims the death twins chunk of rows by chunk (for a parent of tens of
    # thousands of children); with chunks of 2 rows the masses and trims of several chunks are compared
    import hypotrack.hypotheses.one_return_children as orc
    monkeypatch.setattr(filter_mod, "_CHUNK", 2)
    monkeypatch.setattr(orc, "_CHUNK", 2)
    for seed in range(4):
        _compare(kind, 50 + seed)


def _compare(kind, seed):
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(6):
        f = _filter(kind, k=int(rng.integers(1, 6)), p_D=float(rng.choice([0.5, 0.9])))
        state = _scene(rng, int(rng.integers(1, 7)), int(rng.integers(1, 5)))
        pred = f.predict(state.store, 1.0)
        z = np.array([[rng.uniform(-6, 6), rng.uniform(-6, 6)]])
        ctx = f.scan_context(pred, z)
        for h in range(len(state.log_w)):
            for keep in (None, 1, 2, f.max_hypotheses, 50):
                assert applies(f.population, ctx, None, False)
                _same_children(f.children_of(ctx, state, h, keep, None), _general(f, ctx, state, h, keep, None))
                checked += 1
        # a whole step: the same posterior, weights and lineage to the bit
        ctx_a, ctx_b = f.scan_context(pred, z), f.scan_context(pred, z)
        a = f.advance(state, pred, ctx_a)
        orig = filter_mod.applies
        filter_mod.applies = lambda *a: False
        try:
            b = f.advance(state, pred, ctx_b)
        finally:
            filter_mod.applies = orig
        assert a.state.same_as(b.state) and a.state.keys == b.state.keys and a.stats.keys() == b.stats.keys()
        assert all(a.stats[s] == b.stats[s] for s in a.stats if not s.startswith("time"))
    assert checked >= 6 * 5


def test_other_scans_take_the_general_path():
    f = _filter("survival")
    state = _scene(np.random.default_rng(3), 4, 2)
    pred = f.predict(state.store, 1.0)
    assert not applies(f.population, f.scan_context(pred, np.zeros((2, 2))), None, False)  # two returns
    assert not applies(f.population, f.scan_context(pred, np.zeros((0, 2))), None, False)  # none
    ctx = f.scan_context(pred, np.zeros((1, 2)))
    assert not applies(f.population, ctx, np.random.default_rng(0), False)  # the sampled cap's Gumbel keys
    assert not applies(f.population, ctx, None, True)  # the fallback's null association
    with_birth = HypothesisFilter(**{**f.configuration(), "weights": _filter("binomial").weights,
                                     "population": single_event_population(0.1, 0.05, 1)})
    assert not applies(with_birth.population, with_birth.scan_context(pred, np.zeros((1, 2))), None, False)


def _children_with_duplicates(rng):
    """A step's children from random parents whose objects may die: parent {a, b} with b dead equals parent {a}."""
    f = _filter("binomial", k=int(rng.integers(2, 6)))
    n = int(rng.integers(1, 4))
    base = _scene(rng, n, 1)
    subsets = [np.arange(n)] + [np.delete(np.arange(n), j) for j in range(n)]
    lw = 3.0 * rng.normal(size=len(subsets))  # spread: the heaviest of a set of duplicates is any of them
    lw -= np.logaddexp.reduce(lw)
    state = FilterState(base.store, lw, [s.astype(np.int64) for s in subsets], list(range(len(subsets))), n)
    pred = f.predict(state.store, 1.0)
    ctx = f.scan_context(pred, rng.uniform(-6, 6, size=(int(rng.integers(1, 3)), 2)))
    parts = [f.children_of(ctx, state, h, None, None) for h in range(len(subsets))]
    children = ChildSet.concatenate([p[0] for p in parts], ctx.n_returns)
    return children, np.concatenate([p[1] for p in parts]), state.tracks


@pytest.mark.parametrize("seed", range(10))
def test_merge_few_equal_to_merge_duplicates(seed):
    rng = np.random.default_rng(100 + seed)
    merged_some = False
    for _ in range(8):
        children, keys, tracks = _children_with_duplicates(rng)
        want, wkeys, wn = merge_duplicates(children, keys, tracks, 0)
        got, gkeys, gn, pairs = merge_few(children, keys, tracks, 0)
        assert gn == wn and gkeys.tobytes() == np.asarray(wkeys, dtype=float).tobytes()
        for field in ("parent", "events", "kind", "arg", "log_weights"):
            assert getattr(got, field).tobytes() == getattr(want, field).tobytes(), field
        if len(children) <= FEW and np.any(children.kind == ChildSet.DEATH):
            assert pairs == [child_pairs(got, c, tracks[got.parent[c]], 0) for c in range(len(got))]
        else:
            assert pairs is None
        merged_some |= wn > 0
    assert merged_some  # the scenes hold duplicates


def test_merge_few_leaves_large_and_death_free_steps_alone(monkeypatch):
    children, keys, tracks = _children_with_duplicates(np.random.default_rng(7))
    alive = np.flatnonzero(children.kind != ChildSet.DEATH)
    out = merge_few(children.take(alive), keys[alive], tracks, 0)
    assert out[2] == 0 and out[3] is None and out[0].log_weights.tobytes() == children.log_weights[alive].tobytes()
    calls = []
    monkeypatch.setattr("hypotrack.hypotheses.duplicates.FEW", 1)
    import hypotrack.hypotheses.duplicates as dup
    orig = dup.merge_duplicates
    monkeypatch.setattr(dup, "merge_duplicates", lambda *a: calls.append(1) or orig(*a))
    assert dup.merge_few(children, keys, tracks, 0)[3] is None and calls == [1]
    with pytest.raises(ValueError, match="keys must have shape"):
        merge_few(children, keys[:-1], tracks, 0)


def _glmb_filter():
    from hypotrack.hypotheses import glmb
    from hypotrack.hypotheses.population_lmb import GaussianBirthTerm, LabeledMultiBernoulliPopulation
    sensor = position_sensor(0.5, 0.8, REGION, 2.0)
    terms = [GaussianBirthTerm(np.array([x, 0.0, 0.0, 0.0]), np.diag([4.0, 4.0, 1.0, 1.0]), sensor.measurement.H,
                               sensor.measurement.R) for x in (-3.0, 3.0)]
    return glmb(MOTION, sensor, population=LabeledMultiBernoulliPopulation(terms, r_birth=0.1, p_survive=0.9),
                n_sweeps=20, max_hypotheses=10, seed=1)


@pytest.mark.parametrize("seed", range(4))
def test_pairs_function_is_child_pairs(seed):
    # every kind of child: association, death (binomial), undetected birth (single-event regions), seeded births
    # (Reid's), silent-event sets (the δ-GLMB's), on scans of 0 to 3 returns
    rng = np.random.default_rng(200 + seed)
    with_regions = homht_kbest(MOTION, position_sensor(0.5, 0.8, REGION, 2.0), k=6, max_hypotheses=6,
                               population=single_event_population(0.05, 0.05, 2, HALVES))
    checked = set()
    for f in (_filter("survival", k=6), _filter("binomial", k=6), with_regions, _glmb_filter()):
        state = _scene(rng, 5, 3)
        f.initialise(state.store.means, state.store.covs)
        f.state = state
        for m in range(4):
            children = f.expand(rng.uniform(-6, 6, size=(m, 2)))
            n_birth = with_regions.population.n_birth_regions if f is with_regions else (2 if f.population is not None
                      and hasattr(f.population, "children") else 0)
            pairs = pairs_function(children, state.tracks, n_birth)
            for c in range(len(children)):
                assert pairs(c) == child_pairs(children, c, state.tracks[children.parent[c]], n_birth)
            checked.update(children.kind.tolist())
    assert checked == {0, 1, 2, 3}


@pytest.mark.parametrize("seed", range(4))
def test_merge_few_on_silent_event_sets(seed):
    # δ-GLMB children (bit masks of deaths and unborn terms): parents {a, b} and {a} give the same child when b dies
    rng = np.random.default_rng(300 + seed)
    f = _glmb_filter()
    merged_some = False
    for _ in range(4):
        base = _scene(rng, 3, 1)
        subsets = [np.arange(3), np.array([0, 1]), np.array([0, 2]), np.array([1])]
        lw = 3.0 * rng.normal(size=4)
        state = FilterState(base.store, lw - np.logaddexp.reduce(lw), [s.astype(np.int64) for s in subsets],
                            list(range(4)), 3)
        f.initialise(state.store.means, state.store.covs)
        f.state = state
        children = f.expand(rng.uniform(-6, 6, size=(int(rng.integers(0, 2)), 2)))
        assert ChildSet.POPULATION_SET in children.kind
        keys = children.log_weights + rng.gumbel(size=len(children))  # the sampled cap's keys move with the merge
        for n in (len(children), min(len(children), FEW)):
            sub = children.take(np.arange(n))
            want, wkeys, wn = merge_duplicates(sub, keys[:n], state.tracks, 2)
            got, gkeys, gn, pairs = merge_few(sub, keys[:n], state.tracks, 2)
            assert gn == wn and gkeys.tobytes() == np.asarray(wkeys, dtype=float).tobytes()
            for field in ("parent", "events", "kind", "arg", "log_weights"):
                assert getattr(got, field).tobytes() == getattr(want, field).tobytes(), field
            merged_some |= wn > 0
    assert merged_some

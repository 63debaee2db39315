"""The quiet group's closed-form step on Python floats (:mod:`...factored.sleeping`, itself the general engine's step,
test_sleeping.py) against its array form (``tests/sleeping_arrays.py``) bit for bit: weights,
tracks, keys, labels, means and covariances, on random groups with tracks out of view (``p_D = 0``), tracks that cannot
die (``p_S = 1``: no death twin, hence no merging), a track shared by two hypotheses, tied weights, a validity test
that fails some tracks, caps that drop children; its cases declined alike; and the general engine's step by hand."""

import dataclasses

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay, homht_kbest
from hypotrack.hypotheses.factored import sleeping
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor
from sleeping_arrays import sleeping_step as array_step

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))


def _engine(max_hypotheses=20, cap="top", validity=None):
    pop = BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=DECAY)
    return homht_kbest(ConstantVelocity(0.01), position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=1.0), k=20,
                       birth_intensity=0.5 / VIEW.area, birth_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0),
                       population=pop, max_hypotheses=max_hypotheses, cap=cap, validity=validity, seed=0,
                       means=np.zeros((1, 4)), covs=np.eye(4)[None])


def _case(rng, n_tracks, H, ties):
    means = rng.normal(scale=40.0, size=(n_tracks, 4))
    covs = np.array([np.diag(rng.uniform(0.1, 2.0, 4)) for _ in range(n_tracks)])
    store = TrackStore(means, covs, rng.permutation(1000)[:n_tracks].astype(np.int64))
    tracks = [np.zeros(0, np.int64) if rng.random() < 0.25 else np.array([rng.integers(n_tracks)], np.int64)
              for _ in range(H)]
    w = rng.dirichlet(np.ones(H))
    if ties:
        w = np.round(w * 4) / 4 + 1e-3
    state = FilterState(store, np.log(w / w.sum()), tracks, [("k", h) for h in range(H)], 0)
    p_d = np.where(rng.random(n_tracks) < 0.3, 0.0, rng.uniform(0.01, 0.95, n_tracks))
    p_s = np.where(rng.random(n_tracks) < 0.3, 1.0, rng.uniform(0.5, 0.999, n_tracks))
    return state, p_d, p_s


def _ctx(engine, pred, p_d, p_s):
    ctx = engine.scan_context(pred, np.zeros((0, 2)))
    return dataclasses.replace(ctx, p_detect=p_d, p_survive=p_s)


def _assert_identical(a, b):
    (sa, na), (sb, nb) = a, b
    assert na == nb and sa.next_label == sb.next_label == 0
    assert sa.log_w.tobytes() == sb.log_w.tobytes()
    assert [t.dtype for t in sa.tracks] == [t.dtype for t in sb.tracks]
    assert [t.tolist() for t in sa.tracks] == [t.tolist() for t in sb.tracks] and sa.keys == sb.keys
    for f in ("means", "covs", "labels"):
        x, y = getattr(sa.store, f), getattr(sb.store, f)
        assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


@pytest.mark.parametrize("seed", range(8))
def test_bit_for_bit_the_closed_form(seed):
    rng = np.random.default_rng(seed)
    n_same = 0
    for trial in range(30):
        cap = int(rng.choice([2, 3, 5, 20]))
        validity = (lambda m: m[:, 0] < 30.0) if trial % 3 == 0 else None
        engine = _engine(max_hypotheses=cap, validity=validity)
        state, p_d, p_s = _case(rng, int(rng.integers(1, 6)), int(rng.integers(1, 12)), ties=trial % 2 == 1)
        pred = engine.predict(state.store, 1.0)
        ctx = _ctx(engine, pred, p_d, p_s)
        ref = array_step(engine, state, pred, ctx)
        new = sleeping.sleeping_step(engine, state, pred, ctx)
        assert (ref is None) == (new is None)
        if ref is not None:
            _assert_identical(new, ref)
            n_same += 1
    assert n_same >= 20  # most cases are the closed form's, not declined


def test_merges_a_shared_track_and_matches_the_general_step():
    engine = _engine(max_hypotheses=20)
    rng = np.random.default_rng(3)
    state, _, _ = _case(rng, 3, 1, ties=False)
    state = FilterState(state.store, np.log([0.2, 0.3, 0.3, 0.2]), [np.zeros(0, np.int64)] + [np.array([t]) for t in (0, 0, 2)],
                        [("k", h) for h in range(4)], 0)
    pred = engine.predict(state.store, 1.0)
    ctx = _ctx(engine, pred, np.array([0.5, 0.2, 0.0]), np.array([0.9, 0.8, 1.0]))
    new = sleeping.sleeping_step(engine, state, pred, ctx)
    _assert_identical(new, array_step(engine, state, pred, ctx))
    general = engine.advance(state, pred, ctx).state
    np.testing.assert_allclose(new[0].log_w, general.log_w, rtol=0, atol=1e-12)
    assert new[0].keys == general.keys
    # by hand: the two "missed" children of track 0 merged, the deaths into "no object", track 2 (p_D 0, p_S 1) as it was
    missed0 = 0.3 * 0.5 * 0.9 * 2
    none = 0.2 + 0.3 * 0.1 * 2
    want = np.array([missed0, 0.2, none])
    order = np.argsort(-want, kind="stable")
    np.testing.assert_allclose(np.exp(new[0].log_w), (want / want.sum())[order], rtol=1e-12)
    assert new[1] == 3  # one "missed" twin of track 0 and the two deaths merged


def test_declines_as_the_closed_form_does():
    engine = _engine()
    rng = np.random.default_rng(1)
    state, p_d, p_s = _case(rng, 2, 3, ties=False)
    two = FilterState(state.store, np.log([0.5, 0.5]), [np.zeros(0, np.int64), np.array([0, 1])], [("k", 0), ("k", 1)], 0)
    pred = engine.predict(state.store, 1.0)
    ctx = _ctx(engine, pred, p_d, p_s)
    assert sleeping.sleeping_step(engine, two, pred, ctx) is None
    assert sleeping.sleeping_step(_engine(cap="sample"), state, pred, ctx) is None
    assert sleeping.sleeping_step(_engine(max_hypotheses=1), state, pred, ctx) is None
    assert sleeping.sleeping_step(engine, state, pred, _ctx(engine, pred, np.array([1.0, 0.5]), p_s)) is None

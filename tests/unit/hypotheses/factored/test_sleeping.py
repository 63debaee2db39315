"""The closed-form step of a quiet group of one-track hypotheses under per-track deaths (:mod:`...factored.sleeping`)
against the general engine's step on the empty scan (:meth:`HypothesisFilter.advance`) and against the weights by
hand: "missed" ``w_h (1 − p_D,h) p_S,h`` with the predicted track, every death and "no object" merged into one
hypothesis ``w_∅ + Σ_h w_h (1 − p_S,h)``; through a track out of view, a predicted track failing the validity test,
ties, a cap that drops children; and the cases it declines. (The catalogue run through it, scan by scan against
the general engine: test_fast_mixture.py.)"""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay, homht_kbest
from hypotrack.hypotheses.factored.sleeping import sleeping_step
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))
# one object's alternatives: in view (tentative: wide velocity), in view (confirmed), out of view, and the
# track the validity test below fails
MEANS = np.array([[0.0, 0.0, 1.0, 0.0], [2.0, 1.0, 1.0, 0.0], [300.0, 0.0, 0.0, 0.0], [70.0, 70.0, 0.0, 0.0]])
COVS = np.array([np.diag(d) for d in ([0.5, 0.5, 4.0, 4.0], [0.5, 0.5, 0.01, 0.01], [0.5, 0.5, 0.01, 0.01],
                                      [0.5, 0.5, 0.01, 0.01])])


def _engine(max_hypotheses=20, cap="top", validity=None, survival=DECAY):
    pop = BinomialPopulation([], alpha=0.0, p_survive=0.95 if survival is None else 1.0, survival=survival)
    return homht_kbest(ConstantVelocity(0.01), position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=1.0), k=20,
                       birth_intensity=0.5 / VIEW.area, birth_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0),
                       population=pop, max_hypotheses=max_hypotheses, cap=cap, validity=validity, seed=0,
                       means=MEANS[:1], covs=COVS[:1])


def _north_east(means):
    return ~((means[:, 0] > 55) & (means[:, 1] > 55))


def _state(log_w, tracks):
    store = TrackStore(MEANS.copy(), COVS.copy(), np.array([7, 8, 9, 10]))
    return FilterState(store, np.asarray(log_w, dtype=float), [np.asarray(t, dtype=np.int64) for t in tracks],
                       [("k", h) for h in range(len(tracks))], 0)


def _both(engine, state):
    pred = engine.predict(state.store, 1.0)
    ctx = engine.scan_context(pred, np.zeros((0, 2)))
    general = engine.advance(state, pred, ctx)
    return general, sleeping_step(engine, state, pred, ctx), ctx


def _assert_same(general, slept):
    new, n_dup = slept
    g = general.state.with_next_label(0)
    np.testing.assert_allclose(new.log_w, g.log_w, rtol=0, atol=1e-12)
    assert [t.tolist() for t in new.tracks] == [t.tolist() for t in g.tracks] and new.keys == g.keys
    np.testing.assert_array_equal(new.store.labels, g.store.labels)
    np.testing.assert_array_equal(new.store.means, g.store.means)
    np.testing.assert_array_equal(new.store.covs, g.store.covs)
    assert n_dup == general.stats["n_duplicates_merged"] and new.next_label == 0


@pytest.mark.parametrize("survival", [DECAY, None])
def test_the_closed_form_is_the_engine_s_step_and_the_weights_by_hand(survival):
    engine = _engine(validity=_north_east, survival=survival)
    w = np.array([0.1, 0.4, 0.3, 0.15, 0.05])
    state = _state(np.log(w), [[], [0], [1], [2], [3]])
    general, slept, ctx = _both(engine, state)
    _assert_same(general, slept)
    p_d = ctx.p_detect
    p_s = np.full(4, 0.95) if survival is None else ctx.p_survive
    assert p_d[2] == 0 and p_d[0] == pytest.approx(0.8) and (np.ptp(p_s) > 0.01 or survival is None)
    missed = w[1:] * (1 - p_d) * p_s
    empty = w[0] + np.sum(w[1:] * (1 - p_s))
    # hypothesis 4's track fails the test: its "missed" child is dropped, its death merged into "no object"
    want = np.r_[missed[:3], empty]
    order = np.argsort(-want, kind="stable")
    np.testing.assert_allclose(np.exp(slept[0].log_w), (want / want.sum())[order], rtol=1e-12)
    assert slept[1] == 4  # four deaths merged into "no object"


def test_a_cap_that_drops_children_and_tied_weights():
    engine = _engine(max_hypotheses=2)
    state = _state(np.log([0.2, 0.4, 0.4]), [[], [0], [0]])  # the same track in two hypotheses: merged too
    general, slept, _ = _both(engine, state)
    _assert_same(general, slept)
    assert len(slept[0].log_w) == 2
    state = _state(np.log([0.25, 0.25, 0.25, 0.25]), [[], [1], [2], [3]])
    _assert_same(*_both(engine, state)[:2])


def test_it_declines_what_is_not_its_case():
    state = _state(np.log([0.5, 0.5]), [[], [0, 1]])  # two tracks in a hypothesis
    assert _both(_engine(), state)[1] is None
    state = _state(np.log([0.5, 0.5]), [[], [0]])
    assert _both(_engine(cap="sample"), state)[1] is None
    assert _both(_engine(max_hypotheses=1), state)[1] is None
    engine = _engine(validity=lambda m: np.zeros(len(m), bool))
    only = _state(np.zeros(1), [[0]])  # no death (p_S of the track < 1, but its twin is valid): kept
    _assert_same(*_both(engine, only)[:2])

"""Document 001's binomial population with per-track survival (``BinomialPopulation.survival``, Eq. 59 with each
track's own ``p_S``): the no-event term and the death twins, hand-computed; bad input."""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, HypothesisFilter, UnconfirmedDecay, homht_kbest
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
MOTION = ConstantVelocity(0.01)
CONF = np.diag([0.5, 0.5, 0.01, 0.01])
X0 = np.array([[0.0, 0.0, 1.0, 0.0]])
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))


def _sensor():
    return position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=1.0)


def test_the_binomial_population_s_per_track_survival_hand_computed():
    """One parent of two tracks (p_S 0.6 tentative, 0.97 confirmed), no return: document 001's binomial children are
    "both missed" (0.6 · 0.97 · 0.2²), "tentative died" (0.4 · 0.97 · 0.2) and "confirmed died" (0.6 · 0.03 · 0.2),
    normalised; without the survival (p_S = 1) the one child "both missed"."""
    covs = np.stack([np.diag([0.5, 0.5, 4.0, 4.0]), CONF])
    means = np.array([[0.0, 0.0, 0.0, 0.0], [50.0, 0.0, 0.0, 0.0]])
    pop = BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=DECAY)
    f = homht_kbest(MOTION, _sensor(), k=20, population=pop, dt=1.0, max_hypotheses=100, means=means, covs=covs, seed=0)
    post = f.step(np.zeros((0, 2)))
    w = {tuple(sorted(h.labels.tolist())): h.weight for h in post.top}
    hand = {(0, 1): 0.6 * 0.97 * 0.04, (1,): 0.4 * 0.97 * 0.2, (0,): 0.6 * 0.03 * 0.2}
    total = sum(hand.values())
    assert sorted(w) == sorted(hand)
    for key, v in hand.items():
        assert w[key] == pytest.approx(v / total, rel=1e-12)
    f0 = homht_kbest(MOTION, _sensor(), k=20, population=BinomialPopulation([], alpha=0.0), dt=1.0,
                     max_hypotheses=100, means=means, covs=covs, seed=0)
    assert len(f0.step(np.zeros((0, 2))).top) == 1


def test_binomial_survival_is_checked():
    with pytest.raises(TypeError, match="survival must be callable"):
        BinomialPopulation([], alpha=0.0, survival=0.9)
    pop = BinomialPopulation([], alpha=0.0, survival=lambda m, c: np.full(len(m), 1.5))
    f = homht_kbest(MOTION, _sensor(), k=5, population=pop, means=X0[:1], covs=CONF[None], seed=0)
    with pytest.raises(ValueError, match=r"survival must return one p_S in \(0, 1\]"):
        f.step(np.zeros((0, 2)))
    with pytest.raises(ValueError, match="p_survive must hold one p_S per object"):
        BinomialPopulation([], alpha=0.0).log_event_prob(0, 2, p_survive=np.ones(3))
    assert isinstance(f, HypothesisFilter)

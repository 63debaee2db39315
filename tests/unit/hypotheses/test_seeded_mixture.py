"""Reid's births seeded at a return from a Gaussian mixture (:mod:`hypotrack.hypotheses.seeded`): one option per
component, weight ``λ_B w_c`` (document 001 Eq. 35 with the newborn's density a mixture).

Oracle: one parent with two objects and a scan of m = 3 returns whose mixtures have 3, 1 and 0 components; every
association (each return on clutter, an object or one of its components; no object twice) weighed term by term
(``p_D N(z; Hx, S)``, ``1 − p_D``, ``λ_C``, ``λ_B w_c``) with scipy's Gaussian density.
"""
import itertools

import numpy as np
import pytest
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

from hypotrack.hypotheses import ExhaustiveGenerator, FactoredFilter, HypothesisFilter, MurtyGenerator, ReidWeights
from hypotrack.hypotheses.factored.fast_path import fast_rule
from hypotrack.hypotheses.seeded import seeded_option_scores, seeded_state
from hypotrack.models import ConstantVelocity
from scenes import H_POSITION, position_sensor
from hypotrack.models.sensors import Box

REGION = Box([-50.0, -50.0], [50.0, 50.0])
V = 100.0 * 100.0
MOTION = ConstantVelocity(0.05)
H, R = H_POSITION, np.eye(2) * 0.5
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [4.0, 1.0, 0.0, 1.0]])
P0 = np.stack([np.diag([1.0, 1.0, 0.2, 0.2]), np.diag([0.5, 0.8, 0.1, 0.3])])
Z = np.array([[1.3, -0.2], [4.2, 1.7], [-30.0, 20.0]])  # near object 0, near object 1, far from both
LAM_B, P_D, RATE = 2e-3, 0.8, 1.0
W = {0: np.array([0.5, 0.3, 0.2]), 1: np.array([1.0]), 2: np.zeros(0)}  # return 2: no admissible state


class ToyMixture:
    """Return ``i``'s mixture: ``len(W[i])`` components at the return with velocities (c − 1, 0.5 c)."""

    def components(self, z):
        i = int(np.argmin(np.abs(Z - z).sum(axis=1)))
        w = W[i]
        means = np.array([[z[0], z[1], c - 1.0, 0.5 * c] for c in range(len(w))]).reshape(-1, 4)
        covs = np.array([np.diag([0.5, 0.5, 0.1 + c, 0.2]) for c in range(len(w))]).reshape(-1, 4, 4)
        return w, means, covs


def _filter(generator, **kw):
    return HypothesisFilter(MOTION, position_sensor(R, P_D, REGION, RATE),
                            ReidWeights(birth_intensity=LAM_B, birth_density=ToyMixture()), generator,
                            means=X0, covs=P0, labels=[0, 1], **kw)


def oracle():
    """{event tuple: log-weight} of every child of the initial parent."""
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    logg = [multivariate_normal(H @ F @ x, H @ F @ P @ F.T @ H.T + H @ Q @ H.T + R).logpdf(Z) for x, P in zip(X0, P0)]
    out = {}
    options = [[-1, 0, 1] + [-2 - c for c in range(len(W[i]))] for i in range(3)]
    for ev in itertools.product(*options):
        used = [a for a in ev if a >= 0]
        if len(used) != len(set(used)):
            continue
        lw = sum(np.log(P_D) + logg[a][i] if a >= 0 else np.log(RATE / V) if a == -1 else
                 np.log(LAM_B) + np.log(W[i][-2 - a]) for i, a in enumerate(ev))
        out[ev] = lw + sum(np.log1p(-P_D) for j in range(2) if j not in used)
    return out


def test_option_scores_are_log_lambda_b_w_c_per_component_and_none_without_mass():
    s = seeded_option_scores(ToyMixture(), Z, np.log(LAM_B))
    want = np.full((3, 3), -np.inf)
    want[0] = np.log(LAM_B * W[0])
    want[1, 0] = np.log(LAM_B)
    np.testing.assert_allclose(s, want, rtol=1e-15)
    assert seeded_option_scores(ToyMixture(), np.zeros((0, 2)), 0.0).shape == (0, 0)
    mean, cov = seeded_state(ToyMixture(), Z[0], R, 2)
    np.testing.assert_array_equal(mean, [1.3, -0.2, 1.0, 1.0])
    with pytest.raises(ValueError, match=r"^component must lie in \[0, 0\] for this return, got 1$"):
        seeded_state(ToyMixture(), Z[1], R, 1)


@pytest.mark.parametrize("generator", [ExhaustiveGenerator(), MurtyGenerator(k=10_000)], ids=["exhaustive", "murty"])
def test_every_child_weight_is_the_hand_computed_one(generator):
    want = oracle()
    ch = _filter(generator).expand(Z)
    got = {tuple(int(a) for a in ev): lw for ev, lw in zip(ch.events, ch.log_weights)}
    assert set(got) == set(want) and len(got) == len(ch.events)
    for ev, lw in want.items():
        assert got[ev] == pytest.approx(lw, rel=0, abs=1e-10)
    # Reid's Eq. 35 marginally: summed over return 0's components, a seeded child weighs λ_B × the rest
    for rest in [(-1, -1), (1, -1), (-2, -1)]:
        seeded = logsumexp([got[(-2 - c, *rest)] for c in range(3)])
        assert seeded - got[(-1, *rest)] == pytest.approx(np.log(LAM_B) - np.log(RATE / V), abs=1e-12)


def test_kept_children_hold_the_component_tracks_one_label_per_return_and_component():
    f = _filter(ExhaustiveGenerator(), max_hypotheses=1000)
    f.step(Z)
    store, kept, mix = f.store, f.last_kept, ToyMixture()
    labels = {}
    for c, tracks in enumerate(f.track_lists):
        ev = kept.events[c]
        born = [i for i in range(3) if ev[i] <= -2]
        assert len(tracks) == 2 + len(born)
        for t, i in zip(tracks[2:], born):
            w, means, covs = mix.components(Z[i])
            np.testing.assert_array_equal(store.means[t], means[-2 - ev[i]])
            np.testing.assert_array_equal(store.covs[t], covs[-2 - ev[i]])
            assert labels.setdefault((i, int(ev[i])), int(store.labels[t])) == store.labels[t]
    assert len(labels) == 4 and sorted(labels.values()) == list(range(2, 6))  # (0, c) for c < 3 and (1, 0)
    want = oracle()
    lw = np.array([want[tuple(int(a) for a in ev)] for ev in kept.events])
    np.testing.assert_allclose(f.log_weights, lw - logsumexp(lw), rtol=0, atol=1e-10)


def test_the_factored_engine_keeps_a_returns_components_in_one_object():
    """Object 0's group: detected, or missed with return 0 clutter or in one of its 3 components (Reid's weights,
    normalised); the component newborns are one object (never two in one joint hypothesis)."""
    f = FactoredFilter.from_filter(_filter(MurtyGenerator(k=50), max_hypotheses=50, gate_probability=0.9),
                                   lazy=True, min_weight=1e-12)
    rule = fast_rule(f.engine, True, 1e-3)  # a lone track's mixture children (hypotheses.factored.fast_mixture)
    assert rule.seeded_children == 50 and rule.max_hypotheses == 50  # Murty's k, the cap
    f.step(Z, 1.0)
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    x, P = F @ X0[0], F @ P0[0] @ F.T + Q
    g = multivariate_normal(H @ x, H @ P @ H.T + R).pdf(Z[0])
    w = np.r_[P_D * g, (1 - P_D) * RATE / V, (1 - P_D) * LAM_B * W[0]]
    groups = [s for s in f.groups if 0 in s.store.labels]
    assert len(groups) == 1
    got = np.sort(np.exp(groups[0].log_w))
    np.testing.assert_allclose(got, np.sort(w / w.sum()), rtol=1e-9)
    for h in f.joint_hypotheses():
        newborn = np.asarray(h.labels)[np.asarray(h.labels) >= 2]
        born_at = {int(np.argmin(np.abs(Z - m[:2]).sum(axis=1))) for m in np.asarray(h.means)[np.asarray(h.labels) >= 2]}
        assert len(born_at) == len(newborn)  # one newborn per return at most

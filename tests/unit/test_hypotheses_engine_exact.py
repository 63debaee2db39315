"""The hypothesis filter and its child generators on exact oracles: hand-computed weights with
births and deaths, in-view versus out-of-view objects, brute-force enumeration, exact top-k.

The child oracle enumerates, for one parent and a scan of m = 3 returns, every association
(each return on clutter, an object or a birth region, no column twice) and every allowed
silent event (an undetected birth in an unused region, a death of an undetected object), and
weighs each child with seed 000 Eq. 8 × Eq. 30 (H-FISST, single event) or seed 001 Eq. 6–7 ×
Eq. 31, 59 (FISST with Poisson clutter, binomial population), written out term by term with
scipy's Gaussian densities.
"""

import itertools
import math

import numpy as np
import pytest
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

from hypotrack.hypotheses import (
    BinomialPopulation,
    ChildSet,
    ExhaustiveGenerator,
    FISSTPoissonWeights,
    HFISSTWeights,
    HypothesisFilter,
    SingleEventPopulation,
)
from hypotrack.hypotheses.generators import top_k
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

REGION = Box([-50.0, -50.0], [50.0, 50.0])
V = 100.0 * 100.0
HALVES = [Box([-50.0, -50.0], [0.0, 50.0]), Box([0.0, -50.0], [50.0, 50.0])]
MOTION = ConstantVelocity(0.05)
H = np.hstack([np.eye(2), np.zeros((2, 2))])
R = np.eye(2) * 0.5
# objects 0 and 1 in view, object 2 out of view (x = 60 > 50: p_D = 0)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [4.0, 1.0, 0.0, 1.0], [60.0, 0.0, 0.0, 0.0]])
P0 = np.stack([np.diag([1.0, 1.0, 0.2, 0.2]), np.diag([0.5, 0.8, 0.1, 0.3]), np.eye(4)])
Z = np.array([[1.3, -0.2], [4.2, 1.7], [-30.0, 20.0]])  # near object 0, near object 1, in the left half


def _sensor(p_D, rate=1.0):
    return Sensor(LinearPositionSensor(R, 4), DetectionModel(p_D, REGION), PoissonClutter(rate, REGION))


def _births():
    return [UniformBirthDensity(h, np.eye(2) * 4.0) for h in HALVES]


def oracle(model, p_D, rate=1.0, alpha=0.0, beta=0.0, p_s=1.0):
    """{(kind, arg, events): log-weight} of every child of the initial parent for scan Z."""
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    M, B, m = len(X0), len(HALVES), len(Z)
    logg, p = [], []
    for j in range(M):
        x, P = F @ X0[j], F @ P0[j] @ F.T + Q
        logg.append(multivariate_normal(H @ x, H @ P @ H.T + R).logpdf(Z))
        p.append(p_D if REGION.contains((H @ x)[None])[0] else 0.0)
    in_view = [j for j in range(M) if p[j] > 0]
    birth_g = [[-np.log(h.area) if h.contains(z[None])[0] else -np.inf for h in HALVES] for z in Z]
    out = {}
    for ev in itertools.product(range(-1, M + B), repeat=m):
        used = [c for c in ev if c >= 0]
        if len(used) != len(set(used)):
            continue
        det_obj = {c for c in used if c < M}
        det_births = [c - M for c in used if c >= M]
        silent = [None] + [("birth", r) for r in range(B) if r not in det_births]
        silent += [("death", j) for j in range(M) if j not in det_obj]
        for s in silent:
            born = det_births + ([s[1]] if s and s[0] == "birth" else [])
            dead = [s[1]] if s and s[0] == "death" else []
            if model == "single":
                if len(born) + len(dead) > 1 or (dead and dead[0] not in in_view):
                    continue
                lp = np.log(alpha) if born else np.log(beta) if dead else np.log(1 - B * alpha - len(in_view) * beta)
            else:
                lp = len(born) * np.log(alpha) + (B - len(born)) * np.log1p(-alpha)
                lp += len(dead) * np.log1p(-p_s) + (M - len(dead)) * np.log(p_s)
            lw = lp
            for j in range(M):
                if j in dead:
                    continue
                if j in det_obj:
                    i = ev.index(j)
                    lw += np.log(p[j]) + logg[j][i] if p[j] > 0 else -np.inf
                else:
                    lw += np.log1p(-p[j])
            for i, c in enumerate(ev):
                if c >= M:
                    lw += np.log(p_D) + birth_g[i][c - M]
            if s and s[0] == "birth":
                lw += np.log1p(-p_D)
            n_det, n_clutter = len(used), m - len(used)
            if model == "single":  # H-FISST: clutter density 1/V and −log(C(m, k) k!)
                lw += n_clutter * -np.log(V) - (math.lgamma(m + 1) - math.lgamma(m - n_det + 1))
            else:  # FISST, Poisson clutter: Eq. 6 × Eq. 7
                lw += -rate + n_clutter * np.log(rate) - math.lgamma(n_clutter + 1)
                lw += math.lgamma(n_clutter + 1) - n_clutter * np.log(V)
            if not np.isfinite(lw):
                continue
            kind = (ChildSet.ASSOCIATION if s is None else
                    ChildSet.UNDETECTED_BIRTH if s[0] == "birth" else ChildSet.DEATH)
            out[(kind, -1 if s is None else s[1], ev)] = lw
    return out


def _filter(model, p_D, rate=1.0, alpha=0.0, beta=0.0, p_s=1.0, max_hypotheses=10**6):
    if model == "single":
        pop = SingleEventPopulation(SingleEventBirthDeath(alpha, beta, 2), birth_densities=_births())
        weights = HFISSTWeights()
    else:
        pop = BinomialPopulation(_births(), alpha=alpha, p_survive=p_s)
        weights = FISSTPoissonWeights()
    return HypothesisFilter(MOTION, _sensor(p_D, rate), weights, ExhaustiveGenerator(), population=pop,
                            max_hypotheses=max_hypotheses, means=X0, covs=P0, seed=0)


def _by_key(ch):
    return {(int(k), int(a), tuple(int(e) for e in ev)): lw
            for k, a, ev, lw in zip(ch.kind, ch.arg, ch.events, ch.log_weights)}


CASES = [
    dict(model="single", p_D=0.8, alpha=0.01, beta=0.05),
    dict(model="single", p_D=0.99, alpha=0.01, beta=0.2),  # death twins outweigh their children
    dict(model="binomial", p_D=0.8, alpha=0.02, p_s=0.9, rate=2.0),
    dict(model="binomial", p_D=0.95, alpha=0.3, p_s=0.9, rate=0.5),
]


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['model']}-pD{c['p_D']}")
def test_every_child_of_three_objects_and_three_returns_weighed_by_hand(case):
    want = oracle(**case)
    got = _by_key(_filter(**case).expand(Z))
    assert got.keys() == want.keys()
    for key, lw in want.items():
        assert got[key] == pytest.approx(lw, abs=1e-9), key
    # the out-of-view object (2) is never detected; it dies only under the binomial model
    assert not any(2 in ev for _, _, ev in got)
    assert any(k == ChildSet.DEATH and a == 2 for k, a, _ in got) == (case["model"] == "binomial")


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['model']}-pD{c['p_D']}")
@pytest.mark.parametrize("keep", [1, 4, 25])
def test_kept_children_are_the_exact_top_k_and_normalised(case, keep):
    want = oracle(**case)
    f = _filter(**case, max_hypotheses=keep)
    post = f.step(Z)
    best = sorted(want.values(), reverse=True)[:keep]
    np.testing.assert_allclose(np.sort(f.last_kept.log_weights)[::-1], best, atol=1e-9)
    for key, lw in _by_key(f.last_kept).items():
        assert lw == pytest.approx(want[key], abs=1e-9), key
    np.testing.assert_allclose(post.log_weights, np.array(best) - logsumexp(best), atol=1e-9)
    st = f.last_stats
    assert st["n_parents"] == 1 and st["n_kept"] == keep
    assert st["mass_retained"] == pytest.approx(np.exp(logsumexp(best) - st["log_mass_generated"]), rel=1e-9)
    assert 0 < st["mass_retained"] <= 1


@pytest.mark.parametrize("case", CASES[1:3], ids=lambda c: f"{c['model']}-pD{c['p_D']}")
def test_stats_of_an_uncapped_step_count_every_child(case):
    want = oracle(**case)
    f = _filter(**case)
    f.step(Z)
    st = f.last_stats
    n_assoc = sum(k[0] == ChildSet.ASSOCIATION for k in want)
    assert st["n_association_children"] == n_assoc
    assert st["n_twin_children"] == len(want) - n_assoc
    assert st["n_kept"] == len(want)
    assert st["log_mass_generated"] == pytest.approx(logsumexp(list(want.values())), abs=1e-9)
    assert st["mass_retained"] == pytest.approx(1.0, abs=1e-12)


def test_top_k_is_the_k_largest_best_first_with_stable_ties():
    lw = np.array([0.5, 2.0, -1.0, 2.0, 0.5, 3.0])
    np.testing.assert_array_equal(top_k(lw, 3), [5, 1, 3])
    np.testing.assert_array_equal(top_k(lw, None), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 6), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 1), [5])
    np.testing.assert_array_equal(top_k(lw, 5), [5, 1, 3, 0, 4])

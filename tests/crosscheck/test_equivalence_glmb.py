"""The δ-GLMB filter as a configuration of the engine, checked against the labeled-RFS formulas.

(a) Exhaustive generation under the GLMB weight model and the labeled multi-Bernoulli population
    equals a brute-force δ-GLMB posterior computed here from the formulas of Vo & Vo (2013,
    Prop. 7–8: survival p_S and LB birth r_B per label, update factor p_D g / κ or 1 − p_D) —
    its own Kalman filter, its own enumeration of label sets × association maps, no engine code —
    over two scans with births, deaths, an object out of view and m ≥ 3.
(b) Nesting: under Poisson clutter the binomial population of document 001 (independent survival
    p_s, birth α per region, at most one silent event per child) produces exactly the GLMB children
    with at most one death / undetected birth, with identical weights; the GLMB's extra children
    are exactly those with two or more, so the posteriors coincide exactly when no child can hold
    two (one object, no birth term) and differ by that mass otherwise.
(c) With p_S = 1 and no birth terms the GLMB posterior equals Reid's HOMHT hypothesis by
    hypothesis over several scans (the fixed-number case of document 001 Sec. V-A).
Each would fail if a birth or survival term changed: (d) mutates one and shows the mismatch.
"""

import functools
import itertools

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack.hypotheses import (
    BinomialPopulation,
    ChildSet,
    ExhaustiveGenerator,
    FISSTPoissonWeights,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    ReidWeights,
)
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

R = np.eye(2) * 0.5
P_D = 0.8
MOTION = ConstantVelocity(q=0.05)
VIEW = Box([-10.0, -10.0], [10.0, 10.0])  # detection region; clutter over a larger box
SENSOR = position_sensor(R, P_D, VIEW, 1.5, Box([-20.0, -20.0], [20.0, 20.0]))
H = SENSOR.measurement.H
# object 1 starts at x = 11 and moves out: it is out of view at every scan (p_D = 0)
X0 = np.array([[0.0, 0.0, 1.0, 0.5], [11.0, 0.0, 1.0, 0.0], [5.0, 2.0, -0.5, 0.6]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 3, axis=0)
BIRTH_MEAN, BIRTH_COV = np.array([-5.0, 6.0, 0.0, 0.0]), np.diag([2.0, 2.0, 0.5, 0.5])
SCANS = [np.array([[1.1, 0.4], [4.4, 2.7], [-4.8, 6.3]]),
         np.array([[2.0, 1.1], [-5.1, 5.9]])]
ORACLE_SCANS = tuple(tuple(map(tuple, Z)) for Z in SCANS)  # hashable, for the cached oracle
P_S, R_B = 0.9, 0.2


def lmb(p_s=P_S, r_b=R_B, births=True):
    terms = [GaussianBirthTerm(BIRTH_MEAN, BIRTH_COV, H, R)] if births else []
    return LabeledMultiBernoulliPopulation(terms, r_birth=r_b, p_survive=p_s)


def glmb_filter(population, n=2):
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=population,
                            max_hypotheses=10**7, means=X0[:n], covs=P0[:n], seed=0)


# ---------------------------------------------------------------- brute-force δ-GLMB oracle
def _kf_update(m, P, z):
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    IKH = np.eye(4) - K @ H
    return m + K @ (z - H @ m), IKH @ P @ IKH.T + K @ R @ K.T, multivariate_normal(H @ m, S).pdf(z)


@functools.lru_cache
def oracle_posterior(scans, p_s, r_b, n=2, births=True):
    """δ-GLMB posterior after ``scans`` as {sorted rounded means: probability}."""
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    kappa = SENSOR.clutter.intensity
    comps = [(1.0, [(X0[i], P0[i]) for i in range(n)])]
    for Z in scans:
        Z = np.array(Z)
        new = []
        for w, tracks in comps:
            objs = [(F @ m, F @ P @ F.T + Q, p_s) for m, P in tracks]
            if births:
                objs.append((BIRTH_MEAN, BIRTH_COV, r_b))
            # each object: -2 absent (died / not born), -1 present and missed, j detected by z_j
            for gamma in itertools.product(range(-2, len(Z)), repeat=len(objs)):
                used = [g for g in gamma if g >= 0]
                if len(used) != len(set(used)):
                    continue
                wt, out = w, []
                for (m, P, r), g in zip(objs, gamma):
                    pd = P_D if VIEW.contains((H @ m)[None])[0] else 0.0
                    if g == -2:
                        wt *= 1 - r
                    elif g == -1:
                        wt *= r * (1 - pd)
                        out.append((m, P))
                    else:
                        mu, Pu, lik = _kf_update(m, P, Z[g])
                        wt *= r * pd * lik / kappa
                        out.append((mu, Pu))
                if wt > 0:
                    new.append((wt, out))
        total = sum(w for w, _ in new)
        comps = [(w / total, t) for w, t in new]
    return _by_states([(w, [m for m, _ in t]) for w, t in comps])


def _by_states(items):
    post = {}
    for w, means in items:
        key = tuple(sorted(tuple(np.round(m, 6)) for m in means))
        post[key] = post.get(key, 0.0) + w
    return post


def engine_posterior(f):
    return _by_states([(np.exp(lw), f.store.means[t]) for lw, t in zip(f.log_weights, f.track_lists)])


def assert_same_posterior(a, b, atol=1e-10):
    assert a.keys() == b.keys()
    for k in a:
        assert a[k] == pytest.approx(b[k], abs=atol)


# ---------------------------------------------------------------- (a)
def test_a_exhaustive_glmb_equals_brute_force_delta_glmb_posterior():
    f = glmb_filter(lmb())
    for Z in SCANS:
        f.step(Z)
    oracle = oracle_posterior(ORACLE_SCANS, P_S, R_B)
    assert_same_posterior(engine_posterior(f), oracle)
    # the problem exercises births, deaths and ambiguity: several components above 1 %
    assert sum(p > 0.01 for p in oracle.values()) >= 4
    card = f.posterior().cardinality
    # two objects and one birth term per scan: deaths (mostly of the object out of view) and
    # births both carry weight
    assert card[2] > 0.1 and card[3] > 0.5 and card[4] > 0.01


# ---------------------------------------------------------------- (d)
@pytest.mark.parametrize("mutation", [dict(p_s=P_S * 0.99), dict(r_b=R_B * 1.01)])
def test_d_equivalence_fails_when_a_survival_or_birth_term_changes(mutation):
    f = glmb_filter(lmb(**mutation))
    for Z in SCANS:
        f.step(Z)
    with pytest.raises(AssertionError):
        assert_same_posterior(engine_posterior(f), oracle_posterior(ORACLE_SCANS, P_S, R_B))


# ---------------------------------------------------------------- (b)
def _uniform_birth():
    return UniformBirthDensity(Box([-8.0, 4.0], [-2.0, 8.0]), velocity_cov=np.eye(2) * 0.5)


def _child_keys(children, n_objects):
    """(event bytes, sorted dead objects, sorted unseen births) per child, and its log-weight."""
    out = {}
    for c in range(len(children)):
        dead, unseen = children.silent_events(c, n_objects)
        key = (children.events[c].tobytes(), tuple(sorted(dead)), tuple(sorted(unseen)))
        assert key not in out
        out[key] = children.log_weights[c]
    return out


@pytest.mark.parametrize("n_objects,n_births", [(3, 1), (1, 0), (0, 1)])
def test_b_binomial_population_is_the_glmb_with_at_most_one_silent_event(n_objects, n_births):
    births = [_uniform_birth()] * n_births
    alpha = 0.2
    fb = HypothesisFilter(MOTION, SENSOR, FISSTPoissonWeights(), ExhaustiveGenerator(),
                          population=BinomialPopulation(births, alpha=alpha, p_survive=P_S),
                          max_hypotheses=10**7, means=X0[:n_objects], covs=P0[:n_objects])
    fg = glmb_filter(LabeledMultiBernoulliPopulation(births, r_birth=alpha, p_survive=P_S), n=n_objects)
    Z = SCANS[0]
    binom = _child_keys(fb.expand(Z), n_objects)
    glmb = _child_keys(fg.expand(Z), n_objects)
    assert set(binom) <= set(glmb)
    for key, lw in binom.items():
        assert lw == pytest.approx(glmb[key], abs=1e-10)  # identical weights, not just proportional
    extra = [key for key in glmb if key not in binom]
    assert all(len(key[1]) + len(key[2]) >= 2 for key in extra)
    assert not [key for key in glmb if key not in binom and len(key[1]) + len(key[2]) < 2]
    if n_objects + n_births <= 1:
        assert not extra  # no child can hold two silent events: the posteriors coincide
    else:
        log_extra = np.logaddexp.reduce([glmb[k] for k in extra])
        log_all = np.logaddexp.reduce(list(glmb.values()))
        assert 1e-4 < np.exp(log_extra - log_all) < 0.5  # the mass the binomial filter leaves out


# ---------------------------------------------------------------- (c)
def test_c_glmb_without_births_or_deaths_equals_homht_over_several_scans():
    fg = glmb_filter(lmb(p_s=1.0, births=False), n=3)
    fr = HypothesisFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), max_hypotheses=10**7,
                          means=X0, covs=P0)
    for Z in SCANS + [SCANS[1] + 0.7]:
        fg.step(Z)
        fr.step(Z)
        assert_same_posterior(engine_posterior(fg), engine_posterior(fr), atol=1e-12)
    assert len(fg.log_weights) > 20
    assert all(k == ChildSet.POPULATION_SET for k in fg.last_kept.kind)

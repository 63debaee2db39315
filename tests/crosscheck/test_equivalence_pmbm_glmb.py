"""PMBM with an empty Poisson part and Bernoulli births equals the δ-GLMB filter (the 2018 PMBM paper, Sec. V:
a δ-GLMB density is a multi-Bernoulli mixture with labels).

Both filters run exhaustively (no truncation) over three scans of a scene with m = 3, 3, 1 returns, an object out
of view (p_D = 0), labeled-Bernoulli births (the same birth term, ``r_B``), deaths (``p_S`` < 1) and clutter.
A PMBM global hypothesis is a multi-Bernoulli; expanding every Bernoulli into "exists" / "does not exist"
gives label-set components of weight ``W_a Π r_i Π (1 − r_i)``; those with the same objects (the same
Gaussians) are the δ-GLMB's hypotheses (whose engine merges identical children). The two posteriors must
agree component by component, hence in cardinality, and the δ-GLMB's maximum-a-posteriori hypothesis must be
the PMBM's ``joint_map`` estimate.
"""

import itertools

import numpy as np
import pytest

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    MurtyGenerator,
)
from hypotrack.hypotheses.pmbm import PMBMFilter
from hypotrack.hypotheses.presets import pmbm_births
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor

TOL = 1e-10
R = np.eye(2) * 0.5
MOTION = ConstantVelocity(q=0.05)
VIEW = Box([-10.0, -10.0], [10.0, 10.0])
SENSOR = position_sensor(R, 0.8, VIEW, 1.5, Box([-20.0, -20.0], [20.0, 20.0]))
H = SENSOR.measurement.H
# object 1 starts at x = 11 and moves out of view: p_D = 0 at every scan
X0 = np.array([[0.0, 0.0, 1.0, 0.5], [11.0, 0.0, 1.0, 0.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 2, axis=0)
BIRTH = GaussianBirthTerm([-5.0, 6.0, 0.0, 0.0], np.diag([2.0, 2.0, 0.5, 0.5]), H, R)
SCANS = [np.array([[1.1, 0.4], [4.4, 2.7], [-4.8, 6.3]]),
         np.array([[2.0, 1.1], [-5.1, 5.9], [7.0, -3.0]]),
         np.array([[-4.6, 6.4]])]
POP = LabeledMultiBernoulliPopulation([BIRTH], r_birth=0.2, p_survive=0.9)


def _key(mean, cov):
    return tuple(np.round(mean, 7)) + tuple(np.round(cov.ravel(), 7))


def glmb_components(f):
    s = f.state
    out = {}
    for lw, tr in zip(s.log_w, s.tracks):
        k = tuple(sorted(_key(s.store.means[j], s.store.covs[j]) for j in tr))
        out[k] = out.get(k, 0.0) + np.exp(lw)
    return out


def pmbm_components(f):
    out = {}
    for h in f.global_hypotheses():
        for on in itertools.product([False, True], repeat=len(h.existence)):
            on = np.array(on, bool)
            w = h.weight * np.prod(np.where(on, h.existence, 1 - h.existence))
            k = tuple(sorted(_key(h.means[i], h.covs[i]) for i in np.flatnonzero(on)))
            out[k] = out.get(k, 0.0) + w
    return out


def cardinality(components):
    card = np.zeros(1 + max(len(k) for k in components))
    for k, w in components.items():
        card[len(k)] += w
    return card


def make_pmbm(generator=None, **kw):
    opts = dict(max_hypotheses=10**7, hypothesis_threshold=0.0, existence_threshold=0.0, poisson_threshold=0.0,
                estimator="joint_map", allocation="exact")
    opts.update(kw)
    f = PMBMFilter(MOTION, SENSOR, generator or ExhaustiveGenerator(), **pmbm_births(POP, "bernoulli"), **opts)
    f.initialise(X0, P0)
    return f


@pytest.fixture(scope="module")
def runs():
    glmb = HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), population=POP,
                            max_hypotheses=10**7, means=X0, covs=P0, seed=0)
    pmbm = make_pmbm()
    out = []
    for t, Z in enumerate(SCANS, start=1):
        glmb.step(Z, float(t))
        pmbm.step(Z, float(t))
        out.append((glmb_components(glmb), pmbm_components(pmbm), glmb.estimates(), pmbm.estimates(),
                    pmbm.posterior(), len(glmb.log_weights)))
    return out


def test_every_scan_the_expanded_pmbm_is_the_glmb_posterior(runs):
    for g, p, *_ in runs:
        p = {k: w for k, w in p.items() if w > 0}
        assert set(g) == set(p)
        assert max(abs(g[k] - p[k]) for k in g) < TOL
    assert runs[-1][-1] > 100  # a posterior with more than a hundred δ-GLMB components


def test_cardinality_and_expected_number_agree(runs):
    for g, _, _, _, post, _ in runs:
        card = cardinality(g)
        np.testing.assert_allclose(post.cardinality[:len(card)], card, rtol=0, atol=TOL)
        assert abs(post.expected_number - np.arange(len(card)) @ card) < TOL
        assert post.undetected_mean == 0.0
    # births and deaths change the number of objects: three or more objects have mass after three scans
    assert runs[-1][4].cardinality[3:].sum() > 0.05


def test_joint_map_estimate_is_the_glmb_map_hypothesis(runs):
    for _, _, ge, pe, _, _ in runs:
        np.testing.assert_allclose(ge.x[np.lexsort(ge.x.T[::-1])], pe.x[np.lexsort(pe.x.T[::-1])], atol=TOL, rtol=0)
    # the detected object, the object out of view (survived, p_S = 0.9) and the object born near (-5, 6)
    est = runs[-1][2]
    assert len(est) == 3 and np.sum(np.hypot(est.x[:, 0] + 4.6, est.x[:, 1] - 6.4) < 1.0) == 1


def test_murty_pmbm_keeps_the_exact_best_hypotheses():
    """Murty's k best per global hypothesis and the global cap keep the ``H`` heaviest children of the exhaustive
    recursion at the first scan (whose parents are exact)."""
    full, capped = make_pmbm(), make_pmbm(MurtyGenerator(k=5), max_hypotheses=5)
    full.step(SCANS[0], 1.0)
    capped.step(SCANS[0], 1.0)
    best = np.sort(full.log_w)[::-1][:5]
    kept = np.sort(capped.log_w + np.log(np.exp(best).sum()))[::-1]  # capped weights renormalised over 5
    np.testing.assert_allclose(kept, best, atol=TOL, rtol=0)

"""The thesis of document 001 Sec. V-A and document 000 Sec. II-B, checked on the engine's own numbers.

(a) Fixed number of targets, Poisson clutter: FISST (document 001 Eq. 6–7, 18) and Reid's HOMHT
    (Eq. 30) give the same posterior — weights and track pdfs — over several scans.
(b) H-FISST (document 000 Eq. 8, 17–19) and HOMHT: the same children with the same track pdfs;
    per child the log-weights differ by exactly −log(C(m,k) k!) plus the clutter term
    k'(log g − log λ_C), up to one normalising constant per scan.
"""

import math

import numpy as np
import pytest

from hypotrack.hypotheses import ExhaustiveGenerator, FISSTPoissonWeights, HFISSTWeights, HypothesisFilter, ReidWeights
from hypotrack.models.sensors import Box
from hypotrack.scenarios.cluttered import simulate_cv_targets

X0 = np.array([[0.0, 0.0, 1.0, 0.5], [6.0, 2.0, -0.5, 0.6], [3.0, 8.0, 0.2, -1.0]])
P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 3, axis=0)


def scenario(seed=3, n_scans=5):
    return simulate_cv_targets(X0, n_scans=n_scans, dt=1.0, q_truth=0.05, R=np.eye(2) * 0.5, p_D=0.85,
                               clutter_rate=2.0, region=Box([-15.0, -15.0], [25.0, 25.0]), rng=seed)


def make_filter(scen, weights, max_hypotheses):
    return HypothesisFilter(scen.motion, scen.sensor, weights, ExhaustiveGenerator(), dt=1.0,
                            max_hypotheses=max_hypotheses, means=X0, covs=P0, seed=0)


def by_lineage(f):
    store = f.store
    return {key: (lw, store.means[t], store.covs[t])
            for key, lw, t in zip(f.lineage_keys, f.log_weights, f.track_lists)}


def test_a_fisst_poisson_equals_reid_over_several_scans():
    scen = scenario()
    fa = make_filter(scen, FISSTPoissonWeights(), 400)
    fb = make_filter(scen, ReidWeights(), 400)
    for _, Z in scen.scan_list()[1:]:
        fa.step(Z)
        fb.step(Z)
        a, b = by_lineage(fa), by_lineage(fb)
        assert a.keys() == b.keys()
        for key, (lw, means, covs) in a.items():
            assert lw == pytest.approx(b[key][0], abs=1e-12)
            np.testing.assert_allclose(means, b[key][1], rtol=0, atol=1e-12)
            np.testing.assert_allclose(covs, b[key][2], rtol=0, atol=1e-12)
    # the test must have exercised real ambiguity: several hypotheses with weight > 1e-3
    assert np.sum(np.exp(fa.log_weights) > 1e-3) >= 3


def child_keys(f, children):
    """The lineage key each child will have (see HypothesisFilter.lineage_keys)."""
    keys = f.lineage_keys
    return [(keys[p], int(k), int(a), ev.tobytes())
            for p, k, a, ev in zip(children.parent, children.kind, children.arg, children.events)]


def known_difference(events, m, V, clutter_intensity, n_objects):
    """log w_HFISST − log w_Reid of one child: −log(C(m,k) k!) + k'(log(1/V) − log λ_C)."""
    k = np.sum((events >= 0) & (events < n_objects), axis=1)
    kc = m - k
    return np.array([-math.log(math.comb(m, int(kk)) * math.factorial(int(kk))) for kk in k]) \
        + kc * (math.log(1.0 / V) - math.log(clutter_intensity))


def test_b_hfisst_and_reid_children_same_weights_differ_by_known_terms():
    scen = scenario(seed=4)
    V = scen.sensor.clutter.region.area
    lam = scen.sensor.clutter.intensity
    fh = make_filter(scen, HFISSTWeights(), 10**6)
    fr = make_filter(scen, ReidWeights(), 10**6)
    scans = scen.scan_list()[1:3]
    offsets = {(): 0.0}
    for _, Z in scans:
        ch, cr = fh.expand(Z), fr.expand(Z)
        kh, kr = child_keys(fh, ch), child_keys(fr, cr)
        assert set(kh) == set(kr) and len(kh) == len(ch)
        lw_r = dict(zip(kr, cr.log_weights))
        diff = ch.log_weights - np.array([lw_r[k] for k in kh])
        # unnormalised children of the same parent: the difference is exactly the known terms
        # plus the parents' log-weight difference (carried in `offsets`)
        parent_offset = np.array([offsets[fh.lineage_keys[p]] for p in ch.parent])
        expected = known_difference(ch.events, len(Z), V, lam, X0.shape[0]) + parent_offset
        np.testing.assert_allclose(diff, expected, rtol=0, atol=1e-11)
        fh.step(Z)
        fr.step(Z)
        h, r = by_lineage(fh), by_lineage(fr)
        assert h.keys() == r.keys() and len(h) == len(ch)
        for key, (_lw, means, covs) in h.items():
            np.testing.assert_allclose(means, r[key][1], rtol=0, atol=1e-12)
            np.testing.assert_allclose(covs, r[key][2], rtol=0, atol=1e-12)
        offsets = {key: h[key][0] - r[key][0] for key in h}
    assert len(offsets) > 1000  # two scans of every child: a real comparison

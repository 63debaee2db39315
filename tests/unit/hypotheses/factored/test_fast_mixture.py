"""The fast path for HOMHT's births seeded as an admissible-region mixture (one child per component):

* :func:`mixture_takes` against a brute-force oracle that lists the general step's children one by one (the
  table of :mod:`hypotrack.hypotheses.factored.fast_mixture`), normalises the valid ones and counts the newborn
  components they hold — random tracks of 0-9 components, valid or not, with or without the "died"/"not" children,
  and the decision on either side of ``min_weight``;
* the default catalogue configuration (documented radar, admissible births, plausibility test, the decaying
  survival whose lone tracks are the lane's Bernoullis) stepped with the fast path and without it: the same
  groups, labels, tracks and hypothesis keys, weights and moments to 1e-12, scan by scan, the fast path taking
  lone tracks and the newborns' quiet groups stepped in closed form (:mod:`...factored.sleeping`).
"""

import numpy as np
import pytest
from scenes import catalogue_scene, default_catalogue_config

from hypotrack.experiments.ssa_catalogue.run import make_tracker
from hypotrack.hypotheses.factored.fast_mixture import mixture_takes
from hypotrack.hypotheses.factored.fast_path import MARGIN, FastRule

LAM_C, LAM_B, MIN_W, H_MAX = 2e-3, 5e-4, 1e-3, 20


class ToyMixture:
    """``components(z)``: the mixture stored under ``int(z[0])``; a mean whose first coordinate is negative
    fails the toy validity test."""

    def __init__(self, table):
        self.table = table

    def components(self, z):
        w, x = self.table[int(z[0])]
        return w.copy(), x.copy(), np.repeat(np.eye(2)[None], len(w), axis=0)


def _valid(means):
    return means[:, 0] >= 0


def _rule(density, validity=_valid, seeded_children=H_MAX):
    return FastRule(0.0, np.log([LAM_C, LAM_B]), 1, float(np.log(MIN_W) + np.log1p(-MARGIN)), 0.9, validity,
                    density, True, H_MAX, seeded_children)


def _oracle(w, seed_ok, p, ll, e, pred_ok, upd_ok, gen_k=H_MAX):
    """The general step's children listed one by one: ``(log-weight, valid, newborn components held)``."""
    kids = [(np.log(p) + ll, upd_ok, set())]
    kids.append((np.log1p(-p) + np.log(LAM_C), pred_ok, set()))
    kids += [(np.log1p(-p) + np.log(LAM_B) + np.log(w[c]), pred_ok and seed_ok[c], {c}) for c in range(len(w))]
    if e > -np.inf:
        kids.append((e + np.log(LAM_C), True, set()))
        kids += [(e + np.log(LAM_B) + np.log(w[c]), bool(seed_ok[c]), {c}) for c in range(len(w))]
    valid = [k for k in kids if k[1]]
    total = np.logaddexp.reduce([k[0] for k in valid])
    light = all(k[0] - total < np.log(MIN_W) + np.log1p(-MARGIN) for k in valid[1:]) if upd_ok else False
    fits = 3 + 2 * len(w) <= H_MAX and 2 + len(w) <= gen_k
    return light and fits and 0 < p < 1, len(set().union(*[k[2] for k in valid]))


def test_the_decision_and_the_labels_are_the_listed_children_s():
    rng = np.random.default_rng(5)
    n = 400
    K = rng.integers(0, 10, n)
    table, pred, Z = {}, np.zeros((n, 2)), np.zeros((n, 2))
    for i in range(n):
        w = rng.dirichlet(np.ones(K[i])) if K[i] else np.zeros(0)
        table[i] = (w, np.column_stack([np.where(rng.random(K[i]) < 0.15, -1.0, 1.0), np.zeros(K[i])]))
        Z[i, 0] = i
    pred[:, 0] = np.where(rng.random(n) < 0.2, -1.0, 1.0)
    p = rng.uniform(0.5, 0.99, n)
    ll = rng.uniform(-12.0, 8.0, n)
    e = np.where(rng.random(n) < 0.3, -np.inf, rng.uniform(-14.0, -2.0, n))
    upd = rng.random(n) > 0.1
    density = ToyMixture(table)
    take, n_new = mixture_takes(_rule(density), ll, p, pred, Z, e, upd)
    want = [_oracle(table[i][0], table[i][1][:, 0] >= 0, p[i], ll[i], e[i], pred[i, 0] >= 0, upd[i]) for i in range(n)]
    assert take.tolist() == [t for t, _ in want]
    np.testing.assert_array_equal(n_new, [m for _, m in want])
    assert 40 < take.sum() < n - 40 and (~take & (K <= 8)).any()  # both decisions among tracks that fit
    assert not take[K == 9].any()  # 21 children: the cap of 20 would drop one
    # no "died"/"not" children (r p_S = 1): a track whose prediction fails the test has none of its newborns kept
    _, n0 = mixture_takes(_rule(density), ll, p, pred, Z, None, upd)
    np.testing.assert_array_equal(n0[pred[:, 0] < 0], 0)
    # Murty's k below 2 + K: the generator would not make every child
    take_k, _ = mixture_takes(_rule(density, seeded_children=6), ll, p, pred, Z, e, upd)
    assert take_k.tolist() == [t and K[i] <= 4 for i, t in enumerate(take)]


@pytest.mark.parametrize("side", [0.999, 1.001])
def test_the_decision_turns_at_min_weight(side):
    """One track, three components ``(0.5, 0.3, 0.2)``, no death: the heaviest alternative (missed, the return a
    newborn in component 0) at ``side × min_weight`` of the total is pruned (below) or kept (above)."""
    w = np.array([0.5, 0.3, 0.2])
    density = ToyMixture({0: (w, np.ones((3, 2)))})
    p = 0.9
    alts = np.log1p(-p) + np.log(np.r_[LAM_C, LAM_B * w])
    heavy = alts.max()
    # det such that exp(heavy - total) = side * MIN_W
    det = np.log(np.exp(heavy) / (side * MIN_W) - np.exp(np.logaddexp.reduce(alts)))
    take, n_new = mixture_takes(_rule(density), np.array([det - np.log(p)]), np.array([p]), np.ones((1, 2)),
                                np.zeros((1, 2)), None, np.array([True]))
    assert take.tolist() == [side < 1] and n_new.tolist() == [3]


def test_no_candidate_and_a_bad_validity_answer():
    density = ToyMixture({0: (np.array([1.0]), np.ones((1, 2)))})
    take, n_new = mixture_takes(_rule(density), np.zeros(0), np.zeros(0), np.zeros((0, 2)), np.zeros((0, 2)))
    assert take.shape == (0,) and n_new.dtype == np.int64
    with pytest.raises(ValueError, match="one bool per track"):
        mixture_takes(_rule(density, validity=lambda m: np.ones(len(m) + 1, bool)), np.zeros(1), np.full(1, 0.9),
                      np.ones((1, 2)), np.zeros((1, 2)))


N_SCANS = 50


@pytest.fixture(scope="module")
def decaying_catalogue():
    """The default section as it is (admissible births, plausibility, the decaying survival), 300 objects."""
    cfg = default_catalogue_config(N_SCANS)
    assert "unconfirmed_decay" in cfg["model"] and cfg["model"]["birth"] == "admissible"
    scene = catalogue_scene(cfg, 300)  # p_D from the SNR, as the experiment
    return cfg, scene.problem(), scene.sensor, scene.scans


def test_homht_with_mixture_births_and_the_bernoulli_lane_is_the_general_engine(decaying_catalogue):
    cfg, problem, tsensor, scans = decaying_catalogue
    general, fast = (make_tracker("homht_kbest", cfg, problem, 1, fast_path=on) for on in (False, True))
    n_fast = n_lone = n_slept = 0
    for t, Z, theta in scans:
        tsensor.at(theta)  # the sensor frame and the admissible regions at the scan's GMST
        general.step(Z, t)
        fast.step(Z, t)
        ga, gb = general.groups, fast.groups
        assert len(ga) == len(gb) and general.next_label == fast.next_label
        for s, u in zip(ga, gb):
            np.testing.assert_array_equal(s.store.labels, u.store.labels)
            assert all(np.array_equal(x, y) for x, y in zip(s.tracks, u.tracks)) and s.keys == u.keys
            np.testing.assert_allclose(s.log_w, u.log_w, rtol=0, atol=1e-12)
            np.testing.assert_allclose(s.store.means, u.store.means, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(s.store.covs, u.store.covs, rtol=1e-12, atol=1e-12)
        n_fast += fast.last_stats["n_fast_path"]
        n_lone += general.last_stats["n_touched"]
        # the steps neither run nor the fast path's: quiet groups stepped in closed form (sleeping.py)
        n_slept += general.last_stats["n_jobs"] - fast.last_stats["n_jobs"] - fast.last_stats["n_fast_path"]
    # the run holds what the check is for: lone tracks the fast path takes (about half the steps here; with
    # 10,855 objects nine in ten), births that took labels
    assert n_fast > 0.4 * n_lone > 0 and fast.next_label > len(problem.labels) and n_slept > N_SCANS

"""Bernoulli singletons in the lane for document 001's binomial population with per-track survival: HOMHT k-best
(Reid's weights, births seeded at the returns, a binomial population holding only the deaths) and R-FISST (H-FISST
weights, MCMC search, the binomial population with measurement-driven birth terms).

A lone track's group has one object and no birth term, so the binomial population's "at most one death per child"
loses nothing and its children are the labeled problem's ("missed" ``p_S (1 − p_D)``, "died" ``1 − p_S``, "not"
``1 − r``; the clutter and count factors are the scan's, common to the three): the lane's closed form is exact.
Checked against the general engine (every track a group stepped every scan) each scan to 1e-12: the catalogued
labels one by one, the tracks born during the run up to their numbering (Reid's seeded births take new labels in the
order the components are stepped, which the lane changes); the lane with and without its fast path bit for bit,
labels included. R-FISST's MCMC search is made complete (start at the best assignment, completion rounds), so its
posterior does not depend on the order in which the groups draw from the random stream (checked over two seeds).
"""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay, homht_kbest, rfisst
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredFilter
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor, hypotheses_by_label, label_existence

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
MOTION = ConstantVelocity(0.01)
CONF = np.diag([0.5, 0.5, 0.01, 0.01])
BIRTH = AdaptiveBirth(position_std=0.0, velocity_std=2.0, r_birth=0.05, gate_probability=0.999)
# the catalogue at scan 0 (all r = 1): A seen, B leaving the view, C with no object behind it, D out of view
# throughout (asleep), E seen
X0 = np.array([[0.0, 0.0, 1.0, 0.0],        # A
               [80.0, 0.0, 6.0, 0.0],       # B: out of view from scan 4 (x = 104)
               [-50.0, 50.0, 0.0, 0.0],     # C: nothing there
               [500.0, 500.0, 0.0, 0.0],    # D: out of view
               [-80.0, -80.0, 0.0, 1.0]])   # E
TRUTH = X0[[0, 1, 4]]
NEWBORN = np.array([30.0, -60.0, 0.0, 1.5])  # unknown, first seen at scan 3
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.97, velocity_components=(2, 3))


def _returns(k):
    """Scan ``k``'s returns: A (missed at 4 and 7), B while in view (missed at 2), E (missed at 5), the newborn from
    scan 3 (missed at 6), a clutter return at (60, 60) at scans 2, 4 and 8."""
    off = np.array([0.3, -0.2]) * np.cos(k)
    Z = []
    for i, x in enumerate(TRUTH):
        pos = x[:2] + k * x[2:]
        if {0: k not in (4, 7), 1: k != 2 and np.all(np.abs(pos) <= 100), 2: k != 5}[i]:
            Z.append(pos + off)
    if k >= 3 and k != 6:
        Z.append(NEWBORN[:2] + (k - 3) * NEWBORN[2:] - off)
    if k in (2, 4, 8):
        Z.append(np.array([60.0, 60.0]))
    return np.array(Z).reshape(-1, 2)


def _sensor():
    return position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=1.0)


def _north_east(means):
    """A validity test that the tracks started at the clutter return (60, 60) fail."""
    return ~((means[:, 0] > 55) & (means[:, 1] > 55))


def _homht(bern, fast=False, validity=None):
    pop = BinomialPopulation([], alpha=0.0, p_survive=1.0, survival=DECAY)
    f = homht_kbest(MOTION, _sensor(), k=20, birth_intensity=0.5 / VIEW.area,
                    birth_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0), population=pop, dt=1.0,
                    max_hypotheses=100, means=X0, covs=np.repeat(CONF[None], len(X0), axis=0), seed=0,
                    gate_probability=0.999, validity=validity)
    return FactoredFilter.from_filter(f, min_weight=1e-3, lazy=True, replay=True, gate_out_of_view=False,
                                      bernoulli_lane=bern, fast_path=fast)


def _rfisst(bern, fast=False, seed=0):
    pop = BinomialPopulation([], alpha=BIRTH.r_birth, p_survive=1.0, survival=DECAY)
    # init "best" and 4 completion rounds: every child of these groups (at most 3 returns) is found whatever the
    # chain's draws, so the posterior does not depend on the order the groups draw from the stream
    f = rfisst(MOTION, _sensor(), n_steps=200, init="best", completion_rounds=4,
               population=pop, dt=1.0, max_hypotheses=100, means=X0, covs=np.repeat(CONF[None], len(X0), axis=0),
               seed=seed, gate_probability=0.999)
    return FactoredFilter.from_filter(f, adaptive_birth=BIRTH, min_weight=1e-3, lazy=True, replay=True,
                                      gate_out_of_view=False, bernoulli_lane=bern, fast_path=fast)


def _assert_same(a, b):
    """Every label's hypotheses (weight, mean, covariance) the same to 1e-12: the catalogued labels 0-4 as they are;
    the labels born during the run up to their numbering (with Reid's births seeded at the returns each component's
    step takes new labels in plan order, in which the lane's singletons and the groups come apart), matched by
    their hypotheses."""
    la, lb = hypotheses_by_label(a), hypotheses_by_label(b)
    assert sorted(k for k in la if k < 5) == sorted(k for k in lb if k < 5) and len(la) == len(lb)

    def key(v):
        return (round(sum(w for w, _, _ in v), 9), *np.round(v[0][1], 6))

    pairs = [(la[k], lb[k]) for k in la if k < 5]
    pairs += zip(sorted((v for k, v in la.items() if k >= 5), key=key), sorted((v for k, v in lb.items() if k >= 5), key=key))
    for va, vb in pairs:
        assert len(va) == len(vb)
        for (wa, ma, Pa), (wb, mb, Pb) in zip(va, vb):
            assert wa == pytest.approx(wb, abs=1e-12, rel=0)
            np.testing.assert_allclose(ma, mb, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(Pa, Pb, rtol=1e-12, atol=1e-12)
    pa, pb = a.posterior(), b.posterior()
    assert pa.expected_number == pytest.approx(pb.expected_number, abs=1e-12, rel=0)
    np.testing.assert_allclose(pa.cardinality, pb.cardinality, rtol=0, atol=1e-12)
    ea, eb = a.estimates().labels, b.estimates().labels
    assert sorted(ea[ea < 5].tolist()) == sorted(eb[eb < 5].tolist()) and len(ea) == len(eb)


BUILD = {"homht_kbest": _homht, "rfisst": _rfisst}


@pytest.mark.parametrize("use_fast", [False, True])
@pytest.mark.parametrize("kind", sorted(BUILD))
def test_bernoulli_lane_is_the_general_engine(kind, use_fast):
    """Five catalogued objects (A, E seen with misses, B leaving the view, C with nothing behind it, D out of view)
    and births (HOMHT: seeded at the returns; R-FISST: measurement-driven terms), 12 scans: with Bernoulli singletons
    in the lane each label's hypotheses (weight, mean, covariance), the cardinality and the MAP labels are the general
    engine's to 1e-12, and the lane held tracks of r < 1 and sleeping ones. C is deleted; D, asleep and confirmed,
    decays as p_S^12 = 0.97^12."""
    build = BUILD[kind]
    lane, general, plain = build(True, fast=use_fast), build(False), build(True)
    assert lane._bern and not general._bern  # the lane holds the binomial population's Bernoulli singletons
    assert len(lane.state().lane) == 5 and len(general.state().lane) == 0
    n_unsure = n_asleep = n_fast = 0
    for k in range(1, 13):
        Z = _returns(k)
        lane.step(Z, float(k))
        general.step(Z, float(k))
        plain.step(Z, float(k))
        _assert_same(lane, general)
        assert lane.same_posterior(plain)  # the fast path's results are the general path's, labels included
        n_unsure += int(np.sum(lane.state().lane.r < 1))
        n_asleep += int(lane.last_stats["n_predicted"] < general.last_stats["n_predicted"])
        n_fast += lane.last_stats["n_fast_path"]
        assert lane.last_stats["n_singletons"] >= 3
    assert n_unsure >= 20 and n_asleep >= 10
    assert n_fast >= 10 or not use_fast
    assert 2 not in hypotheses_by_label(lane)  # C deleted
    assert label_existence(lane, 3) == pytest.approx(0.97**12, rel=1e-12)
    assert {0, 1, 3, 4} <= set(lane.estimates().labels.tolist())


def test_rfisst_lane_does_not_depend_on_the_chain_s_draws():
    """The R-FISST comparison above is exact because the search finds every child: two seeds give the same
    posterior to 1e-12."""
    a, b = _rfisst(True, seed=0), _rfisst(True, seed=12345)
    for k in range(1, 13):
        a.step(_returns(k), float(k))
        b.step(_returns(k), float(k))
        _assert_same(a, b)


@pytest.mark.parametrize("use_fast", [False, True])
def test_homht_with_a_validity_test_is_the_general_engine(use_fast):
    """With the engine's validity test (tracks at the clutter return fail it) the seeded-birth children of a lone
    Bernoulli's "missed", "died" and "not" hypotheses carry the newborn track and are dropped with it: the lane (and
    its fast path, which tests them as the general step does) is still the general engine's, labels included."""
    lane, general, plain = (_homht(b, fast=f, validity=_north_east) for b, f in ((True, use_fast), (False, False),
                                                                                (True, False)))
    n_fast = 0
    for k in range(1, 13):
        Z = _returns(k)
        for f in (lane, general, plain):
            f.step(Z, float(k))
        _assert_same(lane, general)
        assert lane.same_posterior(plain)
        n_fast += lane.last_stats["n_fast_path"]
        assert not any(np.any(_north_east(g.store.means) == 0) for g in lane.groups)
    assert n_fast >= 10 or not use_fast

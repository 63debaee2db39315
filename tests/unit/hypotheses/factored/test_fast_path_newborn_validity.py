"""The fast path's validity test of a lone Bernoulli track's "died"/"not" children with a one-Gaussian seeded birth
(HOMHT k-best: Reid's weights, births seeded at the returns, document 001's binomial population with ``p_S < 1``).

The general step of a lone track of ``r p_S < 1`` with one return ``z`` makes, relative to the parent's ``r p_S``,
the children "detected" ``p_D g(z)``, "missed, ``z`` clutter" ``(1 − p_D) λ_C``, "missed, ``z`` a new object"
``(1 − p_D) λ_B`` (the predicted track and the newborn), "died/not, ``z`` clutter" ``e λ_C`` (no track) and
"died/not, ``z`` a new object" ``e λ_B`` (the newborn alone), ``e = (1 − r p_S) / (r p_S)``. The validity test
drops a child whose own tracks fail: with the predicted track invalid and the newborn valid, both missed children go
but "died/not, new object" stays — in the normalisation, and holding the newborn's label. The fast path used the
missed child's verdict (predicted track and newborn) for it, so it dropped that child: it took a track the general
path keeps two hypotheses for, and it counted no label for a newborn the general path numbers.

The scene: one catalogued track at ``x = −0.5`` at rest (``r = 1``, ``p_S = 0.9``), a validity test rejecting
``x ≤ 0``; its return at ``(1, 0)``: the prediction fails, the update (``x ≈ 0.51``) and the newborn (at ``z``) pass.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, homht_kbest
from hypotrack.hypotheses.factored import FactoredFilter
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import hypotheses_by_label, position_sensor

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
MOTION = ConstantVelocity(0.01)
P_D, P_S, R, CLUTTER_RATE = 0.8, 0.9, 0.25, 1.0
X0, P0 = np.array([-0.5, 0.0, 0.0, 0.0]), np.diag([0.5, 0.5, 0.01, 0.01])
Z1 = np.array([[1.0, 0.0]])                 # the track's return: prediction invalid, update and newborn valid
Z2 = np.array([[1.0, 0.0], [50.0, 50.0]])   # then the track again and a return far from it (a newborn's label)
LIGHT, HEAVY = 0.5 / VIEW.area, 0.01        # λ_B: "died + newborn" below / above min_weight after scan 1


def _east(means):
    """Valid east of x = 0."""
    return means[:, 0] > 0


def _east_moving(means):
    """Valid east of x = 0 and moving east: a newborn (at rest) fails too."""
    return (means[:, 0] > 0) & (means[:, 2] > 0)


def _filter(bern, fast, lam_b, validity):
    pop = BinomialPopulation([], alpha=0.0, p_survive=P_S)
    f = homht_kbest(MOTION, position_sensor(R=R, p_D=P_D, view=VIEW, clutter_rate=CLUTTER_RATE), k=20,
                    birth_intensity=lam_b, birth_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0), population=pop,
                    dt=1.0, max_hypotheses=100, means=X0[None], covs=P0[None], seed=0, gate_probability=0.999,
                    validity=validity)
    return FactoredFilter.from_filter(f, min_weight=1e-3, lazy=True, replay=True, gate_out_of_view=False,
                                      bernoulli_lane=bern, fast_path=fast)


def _assert_same(a, b):
    """The same labels, each with the same hypotheses (weight, mean, covariance) to 1e-12, and the same next label."""
    la, lb = hypotheses_by_label(a), hypotheses_by_label(b)
    assert sorted(la) == sorted(lb) and a.next_label == b.next_label
    for k in la:
        assert len(la[k]) == len(lb[k])
        for (wa, ma, Pa), (wb, mb, Pb) in zip(la[k], lb[k]):
            assert wa == pytest.approx(wb, abs=1e-12, rel=0)
            np.testing.assert_allclose(ma, mb, rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(Pa, Pb, rtol=1e-12, atol=1e-12)


def _newborn_weight(lam_b):
    """After scan 1 with λ_B heavy, by hand: the kept children are "detected" ``p_D g(z)`` and "died/not + newborn"
    ``e λ_B`` ("died/not + clutter", ``e λ_C``, is pruned: 3.6e-5 normalised); the newborn's weight
    ``e λ_B / (p_D g(z) + e λ_B)``, ``g`` the 2-D Gaussian of innovation ``(1.5, 0)``, per-axis variance
    ``S = 0.5 + 0.01 + q/3 + R`` (constant velocity, ``dt = 1``, ``q = 0.01``; the velocity variance 0.01)."""
    s = 0.5 + 0.01 + 0.01 / 3 + R
    g = np.exp(-0.5 * 1.5**2 / s) / (2 * np.pi * s)
    e = (1 - P_S) / P_S
    return e * lam_b / (P_D * g + e * lam_b)


@pytest.mark.parametrize("lam_b, validity, fast_takes, labels_used", [
    (LIGHT, _east, True, 2),          # "died + newborn" light: taken, but its newborn numbered (label 1)
    (HEAVY, _east, False, 2),         # "died + newborn" kept: the general path's two hypotheses
    (LIGHT, _east_moving, True, 1),   # the newborn fails too: every alternative but "died + clutter" dropped
])
def test_died_newborn_child_is_tested_on_its_own_track(lam_b, validity, fast_takes, labels_used):
    """The lane with its fast path, the lane without it and the general engine (every track a group) agree to
    1e-12 over two scans, labels included; the fast path takes the track exactly when the general step keeps its
    detected child alone, and uses the labels the general step uses (``next_label`` after scan 1: the catalogued
    track's label 0 and, when "died + newborn" is valid, the newborn's 1; scan 2's newborn at (50, 50) then takes
    the next one). With λ_B heavy the newborn's weight is the hand-computed ``e λ_B / (p_D g + e λ_B)`` = 0.0283."""
    fast, lane, general = _filter(True, True, lam_b, validity), _filter(True, False, lam_b, validity), \
        _filter(False, False, lam_b, validity)
    for k, Z in enumerate((Z1, Z2)):
        for f in (fast, lane, general):
            f.step(Z, float(k + 1))
        _assert_same(fast, general)
        _assert_same(lane, general)
        assert fast.same_posterior(lane)  # bit for bit, labels included
        if k == 0:
            assert fast.last_stats["n_fast_path"] == int(fast_takes)
            assert fast.next_label == labels_used
            held = hypotheses_by_label(general)
            if lam_b == HEAVY:
                assert sorted(held) == [0, 1]
                w = _newborn_weight(lam_b)
                assert w == pytest.approx(0.0283, abs=1e-4)
                assert held[1][0][0] == pytest.approx(w, abs=1e-12, rel=0)
                assert held[0][0][0] == pytest.approx(1 - w, abs=1e-12, rel=0)
                np.testing.assert_allclose(held[1][0][1], [1.0, 0.0, 0.0, 0.0], rtol=0, atol=1e-12)  # at z, at rest
            else:
                assert sorted(held) == [0] and held[0][0][0] == pytest.approx(1.0, abs=1e-12, rel=0)
            assert _east(held[0][0][1][None])[0]  # the update is valid


def test_scan_without_a_lone_track_under_a_validity_test():
    """A scan in which no lane singleton has a lone return (the track's gate is empty; the return at (50, 50)
    starts a newborn) with a validity test and seeded births: the fast path has no candidate (it used to fail
    reshaping the empty newborn array) and the result is the general engine's: the invalid predicted track of
    ``r p_S < 1`` is deleted, the newborn takes label 1 with weight ``λ_B / (λ_B + λ_C) = 1/3``."""
    fast, general = _filter(True, True, LIGHT, _east), _filter(False, False, LIGHT, _east)
    Z = np.array([[50.0, 50.0]])
    fast.step(Z, 1.0)
    general.step(Z, 1.0)
    _assert_same(fast, general)
    held = hypotheses_by_label(fast)
    assert sorted(held) == [1]
    lam_c = CLUTTER_RATE / VIEW.area
    assert held[1][0][0] == pytest.approx(LIGHT / (LIGHT + lam_c), abs=1e-12, rel=0)

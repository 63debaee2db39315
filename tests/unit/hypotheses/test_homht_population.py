"""Reid's HOMHT with a population model (document 000 Eq. 30 births and deaths) on a brute-force oracle.

The scene: two objects (object 0 in view, so it may be missed or die; object 1 out of view, so it is
never detected and, under Eq. 30, cannot die), one birth region (the left half of the field of view)
and m = 4 returns (near object 0, two in the birth region, one in the right half). The oracle below
enumerates every data association (each return on clutter, object 0 or the birth region, no column
twice) times every population event (nothing, one birth detected or not, one death of object 0), and
weighs each child with Reid's product (document 001 Eq. 30/35: ``p_D N(z; H x̂⁻, S)`` per detected
object, ``1 − p_D`` per missed one, the clutter intensity ``λ_C = λV/V`` per clutter return) times
the event's probability (document 000 Eq. 30: ``1 − M_b α − M_d β``, ``α`` or ``β``) times, for a
newborn, ``p_D / V̄`` if its return is in the scan and ``1 − p_D`` if not — written out term by term
with scipy's Gaussian density, independently of the engine.
"""

import itertools

import numpy as np
import pytest
from scipy.special import logsumexp
from scipy.stats import multivariate_normal

from hypotrack.hypotheses import (
    ChildSet,
    ExhaustiveGenerator,
    HypothesisFilter,
    ReidWeights,
    homht,
    homht_kbest,
)
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import H_POSITION, position_sensor, single_event_population

REGION = Box([-50.0, -50.0], [50.0, 50.0])
V = 100.0 * 100.0
BIRTH = Box([-50.0, -50.0], [0.0, 50.0])  # the one birth region: the left half, V̄ = 5000
V_BAR = 50.0 * 100.0
MOTION = ConstantVelocity(0.05)
H = H_POSITION
R = np.eye(2) * 0.5
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [70.0, 0.0, 0.0, 0.0]])  # object 1 at x = 70 > 50: out of view
P0 = np.stack([np.diag([1.0, 1.0, 0.2, 0.2]), np.eye(4)])
# near object 0 (predicted at (1, 0)), two in the birth region, one in the right half (clutter only)
Z = np.array([[1.3, -0.2], [-30.0, 20.0], [-10.0, -40.0], [30.0, 10.0]])
P_D, RATE = 0.8, 2.0
LAM_C = RATE / V


def _sensor():
    return position_sensor(R, P_D, REGION, RATE)


def _population(alpha, beta):
    return single_event_population(alpha, beta, 1, (BIRTH,), np.eye(2) * 4.0)


def oracle(alpha, beta, mutate=None):
    """{(kind, arg, event): log-weight} of every child of the initial parent for scan Z.

    ``mutate`` changes one factor (to show that the comparison has power): ``"birth_p_D"`` drops
    the newborn's ``p_D``, ``"death_beta"`` weighs a death by ``α`` instead of ``β``,
    ``"no_event"`` uses ``1 − α`` (forgets the in-view object's ``β``), ``"clutter"`` uses ``1/V``
    (H-FISST's clutter density) instead of Reid's ``λ_C``.
    """
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    x, P = F @ X0[0], F @ P0[0] @ F.T + Q
    log_g = multivariate_normal(H @ x, H @ P @ H.T + R).logpdf(Z)  # object 0's predictive density
    in_birth = BIRTH.contains(Z)
    p_none = 1.0 - alpha - (0.0 if mutate == "no_event" else beta)  # M_b = 1 region, M_d = 1 in view
    lam_c = 1.0 / V if mutate == "clutter" else LAM_C
    with np.errstate(divide="ignore"):
        log_a, log_b = np.log(alpha), np.log(alpha if mutate == "death_beta" else beta)
    out = {}
    # column codes: -1 clutter, 0 object 0, 1 object 1 (never: out of view), 2 the birth region
    for ev in itertools.product((-1, 0, 2), repeat=len(Z)):
        if ev.count(0) > 1 or ev.count(2) > 1:
            continue
        if any(c == 2 and not in_birth[i] for i, c in enumerate(ev)):
            continue
        detected_birth = 2 in ev
        silent = [None]
        if not detected_birth:
            silent.append("birth")
            if 0 not in ev:
                silent.append("death")
        for s in silent:
            if detected_birth or s == "birth":
                lw = log_a
            elif s == "death":
                lw = log_b
            else:
                lw = np.log(p_none)
            if s != "death":  # object 0 alive: detected or missed (Reid's factors)
                lw += np.log(P_D) + log_g[ev.index(0)] if 0 in ev else np.log(1 - P_D)
            # object 1 is out of view: p_D = 0, its factor 1 - 0 = 1
            for c in ev:
                if c == -1:
                    lw += np.log(lam_c)
                elif c == 2:
                    lw += (0.0 if mutate == "birth_p_D" else np.log(P_D)) - np.log(V_BAR)
            if s == "birth":
                lw += np.log(1 - P_D)
            if not np.isfinite(lw):
                continue
            kind = {None: ChildSet.ASSOCIATION, "birth": ChildSet.UNDETECTED_BIRTH, "death": ChildSet.DEATH}[s]
            out[(kind, {None: -1, "birth": 0, "death": 0}[s], ev)] = lw
    return out


def _engine(filt):
    ch = filt.expand(Z)
    return {(int(k), int(a), tuple(int(e) for e in ev)): float(lw)
            for k, a, ev, lw in zip(ch.kind, ch.arg, ch.events, ch.log_weights)}


def _normalised(d):
    total = logsumexp(list(d.values()))
    return {k: v - total for k, v in d.items()}


def _homht(alpha, beta, max_hypotheses=10**6):
    return homht(MOTION, _sensor(), population=_population(alpha, beta), max_hypotheses=max_hypotheses, means=X0,
                 covs=P0, seed=0)


def _max_gap(a, b):
    if a.keys() != b.keys():
        return np.inf
    na, nb = _normalised(a), _normalised(b)
    return max(abs(na[k] - nb[k]) for k in na)


ALPHA, BETA = 0.02, 0.1


def test_every_child_weighs_reids_product_times_the_event_probability():
    want = oracle(ALPHA, BETA)
    got = _engine(_homht(ALPHA, BETA))
    assert got.keys() == want.keys()
    # 5 associations without a birth (object 0 on one of the 4 returns or missed; each has an undetected-birth
    # twin, the one with object 0 missed also a death twin) + 8 with the detected birth (on return 1 or 2,
    # object 0 on one of the 3 others or missed): 5 + 5 + 1 + 8 = 19 children
    assert len(want) == 19
    kinds = [k for k, _, _ in want]
    assert (kinds.count(ChildSet.UNDETECTED_BIRTH), kinds.count(ChildSet.DEATH)) == (5, 1)
    assert _max_gap(got, want) < 1e-12
    for key, lw in want.items():  # not only after normalising: the same absolute weights
        assert got[key] == pytest.approx(lw, abs=1e-12), key


@pytest.mark.parametrize("mutate", ["birth_p_D", "death_beta", "no_event", "clutter"])
def test_the_comparison_fails_when_one_factor_is_changed(mutate):
    """The oracle comparison has power: each wrong factor moves some child's probability by far more
    than the comparison's tolerance (checked by hand: e.g. without the newborn's p_D the 8
    detected-birth children are each 1/0.8 heavier, before normalising)."""
    got = _engine(_homht(ALPHA, BETA))
    wrong = oracle(ALPHA, BETA, mutate=mutate)
    assert wrong.keys() == got.keys()
    assert _max_gap(got, wrong) > 1e-3


def test_by_hand_two_children():
    """Two weights written out as numbers: the death of object 0 with every return clutter, and the
    detected birth at return 1 with object 0 at return 0 and returns 2, 3 clutter."""
    got = _engine(_homht(ALPHA, BETA))
    death = got[(ChildSet.DEATH, 0, (-1, -1, -1, -1))]
    assert death == pytest.approx(np.log(BETA) + 4 * np.log(2.0 / 1e4), abs=1e-12)
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    S = H @ (F @ P0[0] @ F.T + Q) @ H.T + R
    d = Z[0] - H @ F @ X0[0]
    g = np.exp(-0.5 * d @ np.linalg.solve(S, d)) / (2 * np.pi * np.sqrt(np.linalg.det(S)))
    birth = got[(ChildSet.ASSOCIATION, -1, (0, 2, -1, -1))]
    assert birth == pytest.approx(np.log(ALPHA * P_D * g * P_D / 5000.0 * (2.0 / 1e4) ** 2), abs=1e-12)


def test_without_births_and_deaths_the_weights_are_the_fixed_number_homhts_exactly():
    with_pop = _homht(0.0, 0.0)
    fixed = homht(MOTION, _sensor(), max_hypotheses=10**6, means=X0, covs=P0, seed=0)
    a, b = _engine(with_pop), _engine(fixed)
    assert a == b  # the same children, bitwise the same weights: no birth or death child survives
    assert len(a) == 5 and all(k == ChildSet.ASSOCIATION for k, _, _ in a)
    # and over scans: the same hypotheses, weights and estimates
    with_pop = _homht(0.0, 0.0, max_hypotheses=10)
    fixed = homht(MOTION, _sensor(), max_hypotheses=10, means=X0, covs=P0, seed=0)
    rng = np.random.default_rng(5)
    for _ in range(4):
        scan = np.vstack([Z[:1] + rng.normal(0, 0.5, (1, 2)), rng.uniform(-50, 50, (2, 2))])
        pa, pb = with_pop.step(scan), fixed.step(scan)
        np.testing.assert_array_equal(pa.log_weights, pb.log_weights)
        np.testing.assert_array_equal(with_pop.estimates().x, fixed.estimates().x)


def test_a_binomial_population_falls_out_too():
    """Document 001's binomial births (Eq. 31–33) and survival (Eq. 59) with Reid's factors: a child
    with one detected birth and no death weighs α (1 − α)^0 p_S² × p_D / V̄ relative to the same
    association's objects' factors; checked against the single-event weights on the same child."""
    from hypotrack.hypotheses import BinomialPopulation

    pop = BinomialPopulation([UniformBirthDensity(BIRTH, np.eye(2) * 4.0)], alpha=ALPHA, p_survive=0.9)
    f = homht(MOTION, _sensor(), population=pop, max_hypotheses=10**6, means=X0, covs=P0, seed=0)
    got = _engine(f)
    single = oracle(ALPHA, BETA)
    key_birth, key_none = (ChildSet.ASSOCIATION, -1, (0, 2, -1, -1)), (ChildSet.ASSOCIATION, -1, (0, -1, -1, -1))
    # binomial: birth α p_S², no birth (1 − α) p_S²; single event: α and 1 − α − β
    assert got[key_birth] - single[key_birth] == pytest.approx(2 * np.log(0.9), abs=1e-12)
    assert got[key_none] - single[key_none] == pytest.approx(np.log((1 - ALPHA) * 0.81 / (1 - ALPHA - BETA)),
                                                             abs=1e-12)


def test_k_best_with_the_population_returns_the_exact_best_children():
    want = oracle(ALPHA, BETA)
    assoc = sorted((lw for (k, _, _), lw in want.items() if k == ChildSet.ASSOCIATION), reverse=True)
    f = homht_kbest(MOTION, _sensor(), k=5, population=_population(ALPHA, BETA), max_hypotheses=10**6,
                    means=X0, covs=P0, seed=0)
    got = _engine(f)
    got_assoc = sorted((lw for (k, _, _), lw in got.items() if k == ChildSet.ASSOCIATION), reverse=True)
    np.testing.assert_allclose(got_assoc, assoc[:5], atol=1e-12)
    for key, lw in got.items():
        assert lw == pytest.approx(want[key], abs=1e-12), key


def test_two_birth_models_at_once_are_refused():
    birth = UniformBirthDensity(BIRTH, np.eye(2) * 4.0)
    with pytest.raises(ValueError, match="birth_intensity must be 0 when population has birth regions"):
        homht(MOTION, _sensor(), birth_intensity=1e-4, birth_density=birth, population=_population(ALPHA, BETA))
    with pytest.raises(ValueError, match="birth_intensity must be 0"):
        homht_kbest(MOTION, _sensor(), birth_intensity=1e-4, birth_density=birth,
                    population=_population(ALPHA, BETA))
    # the weight model itself refuses a scan with birth regions when it seeds births
    f = HypothesisFilter(MOTION, _sensor(), ReidWeights(), ExhaustiveGenerator(), population=_population(ALPHA, BETA),
                         means=X0, covs=P0)
    seeded = ReidWeights(birth_intensity=1e-4, birth_density=birth)
    ctx = f.scan_context(f.store.predict(MOTION, 1.0), Z)
    with pytest.raises(ValueError, match="birth_intensity = 0.0001 > 0"):
        seeded.problem(ctx, np.arange(2))

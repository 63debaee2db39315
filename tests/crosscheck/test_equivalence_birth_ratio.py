"""(e) Document 001 Eq. 39 in the engine's own weights.

With document 001's binomial birth in its Poisson limit (Eq. 33) and FISST weights (Eq. 6–7, 29,
34), a hypothesis with one undetected birth and its twin without that birth (same parent, same
data association, same other births) have weights in the ratio ``(1 − p_D) α`` (Eq. 39) — for
twins without detected births and for twins that also hold a detected birth (Eq. 37–38 with
``s`` detected births). Document 000's single-event model gives ``(1 − p_D) α / (1 − M_b α − M_d β)``.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import ChildSet, ExhaustiveGenerator, FISSTPoissonWeights, HFISSTWeights, HypothesisFilter
from hypotrack.hypotheses.population_events import BinomialPopulation, SingleEventPopulation
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

P_D = 0.9
ALPHA = 2e-3
REGION = Box([0.0, 0.0], [40.0, 40.0])
PIXELS = [Box([0.0, 0.0], [12.0, 40.0]), Box([12.0, 0.0], [24.0, 40.0]), Box([24.0, 0.0], [40.0, 40.0])]
X0 = np.array([[5.0, 5.0, 1.0, 0.0], [30.0, 30.0, 0.0, -1.0]])
P0 = np.repeat(np.eye(4)[None], 2, axis=0)
# two returns near the targets, one in each pixel far from both (a candidate birth)
Z = np.array([[6.2, 5.1], [29.8, 29.0], [15.0, 35.0], [35.0, 10.0]])


def make_filter(weights, population):
    sensor = position_sensor(1.0, P_D, REGION, 0.5)
    return HypothesisFilter(ConstantVelocity(0.1), sensor, weights, ExhaustiveGenerator(), population=population,
                            max_hypotheses=10**6, means=X0, covs=P0)


def twin_log_ratios(children, n_objects):
    """log(w_undetected-birth / w_twin) for every undetected-birth child, with the number of
    detected births of the pair."""
    base = {(p, ev.tobytes()): w for p, ev, k, w in
            zip(children.parent, children.events, children.kind, children.log_weights) if k == ChildSet.ASSOCIATION}
    ratios, detected_births = [], []
    for p, ev, k, w in zip(children.parent, children.events, children.kind, children.log_weights):
        if k == ChildSet.UNDETECTED_BIRTH:
            ratios.append(w - base[(p, ev.tobytes())])
            detected_births.append(int(np.sum(ev >= n_objects)))
    return np.array(ratios), np.array(detected_births)


def densities():
    return [UniformBirthDensity(px, np.eye(2)) for px in PIXELS]


def test_e_undetected_birth_ratio_is_one_minus_pd_times_alpha():
    pop = BinomialPopulation(densities(), alpha=ALPHA, poisson_limit=True)
    f = make_filter(FISSTPoissonWeights(), pop)
    ratios, births = twin_log_ratios(f.expand(Z), n_objects=2)
    assert len(ratios) > 50 and set(births) == {0, 1, 2}  # pairs with 0, 1 and 2 detected births
    np.testing.assert_allclose(ratios, np.log((1 - P_D) * ALPHA), rtol=0, atol=1e-12)


def test_e_single_event_model_ratio():
    model = SingleEventBirthDeath(ALPHA, 1e-4, 3)
    pop = SingleEventPopulation(model, birth_densities=densities())
    f = make_filter(HFISSTWeights(), pop)
    ratios, births = twin_log_ratios(f.expand(Z), n_objects=2)
    assert len(ratios) > 10 and set(births) == {0}  # Eq. 30: at most one birth, so none detected
    p_no_event = 1 - 3 * ALPHA - 2 * 1e-4  # both objects are in view
    np.testing.assert_allclose(ratios, np.log((1 - P_D) * ALPHA / p_no_event), rtol=0, atol=1e-12)


def test_single_event_children_match_seed000_count():
    """Document 000 Sec. II-C: A(M,m) + M_b A(M+1,m) + M_d A(M-1,m) children when every return can
    be a birth in every region (two regions covering the whole field of view)."""
    from hypotrack.association import count_children

    model = SingleEventBirthDeath(ALPHA, 1e-4, 2)
    pop = SingleEventPopulation(model, birth_densities=[UniformBirthDensity(REGION, np.eye(2))] * 2)
    f = make_filter(HFISSTWeights(), pop)
    children = f.expand(Z)
    assert len(children) == count_children(2, len(Z), 2, 2)
    assert len({(p, k, a, e.tobytes()) for p, k, a, e in
                zip(children.parent, children.kind, children.arg, children.events)}) == len(children)


def test_binomial_population_bad_input():
    with pytest.raises(ValueError, match="alpha"):
        BinomialPopulation(densities(), alpha=1.0)
    with pytest.raises(ValueError, match="p_survive"):
        BinomialPopulation(densities(), alpha=0.1, p_survive=0.0)

"""The populations' own methods for their birth terms and cache: ``restricted_to``,
``with_birth_terms``, ``clear_cache``."""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, GaussianBirthTerm, LabeledMultiBernoulliPopulation
from hypotrack.hypotheses.factored_groups import restrict_population
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box

H = np.hstack([np.eye(2), np.zeros((2, 2))])
R = np.eye(2) * 0.5


def _terms(n):
    return [GaussianBirthTerm(np.array([float(i), 0.0, 0.0, 0.0]), np.eye(4), H, R) for i in range(n)]


def test_restricted_to_keeps_the_chosen_terms_and_their_existence():
    pop = LabeledMultiBernoulliPopulation(_terms(3), r_birth=[0.1, 0.2, 0.3], p_survive=0.9)
    sub = pop.restricted_to([2, 0])
    assert sub.birth_densities == (pop.birth_densities[2], pop.birth_densities[0])
    assert sub.r_birth.tolist() == [0.3, 0.1] and sub.p_survive == 0.9
    assert pop.r_birth.tolist() == [0.1, 0.2, 0.3] and pop.n_birth_regions == 3  # unchanged
    assert pop.restricted_to([0, 1, 2]) is pop and restrict_population(pop, [0, 1, 2]) is pop
    assert restrict_population(None, [0]) is None
    Z = np.array([[2.0, 0.1], [0.0, -0.2]])
    np.testing.assert_array_equal(sub.birth_loglik(Z), pop.birth_loglik(Z)[:, [2, 0]])


def test_a_restricted_population_shares_the_undetected_birth_cache():
    """Document 001 regions: the moment-matched undetected birth of region 1 computed through a
    restriction is the full population's (one computation per region and scan, not per group)."""
    regions = [UniformBirthDensity(Box([0.0, 0.0], [10.0, 10.0]), np.eye(2) * 0.5) for _ in range(2)]
    pop = BinomialPopulation(regions, alpha=0.01)
    sub = pop.restricted_to([1])
    mean, cov = sub.birth_track(0, None, R)
    assert 1 in pop.undetected_cache and pop.undetected_cache[1][0] is mean
    assert pop.birth_track(1, None, R)[1] is cov
    pop.clear_cache()
    assert pop.undetected_cache == {} and pop.birth_track(1, None, R)[0] is not mean


def test_with_birth_terms_makes_a_new_population():
    pop = LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0)
    new = pop.with_birth_terms(_terms(2), r_birth=0.01)
    assert new.n_birth_regions == 2 and new.r_birth.tolist() == [0.01, 0.01] and pop.n_birth_regions == 0
    with pytest.raises(ValueError, match="r_birth is required"):
        pop.with_birth_terms(_terms(1))
    with pytest.raises(ValueError, match="r_birth"):
        pop.with_birth_terms(_terms(1), r_birth=1.0)
    binomial = BinomialPopulation([], alpha=0.2)
    assert binomial.with_birth_terms(_terms(3), r_birth=0.9).n_birth_regions == 3  # its alpha, not r_birth

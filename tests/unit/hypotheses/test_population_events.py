"""Population events as the engine uses them: event probabilities and twin log-ratios by hand
(document 000 Eq. 30, document 001 Eq. 31–33, 39, 59)."""

import math
import warnings

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation
from hypotrack.hypotheses.population_events import SingleEventPopulation
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box

HALVES = [Box([-10.0, -10.0], [0.0, 10.0]), Box([0.0, -10.0], [10.0, 10.0])]
DENSITIES = [UniformBirthDensity(h, np.eye(2)) for h in HALVES]


def test_single_event_probabilities_and_ratios_by_hand():
    pop = SingleEventPopulation(SingleEventBirthDeath(0.02, 0.05, 2), birth_densities=DENSITIES)
    none = math.log(1 - 2 * 0.02 - 3 * 0.05)  # three objects in view (of five)
    np.testing.assert_allclose(pop.log_event_prob(3, 5), [none, math.log(0.02), -np.inf])
    np.testing.assert_allclose(pop.undetected_birth_log_ratio(3, 5), [math.log(0.02) - none, -np.inf, -np.inf])
    np.testing.assert_allclose(pop.death_log_ratio(3, 5), [math.log(0.05) - none, -np.inf, -np.inf])
    np.testing.assert_array_equal(pop.death_eligible(np.array([True, False, True])), [True, False, True])


def test_binomial_probabilities_and_ratios_by_hand():
    """Two pixels, α = 0.1, p_s = 0.8, four objects: P(b births) = α^b (1 − α)^(2−b) p_s^4; the
    undetected-birth ratio is α / (1 − α) while a pixel is free; death (1 − p_s) / p_s for any b."""
    pop = BinomialPopulation(DENSITIES, alpha=0.1, p_survive=0.8)
    surv = 4 * math.log(0.8)
    want = [2 * math.log(0.9) + surv, math.log(0.1) + math.log(0.9) + surv, 2 * math.log(0.1) + surv]
    np.testing.assert_allclose(pop.log_event_prob(1, 4), want, rtol=1e-14)
    r = math.log(0.1 / 0.9)
    np.testing.assert_allclose(pop.undetected_birth_log_ratio(1, 4), [r, r, -np.inf], rtol=1e-14)
    np.testing.assert_allclose(pop.death_log_ratio(1, 4), np.full(3, math.log(0.2 / 0.8)), rtol=1e-14)
    np.testing.assert_array_equal(pop.death_eligible(np.array([True, False])), [True, True])


def test_binomial_poisson_limit_eq33_and_eq39():
    """Poisson limit: P(b) = e^{−M_b α} α^b (Eq. 33), so the undetected-birth ratio is exactly α (Eq. 39)."""
    pop = BinomialPopulation(DENSITIES, alpha=0.1, p_survive=1.0, poisson_limit=True)
    np.testing.assert_allclose(pop.log_event_prob(0, 0), [-0.2, math.log(0.1) - 0.2, 2 * math.log(0.1) - 0.2],
                               rtol=1e-14)
    np.testing.assert_allclose(pop.undetected_birth_log_ratio(0, 0), [math.log(0.1), math.log(0.1), -np.inf],
                               rtol=1e-14)


def test_impossible_events_are_minus_infinity_without_warnings():
    """α = 0 (no birth) and p_s = 1 (no death): ratios are −inf, never NaN, and no divide warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pop = BinomialPopulation(DENSITIES, alpha=0.0, p_survive=1.0)
        np.testing.assert_array_equal(pop.undetected_birth_log_ratio(0, 2), [-np.inf] * 3)
        np.testing.assert_array_equal(pop.death_log_ratio(0, 2), [-np.inf] * 3)
        np.testing.assert_allclose(pop.log_event_prob(0, 2), [0.0, -np.inf, -np.inf])


def test_binomial_bad_object_count():
    with pytest.raises(ValueError) as info:
        BinomialPopulation(DENSITIES, alpha=0.1).log_event_prob(0, -1)
    assert str(info.value) == "n_objects must be an integer in [0, inf], got -1"


def test_single_event_death_eligibility_reads_flags_as_a_mask():
    """0/1 in-view flags are a boolean mask: its complement (the objects that may not die) is
    the out-of-view ones, not a bitwise complement of integers."""
    pop = SingleEventPopulation(SingleEventBirthDeath(0.02, 0.05, 2), birth_densities=DENSITIES)
    elig = pop.death_eligible([1, 0, 1])
    assert elig.dtype == bool
    np.testing.assert_array_equal(~elig, [False, True, False])


def test_single_event_population_needs_one_density_per_region():
    with pytest.raises(ValueError) as info:
        SingleEventPopulation(SingleEventBirthDeath(0.02, 0.05, 2), birth_densities=DENSITIES[:1])
    assert str(info.value) == "birth_densities must hold n_birth_regions = 2 densities, got 1"

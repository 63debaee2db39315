"""δ-GLMB pieces against hand values and brute-force enumeration of association maps
(population_lmb, weights_glmb, gibbs)."""

import numpy as np
import pytest

from hypotrack.hypotheses import LabeledMultiBernoulliPopulation


def test_log_existence_is_survival_for_tracks_and_birth_probability_for_terms():
    pop = LabeledMultiBernoulliPopulation([None, None], r_birth=[0.1, 0.3], p_survive=0.8)
    log_r, log_not = pop.log_existence(3)
    np.testing.assert_allclose(log_r, np.log([0.8, 0.8, 0.8, 0.1, 0.3]), rtol=0, atol=1e-15)
    np.testing.assert_allclose(log_not, np.log([0.2, 0.2, 0.2, 0.9, 0.7]), rtol=0, atol=1e-15)

"""The engine's 1-D log-sum-exp against SciPy's, on the cases where a shortcut would differ."""

import numpy as np
import pytest
from scipy.special import logsumexp as scipy_logsumexp

from hypotrack._logspace import logsumexp


@pytest.mark.parametrize("a", [[0.0], [np.log(2.0), np.log(3.0)], [-1000.0, -1001.0, -1002.5], [700.0, 710.0],
                               [-np.inf, 0.5], [-np.inf, -np.inf]])
def test_equals_scipy(a):
    assert logsumexp(np.array(a)) == pytest.approx(float(scipy_logsumexp(a)), abs=1e-12, rel=1e-14)


def test_by_hand_and_edge_cases():
    assert logsumexp([np.log(2.0), np.log(3.0)]) == pytest.approx(np.log(5.0), abs=1e-15)
    assert logsumexp(np.zeros(0)) == -np.inf  # an empty sum is 0
    assert logsumexp([np.inf, 0.0]) == np.inf
    assert logsumexp([-1000.0, -1000.0]) == pytest.approx(-1000.0 + np.log(2.0), abs=1e-12)  # no underflow

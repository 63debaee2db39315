"""The vectorised two-target MOSPA of Table 6.1 against hypotrack.metrics.ospa (peer code path)."""

import numpy as np
import pytest

from hypotrack.metrics import ospa
from hypotrack.trackers.ecmht import mospa_two_targets


def test_mospa_is_the_squared_ospa_of_order_2_without_cut_off():
    rng = np.random.default_rng(11)
    est, truth = rng.normal(size=(200, 2)), rng.normal(size=(200, 2))
    got = mospa_two_targets(est, truth)
    # a cut-off larger than any distance makes OSPA's cut-off inactive (reconstruction §5.4)
    want = np.array([ospa(est[i], truth[i], c=1e6, p=2) ** 2 for i in range(200)])
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-14)
    assert mospa_two_targets([[1.0, 1.0]], [[1.0, 1.0]])[0] == pytest.approx(0.0)

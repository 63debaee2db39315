"""M-of-N initiation from a birth mixture: one tentative track per component, at most one confirmed per return
chain (the best-scored sibling), siblings leaving the admissible set dropped. Hand-computed on a 2-D constant-
velocity case where the two components of one return each catch a return of the next scan."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.trackers import MOfNInitiator, ScanModel

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
R = np.eye(2) * 0.01


class TwoWay:
    """Components at the return with velocity (+1, 0) and (−1, 0), weights ``w``; optionally an admissible set."""

    def __init__(self, w, admissible=None):
        self.w = np.asarray(w, dtype=float)
        if admissible is not None:
            self.admissible = admissible

    def components(self, z):
        means = np.array([[z[0], z[1], 1.0, 0.0], [z[0], z[1], -1.0, 0.0]])
        return self.w.copy(), means, np.stack([np.diag([0.01, 0.01, 0.01, 0.01])] * 2)


def _run(mixture, m=2):
    init = MOfNInitiator(ConstantVelocity(1e-6), ScanModel(H, R, 0.9, 0.999, 1e-3, 1e-4), m=m, n=3, mixture=mixture)
    x0, _ = init.step(0.0, [[0.0, 0.0]])
    assert len(x0) == 0 and len(init) == 2 and init.family.tolist() == [0, 0]
    np.testing.assert_allclose(init.score, np.log(mixture.w))
    x1, P1 = init.step(1.0, [[1.0, 0.0], [-1.0, 0.0]])  # each sibling's prediction meets one return exactly
    return init, x1, P1


@pytest.mark.parametrize("w, vx", [([0.7, 0.3], 1.0), ([0.3, 0.7], -1.0)])
def test_both_siblings_confirm_and_only_the_heavier_is_output(w, vx):
    init, x, _ = _run(TwoWay(w))
    # equal gains (zero innovation, equal covariances): the score is decided by log w_c
    assert len(x) == 1
    np.testing.assert_allclose(x[0], [vx, 0.0, vx, 0.0], atol=1e-12)
    assert len(init) == 0  # the family is gone; the two returns were used, so no new family


def test_a_sibling_leaving_the_admissible_set_is_dropped():
    init, x, _ = _run(TwoWay([0.3, 0.7], admissible=lambda X: X[:, 2] > 0))
    assert len(x) == 1 and x[0][2] == pytest.approx(1.0)  # the lighter, admissible sibling confirms
    assert len(init) == 0


def test_one_of_n_confirms_one_component_per_return_at_once():
    init = MOfNInitiator(ConstantVelocity(1e-6), ScanModel(H, R, 0.9, 0.999, 1e-3, 1e-4), m=1, n=1,
                         mixture=TwoWay([0.4, 0.6]))
    x, _ = init.step(0.0, [[0.0, 0.0], [5.0, 5.0]])
    np.testing.assert_allclose(x[:, 2], [-1.0, -1.0])  # per return, the heavier component
    np.testing.assert_allclose(x[:, :2], [[0.0, 0.0], [5.0, 5.0]])
    assert len(init) == 0


def test_mixture_must_have_components():
    with pytest.raises(TypeError, match=r"^mixture must have components\(z\) -> \(weights, means, covs\), got int$"):
        MOfNInitiator(ConstantVelocity(1.0), ScanModel(H, R, 0.9, 0.999, 1e-3), mixture=3)

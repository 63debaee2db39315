"""A track whose prediction diverged (innovation covariance not positive definite) takes no return and is not
missed; the scan goes on and the other objects' posterior is the one without it.

Three returns in the gates of two tracks (labels 0 and 1, at x = 1 and 4 after the prediction); a third
track (label 2, at x = 60, outside the view) whose motion model's Jacobian maps its covariance onto one huge
direction: ``S`` is numerically singular, and scoring it used to abort the scan."""

import numpy as np
import pytest
from scenes import position_sensor

from hypotrack.hypotheses import ExhaustiveGenerator, FactoredFilter, ReidWeights
from hypotrack.hypotheses.factored.planner import scorable
from hypotrack.models.motion import ConstantVelocity


class Diverging(ConstantVelocity):
    """Constant velocity, except that a state beyond x = 50 gets a degenerate, huge Jacobian."""

    def transition(self, x, dt):
        xp, F = super().transition(x, dt)
        F = np.array(np.broadcast_to(F, (len(x),) + F.shape[-2:]))
        far = x[:, 0] > 50.0
        F[far, :2, :2] = [[1e10, 1e10], [1e10, 1e10 + 1e-3]]
        return xp, F


MOTION = Diverging(q=0.05)
SENSOR = position_sensor(R=0.5, p_D=0.9)
X = np.array([[0.0, 0.0, 1.0, 0.0], [3.0, 0.0, 1.0, 0.0], [60.0, 0.0, 1.0, 0.0]])
Z = np.array([[1.0, 0.1], [2.2, -0.2], [1.6, 0.3]])


def _step(n):
    f = FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=X[:n],
                       covs=np.repeat(np.eye(4)[None], n, 0), labels=np.arange(n), gate_probability=0.99)
    f.step(Z, 1.0)
    return f


def test_scorable_by_hand():
    S = np.repeat(np.eye(2)[None], 4, 0)
    S[1] = [[2e20, 2e20], [2e20, 2e20]]  # singular to working precision
    S[2, 0, 0] = np.inf
    S[3] = [[1.0, 2.0], [2.0, 1.0]]  # indefinite: eigenvalues 3 and -1
    assert scorable(S).tolist() == [True, False, False, False]
    assert scorable(np.zeros((0, 2, 2))).tolist() == []


def test_diverged_track_takes_no_return_and_the_others_are_as_without_it():
    f3, f2 = _step(3), _step(2)
    g3 = {tuple(g.labels.tolist()): g for g in f3.groups}
    g2 = {tuple(g.labels.tolist()): g for g in f2.groups}
    assert (0, 1) in g3 and (0, 1) in g2 and (2,) in g3  # 0 and 1 share the three returns; 2 alone
    a, b = g3[(0, 1)], g2[(0, 1)]
    assert len(a.log_w) == len(b.log_w) > 6
    np.testing.assert_allclose(np.sort(a.log_w), np.sort(b.log_w), atol=1e-12)
    np.testing.assert_allclose(a.store.means[np.lexsort(a.store.means.T)], b.store.means[np.lexsort(b.store.means.T)],
                               atol=1e-12)
    (h,) = g3[(2,)].tracks  # one hypothesis: the diverged track, not updated
    assert g3[(2,)].store.means[h[0], 0] == pytest.approx(61.0)

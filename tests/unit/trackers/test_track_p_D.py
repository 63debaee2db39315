"""GNN/JPDA with a state-dependent p_D (``detection.p_D_of`` through the registry): hand-computed PDA weights."""

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import chi2, multivariate_normal

from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.registry import TrackingProblem, build
from hypotrack.trackers._sht_common import ScanModel, with_track_p_D

MEANS = np.array([[0.0, 0, 1, 0], [20, 0, -1, 0]])
Z = np.array([[1.8, 0.5], [19.5, -0.4]])
P_G = 0.99


class _ByX:
    """p_D 0.3 left of x = 5, else 0.95."""

    def __init__(self, base):
        self.p_D, self._base = base.p_D, base

    def in_view(self, z):
        return self._base.in_view(z)

    def p_D_of(self, means):
        return np.where(np.asarray(means)[:, 0] < 5, 0.3, 0.95)


def _problem(state_dependent):
    s = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4, position_indices=(0, 1)),
               DetectionModel(0.9), PoissonClutter(2.0, Box([-50, -50], [50, 50])))
    if state_dependent:
        s = SimpleNamespace(measurement=s.measurement, detection=_ByX(s.detection), clutter=s.clutter)
    return TrackingProblem(ConstantVelocity(0.1), s, means=MEANS, covs=np.stack([np.eye(4)] * 2))


def _beta_oracle(p):
    """PDA weights of each track (its own return only in its gate): missed 1 − p P_G, detected p N(z; ẑ, S)/β_FA."""
    F = np.eye(4)
    F[0, 2] = F[1, 3] = 1.0
    Q = 0.1 * np.kron([[1 / 3, 1 / 2], [1 / 2, 1]], np.eye(2))
    S = (F @ F.T + Q)[:2, :2] + np.eye(2)
    beta_fa = 2.0 / 100**2
    out = []
    for j, x in enumerate(MEANS @ F.T):
        miss, det = 1 - p[j] * P_G, p[j] * multivariate_normal(x[:2], S).pdf(Z[j]) / beta_fa
        out.append([miss / (miss + det), det / (miss + det)])
    return np.array(out)


@pytest.mark.parametrize("state_dependent", [False, True])
def test_jpda_weights_with_state_dependent_p_D(state_dependent):
    tracker = build({"kind": "jpda", "gate_probability": P_G, "m_of_n": None}, _problem(state_dependent), seed=0)
    tracker.step(Z, 1.0)
    # each return lies in its own track's gate only (d^2 far above chi2(0.99, 2) = 9.21 for the other)
    assert tracker.last_gated.valid.tolist() == [[True, False], [False, True]]
    beta = np.asarray(tracker.last_association)
    oracle = _beta_oracle([0.3, 0.95] if state_dependent else [0.9, 0.9])
    assert beta[:, [0, 1]][0] == pytest.approx(oracle[0], rel=1e-9)
    assert beta[1, [0, 2]] == pytest.approx(oracle[1], rel=1e-9)


def test_gnn_gain_uses_each_tracks_p_D():
    model = ScanModel(np.eye(2, 4), np.eye(2), 0.9, P_G, 2e-4)
    per = with_track_p_D(model, [0.3, 0.95])
    assert per.log_missed.tolist() == pytest.approx([np.log(1 - 0.3 * P_G), np.log(1 - 0.95 * P_G)], rel=1e-12)
    assert model.log_missed == pytest.approx(np.log(1 - 0.9 * P_G), rel=1e-12)
    with pytest.raises(ValueError, match="p_D per track"):
        with_track_p_D(model, [0.0, 0.5])
    assert chi2.ppf(P_G, 2) == pytest.approx(model.gate)


def test_gnn_registry_build_takes_the_hook():
    tracker = build({"kind": "gnn", "gate_probability": P_G, "m_of_n": None}, _problem(True), seed=0)
    assert tracker.p_detect is not None
    plain = build({"kind": "gnn", "gate_probability": P_G, "m_of_n": None}, _problem(False), seed=0)
    assert plain.p_detect is None

"""State-dependent p_D (``detection.p_D_of``): hand-computed HOMHT weights, the factored engine the same,
constant p_D untouched."""

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack.hypotheses.detection import state_p_detect
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.registry import TrackingProblem, build

MEANS = np.array([[0.0, 0, 1, 0], [10, 0, -1, 0], [30, 0, 0, 0]])
Z = np.array([[1.1, 0.2], [9.0, -0.1]])


class _ByX:
    """p_D 0.3 left of x = 5, 0.6 beyond x = 20, else 0.9 (a stand-in for a range-dependent p_D)."""

    def __init__(self, base):
        self.p_D, self._base = base.p_D, base

    def in_view(self, z):
        return self._base.in_view(z)

    def p_D_of(self, means):
        x = np.asarray(means)[:, 0]
        return np.where(x < 5, 0.3, np.where(x > 20, 0.6, 0.9))


def _sensor(state_dependent):
    s = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4, position_indices=(0, 1)),
               DetectionModel(0.9), PoissonClutter(2.0, Box([-50, -50], [50, 50])))
    if not state_dependent:
        return s
    return SimpleNamespace(measurement=s.measurement, detection=_ByX(s.detection), clutter=s.clutter)


def _oracle(p):
    """Reid's weights of the hypotheses (z0 -> a, z1 -> b) by hand: p_D N(z; H x, S) for a detection,
    (1 - p_D) for a miss, kappa = 2/100^2 for a false return."""
    F = np.eye(4)
    F[0, 2] = F[1, 3] = 1.0
    Q = 0.1 * np.kron([[1 / 3, 1 / 2], [1 / 2, 1]], np.eye(2))  # q [[dt^3/3, dt^2/2], [dt^2/2, dt]], dt = 1
    P = F @ np.eye(4) @ F.T + Q
    S = P[:2, :2] + np.eye(2)
    xs = MEANS @ F.T
    kappa = 2.0 / 100**2
    g = np.array([[multivariate_normal(x[:2], S).pdf(z) for x in xs] for z in Z])
    out = {}
    for a in (-1, 0, 1, 2):
        for b in (-1, 0, 1, 2):
            if a >= 0 and a == b:
                continue
            w = kappa ** ((a < 0) + (b < 0))
            for j in range(3):
                used = [i for i, t in enumerate((a, b)) if t == j]
                w *= p[j] * g[used[0], j] if used else 1 - p[j]
            out[(a, b)] = w
    tot = sum(out.values())
    K = P[:, :2] @ np.linalg.inv(S)
    upd = xs[None, :, :] + (Z[:, None, :] - xs[None, :, :2]) @ K.T  # (return, track, 4): Kalman-updated means
    return {k: v / tot for k, v in out.items()}, upd


@pytest.mark.parametrize("state_dependent", [False, True])
@pytest.mark.parametrize("factored", [False, True])
def test_reid_weights_with_state_dependent_p_D(state_dependent, factored):
    p = [0.3, 0.9, 0.6] if state_dependent else [0.9, 0.9, 0.9]
    problem = TrackingProblem(ConstantVelocity(0.1), _sensor(state_dependent), means=MEANS,
                              covs=np.stack([np.eye(4)] * 3), labels=[0, 1, 2])
    spec = {"kind": "homht", "max_hypotheses": 1000, "population": False}
    if factored:
        spec["factored"] = {"split": "exact"}
    tracker = build(spec, problem, seed=1)
    tracker.step(Z, 1.0)
    oracle, upd = _oracle(p)
    hyps = tracker.joint_hypotheses() if factored else tracker.posterior(n_top=1000).top
    got = {}
    for h in hyps:
        # which label each return updated: the track whose mean is its Kalman update with that return
        a_b = []
        for i in range(len(Z)):
            hit = [int(lab) for lab, x in zip(h.labels, h.means) if np.allclose(x, upd[i, int(lab)], atol=1e-9)]
            a_b.append(hit[0] if hit else -1)
        got[tuple(a_b)] = got.get(tuple(a_b), 0.0) + h.weight
    top = sorted(oracle, key=oracle.get, reverse=True)[:3]
    for k in top:
        assert got.get(k, 0.0) == pytest.approx(oracle[k], rel=1e-6), k


def test_no_hook_returns_the_same_array():
    det = DetectionModel(0.9)
    arr = np.array([0.9, 0.0, 0.9])
    assert state_p_detect(det, MEANS, arr) is arr
    hooked = _ByX(det)
    assert state_p_detect(hooked, MEANS, arr).tolist() == [0.3, 0.0, 0.6]


def test_bad_hook_is_refused():
    class Bad(_ByX):
        def p_D_of(self, means):
            return np.ones(len(means))

    with pytest.raises(ValueError, match="p_D_of"):
        state_p_detect(Bad(DetectionModel(0.9)), MEANS, np.full(3, 0.9))

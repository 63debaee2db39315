"""GNN's and JPDA's updates through the EKF surface (a range-bearing measurement, Jacobian per track, bearing
wrapped): a track given a return is updated exactly as the measurement model's own EKF update
(:meth:`ExtendedMeasurement.update`, tested against exact moments in tests/unit/models), a missed track keeps
its prediction, and the PDA update is the mixture of the measurement model's pieces (Bar-Shalom & Li, PDAF:
``x + K ν̄``, ``β₀ P + (1 − β₀) P_c + K (Σ βᵢ νᵢ νᵢᵀ − ν̄ ν̄ᵀ) Kᵀ``)."""

import numpy as np

from hypotrack.models.measurement import ExtendedMeasurement
from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.gnn import gnn_update
from hypotrack.trackers.jpda import pda_update


class _RangeBearing(ExtendedMeasurement):
    """``(√(x² + y²), atan2(y, x))`` of a state ``(x, vx, y, vy)``."""

    wrapped = (1,)
    ndim_state = 4

    def __init__(self):
        self.R = np.diag([0.04, 1e-4])

    def h(self, means):
        x, y = means[:, 0], means[:, 2]
        return np.column_stack([np.hypot(x, y), np.arctan2(y, x)])

    def jacobian(self, means):
        x, y = means[:, 0], means[:, 2]
        r2 = x * x + y * y
        r = np.sqrt(r2)
        J = np.zeros((len(means), 2, 4))
        J[:, 0, 0], J[:, 0, 2] = x / r, y / r
        J[:, 1, 0], J[:, 1, 2] = -y / r2, x / r2
        return J


def _scene():
    m = _RangeBearing()
    model = ScanModel(None, m.R, 0.9, 0.999, 1e-3, measurement=m)
    x = np.array([[10.0, 1.0, 0.5, 0.0], [-8.0, 0.0, -0.1, 1.0], [3.0, 0.0, 9.0, -1.0]])  # track 1 across the wrap
    G = np.random.default_rng(3).normal(0, 0.3, (3, 4, 4))
    P = G @ np.swapaxes(G, 1, 2) + 0.1 * np.eye(4)
    Z = np.vstack([m.h(x[[0]]) + [0.1, 0.01], m.h(x[[2]]) + [-0.2, -0.02]])
    return m, model, x, P, Z


def test_gnn_update_is_the_ekf_update_of_the_assigned_tracks():
    m, model, x, P, Z = _scene()
    gated = gate_tracks(x, P, Z, model)
    x1, P1, detected = gnn_update(gated, [0, 2], model)  # return 0 → track 0, return 1 → track 2, track 1 missed
    xe, Pe = m.update(x[[0, 2]], P[[0, 2]], Z)
    np.testing.assert_allclose(x1[[0, 2]], xe, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(P1[[0, 2]], Pe, rtol=1e-10, atol=1e-12)
    assert np.array_equal(x1[1], x[1]) and np.array_equal(P1[1], P[1])
    assert detected.tolist() == [True, False, True]


def test_pda_update_is_the_mixture_of_the_measurement_models_pieces():
    m, model, x, P, Z = _scene()
    gated = gate_tracks(x, P, Z, model)
    beta = np.array([[0.2, 0.8, 0.0], [1.0, 0.0, 0.0], [0.3, 0.3, 0.4]])
    xu, Pu = pda_update(gated, beta, model)
    assert xu.shape == (3, 4) and Pu.shape == (3, 4, 4)
    z_pred, _, K, _ = m.innovation(x, P)
    for t in range(3):
        nu = m.residual_rows(Z, np.repeat(z_pred[t:t + 1], 2, axis=0))
        nu_bar = beta[t, 1:] @ nu
        spread = np.einsum("i,ia,ib->ab", beta[t, 1:], nu, nu) - np.outer(nu_bar, nu_bar)
        P_c = m.update(x[t:t + 1], P[t:t + 1], z_pred[t:t + 1])[1][0]  # the updated covariance, whatever the return
        np.testing.assert_allclose(xu[t], x[t] + K[t] @ nu_bar, rtol=1e-12, atol=1e-12)
        want = beta[t, 0] * P[t] + (1 - beta[t, 0]) * P_c + K[t] @ spread @ K[t].T
        np.testing.assert_allclose(Pu[t], want, rtol=1e-10, atol=1e-12)
    assert np.array_equal(xu[1], x[1])  # no return: the prediction

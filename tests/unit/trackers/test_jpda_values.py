"""PDAF/JPDA on worked single-target and three-return cases: the weights of each hypothesis by
hand, the single-target PDA update against the moments of the Gaussian mixture it replaces."""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack.gaussian import update
from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.jpda import jpda_log_weights, jpda_probabilities, pda_update, pdaf_probabilities

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
P0 = np.array([[2.0, 0.0, 0.5, 0.0], [0.0, 2.0, 0.0, 0.5], [0.5, 0.0, 1.0, 0.0], [0.0, 0.5, 0.0, 1.0]])


def test_single_target_pda_update_is_the_moment_matched_mixture():
    """One target, three returns in its gate and one outside: x⁺, P⁺ = mean and covariance of
    β₀ N(x, P) + Σ β_i N(x_i, P_i) with x_i, P_i the Kalman updates on each return."""
    model = ScanModel(H, np.eye(2), 0.8, 0.99, 0.02)
    x = np.array([[1.0, -1.0, 0.5, 0.2]])
    P = P0[None]
    Z = np.array([[1.5, -0.5], [0.0, -2.0], [2.5, -1.2], [30.0, 30.0]])
    gated = gate_tracks(x, P, Z, model)
    np.testing.assert_array_equal(gated.valid[:, 0], [True, True, True, False])
    S = H @ P0 @ H.T + np.eye(2)
    L = [0.8 * multivariate_normal.pdf(z, x[0, :2], S) / 0.02 for z in Z[:3]]
    lw = jpda_log_weights(gated, model)
    np.testing.assert_allclose(lw[0], [np.log(1 - 0.8 * 0.99), *np.log(L), -np.inf], rtol=1e-12)
    beta = jpda_probabilities(gated, model)
    norm = 1 - 0.8 * 0.99 + sum(L)
    np.testing.assert_allclose(beta[0], [(1 - 0.8 * 0.99) / norm, *(np.array(L) / norm), 0.0], rtol=1e-12)
    assert beta[0, 1:4].min() > 0.05  # all three returns really mixed
    x_u, P_u = pda_update(gated, beta, model)
    parts = [(beta[0, 0], x[0], P0)] + [(beta[0, 1 + i], *update(x[0], P0, Z[i], H, model.R)) for i in range(3)]
    mean = sum(w * m for w, m, _ in parts)
    cov = sum(w * (C + np.outer(m - mean, m - mean)) for w, m, C in parts)
    np.testing.assert_allclose(x_u[0], mean, atol=1e-12)
    np.testing.assert_allclose(P_u[0], cov, atol=1e-12)
    np.testing.assert_allclose(P_u[0], P_u[0].T, atol=0)


def test_pdaf_probabilities_of_no_targets_and_bad_shapes():
    assert pdaf_probabilities(np.zeros((0, 4))).shape == (0, 4)
    with pytest.raises(ValueError, match=r"log_weights must have shape \(n, m \+ 1\), got \(2, 3, 1\)"):
        pdaf_probabilities(np.zeros((2, 3, 1)))
    np.testing.assert_allclose(pdaf_probabilities([[0.0, np.log(3.0), -np.inf]]), [[0.25, 0.75, 0.0]], rtol=1e-12)


def test_pdaf_probabilities_are_normalised_per_row_without_underflow():
    """Rows of very different scale (one target's returns all ~40 σ away): each row its own softmax."""
    lw = np.array([[0.0, -1.0, -np.inf], [-900.0, -901.0, -899.0]])
    e = np.exp([[0.0, -1.0], [-1.0, -2.0]])
    want = np.array([[e[0, 0], e[0, 1], 0.0], [e[1, 0], e[1, 1], 1.0]])
    want /= want.sum(axis=1, keepdims=True)
    np.testing.assert_allclose(pdaf_probabilities(lw), want, rtol=1e-12)

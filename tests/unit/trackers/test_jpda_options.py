"""JPDA's options against independent numbers: per-track detection probabilities in the log weights
(scipy's normal density by hand), precomputed log weights taken as given (the row softmax of uncontested
targets), and the loopy-belief-propagation marginals with their tolerance and iteration cap passed through
(the LBP routine itself as the peer; on a loopy cluster they differ from the exact ones)."""

import numpy as np
from scipy.stats import multivariate_normal

from hypotrack.association.lbp import lbp_marginals
from hypotrack.trackers._sht_common import ScanModel, gate_tracks, with_track_p_D
from hypotrack.trackers.jpda import jpda_log_weights, jpda_probabilities, pdaf_probabilities

H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
R = 0.25 * np.eye(2)
MODEL = ScanModel(H, R, 0.9, 0.99, 1e-3)


def _tracks(centres, var):
    x = np.zeros((len(centres), 4))
    x[:, [0, 2]] = centres
    return x, np.repeat(var * np.eye(4)[None], len(centres), axis=0)


def test_log_weights_with_a_detection_probability_per_track():
    x, P = _tracks([[0.0, 0.0], [1.0, 0.0], [20.0, 20.0]], 0.5)
    Z = np.array([[0.3, 0.1], [1.2, -0.4]])
    gated = gate_tracks(x, P, Z, MODEL)
    p_D = np.array([0.5, 0.7, 0.95])
    lw = jpda_log_weights(gated, with_track_p_D(MODEL, p_D))
    assert lw.shape == (3, 3)
    np.testing.assert_allclose(lw[:, 0], np.log1p(-p_D * 0.99), rtol=1e-14)
    for j in range(3):
        S = H @ P[j] @ H.T + R
        for i in range(2):
            d2 = (Z[i] - H @ x[j]) @ np.linalg.solve(S, Z[i] - H @ x[j])
            if d2 <= MODEL.gate:
                want = np.log(p_D[j] / 1e-3) + multivariate_normal(H @ x[j], S).logpdf(Z[i])
                assert np.isclose(lw[j, 1 + i], want, rtol=1e-12, atol=0)
            else:
                assert lw[j, 1 + i] == -np.inf
    assert np.all(lw[2, 1:] == -np.inf)  # the far track gates nothing


def test_precomputed_log_weights_are_taken_as_given():
    x, P = _tracks([[0.0, 0.0], [30.0, 0.0]], 0.5)  # far apart: each its own PDAF problem
    Z = np.array([[0.2, 0.1], [30.3, -0.2]])
    gated = gate_tracks(x, P, Z, MODEL)
    lw = jpda_log_weights(gated, MODEL) + np.array([[0.0, 1.5, 0.0], [0.0, 0.0, -2.0]])
    beta = jpda_probabilities(gated, MODEL, log_weights=lw)
    np.testing.assert_allclose(beta, pdaf_probabilities(lw), rtol=1e-14)
    e = np.exp(lw[0] - lw[0].max())
    np.testing.assert_allclose(beta[0], e / e.sum(), rtol=1e-14)  # the row softmax by hand
    assert not np.allclose(beta, jpda_probabilities(gated, MODEL))


def test_lbp_marginals_pass_their_tolerance_and_cap_through():
    x, P = _tracks([[0.0, 0.0], [0.6, 0.0], [0.3, 0.5]], 1.0)  # every return in every gate: a loopy cluster
    Z = np.array([[0.1, 0.0], [0.5, 0.1], [0.3, 0.4]])
    gated = gate_tracks(x, P, Z, MODEL)
    assert gated.valid.all()
    lw = jpda_log_weights(gated, MODEL)
    exact = jpda_probabilities(gated, MODEL)
    lbp = jpda_probabilities(gated, MODEL, marginals="lbp")
    np.testing.assert_allclose(lbp, lbp_marginals(lw).beta, rtol=1e-12)
    assert np.abs(lbp - exact).max() > 1e-4  # approximate on a cluster with cycles
    few = jpda_probabilities(gated, MODEL, marginals="lbp", lbp_max_iter=2)
    np.testing.assert_allclose(few, lbp_marginals(lw, max_iter=2).beta, rtol=1e-12)
    assert np.abs(few - lbp).max() > 1e-6
    loose = jpda_probabilities(gated, MODEL, marginals="lbp", lbp_tol=1e-2)
    np.testing.assert_allclose(loose, lbp_marginals(lw, tol=1e-2).beta, rtol=1e-12)
    assert np.abs(loose - lbp).max() > 1e-9

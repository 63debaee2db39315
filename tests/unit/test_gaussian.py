"""hypotrack.gaussian against the textbook formulas written out directly (explicit inverses)."""

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from hypotrack import gaussian as g
from hypotrack.models import ConstantVelocity, OrnsteinUhlenbeck


def _random_spd(rng, d, n=None):
    shape = (d, d) if n is None else (n, d, d)
    A = rng.normal(size=shape)
    return A @ np.swapaxes(A, -1, -2) + d * np.eye(d)


@pytest.fixture
def rng():
    return np.random.default_rng(7)


def test_predict_matches_direct_formula(rng):
    model = ConstantVelocity(q=0.3)
    x = rng.normal(size=(5, 4))
    P = _random_spd(rng, 4, 5)
    F, Q = model.F(2.0), model.Q(2.0)
    xp, Pp = g.predict_with(model, x, P, 2.0)
    for i in range(5):
        np.testing.assert_allclose(xp[i], F @ x[i], rtol=1e-13)
        np.testing.assert_allclose(Pp[i], F @ P[i] @ F.T + Q, rtol=1e-12)
    # single-track form returns single-track shapes
    x1, P1 = g.predict(x[0], P[0], F, Q)
    assert x1.shape == (4,) and P1.shape == (4, 4)
    np.testing.assert_allclose(P1, Pp[0], rtol=1e-13)


def test_update_matches_textbook_and_joseph_is_spd(rng):
    H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    R = np.array([[2.0, 0.3], [0.3, 1.0]])
    x = rng.normal(size=(6, 4))
    P = _random_spd(rng, 4, 6)
    z = rng.normal(size=(6, 2))
    xu, Pu = g.update(x, P, z, H, R)
    for i in range(6):
        S = H @ P[i] @ H.T + R
        K = P[i] @ H.T @ np.linalg.inv(S)
        np.testing.assert_allclose(xu[i], x[i] + K @ (z[i] - H @ x[i]), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(Pu[i], (np.eye(4) - K @ H) @ P[i], rtol=1e-9, atol=1e-12)
        np.testing.assert_array_equal(Pu[i], Pu[i].T)
        assert np.all(np.linalg.eigvalsh(Pu[i]) > 0)


def test_log_likelihoods_match_scipy(rng):
    Z = rng.normal(size=(4, 2))
    z_pred = rng.normal(size=(3, 2))
    S = _random_spd(rng, 2, 3)
    L = g.log_likelihood_matrix(Z, z_pred, S)
    assert L.shape == (4, 3)
    for i in range(4):
        for j in range(3):
            want = multivariate_normal(z_pred[j], S[j]).logpdf(Z[i])
            assert L[i, j] == pytest.approx(want, rel=1e-12)
    d2, _ = g.mahalanobis2_matrix(Z, z_pred, S)
    assert d2[1, 2] == pytest.approx((Z[1] - z_pred[2]) @ np.linalg.solve(S[2], Z[1] - z_pred[2]), rel=1e-12)
    assert g.log_likelihood(Z[0], z_pred[1], S[1]) == pytest.approx(L[0, 1], rel=1e-12)


def test_empty_scan_and_no_tracks():
    S = np.tile(np.eye(2), (3, 1, 1))
    assert g.log_likelihood_matrix(np.zeros((0, 2)), np.zeros((3, 2)), S).shape == (0, 3)
    assert g.log_likelihood_matrix(np.ones((4, 2)), np.zeros((0, 2)), np.zeros((0, 2, 2))).shape == (4, 0)


def test_ou_exact_discretisation_matches_matrix_exponential():
    from scipy.linalg import expm

    ou = OrnsteinUhlenbeck(sigma2=0.01, gamma=0.005)
    dt = 3.0
    # Van Loan: the exact (F, Q) of dX = -γX dt + σ dW from one matrix exponential.
    A = np.array([[-ou.gamma]])
    M = expm(np.block([[-A, np.array([[ou.sigma2]])], [np.zeros((1, 1)), A.T]]) * dt)
    F = M[1:, 1:].T
    Q = F @ M[:1, 1:]
    assert ou.F(dt)[0, 0] == pytest.approx(F[0, 0], rel=1e-14)
    assert ou.Q(dt)[0, 0] == pytest.approx(Q[0, 0], rel=1e-10)
    assert ou.Q(1e6)[0, 0] == pytest.approx(ou.stationary_variance, rel=1e-12)


def test_cv_q_matches_van_loan():
    from scipy.linalg import expm

    cv = ConstantVelocity(q=0.7)
    dt = 1.5
    A = np.zeros((4, 4))
    A[:2, 2:] = np.eye(2)
    G = np.zeros((4, 4))
    G[2:, 2:] = cv.q * np.eye(2)
    M = expm(np.block([[-A, G], [np.zeros((4, 4)), A.T]]) * dt)
    F = M[4:, 4:].T
    np.testing.assert_allclose(cv.F(dt), F, atol=1e-14)
    np.testing.assert_allclose(cv.Q(dt), F @ M[:4, 4:], rtol=1e-10, atol=1e-14)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: g.GaussianState([0.0, np.nan], np.eye(2)), "mean"),
        (lambda: g.GaussianState([0.0, 0.0], -np.eye(2)), "cov must be positive definite"),
        (lambda: g.GaussianState([0.0, 0.0], [[1.0, 0.5], [0.0, 1.0]]), "cov must be symmetric"),
        (lambda: g.GaussianState([0.0, 0.0], np.eye(3)), "cov must be 2x2"),
        (lambda: g.update(np.zeros(2), np.eye(2), [np.nan, 0.0], np.eye(2), np.eye(2)), "z must be finite"),
        (lambda: g.predict(np.zeros((2, 2)), np.zeros((3, 2, 2)), np.eye(2), np.eye(2)), "do not match"),
        (lambda: ConstantVelocity(q=-1.0), "q must be"),
        (lambda: OrnsteinUhlenbeck(sigma2=0.01, gamma=0.0), "gamma must be"),
        (lambda: ConstantVelocity(q=1.0).F(-1.0), "dt must be"),
    ],
)
def test_bad_input_names_the_parameter(call, match):
    with pytest.raises(ValueError, match=match):
        call()

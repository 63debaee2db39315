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


def test_gaussian_state_holds_its_validated_arrays():
    s = g.GaussianState([1, 2], [[2.0, 0.5], [0.5 + 1e-12, 1.0]])
    np.testing.assert_array_equal(s.mean, [1.0, 2.0])
    assert s.mean.dtype == float and s.dim == 2
    np.testing.assert_array_equal(s.cov, s.cov.T)  # symmetrised
    assert s.cov[0, 1] == pytest.approx(0.5 + 5e-13, abs=1e-15)


def test_per_track_transition_and_noise(rng):
    """``F`` and ``Q`` of shape (n, d, d) — one Jacobian and noise per track (EKF) — equal the
    per-track predictions; a shared (d, d) form broadcasts."""
    x = rng.normal(size=(3, 2))
    P = _random_spd(rng, 2, 3)
    F = rng.normal(size=(3, 2, 2))
    Q = _random_spd(rng, 2, 3)
    xp, Pp = g.predict(x, P, F, Q)
    for i in range(3):
        np.testing.assert_allclose(xp[i], F[i] @ x[i], rtol=1e-13)
        np.testing.assert_allclose(Pp[i], F[i] @ P[i] @ F[i].T + Q[i], rtol=1e-12)
    xs, Ps = g.predict(x, P, F[0], Q[0])
    np.testing.assert_allclose(Ps[2], F[0] @ P[2] @ F[0].T + Q[0], rtol=1e-12)
    np.testing.assert_allclose(xs[1], F[0] @ x[1], rtol=1e-13)


def test_innovation_and_joseph_by_hand():
    x = np.array([1.0, 2.0])
    P = np.array([[2.0, 0.5], [0.5, 1.0]])
    H = np.array([[1.0, 0.0]])
    R = np.array([[0.5]])
    z_pred, S, K = g.innovation(x, P, H, R)
    np.testing.assert_allclose(z_pred, [1.0])
    np.testing.assert_allclose(S, [[2.5]])
    np.testing.assert_allclose(K, [[0.8], [0.2]])
    # Joseph form with a non-optimal gain: (I - KH) P (I - KH)^T + K R K^T, by hand
    K2 = np.array([[0.5], [0.0]])
    A = np.eye(2) - K2 @ H
    np.testing.assert_allclose(g.joseph_covariance(P, K2, H, R), A @ P @ A.T + K2 @ R @ K2.T, rtol=1e-14)
    xu, Pu = g.update(x, P, np.array([2.0]), H, R)
    np.testing.assert_allclose(xu, [1.8, 2.2], rtol=1e-14)
    np.testing.assert_allclose(Pu, [[0.4, 0.1], [0.1, 0.9]], rtol=1e-13)


def test_singular_but_valid_covariances_are_accepted():
    """Q = 0 (no process noise), R = 0 (a perfect measurement) and a P with a zero-variance
    component are valid: only a negative variance, or a singular S, is refused."""
    P = np.diag([1.0, 0.0])
    xp, Pp = g.predict(np.zeros(2), P, np.eye(2), np.zeros((2, 2)))
    np.testing.assert_array_equal(Pp, P)
    xu, Pu = g.update(np.zeros(2), np.eye(2), np.array([1.0, 1.0]), np.eye(2), np.zeros((2, 2)))
    np.testing.assert_allclose(xu, [1.0, 1.0], atol=1e-15)
    np.testing.assert_allclose(Pu, np.zeros((2, 2)), atol=1e-15)


def test_likelihood_shapes_single_and_batched(rng):
    z_pred = rng.normal(size=(3, 2))
    S = _random_spd(rng, 2, 3)
    z = rng.normal(size=(3, 2))
    batch = g.log_likelihood(z, z_pred, S)
    assert batch.shape == (3,)
    for i in range(3):
        assert batch[i] == pytest.approx(multivariate_normal(z_pred[i], S[i]).logpdf(z[i]), rel=1e-12)
    single = g.log_likelihood(z[1], z_pred[1], S[1])
    assert isinstance(single, float) and single == pytest.approx(batch[1], rel=1e-14)
    # one measurement as a 1-D vector against n tracks; an empty scan
    d2, logdet = g.mahalanobis2_matrix(z[0], z_pred, S)
    assert d2.shape == (1, 3)
    np.testing.assert_allclose(logdet, np.linalg.slogdet(S)[1], rtol=1e-12)
    assert d2[0, 2] == pytest.approx((z[0] - z_pred[2]) @ np.linalg.solve(S[2], z[0] - z_pred[2]), rel=1e-12)
    d2, logdet = g.mahalanobis2_matrix(np.zeros(0), z_pred, S)
    assert d2.shape == (0, 3)
    np.testing.assert_allclose(logdet, np.linalg.slogdet(S)[1], rtol=1e-12)


_X, _I2, _H = np.zeros(2), np.eye(2), np.array([[1.0, 0.0]])


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: g.predict(np.zeros(3), _I2, _I2, _I2),
         "means x (n, d) and covariances P (n, d, d) do not match: (1, 3) vs (1, 2, 2)"),
        (lambda: g.predict([np.inf, 0.0], _I2, _I2, _I2), "x must be finite (no NaN or inf)"),
        (lambda: g.predict(_X, -_I2, _I2, _I2),
         "P (state covariance) must be positive semi-definite (Cholesky failed: a negative variance)"),
        (lambda: g.predict(_X, _I2, np.eye(3), _I2), "F must have shape (2, 2) or (1, 2, 2), got (3, 3)"),
        (lambda: g.predict(np.zeros((2, 2)), np.stack([_I2] * 2), np.ones((3, 2, 2)), _I2),
         "F must have shape (2, 2) or (2, 2, 2), got (3, 2, 2)"),
        (lambda: g.predict(_X, _I2, [[np.nan, 0.0], [0.0, 1.0]], _I2), "F must be finite (no NaN or inf)"),
        (lambda: g.predict(_X, _I2, _I2, np.eye(3)), "Q must have shape (2, 2) or (1, 2, 2), got (3, 3)"),
        (lambda: g.predict(_X, _I2, _I2, -_I2),
         "Q (process-noise covariance) must be positive semi-definite (Cholesky failed: a negative variance)"),
        (lambda: g.update(_X, _I2, [0.0], np.ones((1, 3)), [[1.0]]),
         "H must have shape (p, 2) for 2-dimensional states, got (1, 3)"),
        (lambda: g.update(_X, _I2, [0.0], np.ones(2), [[1.0]]),
         "H must have shape (p, 2) for 2-dimensional states, got (2,)"),
        (lambda: g.update(_X, _I2, [0.0], [[np.nan, 0.0]], [[1.0]]), "H must be finite (no NaN or inf)"),
        (lambda: g.update(_X, _I2, [0.0], _H, _I2), "R must have shape (1, 1) for H of shape (1, 2), got (2, 2)"),
        (lambda: g.update(_X, _I2, [0.0], _H, [[-1.0]]),
         "R (measurement-noise covariance) must be positive semi-definite (Cholesky failed: a negative variance)"),
        (lambda: g.update(_X, np.diag([0.0, 1.0]), [0.0], _H, [[0.0]]),
         "S = H P Hᵀ + R (innovation covariance) must be positive definite (Cholesky failed: a zero or negative "
         "variance)"),
        (lambda: g.update(np.zeros((2, 2)), np.stack([_I2] * 2), np.zeros((3, 1)), _H, [[1.0]]),
         "z must have shape (1,) or (2, 1), got (3, 1)"),
        (lambda: g.update(_X, _I2, [np.nan], _H, [[1.0]]), "z must be finite (no NaN or inf)"),
        (lambda: g.innovation([np.nan, 0.0], _I2, _H, [[1.0]]), "x must be finite (no NaN or inf)"),
        (lambda: g.joseph_covariance(_I2, np.zeros((2, 2)), _H, [[1.0]]), "K must have shape (..., 2, 1), got (2, 2)"),
        (lambda: g.joseph_covariance(_I2, [[np.nan], [0.0]], _H, [[1.0]]), "K must be finite (no NaN or inf)"),
        (lambda: g.joseph_covariance(-_I2, np.zeros((2, 1)), _H, [[1.0]]),
         "P (state covariance) must be positive semi-definite (Cholesky failed: a negative variance)"),
        (lambda: g.log_likelihood(_X, _X, np.ones(2)), "S must have shape (p, p) or (n, p, p), got (2,)"),
        (lambda: g.log_likelihood(_X, np.zeros(3), _I2), "z_pred must have shape (n, 2) matching S (2, 2), got (1, 3)"),
        (lambda: g.log_likelihood(np.zeros((2, 2)), np.zeros((2, 2)), np.stack([_I2] * 3)),
         "z_pred must have shape (n, 2) matching S (3, 2, 2), got (2, 2)"),
        (lambda: g.log_likelihood(np.zeros(3), _X, _I2), "z must have 2 components per measurement, got shape (3,)"),
        (lambda: g.log_likelihood(_X, [np.nan, 0.0], _I2), "z_pred must be finite (no NaN or inf)"),
        (lambda: g.log_likelihood(_X, _X, [[1.0, 2.0], [2.0, 1.0]]),
         "S (innovation covariance) must be positive definite (Cholesky failed: a zero or negative variance)"),
        (lambda: g.mahalanobis2_matrix(np.zeros((1, 2)), np.zeros((2, 2)), _I2[None]),
         "z_pred must have shape (n, 2) matching S (1, 2, 2), got (2, 2)"),
        (lambda: g.log_likelihood_matrix([[np.inf, 0.0]], np.zeros((1, 2)), _I2[None]), "Z must be finite (no NaN or inf)"),
        (lambda: g.predict(np.zeros((2, 2, 1)), np.stack([_I2] * 2), _I2, _I2),
         "means x (n, d) and covariances P (n, d, d) do not match: (2, 2, 1) vs (2, 2, 2)"),
        (lambda: g.log_likelihood(np.zeros((2, 2)), np.zeros((2, 2)), np.ones((2, 2, 3))),
         "S must have shape (p, p) or (n, p, p), got (2, 2, 3)"),
        (lambda: g.log_likelihood(_X, _X, np.ones((2, 3))), "S must have shape (p, p) or (n, p, p), got (2, 3)"),
        (lambda: g.log_likelihood(_X, np.zeros((1, 2, 3)), _I2),
         "z_pred must have shape (n, 2) matching S (2, 2), got (1, 2, 3)"),
        (lambda: g.log_likelihood(_X, _X, [[np.nan, 0.0], [0.0, 1.0]]), "S must be finite (no NaN or inf)"),
        (lambda: g.update(_X, _I2, [0.0], _H, [[np.nan]]), "R must be finite (no NaN or inf)"),
        (lambda: g.joseph_covariance([[np.nan, 0.0], [0.0, 1.0]], np.zeros((2, 1)), _H, [[1.0]]),
         "P must be finite (no NaN or inf)"),
        (lambda: g.GaussianState(np.zeros((1, 2)), _I2), "mean must be a 1-D array, got shape (1, 2)"),
        (lambda: g.GaussianState([np.nan, 0.0], _I2), "mean must be finite (no NaN or inf)"),
    ],
)
def test_error_messages_name_the_argument_exactly(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert str(info.value) == message


def test_integer_input_gives_float_results():
    """Lists of integers are converted once at the boundary: no integer arithmetic inside."""
    xp, Pp = g.predict([1, 2], [[1, 0], [0, 1]], [[1, 1], [0, 1]], [[0, 0], [0, 0]])
    assert xp.dtype == float and Pp.dtype == float
    np.testing.assert_array_equal(xp, [3.0, 2.0])
    np.testing.assert_array_equal(Pp, [[2.0, 1.0], [1.0, 1.0]])
    xu, Pu = g.update([0, 0], [[1, 0], [0, 1]], [1, 3], [[1, 0], [0, 1]], [[1, 0], [0, 1]])
    np.testing.assert_array_equal(xu, [0.5, 1.5])
    np.testing.assert_array_equal(Pu, [[0.5, 0.0], [0.0, 0.5]])


def test_one_track_and_no_track_edge_shapes(rng):
    S = _random_spd(rng, 2, 1)
    z_pred = rng.normal(size=(1, 2))
    Z = rng.normal(size=(2, 2))
    d2, logdet = g.mahalanobis2_matrix(Z, z_pred, S)  # one track, two returns
    for i in range(2):
        assert d2[i, 0] == pytest.approx((Z[i] - z_pred[0]) @ np.linalg.solve(S[0], Z[i] - z_pred[0]), rel=1e-12)
    d2, logdet = g.mahalanobis2_matrix(Z, np.zeros((0, 2)), np.zeros((0, 2, 2)))  # no track
    assert d2.shape == (2, 0) and logdet.shape == (0,)
    x1, P1 = g.predict_with(ConstantVelocity(0.3), np.ones(4), np.eye(4), 1.0)  # single-track form
    assert x1.shape == (4,) and P1.shape == (4, 4)
    np.testing.assert_allclose(x1, [2.0, 2.0, 1.0, 1.0])


def test_an_innovation_covariance_that_overflows_is_named():
    """Finite P and H whose product overflows: S = H P Hᵀ + R is inf, reported as S, not as a
    failed Cholesky or a NaN gain."""
    with np.errstate(over="ignore"), pytest.raises(ValueError) as info:
        g.update(_X, 1e300 * _I2, [0.0], [[1e10, 0.0]], [[1.0]])
    assert str(info.value) == "S must be finite (no NaN or inf)"


def test_joseph_covariance_per_track_gains():
    """Gains (n, d, p) for n tracks: each track's P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ by hand."""
    P = np.stack([_I2, 2.0 * _I2])
    K = np.array([[[0.5], [0.0]], [[0.25], [1.0]]])
    out = g.joseph_covariance(P, K, _H, [[1.0]])
    np.testing.assert_allclose(out[0], [[0.5, 0.0], [0.0, 1.0]], rtol=0, atol=1e-15)
    # track 1: I − K H = [[0.75, 0], [-1, 1]]; 2 (I − K H)(I − K H)ᵀ + K Kᵀ
    np.testing.assert_allclose(out[1], [[1.1875, -1.25], [-1.25, 5.0]], rtol=0, atol=1e-15)


def test_mahalanobis_of_one_dimensional_and_single_track_predictions():
    """A scalar predicted measurement is one track with p = 1; a (p,) vector is one track."""
    d2, logdet = g.mahalanobis2_matrix([[0.5], [2.0]], 0.0, [[[4.0]]])
    np.testing.assert_allclose(d2, [[0.0625], [1.0]], rtol=1e-15)
    np.testing.assert_allclose(logdet, [np.log(4.0)], rtol=1e-15)
    d2, _ = g.mahalanobis2_matrix([[0.5, 1.0]], [0.0, 0.0], [[[4.0, 0.0], [0.0, 1.0]]])
    np.testing.assert_allclose(d2, [[1.0625]], rtol=1e-15)

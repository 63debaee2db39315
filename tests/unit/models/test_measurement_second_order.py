"""The second-order EKF of :class:`ExtendedMeasurement` against an independent oracle: for a quadratic ``h`` and a
Gaussian prior the second-order predicted return and innovation covariance are the *exact* mean and covariance of
``h(x) + v``, and its update is the exact linear-MMSE (Gaussian projection) update. The exact moments are computed
here by tensor Gauss-Hermite quadrature (3 nodes per axis integrate every polynomial of degree ≤ 5 per axis exactly;
``h_a h_b`` has degree 4), not from the Hessian formulas the code uses."""

import itertools

import numpy as np
import pytest

from hypotrack.models.measurement import ExtendedMeasurement

# h_a(x) = c_a + b_a·x + ½ xᵀ A_a x on a 3-D state, p = 2
A = np.array([[[2.0, 0.5, 0.0], [0.5, -1.0, 0.3], [0.0, 0.3, 0.8]],
              [[0.0, 1.0, -0.4], [1.0, 0.6, 0.0], [-0.4, 0.0, -1.2]]])
B = np.array([[1.0, -2.0, 0.5], [0.3, 0.0, 1.5]])
C = np.array([0.7, -1.1])
R = np.array([[0.2, 0.05], [0.05, 0.1]])


class _Quadratic(ExtendedMeasurement):
    hessian_steps = (0.3, 0.05, 1.7)  # exact for any step: the Jacobian is linear

    def __init__(self, second_order):
        self.R, self.second_order = R, second_order

    def h(self, means):
        x = np.asarray(means, dtype=float)
        return C + x @ B.T + 0.5 * np.einsum("ni,aij,nj->na", x, A, x)

    def jacobian(self, means):
        x = np.asarray(means, dtype=float)
        return B[None] + np.einsum("aij,nj->nai", A, x)


def _exact(mu, P):
    """(E h, Cov h, Cov(x, h)) of x ~ N(mu, P) by Gauss-Hermite quadrature."""
    nodes, weights = np.polynomial.hermite_e.hermegauss(3)
    weights = weights / weights.sum()
    L = np.linalg.cholesky(P)
    pts, w = [], []
    for idx in itertools.product(range(3), repeat=3):
        pts.append(mu + L @ nodes[list(idx)])
        w.append(np.prod(weights[list(idx)]))
    pts, w = np.array(pts), np.array(w)
    hz = _Quadratic(False).h(pts)
    m = w @ hz
    cov = np.einsum("k,ka,kb->ab", w, hz - m, hz - m)
    cross = np.einsum("k,ki,kb->ib", w, pts - mu, hz - m)
    return m, cov, cross


def _priors():
    rng = np.random.default_rng(11)
    mu = rng.normal(0, 1, (4, 3))
    G = rng.normal(0, 0.6, (4, 3, 3))
    return mu, G @ np.swapaxes(G, 1, 2) + 0.2 * np.eye(3)


def test_second_order_moments_are_the_exact_moments_of_a_quadratic_h():
    mu, P = _priors()
    z_pred, S, K, H = _Quadratic(True).innovation(mu, P)
    for j in range(len(mu)):
        m, cov, cross = _exact(mu[j], P[j])
        np.testing.assert_allclose(z_pred[j], m, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(S[j], cov + R, rtol=1e-11, atol=1e-12)
        np.testing.assert_allclose(K[j], cross @ np.linalg.inv(cov + R), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(H[j], _Quadratic(True).jacobian(mu[j:j + 1])[0], rtol=0, atol=0)
    # first order: h(mu) and J P Jᵀ + R, short of the exact ones by the curvature terms
    z1, S1, _, _ = _Quadratic(False).innovation(mu, P)
    m, cov, _ = _exact(mu[0], P[0])
    np.testing.assert_allclose(z1[0], _Quadratic(False).h(mu[:1])[0], rtol=1e-14)
    assert np.all(np.abs(z1[0] - m) > 1e-3) and np.all(np.diag(S1[0]) < np.diag(cov + R) - 1e-3)


def test_second_order_update_is_the_exact_linear_mmse_update():
    mu, P = _priors()
    rng = np.random.default_rng(12)
    Z = _Quadratic(False).h(mu) + rng.normal(0, 1.0, (len(mu), 2))
    x, Pu = _Quadratic(True).update(mu, P, Z)
    for j in range(len(mu)):
        m, cov, cross = _exact(mu[j], P[j])
        gain = cross @ np.linalg.inv(cov + R)
        np.testing.assert_allclose(x[j], mu[j] + gain @ (Z[j] - m), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(Pu[j], P[j] - gain @ (cov + R) @ gain.T, rtol=1e-9, atol=1e-12)
        assert np.array_equal(Pu[j], Pu[j].T)


def test_hessian_by_central_differences():
    mu, _ = _priors()
    Hxx = _Quadratic(True).hessian(mu)
    assert Hxx.shape == (4, 2, 3, 3)
    np.testing.assert_allclose(Hxx, np.broadcast_to(A, Hxx.shape), rtol=1e-12, atol=1e-12)

    class _Curved(_Quadratic):
        """h_0 = sin(x0) x1² + exp(x2) x0: a Jacobian whose differences differ along each axis."""

        def __init__(self):
            self.R, self.second_order = R[:1, :1], True

        def h(self, means):
            x = np.asarray(means, dtype=float)
            return (np.sin(x[:, 0]) * x[:, 1] ** 2 + np.exp(x[:, 2]) * x[:, 0])[:, None]

        def jacobian(self, means):
            x = np.asarray(means, dtype=float)
            return np.stack([np.cos(x[:, 0]) * x[:, 1] ** 2 + np.exp(x[:, 2]), 2 * np.sin(x[:, 0]) * x[:, 1],
                             np.exp(x[:, 2]) * x[:, 0]], axis=1)[:, None, :]

    m = _Curved()
    m.hessian_steps = (1e-4, 1e-4, 1e-4)
    Hc = m.hessian(mu)
    x0, x1, x2 = mu.T
    exact = np.zeros((4, 3, 3))
    exact[:, 0, 0] = -np.sin(x0) * x1**2
    exact[:, 0, 1] = exact[:, 1, 0] = 2 * np.cos(x0) * x1
    exact[:, 0, 2] = exact[:, 2, 0] = np.exp(x2)
    exact[:, 1, 1] = 2 * np.sin(x0)
    exact[:, 2, 2] = np.exp(x2) * x0
    np.testing.assert_allclose(Hc[:, 0], exact, rtol=1e-6, atol=1e-7)
    m.hessian_steps = (0.4, 0.01, 0.9)  # coarse, unequal steps: the raw differences are not symmetric
    Hs = m.hessian(mu)
    assert np.array_equal(Hs, np.swapaxes(Hs, 2, 3))
    assert not np.allclose(Hs[:, 0], exact, rtol=1e-3)


def test_empty_update_and_wrapping_second_order_returns():
    m = _Quadratic(True)
    x, P = m.update(np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros((0, 2)))
    assert x.shape == (0, 3) and P.shape == (0, 3, 3)
    d2, logdet = m.mahalanobis2(np.zeros((0, 2)), np.zeros((2, 2)), np.repeat(R[None], 2, axis=0))
    assert d2.shape == (0, 2)
    np.testing.assert_allclose(logdet, np.log(np.linalg.det(R)) * np.ones(2), rtol=1e-12)
    d2, logdet = m.mahalanobis2(np.zeros((3, 2)), np.zeros((0, 2)), np.zeros((0, 2, 2)))
    assert d2.shape == (3, 0) and logdet.shape == (0,)
    with pytest.raises(np.linalg.LinAlgError):
        m.mahalanobis2(np.zeros((0, 2)), np.zeros((1, 2)), -np.eye(2)[None])


def test_integer_means_and_the_extended_defaults():
    m = _Quadratic(True)
    mu = np.array([[1, -2, 0], [3, 1, 2]])
    np.testing.assert_array_equal(m.hessian(mu), m.hessian(mu.astype(float)))
    np.testing.assert_array_equal(m.predict(mu.astype(float)), m.h(mu.astype(float)))
    six = np.arange(12.0).reshape(2, 6)
    np.testing.assert_array_equal(m.view_points(six), six[:, :3])  # a position state's first three components
    assert m.dim == 2

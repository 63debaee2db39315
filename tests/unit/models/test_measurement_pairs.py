"""The extended measurement model's squared Mahalanobis distances of every (return, track) pair
(:meth:`~hypotrack.models.measurement.ExtendedMeasurement.mahalanobis2`, one compiled pass over the pairs) against the
array passes: bit for bit the residual wrapped by :func:`~hypotrack.models.measurement.wrap_pi`, ``u = L⁻¹ν`` summed over
its components in order and ``|u|²`` (the arithmetic :func:`~hypotrack.hypotheses.factored.scores.sensor_frame_pairs`
repeats on the gated pairs), and to 1e-12 the einsum of the dense matrices it replaces (whose summation order depends on
the machine's vector width); returns across the azimuth's wrap included, and a hand-computed pair."""

import numpy as np

from hypotrack.models.measurement import ExtendedMeasurement, wrap_pi


class _Model(ExtendedMeasurement):
    """``z = (x₀, x₁)`` with the second component an angle (wrapped)."""

    wrapped = (1,)

    def __init__(self):
        self.R = np.diag([0.5, 0.01])

    def h(self, means):
        return np.asarray(means)[:, :2]

    def jacobian(self, means):
        return np.broadcast_to(np.eye(2, 4), (len(means), 2, 4)).copy()


def test_pair_distances_are_the_array_passes():
    meas = _Model()
    rng = np.random.default_rng(3)
    n, m = 40, 70
    z_pred = np.column_stack([rng.normal(size=n) * 10, rng.uniform(-np.pi, np.pi, n)])
    A = rng.normal(size=(n, 2, 2))
    S = A @ np.swapaxes(A, 1, 2) + 0.1 * np.eye(2)
    Z = np.column_stack([rng.normal(size=m) * 10, rng.uniform(-np.pi, np.pi, m)])
    Z[:10, 1] = np.pi - 1e-3  # returns just below +π against tracks just above −π: a small wrapped residual
    z_pred[:5, 1] = -np.pi + 1e-3
    d2, logdet = meas.mahalanobis2(Z, z_pred, S)
    L = np.linalg.cholesky(S)
    Linv = np.linalg.inv(L)
    nu = Z[:, None, :] - z_pred[None, :, :]
    nu[..., 1] = wrap_pi(nu[..., 1])
    u = Linv[None, :, :, 0] * nu[:, :, None, 0]
    u = u + Linv[None, :, :, 1] * nu[:, :, None, 1]
    np.testing.assert_array_equal(d2, np.sum(u * u, axis=-1))
    np.testing.assert_allclose(d2, np.sum(np.einsum("njk,mnk->mnj", Linv, nu) ** 2, axis=-1), rtol=1e-12)
    np.testing.assert_array_equal(logdet, 2.0 * np.sum(np.log(np.diagonal(L, axis1=1, axis2=2)), axis=1))
    assert np.all(np.abs(nu[:10, :5, 1]) < 3e-3)  # the wrap made these small
    # by hand: S = diag(2, 0.5), ν = (1, 0.5): d² = 1/2 + 0.25/0.5 = 1
    d, _ = meas.mahalanobis2(np.array([[1.0, 0.5]]), np.zeros((1, 2)), np.diag([2.0, 0.5])[None])
    assert abs(d[0, 0] - 1.0) < 1e-15

"""The radar's four-component pairs (``p = 4``: range, azimuth, elevation, range-rate) in
:func:`~hypotrack.models.measurement._pair_distances`'s scalar branch: bit for bit the general loop's arithmetic,
which :mod:`test_measurement_pairs` holds to the array passes; residuals across the azimuth's wrap included."""

import numpy as np
import pytest

from hypotrack.models.measurement import ExtendedMeasurement, _pair_distances, wrap_pi


class _Radar(ExtendedMeasurement):
    """``z = x[:4]`` with the second component an angle (wrapped), as the radar's azimuth."""

    wrapped = (1,)

    def __init__(self):
        self.R = np.diag([1e-3, 1e-6, 1e-6, 1e-4])

    def h(self, means):
        return np.asarray(means)[:, :4]

    def jacobian(self, means):
        return np.broadcast_to(np.eye(4, 6), (len(means), 4, 6)).copy()


def _array_passes(Z, z_pred, Linv, wrapped):
    """The general loop's arithmetic in array passes: ``u`` summed over ``k`` in order, ``|u|²`` left to right."""
    nu = Z[:, None, :] - z_pred[None, :, :]
    for k in wrapped:
        nu[..., k] = wrap_pi(nu[..., k])
    u = Linv[None, :, :, 0] * nu[:, :, None, 0]
    for k in range(1, 4):
        u = u + Linv[None, :, :, k] * nu[:, :, None, k]
    s = 0.0 + u[..., 0] * u[..., 0]
    for a in range(1, 4):
        s = s + u[..., a] * u[..., a]
    return s


def _scene(seed):
    rng = np.random.default_rng(seed)
    n, m = 37, 53
    z_pred = np.column_stack([rng.uniform(500, 3000, n), rng.uniform(-np.pi, np.pi, n), rng.uniform(0, 1.5, n),
                              rng.normal(size=n)])
    Z = np.column_stack([rng.uniform(500, 3000, m), rng.uniform(-np.pi, np.pi, m), rng.uniform(0, 1.5, m),
                         rng.normal(size=m)])
    Z[:8, 1] = np.pi - 1e-4  # returns just below +π against tracks just above −π: a small wrapped residual
    z_pred[:6, 1] = -np.pi + 1e-4
    Z[8, 1] = -np.pi  # exactly on the wrap
    A = rng.normal(size=(n, 4, 4)) * np.array([1e-1, 1e-3, 1e-3, 1e-2])[:, None]
    S = A @ np.swapaxes(A, 1, 2) + np.diag([1e-3, 1e-6, 1e-6, 1e-4])
    return Z, z_pred, S


@pytest.mark.parametrize("wrapped", [(1,), (1, 2), (), (0, 1, 2, 3)])
def test_four_components_are_the_general_arithmetic_bit_for_bit(wrapped):
    Z, z_pred, S = _scene(5)
    Linv = np.linalg.inv(np.linalg.cholesky(S))
    w = np.zeros(4, dtype=np.bool_)
    w[list(wrapped)] = True
    got = _pair_distances(Z, z_pred, Linv, w)
    ref = _array_passes(Z, z_pred, Linv, wrapped)
    assert got.tobytes() == ref.tobytes()
    # the general loop itself (a fifth, zero component of no weight leaves every sum as it is) agrees too
    Z5, z5 = np.column_stack([Z, np.zeros(len(Z))]), np.column_stack([z_pred, np.zeros(len(z_pred))])
    L5 = np.zeros((len(S), 5, 5))
    L5[:, :4, :4] = Linv
    assert _pair_distances(Z5, z5, L5, np.append(w, False)).tobytes() == got.tobytes()


def test_the_radar_model_by_hand():
    # S = diag(4, 1e-6, 1e-6, 1): ν = (2, 2π − 1e-3 → −1e-3 wrapped, 1e-3, 1): d² = 1 + 1 + 1 + 1 = 4
    meas = _Radar()
    Z = np.array([[2.0, np.pi - 0.5e-3, 1e-3, 1.0]])
    z_pred = np.array([[0.0, -np.pi + 0.5e-3, 0.0, 0.0]])
    d2, logdet = meas.mahalanobis2(Z, z_pred, np.diag([4.0, 1e-6, 1e-6, 1.0])[None])
    assert abs(d2[0, 0] - 4.0) < 1e-9
    assert abs(logdet[0] - np.log(4e-12)) < 1e-12

"""The radar Hessian's central differences (radar_kernels._differences, what the second-order EKF's ``_row`` uses):
bit for bit the differences of twelve full Jacobians (radar_jacobian, :func:`~.radar_model.rae_rate_jacobian`'s
bits), though a velocity step recomputes only the range rate's three position derivatives — on tracks of every
geometry, at the zenith (the azimuth's derivatives 0/0: NaN), at the site (ρ = 0), with a non-finite velocity, with
a negative step (a zero's sign), and through the whole second-order innovation."""

import numba
import numpy as np
import pytest

from hypotrack.models.orbit3d_replay import fused_multiply_add
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue import radar_kernels as rk
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor


def full_differences(x, s, sdot, M, steps):
    """The oracle: ``(J(x + h_k e_k) − J(x − h_k e_k)) / 2h_k`` of two full Jacobians per component, in numpy."""
    A = np.empty((4, 6, 6))
    for k in range(6):
        xp, xm = x.copy(), x.copy()
        xp[k], xm[k] = x[k] + steps[k], x[k] - steps[k]
        with np.errstate(invalid="ignore"):  # (inf − inf at the degenerate rows: the NaN compared)
            A[:, :, k] = (rk.radar_jacobian(xp[None], s, sdot, M)[0] - rk.radar_jacobian(xm[None], s, sdot, M)[0]) / (2.0 * steps[k])
    return A


def _bits(a):
    return np.ascontiguousarray(a).view(np.int64)


def _tracks(n, seed):
    rng = np.random.default_rng(seed)
    r = rng.normal(size=(n, 3))
    r *= rng.uniform(6500.0, 42000.0, size=(n, 1)) / np.linalg.norm(r, axis=1, keepdims=True)
    v = rng.normal(size=(n, 3)) * rng.uniform(0.1, 8.0, size=(n, 1))
    return np.hstack([r, v])


def _geometry():
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(0.7).measurement
    s, sdot, M = meas._geometry()[:3]
    return meas, np.asarray(s, float), np.asarray(sdot, float), np.asarray(M, float)


def _kernel(x, s, sdot, M, steps):
    H = rk.radar_jacobian(x[None], s, sdot, M)[0]
    A = np.empty((4, 6, 6))
    rk._differences(x, s, sdot, M, steps, H, np.empty((4, 6)), np.empty((4, 6)), np.empty(6), A)
    return A


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_the_differences_are_those_of_twelve_full_jacobians_bit_for_bit(sign):
    meas, s, sdot, M = _geometry()
    steps = sign * np.asarray(meas.hessian_steps, dtype=float)
    X = _tracks(300, 3)
    up = s + 500.0 * (M[2] / np.linalg.norm(M[2]))  # the zenith: east and north components 0
    X = np.vstack([X, np.r_[up, 1.0, -2.0, 0.5], np.r_[s, 3.0, 0.0, 1.0], np.r_[X[0, :3], np.inf, 0.0, 1.0]])
    n_nan = 0
    for x in X:
        got, want = _kernel(x, s, sdot, M, steps), full_differences(x, s, sdot, M, steps)
        assert np.array_equal(_bits(got), _bits(want))
        n_nan += int(np.isnan(want).any())
    assert n_nan >= 2  # the degenerate rows do reach NaNs: the equality covers them
    assert np.any(_kernel(X[5], s, sdot, M, steps)[3, :3, 3:] != 0)  # a velocity step does move J[3, :3]



@numba.njit(cache=False)
def _moments_reference(X, P, s, sdot, M, steps, R, az_center):
    """The second-order ``(z_pred, R_eff)`` row by row as the kernel first wrote them: twelve full Jacobians, each
    product entry's fused chain and each trace sum alone, one after the other."""
    n = X.shape[0]
    z_out, Re_out = np.empty((n, 4)), np.empty((n, 4, 4))
    H, Jp, Jm, A, Hxx, xs = (np.empty((4, 6)), np.empty((4, 6)), np.empty((4, 6)), np.empty((4, 6, 6)),
                             np.empty((4, 6, 6)), np.empty(6))
    for r in range(n):
        x, Pr, z, Re = X[r], P[r], z_out[r], Re_out[r]
        rk._jacobian(x, s, sdot, M, H)
        rk._h(x, s, sdot, M, az_center, z)
        for k in range(6):
            for c in range(6):
                xs[c] = x[c]
            xs[k] = x[k] + steps[k]
            rk._jacobian(xs, s, sdot, M, Jp)
            xs[k] = x[k] - steps[k]
            rk._jacobian(xs, s, sdot, M, Jm)
            two = 2.0 * steps[k]
            for a in range(4):
                for l in range(6):
                    A[a, l, k] = (Jp[a, l] - Jm[a, l]) / two
        for a in range(4):
            for l in range(6):
                for k in range(6):
                    Hxx[a, l, k] = 0.5 * (A[a, l, k] + A[a, k, l])
        for a in range(4):
            for i in range(6):
                for j in range(6):
                    acc = 0.0
                    for l in range(6):
                        acc = fused_multiply_add(Hxx[a, i, l], Pr[l, j], acc)
                    A[a, i, j] = acc
        for a in range(4):
            tr = A[a, 0, 0]
            for i in range(1, 6):
                tr += A[a, i, i]
            z[a] = z[a] + 0.5 * tr
        for a in range(4):
            for b in range(a, 4):
                sab = 0.0
                sba = 0.0
                for k in range(6):
                    for l in range(6):
                        sab += A[a, k, l] * A[b, l, k]
                        sba += A[b, k, l] * A[a, l, k]
                v = 0.5 * (0.5 * sab + 0.5 * sba)
                Re[a, b] = R[a, b] + v
                Re[b, a] = R[b, a] + v
    return z_out, Re_out


def test_the_second_order_moments_are_the_sequential_kernels_bit_for_bit():
    meas, s, sdot, M = _geometry()
    steps = np.asarray(meas.hessian_steps, dtype=float)
    X = _tracks(200, 7)
    rng = np.random.default_rng(8)
    A = rng.normal(size=(200, 6, 6)) * np.array([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3])[:, None]
    P = A @ np.swapaxes(A, 1, 2) + np.eye(6) * 1e-4
    P[3, 0, 1] = P[3, 1, 0] = np.nan  # a non-finite covariance, a huge one, a zero one
    P[4] *= 1e16
    P[5] = 0.0
    up = s + 500.0 * (M[2] / np.linalg.norm(M[2]))
    X[6] = np.r_[up, 1.0, -2.0, 0.5]  # the zenith
    z, H, Re = rk.radar_moments(X, P, None, s, sdot, M, steps, meas.R, meas.sensor.az_center, True, rk.MOMENTS)
    z_ref, Re_ref = _moments_reference(X, P, s, sdot, M, steps, meas.R, meas.sensor.az_center)
    assert np.array_equal(_bits(z), _bits(z_ref)) and np.array_equal(_bits(Re), _bits(Re_ref))
    assert np.isnan(Re[3]).any() and np.isfinite(Re[0]).all()
    assert np.any(Re[0] != meas.R)  # the second-order terms are there

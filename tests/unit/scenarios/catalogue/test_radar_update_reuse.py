"""The radar's update reuses the linearisation of the rows the last innovation batch held (radar_kernels'
_update_known): bit for bit the update computed afresh (_batch) — on a subset of the rows in another order, rows
the batch did not hold, a row whose covariance differs by one ulp, a zero of the other sign, a NaN row — and after
the geometry changed (another GMST) nothing is reused; the rows reused are counted, so the reuse is what runs."""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue import radar_kernels as rk
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor


def _tracks(n, seed):
    rng = np.random.default_rng(seed)
    r = rng.normal(size=(n, 3))
    r *= rng.uniform(6800.0, 8000.0, size=(n, 1)) / np.linalg.norm(r, axis=1, keepdims=True)
    v = np.cross(r, rng.normal(size=(n, 3)))
    v *= 7.5 / np.linalg.norm(v, axis=1, keepdims=True)
    A = rng.normal(size=(n, 6, 6)) * np.array([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3])[:, None]
    P = A @ np.swapaxes(A, 1, 2) + np.eye(6) * 1e-4
    return np.hstack([r, v]), P


def _fresh(meas, X, P, Z):
    """The update with no batch to reuse: _batch's own."""
    rk._LAST_INNOVATION[0] = None
    return meas.update(X, P, Z)


@pytest.fixture
def meas():
    rk._LAST_INNOVATION[0] = None
    yield RadarTrackerSensor(DEFAULT_RADAR).at(0.7).measurement
    rk._LAST_INNOVATION[0] = None


def test_update_after_innovation_is_the_fresh_update_bit_for_bit(meas):
    X, P = _tracks(150, 1)
    rng = np.random.default_rng(2)
    z_pred = meas.innovation(X, P)[0]
    Z = z_pred[:, :] + rng.normal(size=(150, 4)) * np.array([0.03, 1e-3, 1e-3, 0.01])
    other_X, other_P = _tracks(20, 3)  # rows the batch did not hold
    rows = rng.permutation(150)[:90]
    Xs = np.concatenate([X[rows], other_X])
    Ps = np.concatenate([P[rows], other_P])
    Ps[3, 2, 2] = np.nextafter(Ps[3, 2, 2], np.inf)  # one ulp off: not the batch's row
    Zs = np.concatenate([Z[rows], Z[:20]])
    for _ in range(2):  # twice: the batch kept again after a fresh update dropped it
        meas.innovation(X, P)  # the scan's scores linearise every row
        got = meas.update(Xs, Ps, Zs)
        want = _fresh(meas, Xs, Ps, Zs)
        for g, w in zip(got, want):
            assert np.array_equal(g, w) and np.array_equal(np.signbit(g), np.signbit(w))
    # what ran: 89 rows reused (not the ulp-off one, nor the 20 new ones)
    meas.innovation(X, P)
    last = rk._LAST_INNOVATION[0]
    geo = last[0]
    xo, Po, bad, n_known = rk._update_known(Xs, Ps, Zs, Xs.view(np.int64), Ps.view(np.int64), *last[1:], *geo)
    assert bad == -1 and n_known == 89
    np.testing.assert_array_equal(xo, want[0])
    np.testing.assert_array_equal(Po, want[1])


def test_signed_zero_and_nan_rows_are_not_taken_for_the_batchs(meas):
    X, P = _tracks(30, 4)
    X[5, 2] = 0.0
    Z = meas.innovation(X, P)[0] + 1e-3
    Xs = X[:10].copy()
    Xs[5, 2] = -0.0  # equal as a number, not as bits: computed afresh
    meas.innovation(X, P)
    last = rk._LAST_INNOVATION[0]
    _, _, _, n_known = rk._update_known(Xs, P[:10].copy(), Z[:10], Xs.view(np.int64), P[:10].view(np.int64),
                                        *last[1:], *last[0])
    assert n_known == 9
    got = meas.update(Xs, P[:10], Z[:10])
    want = _fresh(meas, Xs, P[:10], Z[:10])
    for g, w in zip(got, want):
        assert np.array_equal(g, w) and np.array_equal(np.signbit(g), np.signbit(w))
    Xn = X[:4].copy()
    Xn[1, 0] = np.nan
    meas.innovation(X, P)
    got = meas.update(Xn, P[:4], Z[:4])
    want = _fresh(meas, Xn, P[:4], Z[:4])
    for g, w in zip(got, want):
        np.testing.assert_array_equal(g, w)


def test_another_geometry_reuses_nothing(meas):
    X, P = _tracks(40, 5)
    Z = meas.innovation(X, P)[0] + 1e-3
    meas.sensor.at(0.71)  # the next scan's GMST: another linearisation
    got = meas.update(X, P, Z)
    want = _fresh(meas, X, P, Z)
    for g, w in zip(got, want):
        np.testing.assert_array_equal(g, w)
    meas.sensor.at(0.7)
    meas.innovation(X, P)
    stale = meas.update(X, P, Z)  # same geometry again: reused, and different from the other GMST's update
    assert not np.array_equal(stale[0], got[0])
    np.testing.assert_array_equal(stale[0], _fresh(meas, X, P, Z)[0])

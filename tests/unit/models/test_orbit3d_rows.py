"""J2Orbit3D.propagate of a batch of rows in one pass (_rk4_j2_rows: blocks of rows stepped as columns): the same
bits as the columns kernel (_rk4_j2_columns, itself the array passes' bits) for batch sizes around the block's, for
rows given C-ordered, Fortran-ordered or as a strided slice, one to four steps of either sign; non-finite input or
output takes the checked path and raises as before (a bad x reported before a bad dt)."""

import numpy as np
import pytest

from hypotrack.models.orbit3d import J2Orbit3D, _rk4_j2_columns, _rk4_j2_rows

MODEL = J2Orbit3D()
C_J2 = 1.5 * MODEL.j2 * MODEL.mu * MODEL.radius**2


def _states(n, seed):
    rng = np.random.default_rng(seed)
    r = rng.normal(size=(n, 3))
    r *= rng.uniform(6600.0, 26000.0, size=(n, 1)) / np.linalg.norm(r, axis=1, keepdims=True)
    v = np.cross(r, rng.normal(size=(n, 3)))
    v *= rng.uniform(3.0, 8.0, size=(n, 1)) / np.linalg.norm(v, axis=1, keepdims=True)
    return np.hstack([r, v])


def _columns(X, dt):
    n = int(np.ceil(abs(dt) / MODEL.max_step))
    return np.ascontiguousarray(_rk4_j2_columns(np.ascontiguousarray(X.T), dt / n, n, MODEL.mu, C_J2).T)


@pytest.mark.parametrize("size", [1, 63, 64, 65, 129, 3001])
@pytest.mark.parametrize("dt", [10.0, 30.0, 95.0, -45.0])
def test_rows_kernel_is_the_columns_kernel_bit_for_bit(size, dt):
    X = _states(size, size)
    want = _columns(X, dt)
    n = int(np.ceil(abs(dt) / MODEL.max_step))
    out, fin_in, fin_out = _rk4_j2_rows(X, dt / n, n, MODEL.mu, C_J2)
    assert fin_in and fin_out
    np.testing.assert_array_equal(out, want)
    assert not np.array_equal(out, X)
    for layout in (np.asfortranarray(X), np.hstack([X, X])[:, :6], X[::-1][::-1]):
        got = MODEL.propagate(layout, dt)
        np.testing.assert_array_equal(got, want)
        assert got.flags.c_contiguous


def test_non_finite_rows_take_the_checked_path_and_raise_as_before():
    X = _states(200, 3)
    bad = X.copy()
    bad[70, 2] = np.nan
    with pytest.raises(ValueError, match="x must be finite"):
        MODEL.propagate(bad, 10.0)
    centre = X.copy()
    centre[130] = 0.0  # finite in, non-finite out: the refusal names the state
    with pytest.raises(ValueError, match=r"x: state 130 .*non-finite state"):
        MODEL.propagate(centre, 10.0)
    n = int(np.ceil(10.0 / MODEL.max_step))
    with np.errstate(divide="ignore", invalid="ignore"):
        _, fin_in, fin_out = _rk4_j2_rows(centre, 10.0 / n, n, MODEL.mu, C_J2)
        _, nan_in, _ = _rk4_j2_rows(bad, 10.0 / n, n, MODEL.mu, C_J2)
    assert fin_in and not fin_out and not nan_in
    with pytest.raises(ValueError, match="x must be finite"):  # both bad: x first, as before
        MODEL.propagate(bad, float("nan"))
    with pytest.raises(ValueError, match="dt must be finite"):
        MODEL.propagate(X, float("inf"))
    np.testing.assert_array_equal(MODEL.propagate(X, 0.0), X)
    assert MODEL.propagate(np.zeros((0, 6)), 10.0).shape == (0, 6)

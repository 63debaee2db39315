"""``GaussianBirthTerm.many`` (the adaptive birth's terms of a scan, checked in one batch) against one constructor call
per term: field for field the same terms, linear and through a nonlinear measurement, with and without mixture
weights; and the constructor's errors for a bad covariance, mean or weight anywhere in the batch."""

import numpy as np
import pytest

from hypotrack.hypotheses.population_lmb import GaussianBirthTerm


class Polar:
    """A range-bearing measurement of the position (a nonlinear model for the measurement branch)."""

    linear = False
    R = np.diag([0.01, 1e-4])


def _batch(n, d=4, seed=0):
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(n, d)) * 10
    L = rng.normal(size=(n, d, d))
    P = L @ np.swapaxes(L, 1, 2) + np.eye(d)
    return x, 0.5 * (P + np.swapaxes(P, 1, 2)), rng.uniform(0.05, 1.0, n)


def _same(a, b):
    for name in ("mean", "cov", "H", "R"):
        u, v = getattr(a, name), getattr(b, name)
        assert (u is None and v is None) or np.array_equal(u, v)
    assert a.gate_probability == b.gate_probability and a.measurement is b.measurement and a.weight == b.weight


@pytest.mark.parametrize("weighted", [False, True])
@pytest.mark.parametrize("nonlinear", [False, True])
def test_many_is_one_constructor_call_per_term(weighted, nonlinear):
    x, P, w = _batch(5)
    H, R, m = (None, Polar.R, Polar()) if nonlinear else (np.eye(2, 4), np.eye(2) * 0.5, None)
    ws = w if weighted else None
    got = GaussianBirthTerm.many(x, P, H, R, 0.99, m, ws)
    want = [GaussianBirthTerm(x[i], P[i], H, R, 0.99, measurement=m, weight=float(w[i]) if weighted else 1.0)
            for i in range(5)]
    assert len(got) == 5
    for a, b in zip(got, want):
        _same(a, b)
    z = np.array([[1.0, 2.0], [30.0, -4.0]])
    if not nonlinear:
        for a, b in zip(got, want):
            np.testing.assert_array_equal(a.loglik(z), b.loglik(z))
    assert GaussianBirthTerm.many(np.zeros((0, 4)), np.zeros((0, 4, 4)), H, R, 0.99, m) == []


def test_a_bad_term_anywhere_is_refused_as_the_constructor_refuses_it():
    x, P, w = _batch(4)
    H, R = np.eye(2, 4), np.eye(2)
    bad = P.copy()
    bad[2] = -np.eye(4)
    with pytest.raises(ValueError, match=r"^cov must be positive definite \(Cholesky failed\)$"):
        GaussianBirthTerm.many(x, bad, H, R)
    asym = P.copy()
    asym[3, 0, 1] += 1.0
    with pytest.raises(ValueError, match=r"^cov must be symmetric"):
        GaussianBirthTerm.many(x, asym, H, R)
    nan = x.copy()
    nan[1, 0] = np.nan
    with pytest.raises(ValueError, match="mean"):
        GaussianBirthTerm.many(nan, P, H, R)
    w0 = w.copy()
    w0[3] = 0.0
    with pytest.raises(ValueError, match=r"^weight must lie in \(0, 1\], got 0\.0$"):
        GaussianBirthTerm.many(x, P, H, R, weights=w0)
    with pytest.raises(ValueError, match="R"):  # the shared model: checked once, as in each constructor call
        GaussianBirthTerm.many(x, P, H, -np.eye(2))

"""The certified skip of the eigenvalues in :func:`~hypotrack.hypotheses.factored.planner.scorable`
(:mod:`~hypotrack.hypotheses.factored.scorable_kernels`) gives the verdicts of the eigenvalues of every matrix."""

import numpy as np

from hypotrack.hypotheses.factored.planner import MAX_SCALED_CONDITION, scorable
from hypotrack.hypotheses.factored.scorable_kernels import CERTIFIED_CONDITION, certify


def scorable_by_eigenvalues(S):
    """The replaced form: every finite matrix of positive diagonal through ``eigvalsh``, then Cholesky."""
    S = np.asarray(S, dtype=float)
    ok = np.isfinite(S).all(axis=(1, 2))
    d = np.einsum("nii->ni", S)
    ok &= (d > 0).all(axis=1)
    if ok.any():
        s = 1.0 / np.sqrt(d[ok])
        lam = np.linalg.eigvalsh(S[ok] * s[:, :, None] * s[:, None, :])
        ok[np.flatnonzero(ok)[lam[:, 0] * MAX_SCALED_CONDITION <= lam[:, -1]]] = False
    try:
        np.linalg.cholesky(S[ok])
        return ok
    except np.linalg.LinAlgError:
        pass
    for i in np.flatnonzero(ok):
        try:
            np.linalg.cholesky(S[i])
        except np.linalg.LinAlgError:
            ok[i] = False
    return ok


def _matrices(rng, n, p):
    """Covariances of scaled condition numbers from 1 to 1e14 (eigenvalues spread on a log scale, random
    rotations, units from 1e-6 to 1e6), some indefinite, some with a NaN or a zero variance."""
    out = []
    for i in range(n):
        Q, _ = np.linalg.qr(rng.normal(size=(p, p)))
        lam = np.exp(rng.uniform(0, np.log(10.0 ** rng.uniform(0, 14)), size=p))
        if i % 17 == 0:
            lam[0] = -lam[0] * 1e-3
        A = (Q * lam) @ Q.T
        A = 0.5 * (A + A.T)
        u = 10.0 ** rng.uniform(-6, 6, size=p)
        A = A * np.outer(u, u)
        if i % 29 == 0:
            A[1, 1] = 0.0
        if i % 31 == 0:
            A[0, 1] = np.nan
        out.append(A)
    return np.stack(out)


def test_the_verdicts_are_the_eigenvalues_on_conditions_across_the_limit():
    rng = np.random.default_rng(7)
    for p in (2, 3, 4):
        S = _matrices(rng, 3000, p)
        got, ref = scorable(S), scorable_by_eigenvalues(S)
        assert np.array_equal(got, ref)
        st = certify(S)
        assert 0 < np.sum(st == 1) < len(S) and np.sum(st == 2) > 0 and np.sum(ref) < len(S)  # every branch taken


def test_the_unit_correlation_matrix_by_hand():
    # condition (1 + rho)/(1 - rho); Frobenius bound (2 + 2 rho²)/(1 - rho²): certified at 1 - rho = 1e-3 (bound ~1e3),
    # left to the eigenvalues at 1 - rho = 1e-8 (bound ~1e8 > 1e7, condition 2e8 < 1e10: scorable)
    assert CERTIFIED_CONDITION == 1e7
    for one_minus_rho, status, verdict in [(1e-3, 1, True), (1e-8, 2, True), (1e-11, 2, False)]:
        rho = 1.0 - one_minus_rho
        S = np.array([[[4.0, 2.0 * rho * 1e-3], [2.0 * rho * 1e-3, 1e-6]]])
        assert certify(S).tolist() == [status]
        assert scorable(S).tolist() == [verdict]


def test_not_finite_and_non_positive_variances_are_refused_without_eigenvalues():
    S = np.stack([np.diag([1.0, 0.0]), np.diag([-1.0, 1.0]), np.diag([np.inf, 1.0]), np.eye(2)])
    assert certify(S).tolist() == [0, 0, 0, 1]
    assert scorable(S).tolist() == [False, False, False, True]


def test_a_batch_certified_whole_skips_cholesky_and_agrees():
    # every matrix certified (conditions up to ~1e2, far under the bound's 1e7): the Cholesky call is skipped, the
    # verdicts are the eigenvalues' and Cholesky's (all True), and each factorisation indeed succeeds
    rng = np.random.default_rng(11)
    S = []
    for _ in range(500):
        Q, _ = np.linalg.qr(rng.normal(size=(4, 4)))
        A = (Q * np.exp(rng.uniform(0, np.log(1e2), size=4))) @ Q.T
        u = 10.0 ** rng.uniform(-4, 3, size=4)
        S.append(0.5 * (A + A.T) * np.outer(u, u))
    S = np.stack(S)
    assert np.all(certify(S) == 1)
    assert np.all(scorable(S)) and np.array_equal(scorable(S), scorable_by_eigenvalues(S))
    np.linalg.cholesky(S)

"""The scan's birth likelihoods in one batch: :func:`birth_loglik`.

Every birth term of an adaptive birth (:class:`~..population_adaptive.AdaptiveBirth`; with the catalogue's
admissible-region mixture ~15 terms per unexplained return) is a gated Gaussian
(:class:`~..population_lmb.GaussianBirthTerm`): ``log N(z; ẑ_b, S_b)`` where ``d²_b(z) ≤ γ``, ``-inf``
elsewhere. The population's own :meth:`birth_loglik <..population_events._Population.birth_loglik>` asks each
term in turn (an EKF innovation per term: with a second-order measurement twelve Jacobians for the Hessian,
~0.8 ms of Python each). Here the terms that share one measurement model and one gate are linearised in
one batch (the same arrays the per-term call builds, stacked), and a return is scored against a term only
when it passes a bound that cannot reject a gated pair:

    d² = νᵀ S⁻¹ ν ≥ ν_i² / S_ii   for every component i        (Cauchy–Schwarz in the S⁻¹ inner product)

so ``|ν_i| > √(γ S_ii)`` for some ``i`` means ``d² > γ``: outside the gate, likelihood ``-inf`` as the term
gives it. On the first component the bound is a band ``ẑ_0 ± √(γ S_00)`` (range, for the radar), found by
a binary search on the returns sorted by it; the other components are checked on the band's returns. The
pairs left are scored with the term's own arithmetic (its Cholesky factor, the residual solved against it,
the squared norm summed), so every likelihood is bit for bit the term's (tests compare them).
"""

from __future__ import annotations

import numpy as np

from ...association import gate_threshold
from ...models.measurement import ExtendedMeasurement
from ..population_lmb import GaussianBirthTerm
from .births_kernels import band_pairs_compiled

__all__ = ["birth_loglik", "batchable", "band_pairs", "band_pairs_loop"]

_LOG_2PI = float(np.log(2 * np.pi))


def batchable(densities) -> bool:
    """Whether the birth terms ``densities`` can be scored in one batch: gated Gaussian terms observed
    through one (nonlinear) measurement model with one gate probability."""
    if not densities or not all(type(d) is GaussianBirthTerm for d in densities):
        return False
    d0 = densities[0]
    return (d0.measurement is not None and d0.gate_probability is not None
            and all(d.measurement is d0.measurement and d.gate_probability == d0.gate_probability
                    for d in densities))


def birth_loglik(population, Z) -> np.ndarray:
    """``(m, B)`` log-likelihood of each return under each birth term of ``population`` (module docstring),
    equal to ``population.birth_loglik(Z)``; the population's own call when the terms are not
    :func:`batchable`."""
    dens = getattr(population, "birth_densities", ())
    if not batchable(dens):
        return population.birth_loglik(Z)
    meas = dens[0].measurement
    Z = np.asarray(Z, dtype=float).reshape(-1, meas.R.shape[0])
    m, B = len(Z), len(dens)
    out = np.full((m, B), -np.inf)
    if m == 0:
        return out
    means = np.stack([d.mean for d in dens])
    covs = np.stack([d.cov for d in dens])
    z_pred, S, _, _ = meas.innovation(means, covs)
    gate = gate_threshold(dens[0].gate_probability, z_pred.shape[1])
    # (B, p): the per-component bound, widened by 1e-9 so that rounding cannot drop a pair on the gate's edge
    half = np.sqrt(gate * np.diagonal(S, axis1=1, axis2=2)) * (1.0 + 1e-9)
    # the first component is not wrapped (a range): a band of it, by binary search on the sorted returns
    order = np.argsort(Z[:, 0], kind="stable")
    z0 = Z[order, 0]
    lo = np.searchsorted(z0, z_pred[:, 0] - half[:, 0], side="left")
    hi = np.searchsorted(z0, z_pred[:, 0] + half[:, 0], side="right")
    hit, hit_rows, hit_resid = band_pairs(meas, Z, order, lo, hi, z_pred, half)
    if not hit:
        return out
    # the term's own arithmetic (GaussianBirthTerm.loglik) on the rows the bound left; the Cholesky factors of
    # every term hit in one batched call (LAPACK's factorisation matrix by matrix: the same factors)
    chol = np.linalg.cholesky(S[hit])
    const = 0.5 * z_pred.shape[1] * _LOG_2PI
    for b, L, rows, resid in zip(hit, chol, hit_rows, hit_resid):
        r = np.linalg.solve(L, resid.T)
        d2 = np.sum(r * r, axis=0)
        # (the log-determinant summed as the term sums it: a batched row sum may associate differently)
        ll = -0.5 * d2 - np.sum(np.log(np.diag(L))) - const
        out[rows, b] = np.where(d2 <= gate, ll, -np.inf)
    return out


def band_pairs(meas, Z, order, lo, hi, z_pred, half):
    """``(terms hit, rows of each, residuals of each)``: per birth term ``b`` with returns in its band
    (``order[lo[b]:hi[b]]``), the returns whose residual passes the per-component bound ``|ν_i| ≤ half[b, i]``, in
    band order, and their residuals (``meas.residual``). One compiled pass (:mod:`.births_kernels`: the residual
    and its wrap as numpy rounds them, bit for bit) when ``meas`` keeps :class:`~...models.measurement.ExtendedMeasurement`'s
    residual; else :func:`band_pairs_loop`."""
    if not (isinstance(meas, ExtendedMeasurement) and type(meas).residual is ExtendedMeasurement.residual):
        return band_pairs_loop(meas, Z, order, lo, hi, z_pred, half)
    wrapped = np.zeros(Z.shape[1], dtype=np.bool_)
    wrapped[list(meas.wrapped)] = True
    terms, starts, rows, resid = band_pairs_compiled(Z, order, lo, hi, z_pred, half, wrapped)
    return (terms.tolist(), [rows[a:b] for a, b in zip(starts[:-1], starts[1:])],
            [resid[a:b] for a, b in zip(starts[:-1], starts[1:])])


def band_pairs_loop(meas, Z, order, lo, hi, z_pred, half):
    """:func:`band_pairs` term by term in array passes (any measurement model's own ``residual``)."""
    hit, hit_rows, hit_resid = [], [], []
    for b in np.flatnonzero(hi > lo):
        rows = order[lo[b]:hi[b]]
        resid = meas.residual(Z[rows], z_pred[b][None])[:, 0]
        ok = np.all(np.abs(resid) <= half[b], axis=1)
        if ok.any():  # (a residual is row by row: the rows kept are theirs alone)
            hit.append(int(b))
            hit_rows.append(rows[ok])
            hit_resid.append(resid[ok])
    return hit, hit_rows, hit_resid

"""The Poisson part of the PMBM filter: undetected objects as a Gaussian-mixture intensity.

García-Fernández, Williams, Granström & Svensson, "Poisson multi-Bernoulli mixture filter: direct
derivation and implementation", IEEE TAES 54(4), 2018 (below "the 2018 paper"). The undetected
objects form a Poisson point process with intensity ``λ^u(x) = Σ_k w_k N(x; m_k, P_k)``:

* prediction (the 2018 paper's Theorem 1, Poisson part; Gaussian form Sec. IV):
  ``λ^u_{k|k−1}(x) = λ^b(x) + p_S ∫ f(x|x') λ^u(x') dx'``: each component's weight times ``p_S``,
  its moments Kalman-predicted, the birth intensity ``λ^b`` appended;
* update, undetected part (Theorem 2): ``λ^u_{k|k}(x) = (1 − p_D(x)) λ^u_{k|k−1}(x)`` — weights
  thinned by ``1 − p_D`` (``p_D`` read at the component's mean: 0 out of the field of view);
* update, a measurement's new Bernoulli (Theorem 2, the new-track local hypothesis): with
  ``e(z) = Σ_k p_D w_k N(z; H m_k, S_k)``, the Bernoulli has existence ``r = e / (λ_C c(z) + e)``,
  density ``∝ p_D l(z|x) λ^u(x)`` (a mixture of the components' Kalman updates, which Sec. IV
  merges to one Gaussian by moment matching: mean and covariance are exact) and the local
  hypothesis weight ``λ_C c(z) + e(z)``.

All weights are kept as logarithms.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._logspace import logsumexp
from .._validation import check_covariance, check_finite_array
from ..association import gate_threshold
from ..gaussian import innovation_unchecked, predict_with_unchecked, symmetrize, update_unchecked

__all__ = ["PoissonIntensity", "moment_match", "gaussian_loglik"]


def gaussian_loglik(Z, means, covs, H, R, gate_probability=None):
    """``log N(z_j; H m_k, H P_k Hᵀ + R)`` (m, n) for returns ``Z`` and Gaussians ``(means, covs)``;
    ``-inf`` outside the χ² gate of probability ``gate_probability`` (``None``: no gate)."""
    Z = np.asarray(Z, dtype=float)
    n, m = len(means), len(Z)
    if n == 0 or m == 0:
        return np.zeros((m, n))
    z_pred, S, _ = innovation_unchecked(means, covs, H, R)
    L = np.linalg.cholesky(S)
    diff = Z[None, :, :] - z_pred[:, None, :]  # (n, m, p)
    sol = np.linalg.solve(L[:, None], diff[..., None])[..., 0]
    d2 = np.sum(sol * sol, axis=-1)
    logdet = 2 * np.sum(np.log(np.diagonal(L, axis1=1, axis2=2)), axis=1)
    ll = -0.5 * (d2 + logdet[:, None] + H.shape[0] * np.log(2 * np.pi))
    if gate_probability is not None:
        ll = np.where(d2 <= gate_threshold(gate_probability, H.shape[0]), ll, -np.inf)
    return ll.T


def moment_match(log_w, means, covs):
    """The Gaussian with the mean and covariance of the mixture ``Σ w_k N(m_k, P_k)`` (weights
    normalised here): ``m = Σ w_k m_k``, ``P = Σ w_k (P_k + (m_k − m)(m_k − m)ᵀ)``."""
    lw = np.asarray(log_w, dtype=float)
    w = np.exp(lw - logsumexp(lw))
    mean = w @ means
    dev = means - mean
    cov = np.einsum("k,kij->ij", w, covs) + np.einsum("k,ki,kj->ij", w, dev, dev)
    return mean, symmetrize(cov)


@dataclass(frozen=True, eq=False)
class PoissonIntensity:
    """A Gaussian-mixture intensity ``Σ_k exp(log_w[k]) N(x; means[k], covs[k])`` (immutable).

    Weights are non-negative (``log_w`` may be ``-inf``); ``PoissonIntensity.from_weights`` checks
    the weights given as numbers.
    """

    log_w: np.ndarray
    means: np.ndarray
    covs: np.ndarray

    @classmethod
    def empty(cls, d: int) -> "PoissonIntensity":
        return cls(np.zeros(0), np.zeros((0, d)), np.zeros((0, d, d)))

    @classmethod
    def from_weights(cls, weights, means, covs, d: int | None = None) -> "PoissonIntensity":
        """Checked construction from weights ``w_k ≥ 0`` (finite), means ``(n, d)``, covariances ``(n, d, d)``."""
        w = np.atleast_1d(np.asarray(weights, dtype=float))
        if w.ndim != 1 or not np.all(np.isfinite(w)) or np.any(w < 0):
            raise ValueError(f"Poisson weights must be finite numbers >= 0, got {weights!r}")
        n = len(w)
        if n == 0:
            return cls.empty(int(d if d is not None else np.shape(means)[-1]))
        means = check_finite_array(np.asarray(means, dtype=float).reshape(n, -1), "Poisson means")
        covs = check_covariance(np.asarray(covs, dtype=float).reshape(n, means.shape[1], means.shape[1]),
                                "Poisson covs", dim=means.shape[1], batched=True)
        with np.errstate(divide="ignore"):
            return cls(np.log(w), means, covs)

    def __len__(self) -> int:
        return len(self.log_w)

    @property
    def total(self) -> float:
        """Expected number of undetected objects ``∫ λ^u = Σ w_k``."""
        return float(np.exp(logsumexp(self.log_w))) if len(self) else 0.0

    def append(self, other: "PoissonIntensity") -> "PoissonIntensity":
        return PoissonIntensity(np.concatenate([self.log_w, other.log_w]), np.concatenate([self.means, other.means]),
                                np.concatenate([self.covs, other.covs]))

    def predict(self, motion, interval: float, log_p_survive: float, birth: "PoissonIntensity") -> "PoissonIntensity":
        """``λ^b + p_S f λ^u`` (Theorem 1); a zero interval keeps the moments (no motion, no noise)."""
        if len(self) and interval > 0:
            means, covs = predict_with_unchecked(motion, self.means, self.covs, interval)
        else:
            means, covs = self.means, self.covs
        return PoissonIntensity(self.log_w + log_p_survive, means, covs).append(birth)

    def update(self, Z, H, R, p_detect, clutter_intensity: float, gate_probability=None):
        """Theorem 2's Poisson terms for returns ``Z`` (m, p).

        ``p_detect`` (n,): ``p_D`` of each component. Returns ``(undetected, log_e, log_rho,
        new_means, new_covs)``: the thinned intensity ``(1 − p_D) λ^u``; per return ``log e(z_j)``
        (``-inf`` when no component gates it) and ``log ρ_j = log(λ_C c(z_j) + e(z_j))`` (the new
        Bernoulli's local hypothesis weight); the new Bernoulli's moment-matched mean and covariance
        (the prior's first component where ``e = 0``: unused then, its existence is 0).
        """
        m, n, d = len(Z), len(self), self.means.shape[1]
        with np.errstate(divide="ignore"):
            log_pd = np.log(p_detect)
            undetected = PoissonIntensity(self.log_w + np.log1p(-p_detect), self.means, self.covs)
        log_kappa = np.log(clutter_intensity)
        new_means, new_covs = np.zeros((m, d)), np.repeat(np.eye(d)[None], m, axis=0)
        if n == 0 or m == 0:
            log_e = np.full(m, -np.inf)
            return undetected, log_e, np.full(m, log_kappa), new_means, new_covs
        ll = gaussian_loglik(Z, self.means, self.covs, H, R, gate_probability)  # (m, n)
        terms = ll + (self.log_w + log_pd)[None, :]
        log_e = np.array([logsumexp(row) if np.isfinite(row).any() else -np.inf for row in terms])
        log_rho = np.logaddexp(log_kappa, log_e)
        for j in np.flatnonzero(np.isfinite(log_e)):
            used = np.isfinite(terms[j])
            x, P = update_unchecked(self.means[used], self.covs[used], np.broadcast_to(Z[j], (used.sum(), len(Z[j]))),
                                    H, R)
            new_means[j], new_covs[j] = moment_match(terms[j, used], x, P)
        return undetected, log_e, log_rho, new_means, new_covs

    def pruned(self, min_weight: float) -> "PoissonIntensity":
        """Components of weight ≥ ``min_weight`` (an approximation, Sec. IV; 0 keeps every component
        of positive weight)."""
        keep = self.log_w >= (np.log(min_weight) if min_weight > 0 else -np.inf)
        keep &= np.isfinite(self.log_w)
        return PoissonIntensity(self.log_w[keep], self.means[keep], self.covs[keep])

"""Population (birth/death) models of the three source papers.

* :class:`SingleEventBirthDeath` — document 000 Sec. II-C, Eq. 30: at most one birth (in one of
  ``M_b`` birth regions, probability α each) or one death (of one of the ``M_d`` objects in
  view, probability β each) between scans, so a parent has ``1 + M_b + M_d`` population
  children with probabilities ``1 − M_b α − M_d β``, ``α``, ``β``.
* :class:`BinomialBirth`, :class:`BinomialSurvival` — document 001's spatial binomial birth
  process over ``M`` pixels (Eq. 32–33 and its Poisson limit) and binomial survival (Eq. 59).
* :func:`continuous_birth_death` — document 003 Eq. 2.1–2.2 (as reconstructed in
  ``coraluppi_carthel_reconstruction.md`` §1): a continuous-time Poisson birth/death
  process seen at scan times.

All probabilities are also available in log space; log 0 is ``-inf``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

# scipy.stats is imported where it is used: it costs ~1 s, and every Snakemake invocation (each cluster
# job's too) imports this module through the tracker registry.
from .._validation import check_covariance, check_int, check_nonnegative, check_probability
from .sensors import FieldOfView

__all__ = [
    "SingleEventBirthDeath",
    "UniformBirthDensity",
    "BinomialBirth",
    "BinomialSurvival",
    "continuous_birth_death",
]


def _log(p: float) -> float:
    return float(np.log(p)) if p > 0 else -np.inf


@dataclass(frozen=True, eq=False)
class UniformBirthDensity:
    """Birth pdf of one region: position uniform over the region, velocity Gaussian.

    ``p_b(x) = U(position; region) · N(velocity; v̄(position), Σ_v)`` for states ordered
    ``[x, y, vx, vy]`` (positions first). The velocity mean may depend on position — for
    the SSA scenario it is the prograde circular-orbit velocity there
    (:func:`hypotrack.models.orbit.circular_velocity`), because a newly launched object
    in view is far better described by "near-circular orbit at this radius" than by a
    zero-mean velocity prior.

    Parameters
    ----------
    region : FieldOfView or Box (2-D)
        Where the object is born.
    velocity_cov : (2, 2) array_like
        Velocity covariance Σ_v, positive definite.
    velocity_mean : callable, optional
        Maps positions ``(n, 2)`` to mean velocities ``(n, 2)``; ``None`` means zero.
    """

    region: object
    velocity_cov: np.ndarray
    velocity_mean: Callable | None = None

    def __post_init__(self):
        if getattr(self.region, "dim", None) != 2:
            raise ValueError("region must be a 2-D FieldOfView or Box")
        object.__setattr__(self, "velocity_cov", check_covariance(self.velocity_cov, "velocity_cov", dim=2))

    def mean_velocity(self, positions) -> np.ndarray:
        pos = np.atleast_2d(np.asarray(positions, dtype=float))
        if self.velocity_mean is None:
            return np.zeros_like(pos)
        return np.asarray(self.velocity_mean(pos), dtype=float).reshape(pos.shape)

    @property
    def log_position_density(self) -> float:
        """``log(1 / area)`` of the uniform position part."""
        return -float(np.log(self.region.area))

    def logpdf(self, states) -> np.ndarray:
        """``log p_b(x)`` for states ``(n, 4)``; ``-inf`` outside the region."""
        X = np.atleast_2d(np.asarray(states, dtype=float))
        pos, vel = X[:, :2], X[:, 2:4]
        from scipy import stats
        lv = stats.multivariate_normal(np.zeros(2), self.velocity_cov).logpdf(vel - self.mean_velocity(pos))
        return np.where(self.region.contains(pos), self.log_position_density + np.atleast_1d(lv), -np.inf)

    def sample(self, n: int, rng) -> np.ndarray:
        """``n`` states ``(n, 4)`` drawn from the birth pdf."""
        pos = self.region.sample_uniform(n, rng)
        L = np.linalg.cholesky(self.velocity_cov)
        vel = self.mean_velocity(pos) + rng.standard_normal((len(pos), 2)) @ L.T
        return np.hstack([pos, vel]).reshape(len(pos), 4)

    def initial_state(self, z, R):
        """Gaussian state of an object born at measured position ``z`` with noise ``R``.

        With a uniform position prior much wider than ``R`` the position posterior is
        ``N(z, R)``; the velocity is the prior ``N(v̄(z), Σ_v)``. Returns ``(mean (4,),
        cov (4, 4))``, the track a birth hypothesis seeds (document 000 Eq. 29).
        """
        z = np.asarray(z, dtype=float).reshape(2)
        R = check_covariance(R, "R", dim=2)
        mean = np.concatenate([z, self.mean_velocity(z[None])[0]])
        cov = np.zeros((4, 4))
        cov[:2, :2] = R
        cov[2:, 2:] = self.velocity_cov
        return mean, cov


@dataclass(frozen=True, eq=False)
class SingleEventBirthDeath:
    """Document 000's single-event birth/death model (Sec. II-C, Eq. 30).

    Between two scans at most one population event happens: one birth in one of the
    ``M_b = n_birth_regions`` regions (probability α each) or one death of one of the
    ``M_d`` objects in view (probability β each); otherwise nothing, with probability
    ``1 − M_b α − M_d β`` (Remark 6: the first-order expansion of independent Bernoulli
    births and deaths, valid while α², β², αβ ≈ 0).

    Parameters
    ----------
    alpha : float
        Birth probability per region per scan, in [0, 1].
    beta : float
        Death probability per in-view object per scan, in [0, 1].
    n_birth_regions : int
        ``M_b >= 1``.
    fov : FieldOfView, optional
        Field of view split into the ``M_b`` birth regions (equal angles); needed only for
        :meth:`birth_density`.
    velocity_cov, velocity_mean :
        Velocity prior of :class:`UniformBirthDensity` (default ``velocity_cov`` is
        ``I`` in the squared state velocity unit, e.g. (1 km/s)² per axis).
    """

    alpha: float
    beta: float
    n_birth_regions: int
    fov: FieldOfView | None = None
    velocity_cov: np.ndarray | None = None
    velocity_mean: Callable | None = None

    def __post_init__(self):
        object.__setattr__(self, "alpha", check_probability(self.alpha, "alpha"))
        object.__setattr__(self, "beta", check_probability(self.beta, "beta"))
        object.__setattr__(
            self, "n_birth_regions", check_int(self.n_birth_regions, "n_birth_regions", minimum=1)
        )
        if self.fov is not None and not isinstance(self.fov, FieldOfView):
            raise TypeError(f"fov must be a FieldOfView, got {type(self.fov).__name__}")
        cov = (
            np.eye(2)
            if self.velocity_cov is None
            else check_covariance(self.velocity_cov, "velocity_cov", dim=2)
        )
        object.__setattr__(self, "velocity_cov", cov)
        if self.n_birth_regions * self.alpha >= 1:
            raise ValueError(
                f"n_birth_regions * alpha must be < 1 (the probability of no event must stay positive), "
                f"got {self.n_birth_regions} * {self.alpha}"
            )

    def p_no_event(self, n_in_view: int) -> float:
        """``1 − M_b α − M_d β`` (Eq. 30), with ``M_d = n_in_view``.

        Raises ``ValueError`` when it is not positive: the single-event model is only
        valid while ``M_b α + M_d β < 1``.
        """
        m_d = check_int(n_in_view, "n_in_view", minimum=0)
        p = 1.0 - self.n_birth_regions * self.alpha - m_d * self.beta
        if p <= 0:
            raise ValueError(
                f"1 - n_birth_regions*alpha - n_in_view*beta = {p:.6g} <= 0: the single-event model needs "
                f"n_birth_regions*alpha + n_in_view*beta < 1 (alpha={self.alpha}, beta={self.beta}, "
                f"n_birth_regions={self.n_birth_regions}, n_in_view={m_d})"
            )
        return p

    def log_p_no_event(self, n_in_view: int) -> float:
        """``log(1 − M_b α − M_d β)``."""
        return float(np.log(self.p_no_event(n_in_view)))

    @property
    def log_birth_prob(self) -> float:
        """``log α``: log-probability of a birth in one given region (Eq. 30)."""
        return _log(self.alpha)

    @property
    def log_death_prob(self) -> float:
        """``log β``: log-probability that one given in-view object dies (Eq. 30)."""
        return _log(self.beta)

    def event_log_probs(self, n_in_view: int) -> np.ndarray:
        """Log-probabilities of all ``1 + M_b + M_d`` population children, in the order
        [no event, birth in region 0..M_b−1, death of in-view object 0..M_d−1]; they sum
        (in linear space) to 1."""
        m_d = check_int(n_in_view, "n_in_view", minimum=0)
        return np.concatenate(
            [
                [self.log_p_no_event(m_d)],
                np.full(self.n_birth_regions, self.log_birth_prob),
                np.full(m_d, self.log_death_prob),
            ]
        )

    @property
    def birth_regions(self) -> list[FieldOfView]:
        """The ``M_b`` birth regions: the FOV split into equal-angle sub-wedges."""
        if self.fov is None:
            raise ValueError("birth regions need a fov (pass fov=FieldOfView(...))")
        return self.fov.split(self.n_birth_regions)

    def birth_density(self, region: int) -> UniformBirthDensity:
        """Birth pdf ``p_b`` of region ``region`` (0-based): uniform position, Gaussian velocity."""
        r = check_int(region, "region", minimum=0, maximum=self.n_birth_regions - 1)
        return UniformBirthDensity(self.birth_regions[r], self.velocity_cov, self.velocity_mean)


@dataclass(frozen=True)
class BinomialBirth:
    """Document 001's spatial binomial birth process (Sec. II, Fig. 3; Eq. 32–33).

    Each of ``M = n_potential`` pixels independently spawns an object with probability α,
    so the number of births is ``Binomial(M, α)`` and one specific set of ``p`` occupied
    pixels has probability ``α^p (1 − α)^{M−p}``.

    Parameters
    ----------
    n_potential : int
        Number of pixels ``M >= 0``.
    alpha : float
        Per-pixel birth probability in [0, 1].
    """

    n_potential: int
    alpha: float

    def __post_init__(self):
        object.__setattr__(self, "n_potential", check_int(self.n_potential, "n_potential", minimum=0))
        object.__setattr__(self, "alpha", check_probability(self.alpha, "alpha"))

    @property
    def _dist(self):
        from scipy import stats
        return stats.binom(self.n_potential, self.alpha)

    def pmf(self, k):
        """P(exactly ``k`` births) = C(M, k) α^k (1 − α)^{M−k} (left side of Eq. 32)."""
        return self._dist.pmf(k)

    def logpmf(self, k):
        return self._dist.logpmf(k)

    def log_specific_prob(self, p: int) -> float:
        """log of ``α^p (1 − α)^{M−p}``: one given set of ``p`` pixels spawns (left of Eq. 33)."""
        p = check_int(p, "p", minimum=0, maximum=self.n_potential)
        a = self.alpha
        return (p * _log(a) if p else 0.0) + (
            (self.n_potential - p) * float(np.log1p(-a)) if self.n_potential > p else 0.0
        )

    @property
    def mean(self) -> float:
        return self.n_potential * self.alpha

    def poisson_limit(self):
        """The Poisson limit of Eq. 32: ``Poisson(λ_B V)`` with ``λ_B V = M α``.

        Returns a frozen :data:`scipy.stats.poisson` distribution.
        """
        from scipy import stats
        return stats.poisson(self.mean)


@dataclass(frozen=True)
class BinomialSurvival:
    """Binomial survival (document 001 Sec. IV, Eq. 59): each of ``r`` targets survives
    independently with probability ``p_survive`` (the paper's β), so one given set of
    ``p`` survivors has probability ``β^p (1 − β)^{r−p}``.

    (Document 000 uses β for the *death* probability; here the name says which it is.)
    """

    p_survive: float

    def __post_init__(self):
        object.__setattr__(self, "p_survive", check_probability(self.p_survive, "p_survive"))

    def pmf(self, k, r: int):
        """P(exactly ``k`` of ``r`` targets survive)."""
        from scipy import stats
        return stats.binom(check_int(r, "r", minimum=0), self.p_survive).pmf(k)

    def logpmf(self, k, r: int):
        from scipy import stats
        return stats.binom(check_int(r, "r", minimum=0), self.p_survive).logpmf(k)

    def log_specific_prob(self, p: int, r: int) -> float:
        """log ``p(σ_p^d | r) = β^p (1 − β)^{r−p}`` (Eq. 59)."""
        r = check_int(r, "r", minimum=0)
        p = check_int(p, "p", minimum=0, maximum=r)
        b = self.p_survive
        return (p * _log(b) if p else 0.0) + ((r - p) * _log(1.0 - b) if r > p else 0.0)


def continuous_birth_death(birth_rate, death_rate, dt):
    """Per-scan birth mean and termination probability of a continuous-time process.

    Document 003 Eq. 2.1–2.2 (reconstruction §1): births form a Poisson process of rate λ,
    each object dies at rate μ. Objects born in an interval of length Δt and still alive
    at its end form a thinned Poisson process, and an existing object dies within it with
    probability ``1 − e^{−μΔt}``:

    ``λ_b = (λ/μ) (1 − e^{−μΔt})`` (2.1), ``p_χ = 1 − e^{−μΔt}`` (2.2);

    for μ = 0, ``λ_b = λΔt``. The steady-state number of objects is ``λ_b / p_χ = λ/μ``.

    Parameters
    ----------
    birth_rate : float
        λ ≥ 0 (objects per unit time).
    death_rate : float
        μ ≥ 0 (per object per unit time).
    dt : float
        Scan interval Δt ≥ 0.

    Returns
    -------
    lambda_b : float
        Expected number of new objects per scan.
    p_chi : float
        Per-object termination probability per scan.
    """
    lam = check_nonnegative(birth_rate, "birth_rate")
    mu = check_nonnegative(death_rate, "death_rate")
    dt = check_nonnegative(dt, "dt")
    p_chi = float(-np.expm1(-mu * dt))
    lambda_b = lam * dt if mu == 0 else lam / mu * p_chi
    return lambda_b, p_chi

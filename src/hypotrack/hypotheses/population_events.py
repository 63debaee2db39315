"""Population events (birth and death) as they enter the hypothesis recursion.

A child hypothesis is a population event followed by a data association (document 000 Fig. 1,
document 001 Fig. 11). The engine splits the population event in two parts:

* **detected births** are columns of the association matrix (a return is the first detection
  of an object born in region ``r``); their probability enters the count term through
  :meth:`log_event_prob` indexed by the number ``b`` of such births;
* **undetected births and deaths** do not touch the association: such a child is the *twin*
  of a child without that event, and its weight differs by an exact factor
  (:meth:`undetected_birth_log_ratio`, :meth:`death_log_ratio`; the weight model adds the
  object's ``1 − p_D`` factor). Document 001 Eq. 39 is the undetected-birth case:
  ``w_v / w_v' = (1 − p_D) α``.

Two models are offered:

:class:`SingleEventPopulation`
    Document 000 Eq. 30: at most one birth (probability α in each of ``M_b`` regions) or one
    death (probability β for each of the ``M_d`` objects in view) per scan. With it the
    engine's children are exactly the ``A(M,m) + M_b A(M+1,m) + M_d A(M−1,m)`` of Sec. II-C.
:class:`BinomialPopulation`
    Document 001: spatial binomial births over pixels (Eq. 31–33; optionally in the Poisson limit
    ``α^b (1 − α)^{M_b−b} ≈ e^{−λ_B V} α^b``) and binomial survival (Eq. 59). Any number of
    *detected* births per scan; at most one undetected birth or one death per child (twins of
    twins are not generated: each such further event multiplies a weight by ``(1 − p_D) α`` or
    ``(1 − p_s)/(p_s (1 − p_D))``, both ≪ 1 in the papers' settings).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from .._validation import check_int, check_probability

__all__ = ["SingleEventPopulation", "BinomialPopulation", "birth_prior_gaussian"]


def birth_prior_gaussian(density, n_samples: int = 4096):
    """Gaussian moment match of a birth pdf, for an object born but not yet detected.

    The position moments of the (uniform) region are estimated from a fixed, seeded sample
    (deterministic); the velocity is the density's prior at the mean position. Used only for
    undetected-birth children, whose weight is ``(1 − p_D) α`` relative to their twin.
    """
    pos = density.region.sample_uniform(n_samples, np.random.default_rng(0))
    mu = pos.mean(axis=0)
    cov_p = np.cov(pos, rowvar=False)
    mean = np.concatenate([mu, density.mean_velocity(mu[None])[0]])
    cov = np.zeros((4, 4))
    cov[:2, :2] = cov_p
    cov[2:, 2:] = density.velocity_cov
    return mean, cov


def _region_loglik(densities, Z):
    """``log ∫ p(z|x) p_b,r(x) dx ≈ log(1/V̄_r)`` inside region r, ``-inf`` outside.

    Document 001 Sec. V-B: the measurement likelihood's support is much smaller than a birth region,
    so the integral of a position measurement against a uniform position pdf is ``1/V̄``.
    """
    m = len(Z)
    out = np.full((m, len(densities)), -np.inf)
    if m:
        for r, d in enumerate(densities):
            if hasattr(d, "loglik"):  # a density with its own measurement likelihood (Gaussian birth)
                out[:, r] = d.loglik(Z)
            else:
                out[d.region.contains(Z), r] = d.log_position_density
    return out


class _RemappedCache(dict):
    """A population's undetected-birth cache seen through a subset of its birth regions."""

    def __init__(self, base: dict, regions):
        super().__init__()
        self.base, self.regions = base, [int(r) for r in regions]

    def __contains__(self, i):
        return self.regions[i] in self.base

    def __getitem__(self, i):
        return self.base[self.regions[i]]

    def __setitem__(self, i, value):
        self.base[self.regions[i]] = value


class _Population:
    """What every population model shares: birth terms, their likelihoods, newborn tracks, and the
    memo ``undetected_cache`` (region → the moment-matched Gaussian of an undetected birth,
    :func:`birth_prior_gaussian`; a cache only, it changes no number)."""

    birth_densities: tuple

    @property
    def n_birth_regions(self) -> int:
        return len(self.birth_densities)

    def clear_cache(self) -> None:
        """Forget the undetected-birth moments computed so far (after the birth terms changed)."""
        self.undetected_cache = {}

    def restricted_to(self, regions):
        """This population with only birth terms ``regions`` (in that order), all else unchanged.

        The copy shares this population's undetected-birth cache (through the regions' indices).
        Used by the factored engine, which gives every birth term to one group per scan
        (:func:`.factored_groups.restrict_population`)."""
        regions = np.asarray(regions, dtype=np.int64)
        if len(regions) == self.n_birth_regions and np.array_equal(regions, np.arange(len(regions))):
            return self
        sub = copy.copy(self)
        sub.birth_densities = tuple(self.birth_densities[r] for r in regions)
        sub.undetected_cache = _RemappedCache(self.undetected_cache, regions)
        return sub

    def with_birth_terms(self, terms, r_birth=None):
        """A copy of this population with birth terms ``terms`` (and an empty cache).

        ``r_birth``: each term's existence probability, for the labeled multi-Bernoulli population
        (:class:`~.population_lmb.LabeledMultiBernoulliPopulation`); other models ignore it (the
        binomial population's birth probability is its ``alpha``)."""
        new = copy.copy(self)
        new.birth_densities = tuple(terms)
        new.clear_cache()
        return new

    def track_survival(self, store):
        """``p_S`` ``(n,)`` of the predicted tracks of ``store`` (a :class:`~.tracks.TrackStore`) from the
        population's ``survival`` callable, or ``None`` when it has none (every track survives with its one
        ``p_survive``, or the model's own death probability)."""
        survival = getattr(self, "survival", None)
        if survival is None:
            return None
        p = np.asarray(survival(store.means, store.covs), dtype=float)
        if p.shape != (len(store),) or not np.all((p > 0) & (p <= 1)):
            raise ValueError(f"survival must return one p_S in (0, 1] per track, shape ({len(store)},)")
        return p

    def birth_loglik(self, Z) -> np.ndarray:
        """(m, B) log-likelihood of each return under each birth pdf."""
        return _region_loglik(self.birth_densities, Z)

    def birth_track(self, region: int, z, R):
        """Gaussian track of an object born in ``region``: seeded at return ``z`` if detected,
        the moment-matched birth pdf if ``z is None``."""
        d = self.birth_densities[region]
        if z is None:
            if hasattr(d, "prior"):
                return d.prior()
            if region not in self.undetected_cache:
                self.undetected_cache[region] = birth_prior_gaussian(d)
            return self.undetected_cache[region]
        return d.initial_state(z, R)


@dataclass(eq=False)
class SingleEventPopulation(_Population):
    """Document 000's single birth-or-death model (Eq. 30) around
    :class:`hypotrack.models.population.SingleEventBirthDeath`.

    Parameters
    ----------
    model : SingleEventBirthDeath
        α, β and ``M_b`` (with a field of view, for the birth regions).
    birth_densities : sequence, optional
        One birth pdf per region (default ``model.birth_density(r)``), each with ``region``,
        ``log_position_density``, ``initial_state``, ``mean_velocity``, ``velocity_cov``.
    """

    model: object
    birth_densities: tuple = None
    undetected_cache: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        if self.birth_densities is None:
            self.birth_densities = tuple(self.model.birth_density(r) for r in range(self.model.n_birth_regions))
        self.birth_densities = tuple(self.birth_densities)
        if len(self.birth_densities) != self.model.n_birth_regions:
            raise ValueError(
                f"birth_densities must hold n_birth_regions = {self.model.n_birth_regions} densities, "
                f"got {len(self.birth_densities)}"
            )

    def log_event_prob(self, n_in_view: int, n_objects: int, p_survive=None) -> np.ndarray:
        """Over ``b = 0 .. M_b``: log P(no event) for b = 0, log α for one detected birth in a
        given region, ``-inf`` for more (Eq. 30)."""
        out = np.full(self.n_birth_regions + 1, -np.inf)
        out[0] = self.model.log_p_no_event(n_in_view)
        if self.n_birth_regions:
            out[1] = self.model.log_birth_prob
        return out

    def undetected_birth_log_ratio(self, n_in_view: int, n_objects: int) -> np.ndarray:
        """Over ``b``: log of α / P(no event), only for children without a detected birth."""
        out = np.full(self.n_birth_regions + 1, -np.inf)
        out[0] = self.model.log_birth_prob - self.model.log_p_no_event(n_in_view)
        return out

    def death_log_ratio(self, n_in_view: int, n_objects: int, p_survive=None) -> np.ndarray:
        """Over ``b``: log of β / P(no event), only for children without a detected birth (``p_survive``:
        unused, this model has no per-track survival)."""
        out = np.full(self.n_birth_regions + 1, -np.inf)
        out[0] = self.model.log_death_prob - self.model.log_p_no_event(n_in_view)
        return out

    def death_eligible(self, in_view: np.ndarray) -> np.ndarray:
        """Only objects in view may die (the ``M_d`` of Eq. 30)."""
        return np.asarray(in_view, dtype=bool)


@dataclass(eq=False)
class BinomialPopulation(_Population):
    """Document 001's binomial birth (Eq. 31–33) and survival (Eq. 59).

    Parameters
    ----------
    birth_densities : sequence
        One birth pdf per pixel/region (may be empty: no births).
    alpha : float
        Birth probability per pixel per scan (``α = λ_B V̄`` in the Poisson limit).
    p_survive : float
        Survival probability per object per scan (document 001's β in Eq. 59; 1 = no deaths).
    poisson_limit : bool
        Use ``α^b (1 − α)^{M_b−b} ≈ e^{−M_b α} α^b`` (Eq. 33) — with it the undetected-birth
        ratio is exactly ``(1 − p_D) α`` (Eq. 39).
    survival : callable, optional
        ``survival(means (n, d), covs (n, d, d)) -> p_S (n,)`` in (0, 1] of each predicted track, in place of
        ``p_survive`` (e.g. :class:`~.population_lmb.UnconfirmedDecay`): Eq. 59's survival per object, each
        with its own ``p_S,j`` — the no-event term ``Π_j p_S,j`` and the death twin of object ``j``
        ``(1 − p_S,j) / (p_S,j (1 − p_D,j))`` (still at most one death per child).
    """

    birth_densities: tuple = ()
    alpha: float = 0.0
    p_survive: float = 1.0
    poisson_limit: bool = False
    survival: object = None
    undetected_cache: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        self.birth_densities = tuple(self.birth_densities)
        self.alpha = check_probability(self.alpha, "alpha", high_open=True)
        self.p_survive = check_probability(self.p_survive, "p_survive", low_open=True)
        if self.survival is not None and not callable(self.survival):
            raise TypeError(f"survival must be callable (means, covs -> p_S per track) or None, "
                            f"got {type(self.survival).__name__}")

    def _log_birth(self, b):
        B = self.n_birth_regions
        b = np.asarray(b)
        births = np.zeros(b.shape)  # b log α, with 0 log 0 = 0 when α = 0
        with np.errstate(divide="ignore"):
            births[b > 0] = b[b > 0] * np.log(self.alpha)
        if self.poisson_limit:
            return births - B * self.alpha
        return births + (B - b) * np.log1p(-self.alpha)

    def log_event_prob(self, n_in_view: int, n_objects: int, p_survive=None) -> np.ndarray:
        """Over ``b``: the births' term (Eq. 31–33) times every object's survival, ``p_S^M`` (Eq. 59), or
        ``Π_j p_S,j`` with the parent's tracks' own ``p_survive`` (``(n_objects,)``, :attr:`survival`)."""
        n_objects = check_int(n_objects, "n_objects", minimum=0)
        b = np.arange(self.n_birth_regions + 1)
        if p_survive is None:
            return self._log_birth(b) + n_objects * np.log(self.p_survive)
        return self._log_birth(b) + float(np.sum(np.log(_per_track(p_survive, n_objects))))

    def undetected_birth_log_ratio(self, n_in_view: int, n_objects: int) -> np.ndarray:
        b = np.arange(self.n_birth_regions + 1)
        out = np.full(len(b), -np.inf)
        free = b < self.n_birth_regions
        if self.alpha > 0:  # with α = 0 no birth is possible: the ratio stays −inf (not −inf − (−inf))
            out[free] = self._log_birth(b[free] + 1) - self._log_birth(b[free])
        return out

    def death_log_ratio(self, n_in_view: int, n_objects: int, p_survive=None) -> np.ndarray:
        """Over ``b``: ``log((1 − p_S) / p_S)``, the death twin's factor apart from the dead object's
        ``1 − p_D`` (Eq. 59); with the tracks' own ``p_survive`` ``(n_objects,)`` one column per object,
        ``(M_b + 1, n_objects)``."""
        with np.errstate(divide="ignore"):
            if p_survive is None:
                return np.full(self.n_birth_regions + 1, np.log1p(-self.p_survive) - np.log(self.p_survive))
            p = _per_track(p_survive, n_objects)
            return np.repeat((np.log1p(-p) - np.log(p))[None, :], self.n_birth_regions + 1, axis=0)

    def death_eligible(self, in_view: np.ndarray) -> np.ndarray:
        return np.ones(len(in_view), dtype=bool)


def _per_track(p_survive, n_objects: int) -> np.ndarray:
    p = np.asarray(p_survive, dtype=float)
    if p.shape != (n_objects,):
        raise ValueError(f"p_survive must hold one p_S per object, shape ({n_objects},), got {p.shape}")
    return p

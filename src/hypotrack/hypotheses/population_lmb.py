"""Labeled multi-Bernoulli population: the event space of the δ-GLMB joint prediction–update.

Vo, Vo & Hoang (IEEE TSP 65(8), 2017, Sec. III, Eq. 8–12) predict and update a δ-GLMB in one
step. Given a parent (label set ``I`` with Gaussian tracks) and a scan ``Z = (z_1 .. z_m)``
every *object* — each of the parent's ``M`` tracks and each of the ``B`` labeled-Bernoulli
birth terms — takes one value of an association map ``γ``:

=====================  ==========================================  ==============================
object                  ``γ = −1``                                   ``γ = 0`` / ``γ = j``
=====================  ==========================================  ==============================
existing track ``ℓ``    died: ``1 − p_S``                             ``p_S (1 − p_D)`` / ``p_S p_D g(z_j|ℓ) / κ(z_j)``
birth term ``b``        not born: ``1 − r_B``                         ``r_B (1 − p_D)`` / ``r_B p_D g_b(z_j) / κ(z_j)``
=====================  ==========================================  ==============================

(no two objects on one return), and the child's weight is the product ``Π_i η_i(γ_i)``
(their Eq. 12) times the parent's weight and the common factor ``e^{−λ} Π_j κ(z_j)``.
Survival is per object at every scan, in or out of view (out of view ``p_D = 0``: missed with
``p_S``). The weight model :class:`~.weights_glmb.GLMBWeights` writes this as an
:class:`~.AssociationProblem` whose *rows are the objects*; this module turns its events
back into the engine's children (:meth:`LabeledMultiBernoulliPopulation.children`).

How the three population models relate (DESIGN.md §4.7)
--------------------------------------------------------
Call a death or an undetected birth a *silent* event (it leaves the association untouched).

* Document 000's single-event model (Eq. 30) allows one birth *or* one death per scan per parent,
  with probabilities ``α`` and ``β`` that do not depend on the number of objects.
* Document 001's binomial model (Eq. 31–33, 59) has independent survival ``p_s`` per object and
  independent birth ``α`` per region — the labeled multi-Bernoulli probabilities with
  ``p_S = p_s`` and ``r_B = α`` — but generates at most **one** silent event per child.
* The labeled multi-Bernoulli (this module) generates every combination.

So with Poisson clutter (:class:`~.FISSTPoissonWeights`) the binomial filter's children are the
GLMB children with at most one silent event, **with identical weights**; the two coincide as
posteriors exactly when no child can hold two silent events (one object and no birth term, or no
object and one birth term), and otherwise the binomial filter misses exactly the mass of the GLMB
children with two or more. With ``p_S = 1`` and no birth term all three reduce to the
fixed-number posterior, which equals Reid's HOMHT (document 001 Sec. V-A). The single-event model
coincides with the others only when neither a birth nor a death is possible. Tests:
``tests/crosscheck/test_equivalence_glmb.py``.
"""

from __future__ import annotations

from dataclasses import InitVar, dataclass, field

import numpy as np

from .._validation import check_covariance, check_finite_array, check_probability
from ..association import gate_threshold
from ..gaussian import innovation_unchecked, update
from .association_problem import CLUTTER
from .children import feasible_events
from .hypothesis import ChildSet
from .population_events import _Population

__all__ = ["GaussianBirthTerm", "LabeledMultiBernoulliPopulation", "UnconfirmedDecay", "DIED", "MISSED", "MAX_OBJECTS"]

MISSED = -1  #: object code of "exists, not detected" (row option 0 of the labeled problem: always possible)
DIED = -2  #: object code of "died / not born" (row option 1; impossible when ``p_S = 1``)
MAX_OBJECTS = 62  #: tracks + birth terms whose silent-event mask fits an int64 (beyond: Python ints)


#: ``measurement.R`` as :func:`~.._validation.check_covariance` returned it, by its bits: an adaptive birth's terms are
#: made anew each scan (:meth:`GaussianBirthTerm.many`) with the same sensor noise, whose check (~30 µs) would repeat
_CHECKED_NOISE: dict = {}


def _checked_noise(R) -> np.ndarray:
    """``check_covariance(R, "measurement.R")`` (a copy of it): the same array for the same bits, the same error for a
    bad one (only a passed check is remembered)."""
    arr = np.asarray(R)
    key = (arr.dtype.str, arr.shape, arr.tobytes())
    sym = _CHECKED_NOISE.get(key)
    if sym is None:
        sym = check_covariance(R, "measurement.R")
        if len(_CHECKED_NOISE) >= 64:  # a handful of sensors: bounded all the same
            _CHECKED_NOISE.clear()
        _CHECKED_NOISE[key] = sym
    return sym.copy()


@dataclass(frozen=True, eq=False)
class GaussianBirthTerm:
    """Birth density ``N(mean, cov)`` of a labeled-Bernoulli birth term, observed through
    ``z = H x + v``, ``v ~ N(0, R)``.

    ``gate_probability`` (in (0, 1), optional) gates the term like a track: a return whose
    squared Mahalanobis distance to ``H mean`` under ``S = H cov Hᵀ + R`` exceeds the χ² quantile
    cannot be the birth's first detection (likelihood 0). Without it a Gaussian birth term may
    take any return of the scan, which couples every return with every object that gates it —
    the factored engine (:mod:`.factored`) would then have to merge all groups seeing a return.

    ``measurement`` (optional): a nonlinear measurement model (:class:`hypotrack.models.measurement.ExtendedMeasurement`,
    e.g. the catalogue radar's ``(ρ, az, el, ρ̇)``) in place of ``H``: the term is then observed through
    its EKF linearisation at ``mean`` (``ẑ = h(mean)``, ``S = H_m cov H_mᵀ + R``, ``H_m = ∂h/∂x(mean)``, the
    azimuth residual wrapped) and ``H`` is ignored (give ``None``). ``weight`` (in (0, 1], default 1): the
    term's share of a birth mixture (an admissible region's component, :mod:`.population_adaptive`); the
    adaptive birth gives the term the existence ``r_B × weight``.
    """

    mean: np.ndarray
    cov: np.ndarray
    H: np.ndarray
    R: np.ndarray
    gate_probability: float | None = None
    measurement: object = None
    weight: float = 1.0
    #: the moments and the model already checked and converted, in one batch (:meth:`many` alone passes it)
    _checked: InitVar[bool] = False

    def __post_init__(self, _checked=False):
        if _checked:
            return
        mean = check_finite_array(self.mean, "mean", ndim=1)
        object.__setattr__(self, "mean", mean)
        object.__setattr__(self, "cov", check_covariance(self.cov, "cov", dim=len(mean)))
        object.__setattr__(self, "weight", check_probability(self.weight, "weight", low_open=True))
        if self.measurement is not None:
            object.__setattr__(self, "R", _checked_noise(self.measurement.R))
            if self.gate_probability is not None:
                object.__setattr__(self, "gate_probability", check_probability(
                    self.gate_probability, "gate_probability", low_open=True, high_open=True))
            return
        H = check_finite_array(self.H, "H", ndim=2)
        if H.shape[1] != len(mean):
            raise ValueError(f"H must have {len(mean)} columns, got shape {H.shape}")
        object.__setattr__(self, "H", H)
        object.__setattr__(self, "R", check_covariance(self.R, "R", dim=H.shape[0]))
        if self.gate_probability is not None:
            object.__setattr__(self, "gate_probability", check_probability(
                self.gate_probability, "gate_probability", low_open=True, high_open=True))

    @classmethod
    def many(cls, means, covs, H, R, gate_probability=None, measurement=None, weights=None) -> list:
        """The terms ``N(means[i], covs[i])`` of weights ``weights[i]`` (default 1) observed alike: the same terms, and
        the same errors, as one constructor call each, with the shared model (``H``, ``R``, ``measurement``, the gate)
        checked once and the moments in one batch (an adaptive birth makes a few dozen terms a scan, each
        constructor call's checks ~50 µs)."""
        n = len(means)
        if n == 0:
            return []
        w = np.ones(n) if weights is None else np.asarray(weights, dtype=float).reshape(n)
        first = cls(means[0], covs[0], H, R, gate_probability, measurement, float(w[0]))  # the model's checks, once
        means = check_finite_array(means, "mean", ndim=2)
        covs = np.asarray(covs, dtype=float)
        d = means.shape[1]
        if covs.shape != (n, d, d):
            raise ValueError(f"cov must be {d}x{d}, got shape {covs.shape[1:]}")
        if not np.all(np.isfinite(covs)):
            raise ValueError("cov must be finite (no NaN or inf)")
        # check_covariance's tests matrix by matrix: asymmetry against each one's own scale, then Cholesky
        scale = np.maximum(1.0, np.abs(covs).max(axis=(1, 2)))
        asym = np.abs(covs - np.swapaxes(covs, 1, 2)).max(axis=(1, 2))
        if np.any(asym > 1e-8 * scale):
            raise ValueError(f"cov must be symmetric (max asymmetry {asym[np.argmax(asym > 1e-8 * scale)]:.3g})")
        sym = 0.5 * (covs + np.swapaxes(covs, 1, 2))
        try:
            np.linalg.cholesky(sym)
        except np.linalg.LinAlgError:
            raise ValueError("cov must be positive definite (Cholesky failed)") from None
        bad = ~((w > 0) & (w <= 1))
        if bad.any():
            raise ValueError(f"weight must lie in (0, 1], got {float(w[np.argmax(bad)])!r}")
        return [first] + [cls(means[i], sym[i], first.H, first.R, first.gate_probability, first.measurement, float(w[i]),
                              _checked=True) for i in range(1, n)]

    def loglik(self, Z) -> np.ndarray:
        """``log ∫ N(z; H x, R) N(x; mean, cov) dx = log N(z; H mean, H cov Hᵀ + R)`` per return."""
        Z = np.asarray(Z, dtype=float).reshape(-1, self.R.shape[0])
        # the term's moments and model were checked at construction (S = H cov Hᵀ + R is PD: R is)
        if self.measurement is None:
            z_pred, S, _ = (a[0] for a in innovation_unchecked(self.mean[None], self.cov[None], self.H, self.R))
            resid = Z - z_pred
        else:
            z_pred, S, _, _ = (a[0] for a in self.measurement.innovation(self.mean[None], self.cov[None]))
            resid = self.measurement.residual(Z, z_pred[None])[:, 0]
        L = np.linalg.cholesky(S)
        r = np.linalg.solve(L, resid.T)
        d2 = np.sum(r * r, axis=0)
        ll = -0.5 * d2 - np.sum(np.log(np.diag(L))) - 0.5 * len(z_pred) * np.log(2 * np.pi)
        if self.gate_probability is None:
            return ll
        return np.where(d2 <= gate_threshold(self.gate_probability, len(z_pred)), ll, -np.inf)

    def initial_state(self, z, R):
        """The born object's Gaussian: the birth density updated with its first return ``z``."""
        if self.measurement is not None:
            x, P = self.measurement.update(self.mean[None], self.cov[None], np.asarray(z, dtype=float)[None])
            return x[0], P[0]
        return update(self.mean, self.cov, z, self.H, R)

    def prior(self):
        return self.mean, self.cov


@dataclass(eq=False)
class LabeledMultiBernoulliPopulation(_Population):
    """Per-object survival ``p_S`` and labeled-Bernoulli births (the δ-GLMB event space).

    Parameters
    ----------
    birth_densities : sequence
        One density per birth term: :class:`GaussianBirthTerm`, or any birth pdf of
        :mod:`.population_events` (``loglik(Z)`` or a region with ``log_position_density``;
        ``initial_state(z, R)``).
    r_birth : float or sequence
        Existence probability ``r_B`` of each birth term, in (0, 1).
    p_survive : float
        ``p_S`` in (0, 1]; every object survives each scan with it, in view or not.
    survival : callable, optional
        ``survival(means (n, d), covs (n, d, d)) -> p_S (n,)`` in (0, 1] of each predicted track, in place of
        ``p_survive`` (e.g. :class:`UnconfirmedDecay`: a track never re-detected fades out).
    """

    birth_densities: tuple = ()
    r_birth: object = 0.0
    p_survive: float = 1.0
    survival: object = None
    undetected_cache: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        self.birth_densities = tuple(self.birth_densities)
        r = np.broadcast_to(np.asarray(self.r_birth, dtype=float), (self.n_birth_regions,)).copy()
        for x in r:
            check_probability(x, "r_birth", low_open=True, high_open=True)
        self.r_birth = r
        self.p_survive = check_probability(self.p_survive, "p_survive", low_open=True)
        if self.survival is not None and not callable(self.survival):
            raise TypeError(f"survival must be callable (means, covs -> p_S per track) or None, "
                            f"got {type(self.survival).__name__}")

    def restricted_to(self, regions):
        """This population with only birth terms ``regions`` and their ``r_B`` (see the base class)."""
        sub = super().restricted_to(regions)
        if sub is not self:
            sub.r_birth = self.r_birth[np.asarray(regions, dtype=np.int64)]
        return sub

    def with_birth_terms(self, terms, r_birth=None):
        """A copy with birth terms ``terms``, each of existence ``r_birth`` (in (0, 1), required)."""
        if r_birth is None:
            raise ValueError("r_birth is required: the existence probability of each new birth term")
        new = super().with_birth_terms(terms)
        r = np.broadcast_to(np.asarray(r_birth, dtype=float), (new.n_birth_regions,)).copy()
        if not np.all((r > 0) & (r < 1)):  # (one test over the terms; the first bad one named, as one by one)
            for x in r:
                check_probability(x, "r_birth", low_open=True, high_open=True)
        new.r_birth = r
        return new

    def log_existence(self, n_objects: int, p_survive=None):
        """``(log r, log(1 − r))`` per object row: ``p_S`` for the tracks (``p_survive`` (n_objects,) when
        given, else :attr:`p_survive`), ``r_B`` for births."""
        p_s = np.full(n_objects, self.p_survive) if p_survive is None else np.asarray(p_survive, dtype=float)
        r = np.concatenate([p_s, self.r_birth])
        with np.errstate(divide="ignore"):
            return np.log(r), np.log1p(-r)

    def children(self, weights, generator, ctx, tracks, log_weight, rng, keep=None, with_null: bool = False):
        """The parent's children: events, kind, arg and exact log-weights.

        The weight model builds the object-indexed problem (:meth:`GLMBWeights.labeled_problem`),
        the generator (exhaustive, Murty, Gibbs, MCMC) picks association maps ``γ``, and each is
        turned into the engine's return-indexed event plus a bit mask of its silent events
        (``ChildSet.POPULATION_SET``: bit ``j < M`` object ``j`` died, bit ``M + b`` birth term
        ``b`` born undetected). ``with_null``: the maps "every object missed, no birth" and "every object
        died, no birth" alone, where feasible (the engine's fallback when a search found no valid child).
        """
        if not hasattr(weights, "labeled_problem"):
            raise ValueError(f"a labeled multi-Bernoulli population needs GLMB weights, got {type(weights).__name__}")
        tracks = np.asarray(tracks, dtype=np.int64)
        M = len(tracks)
        log_r, log_not = self.log_existence(M, None if ctx.p_survive is None else ctx.p_survive[tracks])
        problem = weights.labeled_problem(ctx, tracks, log_r, log_not, log_weight)
        if with_null:  # the engine's fallback: "every object missed" and "every object died", no search
            nulls = np.full((2, M + ctx.n_birth_regions), DIED, dtype=np.int64)
            nulls[0, :M] = MISSED
            gammas, lw = feasible_events(problem, nulls)
        else:
            gammas, lw = generator.generate(problem, rng, keep=keep)
        events, masks = self.to_events(np.asarray(gammas), M, ctx.n_returns)
        kind = np.full(len(lw), ChildSet.POPULATION_SET, np.int64)
        return events, kind, masks, np.asarray(lw, dtype=float)

    @staticmethod
    def to_events(gammas, n_objects: int, n_returns: int):
        """Object-indexed maps ``γ`` (E, M + B) → return-indexed events (E, m) and silent masks."""
        gammas = np.asarray(gammas, dtype=np.int64).reshape(len(gammas), -1)
        E, P = gammas.shape
        events = np.full((E, n_returns), CLUTTER, dtype=np.int32)
        rows, objs = np.nonzero(gammas >= 0)
        events[rows, gammas[rows, objs]] = objs
        silent = np.zeros((E, P), dtype=bool)
        silent[:, :n_objects] = gammas[:, :n_objects] == DIED
        silent[:, n_objects:] = gammas[:, n_objects:] == MISSED
        if P <= MAX_OBJECTS:
            bits = np.left_shift(np.int64(1), np.arange(P, dtype=np.int64))
            return events, silent.astype(np.int64) @ bits
        # more objects than int64 bits: exact Python integers
        masks = np.empty(E, dtype=object)
        masks[:] = [sum(1 << int(j) for j in np.flatnonzero(row)) for row in silent]
        return events, masks


@dataclass(frozen=True)
class UnconfirmedDecay:
    """Survival of a track by whether it has been confirmed: a death model for objects born from the data.

    A track born from one return (one-point or admissible-region birth) has an undetermined velocity —
    only a second detection fixes it. A track never re-detected keeps that spread, grown by prediction, and
    is the trace of a clutter return or of an object that left; with ``p_S = 1`` it would live for ever.
    Here a track whose largest velocity standard deviation exceeds ``velocity_std`` is *tentative* and
    survives each scan with ``p_tentative``; a confirmed one with ``p_confirmed``. Out of view (nothing to
    re-detect it) a tentative track's existence after ``k`` scans is ``r p_tentative^k``: it falls below a
    pruning threshold ``w`` after ``ceil(log(w / r) / log p_tentative)`` scans; in view each miss multiplies
    its existence odds by ``p_tentative (1 − p_D)`` (the labeled multi-Bernoulli update of a missed track,
    Reuter, Vo, Vo & Dietmayer 2014). "Confirmed" is read from the track's own covariance, so the model needs no per-track
    bookkeeping and holds in every hypothesis alike (the M-of-N confirmation of single-hypothesis trackers
    needs the track history; Blackman & Popoli, *Design and Analysis of Modern Tracking Systems*, 1999).

    Parameters
    ----------
    p_tentative : float
        Per-scan survival of a tentative track, in (0, 1).
    velocity_std : float
        Largest velocity standard deviation (state units per second) of a confirmed track, > 0; e.g. 1 km/s
        against the 8 km/s of a one-point birth and ~0.1 km/s after a second position fix 10 s later.
    p_confirmed : float
        Per-scan survival of a confirmed track, in (0, 1]; default 1. Below 1 a catalogued track with no object
        behind it in view leaves too: with ``p_S = 1`` its existence ``r = 1`` is a fixed point of the miss
        update, with ``p_S < 1`` each miss multiplies its odds by about ``p_S (1 − p_D)``, while out of view
        ``r`` falls only as ``p_S^k`` (the factored engine keeps such tracks in its lane with
        ``bernoulli_lane``, :mod:`.factored.lane`).
    velocity_components : tuple of int
        The state components holding the velocity; default ``(3, 4, 5)`` (``[r, v]`` in 3-D).

    Examples
    --------
    >>> decay = UnconfirmedDecay(p_tentative=0.5, velocity_std=1.0)
    >>> covs = np.stack([np.diag([1, 1, 1, 64, 64, 64.0]), np.diag([1, 1, 1, 0.01, 0.01, 0.01])])
    >>> decay(np.zeros((2, 6)), covs).tolist()
    [0.5, 1.0]
    """

    p_tentative: float
    velocity_std: float
    p_confirmed: float = 1.0
    velocity_components: tuple = (3, 4, 5)

    def __post_init__(self):
        check_probability(self.p_tentative, "p_tentative", low_open=True, high_open=True)
        check_probability(self.p_confirmed, "p_confirmed", low_open=True)
        if not (np.isfinite(self.velocity_std) and self.velocity_std > 0):
            raise ValueError(f"velocity_std must be finite and > 0, got {self.velocity_std!r}")
        object.__setattr__(self, "velocity_components", tuple(int(i) for i in self.velocity_components))

    def __call__(self, means, covs) -> np.ndarray:
        """``p_S`` ``(n,)`` of tracks with covariances ``covs`` ``(n, d, d)``."""
        covs = np.asarray(covs, dtype=float)
        idx = list(self.velocity_components)
        var = np.diagonal(covs, axis1=1, axis2=2)[:, idx] if len(covs) else np.zeros((0, len(idx)))
        tentative = var.max(axis=1, initial=0.0) > self.velocity_std**2
        return np.where(tentative, self.p_tentative, self.p_confirmed)

"""The factored hypothesis engine: the posterior as a product of independent groups.

:class:`~.filter.HypothesisFilter` keeps *global* hypotheses: every parent's association problem
spans every object and every return, so the number of hypotheses — and the work per scan —
grows with the product of the ambiguities anywhere in view, although two objects whose gates
never share a return do not influence each other's weights. :class:`FactoredFilter` keeps the
posterior as a product of *groups* (Beard, Vo & Vo, "A solution for large-scale multi-object
tracking", IEEE TSP 68, 2020): each group is a hypothesis set over its own objects, run by the
engine's own machinery (any weight model × child generator × population, the same children,
duplicate merging, cap and Kalman updates), and a scan touches a group only through the
returns in its gate.

One ``step(Z)``
---------------
1. Predict every group's tracks (with ``lazy``, of the singletons only those that may be in
   view); score every return against them (the engine's
   :meth:`~.filter.HypothesisFilter._track_scores`, each (return, track) pair once). A group's
   *gate* is the set of returns inside the validation gate of any of its tracks, in any of its
   hypotheses (the engine's ``allowed``; the field of view enters through ``p_D``, not the gate,
   unless ``gate_out_of_view=False``, when a track out of view gates nothing).
2. Build the bipartite graph groups/singletons/birth terms — returns (components by
   :func:`scipy.sparse.csgraph.connected_components`; only the components a return or birth term
   reaches are visited in Python): a group is linked to the returns in
   its gate, a birth term (or birth region) to the returns it could be the first detection of
   (finite birth likelihood; see ``births``), and with HOMHT's seeded births each return in no
   gate becomes a node of its own (a new object or clutter). Its connected components are this
   scan's problems: groups in one component are **merged** (the product of their hypotheses,
   capped at ``H∞`` as the engine caps, :func:`.factored_groups.product`), receive the
   component's returns and birth terms, and take one engine step. A birth term linked to no
   return still forms a group (a birth that is not detected). Returns linked to nothing are
   clutter for every hypothesis: a common factor, dropped.
3. A group with no return and no birth term only predicts when that is exact (no population
   events and the same ``Π (1 − p_D)`` in all its hypotheses); otherwise it takes the engine's
   step on an empty scan (deaths, survival and missed detections change its weights).
4. **Split**: the objects of each group are partitioned by this scan's interaction (objects
   linked through a shared gated return, a newborn object with its birth term or return); if
   there are several parts the joint is compared with the product of its marginals
   (:func:`.factored_groups.factorise`). ``split="marginal"`` (Beard et al.'s method) splits
   always, exactly when the joint factorises and otherwise with the marginal-product
   approximation, whose KL and L1 losses are recorded (:attr:`split_records`, ``last_stats``);
   ``split="exact"`` splits off each part that is exactly independent of the rest of its group
   (one two-way check per part) and keeps the others together; ``split="never"`` keeps groups
   merged.

Singletons and lazy prediction
------------------------------
At catalogue scale nearly every group is a *singleton*: one object, one hypothesis, one track
(an object nothing has disturbed). With a population that can take no event in a quiet group
(``_silent``: none, or labeled multi-Bernoulli / binomial with ``p_S = 1``) a singleton is
exactly its Gaussian, so the filter keeps all singletons in one batched *lane* (means,
covariances, labels, the time each was last predicted to) instead of one Python object each;
a scan costs Python work only for the groups and singletons a return or birth term reaches,
and a step's results that are singletons go back to the lane. The lane changes no number.
With ``lazy=True`` a singleton is predicted only when it may be observed: each scan the lane's
means at the last scan (not covariances) are advanced by one scan interval, and only the singletons whose
predicted position is inside the sensor's field of view (``p_D > 0``) are predicted in full
(mean and covariance, over the whole gap since their last prediction) and scored. A track out
of view can take no return, so this changes the posterior only through the process noise: one
EKF prediction over a gap of ``k`` scans adds ``Q(kΔ)`` where ``k`` predictions add
``Σ Φ Q(Δ) Φᵀ`` (equal for a linear constant-velocity model, a few per cent apart on an
orbit over minutes). The means are exact either way for the Kepler model; a numerically integrated
one (``J2Orbit3D``) advances the lane's means scan by scan and a candidate's over its whole gap, equal
up to its integration error.
The same holds for a multi-hypothesis group (an object whose existence or association is still
open) whose tracks are all out of view: it is left as it was, its means advanced a scan at a time
in the same batch, and predicted over its whole gap when one of its tracks may be seen again. At
catalogue scale these groups accumulate out of view (nothing resolves them there) and would otherwise
be predicted and visited every scan. :attr:`~FactoredFilter.posterior` and
:attr:`~FactoredFilter.groups` predict the lazy singletons and groups to the current scan.

When the factored posterior equals the unfactored one
-----------------------------------------------------
The joint children of a product of groups are the products of the groups' children exactly
when each child's weight is a product of per-group factors and no return is open to two
groups — the second holds by construction, the first is a property of the model:

* **separable** (exact, tested in ``tests/crosscheck/test_equivalence_factored.py``): the δ-GLMB
  weights with the labeled multi-Bernoulli population (Vo, Vo & Hoang 2017: ``Π_i η_i(γ_i)``;
  each birth term is given to one group per scan), and Reid's HOMHT with a fixed number of
  objects or Poisson births seeded at returns (document 001 Eq. 30, 35: a product over returns and
  objects), and FISST with Poisson clutter (document 001 Eq. 6–7); all as long as no cap binds
  (each group keeps ``H∞`` hypotheses, so the factored filter keeps more joint hypotheses than
  the unfactored one) and every split was exact. A split after a real interaction is never
  exact: the joint lacks the configurations where both groups took the shared return.
* **not separable** (the factored filter is a different approximation): H-FISST's count term
  ``−log(m!/(m − n)!)`` (document 000 Eq. 8) counts the returns of the whole scan, and a group sees
  its own; document 001's binomial population allows one silent event per child, i.e. per group
  here; document 000's **single-event** population (one birth or one death per scan for the whole
  scene, Eq. 30) couples every object through ``P(no event) = 1 − M_b α − M_d β``. The factored
  engine applies the event model **per group** — one event per group and scan, ``M_d`` the
  group's objects in view — which changes the prior: with ``G`` groups up to ``G`` events
  per scan can happen, and no-event children weigh ``1 − M_b α − M_d,g β`` per group instead
  of ``1 − M_b α − M_d β`` overall. :func:`cardinality_total_variation` measures the effect;
  the test reports it on a small scene.
"""

from __future__ import annotations

import copy
import pickle
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .._validation import check_finite_array, check_int, check_measurements, check_positive
from .factored_groups import GroupState, SplitRecord, compact, components, factorise, product, restrict_population
from ..gaussian import _predict_with, symmetrize
from .filter import HypothesisFilter
from .population_events import BinomialPopulation
from .population_lmb import GaussianBirthTerm, LabeledMultiBernoulliPopulation
from .posterior import HypothesisEstimate, summarise
from .scan_context import ScanContext
from .tracks import TrackStore

__all__ = ["AdaptiveBirth", "FactoredFilter", "FactoredPosterior", "cardinality_total_variation"]

_SPLITS = ("marginal", "exact", "never")
_BIRTHS = ("coupled", "free")
_PARALLEL = ("process", "thread")


class FactoredPosterior:
    """The product posterior as a summary (each part computed when first read).

    Attributes
    ----------
    groups : per group, its :class:`~.posterior.Posterior` (the multi-hypothesis groups first,
        then the singletons in lane order).
    n_groups : the number of groups.
    cardinality : ``P(n objects)``, the convolution of the groups' cardinality distributions
        (a singleton shifts it by one).
    expected_number : the sum of the groups' expected numbers.
    map_estimate : the union of the groups' MAP hypotheses — the MAP of a product of
        independent distributions — with weight the product of theirs.
    """

    def __init__(self, states, singles, n_singles: int, n_top: int = 1, n_states: int | None = None):
        # states, singles: the groups and the lane's TrackStore, or functions giving them (lazy
        # groups and singletons are predicted to the scan only when a summary that needs them is read)
        self._get_states, self._get_singles, self._n_singles, self._n_top = states, singles, n_singles, n_top
        self._n_states = len(states) if n_states is None else n_states

    @cached_property
    def _states(self) -> tuple:
        return tuple(self._get_states() if callable(self._get_states) else self._get_states)

    @cached_property
    def _singles(self) -> TrackStore:
        return self._get_singles() if callable(self._get_singles) else self._get_singles

    @cached_property
    def _posts(self) -> tuple:
        return tuple(summarise(s.log_w, s.tracks, s.store, n_top=self._n_top) for s in self._states)

    @cached_property
    def groups(self) -> tuple:
        one, single = np.zeros(1), [np.zeros(1, dtype=np.int64)]
        L = self._singles
        return self._posts + tuple(
            summarise(one, single, TrackStore(L.means[[j]], L.covs[[j]], L.labels[[j]]), n_top=1) for j in range(len(L)))

    @property
    def n_groups(self) -> int:
        return self._n_states + self._n_singles

    @cached_property
    def cardinality(self) -> np.ndarray:
        card = np.zeros(self._n_singles + 1)
        card[-1] = 1.0
        for p in self._posts:
            card = np.convolve(card, p.cardinality)
        return card

    @cached_property
    def expected_number(self) -> float:
        return float(sum(p.expected_number for p in self._posts) + self._n_singles)

    @cached_property
    def map_estimate(self) -> HypothesisEstimate:
        maps = [p.map_estimate for p in self._posts]
        L = self._singles
        lw = float(sum(e.log_weight for e in maps))
        return HypothesisEstimate(
            float(np.exp(lw)), lw,
            np.concatenate([e.labels for e in maps] + [L.labels]),
            np.concatenate([e.means for e in maps] + [L.means]),
            np.concatenate([e.covs for e in maps] + [L.covs]),
        )


def cardinality_total_variation(p, q) -> float:
    """``½ Σ_n |p(n) − q(n)|`` between two cardinality distributions (zero-padded)."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    n = max(len(p), len(q))
    return 0.5 * float(np.abs(np.pad(p, (0, n - len(p))) - np.pad(q, (0, n - len(q)))).sum())


def _silent(population) -> bool:
    """Whether a group without birth terms can take no population event: no population, or the
    labeled multi-Bernoulli or binomial population with ``p_S = 1`` (its only child of an empty scan is "every object
    missed", as with no population)."""
    return population is None or (isinstance(population, (LabeledMultiBernoulliPopulation, BinomialPopulation))
                                  and population.p_survive == 1.0)


def _predict_each(motion, x, P, dt):
    """EKF prediction of ``(x, P)`` by their own intervals ``dt`` (n,): the motion model's
    ``transition_each``/``Q_each`` where it has them (one batch), else one batch per distinct
    interval (a zero interval leaves a track as it is)."""
    if len(dt) and np.all(dt == dt[0]):
        return _predict_with(motion, x, P, float(dt[0])) if dt[0] != 0 else (x.copy(), P.copy())
    if hasattr(motion, "transition_each"):  # one batch for every interval (a zero one is the identity)
        xo, F = motion.transition_each(x, dt)
        return xo, symmetrize(F @ P @ np.swapaxes(F, -1, -2) + motion.Q_each(dt))
    xo, Po = x.copy(), P.copy()
    for u in np.unique(dt):
        if u != 0:
            sel = dt == u
            xo[sel], Po[sel] = _predict_with(motion, x[sel], P[sel], float(u))
    return xo, Po


def _singleton(store: TrackStore, j) -> GroupState:
    """The group of store entry ``j`` alone: one hypothesis holding one track."""
    return GroupState(TrackStore(store.means[[j]], store.covs[[j]], store.labels[[j]]), np.zeros(1),
                      [np.zeros(1, dtype=np.int64)], [()])


def _is_singleton(state: GroupState) -> bool:
    return len(state.log_w) == 1 and len(state.store) == 1 and len(state.tracks[0]) == 1


def _take(store: TrackStore, idx) -> TrackStore:
    return TrackStore(store.means[idx], store.covs[idx], store.labels[idx])


def _cat(stores, ndim) -> TrackStore:
    stores = [s for s in stores if len(s)]
    if not stores:
        return TrackStore(np.zeros((0, ndim)), np.zeros((0, ndim, ndim)), np.zeros(0, dtype=np.int64))
    if len(stores) == 1:
        return stores[0]
    return TrackStore(*(np.concatenate([getattr(s, f) for s in stores]) for f in ("means", "covs", "labels")))


def _empty_state(ndim: int) -> GroupState:
    return GroupState(TrackStore.from_arrays(np.zeros((0, ndim)), None, ndim=ndim), np.zeros(1),
                      [np.zeros(0, dtype=np.int64)], [()])


@dataclass(frozen=True)
class AdaptiveBirth:
    """Measurement-driven birth: every return no group explained starts a birth term at the next scan.

    Reuter, Vo, Vo & Dietmayer ("The labeled multi-Bernoulli filter", IEEE TSP 62(12), 2014,
    Sec. IV-C) let the birth at scan ``k + 1`` depend on the returns of scan ``k``: a return
    ``z`` gives a labeled-Bernoulli birth term placed at ``z`` with existence ``r_B(z)``
    proportional to ``1 − r_U(z)``, ``r_U(z)`` the probability that ``z`` was associated with
    an existing object. Here ``r_U`` is taken as 0 or 1 from the gates: a return in no group's
    gate and in no birth term's gate (the engine's *unexplained* returns) gives a term of
    existence ``r_birth``; a return in a gate gives none.

    The term of a return ``z`` at scan ``k`` is the one-point initiation ``x₀ = H⁺ z``,
    ``P₀ = H⁺ R H⁺ᵀ + diag(s²)`` (``s`` = ``position_std`` on the measured state components,
    ``velocity_std`` on the others, e.g. zero velocity with a spread covering every orbit's
    speed) predicted by the motion model over the scan interval (EKF, so the position spread at
    ``k + 1`` is ``√(σ_z² + s_p² + Δt² s_v²)`` with the position–velocity correlation that lets
    the second return fix the velocity). Each term is gated with ``gate_probability`` (a
    :class:`~.population_lmb.GaussianBirthTerm`), so it couples only the returns near it and the
    groups gating them: a new object is born inside its own group.

    An object first detected at scan ``k`` is born at the first scan after ``k`` at which it is
    detected again right after a detection — when the hypothesis "born undetected" (weight
    ``r_B (1 − p_D)`` relative to not born) is pruned at once (``min_weight`` above it); kept, it
    can pick the object up later — so with independent detections of probability ``p_D`` the number of scans from its first chance of detection to its birth is
    ``1/p_D + 1/p_D² − 1`` on average (the waiting time for two successes in a row, less one).

    Parameters
    ----------
    position_std : float
        Extra position spread of a term (state units, ≥ 0), added to the return's own noise.
    velocity_std : float
        Spread of each unmeasured component (state units per second), > 0.
    r_birth : float
        Existence probability of each term (labeled multi-Bernoulli ``r_B``) in (0, 1); a
        binomial population uses its own ``alpha``.
    gate_probability : float
        Gate of each term, in (0, 1).
    """

    position_std: float = 0.0
    velocity_std: float = 1.0
    r_birth: float = 0.01
    gate_probability: float = 0.999

    def __post_init__(self):
        if not (np.isfinite(self.position_std) and self.position_std >= 0):
            raise ValueError(f"position_std must be finite and >= 0, got {self.position_std!r}")
        check_positive(self.velocity_std, "velocity_std")
        if not 0.0 < float(self.r_birth) < 1.0:
            raise ValueError(f"r_birth must lie in (0, 1), got {self.r_birth!r}")
        if not 0.0 < float(self.gate_probability) < 1.0:
            raise ValueError(f"gate_probability must lie in (0, 1), got {self.gate_probability!r}")

    def initial(self, Z, H, R):
        """One-point initiation ``(x₀ (m, d), P₀ (m, d, d))`` of returns ``Z`` (m, p)."""
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        Hp = np.linalg.pinv(H)
        measured = np.any(H != 0, axis=0)
        s = np.where(measured, self.position_std, self.velocity_std)
        P0 = Hp @ R @ Hp.T + np.diag(s**2)
        return Z @ Hp.T, np.broadcast_to(P0, (len(Z), *P0.shape)).copy()

    def terms(self, Z, H, R, motion, dt) -> list:
        """The birth terms of the next scan: the one-point initiations of ``Z`` predicted by ``dt``."""
        if len(Z) == 0:
            return []
        x0, P0 = self.initial(Z, H, R)
        x, P = _predict_with(motion, x0, P0, dt)
        return [GaussianBirthTerm(x[i], P[i], H, R, self.gate_probability) for i in range(len(x))]


@dataclass(frozen=True)
class _Scores:
    """A scan's scores of the predicted tracks: ``loglik``, ``allowed`` (m, n), ``p_detect`` (n,)."""

    loglik: np.ndarray
    allowed: np.ndarray
    p_detect: np.ndarray

    def columns(self, cols):
        """``(loglik (m, c), allowed (m, c), p_detect (c,))`` of tracks ``cols``."""
        return self.loglik[:, cols], self.allowed[:, cols], self.p_detect[cols]


_STEP_STATS = ("n_duplicates_merged", "mass_retained", "n_kalman_updates")


def _engine_step(T, state, pred, ctx, regions, base, seed):
    """One group's engine step (the unit of work of a scan, run in any worker).

    ``T``: the filter's template engine (models, population); ``state``: the group's hypotheses;
    ``pred``: its predicted tracks; ``ctx``: the returns of its gate and their scores;
    ``regions``: its birth terms; new labels count from ``base``; ``seed`` seeds the step's own
    random stream. Returns ``(new GroupState, track sources, number of new labels, stats)``.
    """
    g = object.__new__(HypothesisFilter)
    g.__dict__.update(T.__dict__)
    g.population = restrict_population(T.population, regions)
    g.rng = np.random.Generator(np.random.PCG64(seed))
    g._store, g._log_w, g._tracks, g._keys = state.store, state.log_w, state.tracks, state.keys
    g._next_label = base
    g.last_stats, g.last_kept, g.last_track_sources = {}, None, None
    g._advance(pred, ctx, time.perf_counter())
    return (GroupState(g._store, g._log_w, g._tracks, g._keys), g.last_track_sources, g._next_label - base,
            {k: g.last_stats[k] for k in _STEP_STATS})


def _run_jobs(T, jobs):
    return [_engine_step(T, *job) for job in jobs]


def _warm_worker():
    """Initialise numba's typing and target contexts in this worker (done once per process)."""
    from numba.core.registry import cpu_target

    cpu_target.typing_context.refresh()
    cpu_target.target_context.refresh()
    time.sleep(0.05)  # every worker gets a task


def _run_pickled(model, blob):
    """A process worker's chunk: the pickled template and jobs in, the pickled results and the
    worker's CPU seconds out."""
    t0 = time.process_time()
    out = _run_jobs(pickle.loads(model), pickle.loads(blob))
    return pickle.dumps((out, time.process_time() - t0), protocol=pickle.HIGHEST_PROTOCOL)


class FactoredFilter:
    """Hypothesis filter whose posterior is a product of independent groups (module docstring).

    Parameters
    ----------
    motion, sensor, weights, generator, population, dt, max_hypotheses, cap, gate_probability, seed :
        As :class:`~.filter.HypothesisFilter`; ``max_hypotheses`` caps each group (and each merge).
    means, covs, labels : array_like, optional
        Initial objects, one group each.
    split : {"marginal", "exact", "never"}
        When groups whose objects no longer interact are split (module docstring).
    births : {"coupled", "free"}
        ``"coupled"``: a birth term is linked to every return it could be the first detection
        of (exact). ``"free"``: only to returns in no group's gate — returns near an existing
        object are never births (an approximation unless the birth terms and the gates are
        disjoint); use it for birth pdfs that cover the whole view (document 000/001 regions),
        which would otherwise merge every group with a return into one.
    factor_tol : float
        Largest ``|log P − log Π marginals|`` for a split to count as exact (> 0).
    min_weight : float
        Hypotheses of a group below this normalised weight are dropped after each scan
        (in [0, 1); 0 keeps all — needed for exactness; > 0 stops undetected-birth groups of
        negligible existence from accumulating).
    adaptive_birth : AdaptiveBirth, optional
        Measurement-driven birth: the returns a scan leaves unexplained become the next scan's
        birth terms (:class:`AdaptiveBirth`). Needs a population with no birth terms of its own
        (labeled multi-Bernoulli or binomial), whose terms it then sets every scan.
    workers : int
        Processes (or threads) sharing a scan's engine steps (≥ 1). The components of a scan are
        independent problems; ``workers = 1`` runs them here, in order; more splits them into
        ``workers`` chunks of similar cost (hypotheses × returns), one run here and the others in
        a pool. Each step draws from its own random stream (seeded from the filter's generator,
        in component order) and new labels are renumbered in component order, so the posterior
        is the same for any ``workers``. Call :meth:`close` to stop the pool.
    parallel : {"process", "thread"}
        Pool kind: processes (the template engine and the groups' states pickled each scan) or
        threads (useful only where the step's kernels release the GIL).
    measure_transfer : bool
        Record in ``last_stats`` the pickled bytes of the steps' inputs (``bytes_to_workers``: the
        groups' hypotheses, track moments and the returns of their gates) and results
        (``bytes_from_workers``) even when ``workers = 1``.
    lazy : bool
        Predict a singleton, or a group, only when the predicted mean of one of its tracks is in the
        field of view (module docstring, "Singletons and lazy prediction"); ``False`` (default)
        predicts every track every scan, as the unfactored engine does. A track left unpredicted
        gates nothing.
    gate_out_of_view : bool
        ``True`` (default): a track's gate is geometric, the field of view entering only through
        ``p_D`` — a track out of view still links the returns in its gate to its group (a merge
        that changes no weight, since it cannot take them, and is split again exactly).
        ``False``: a track whose predicted mean is out of view (``p_D = 0``) gates nothing. The
        posterior is the same; only merges that cannot matter are avoided — at catalogue scale an
        undetected newborn out of view, whose covariance grows by ~80 km a scan, otherwise gates
        every return in view and merges every object there into one group.

    Attributes
    ----------
    last_stats : dict
        Of the last scan: ``n_groups``, ``largest_group`` (objects), ``largest_group_hypotheses``,
        ``n_touched`` (groups stepped with returns or birth terms), ``n_predict_only`` (groups
        only predicted, or with ``lazy`` left for later), ``n_singletons`` (groups in the lane),
        ``n_predicted`` (tracks predicted this scan), ``n_asleep`` (groups left unpredicted, ``lazy``),
        ``n_merges`` (groups merged away), ``n_splits``, ``n_exact_splits``, ``split_kl`` and
        ``split_l1`` (summed losses of this scan's splits), ``n_duplicates_merged``,
        ``n_kalman_updates``, ``mass_retained_min`` (smallest share of its children's mass a
        touched group kept under the cap), ``n_jobs`` (engine steps), ``time_steps`` (wall seconds running them), ``time_total``; with a process
        pool or ``measure_transfer``, ``bytes_to_workers``/``bytes_from_workers`` (and
        ``bytes_model``, the template sent to the pool; ``worker_cpu_s``, the pool processes' CPU seconds).
    stats_history : list of the ``last_stats`` of every scan.
    split_records : list of :class:`~.factored_groups.SplitRecord`, every split (and, with
        ``split="exact"``, every rejected one), with its KL and L1 loss.
    """

    def __init__(self, motion, sensor, weights, generator, *, population=None, dt=1.0, max_hypotheses=100,
                 cap="top", gate_probability=None, seed=None, means=None, covs=None, labels=None,
                 split="marginal", births="coupled", factor_tol=1e-10, min_weight=0.0, merge_duplicates=True,
                 adaptive_birth=None, workers=1, parallel="process", measure_transfer=False, lazy=False,
                 gate_out_of_view=True):
        template = HypothesisFilter(motion, sensor, weights, generator, population=population, dt=dt,
                                    max_hypotheses=max_hypotheses, cap=cap, gate_probability=gate_probability,
                                    seed=seed, merge_duplicates=merge_duplicates)
        self._configure(template, split, births, factor_tol, min_weight, adaptive_birth, workers, parallel,
                        measure_transfer, lazy, gate_out_of_view)
        self.initialise(np.zeros((0, self.ndim)) if means is None else means, covs, labels)

    @classmethod
    def from_filter(cls, f: HypothesisFilter, **options) -> "FactoredFilter":
        """The factored form of a configured engine (e.g. a preset) and its current posterior.

        ``f``'s configuration is used and its random generator copied (``f`` is not changed).
        Its hypotheses become one group, split exactly into one group per object where the
        joint factorises (a single hypothesis always does). ``options``: ``split``, ``births``,
        ``factor_tol``, ``min_weight``, ``adaptive_birth``, ``workers``, ``parallel``,
        ``measure_transfer``, ``lazy``, ``gate_out_of_view``.
        """
        if not isinstance(f, HypothesisFilter):
            raise TypeError(f"f must be a HypothesisFilter, got {type(f).__name__}")
        allowed = ("split", "births", "factor_tol", "min_weight", "adaptive_birth", "workers", "parallel",
                   "measure_transfer", "lazy", "gate_out_of_view")
        unknown = set(options) - set(allowed)
        if unknown:
            raise ValueError(f"unknown options {sorted(unknown)}; allowed: {', '.join(allowed)}")
        template = object.__new__(HypothesisFilter)
        template.__dict__.update(f.__dict__)
        template.rng = copy.deepcopy(f.rng)
        obj = cls.__new__(cls)
        obj._configure(template, options.get("split", "marginal"), options.get("births", "coupled"),
                       options.get("factor_tol", 1e-10), options.get("min_weight", 0.0),
                       options.get("adaptive_birth"), options.get("workers", 1), options.get("parallel", "process"),
                       options.get("measure_transfer", False), options.get("lazy", False),
                       options.get("gate_out_of_view", True))
        obj._reset()
        state = GroupState(f.store, f.log_weights, f.track_lists, f.lineage_keys)
        groups = [state] if any(len(t) for t in state.tracks) else []
        if groups and len(state.labels) > 1:
            record, parts = factorise(state, np.searchsorted(state.labels, state.store.labels), obj.factor_tol)
            if record.exact:
                groups = parts
        obj._groups, obj._lane = obj._sort_out(groups)
        obj._group_t = np.zeros(len(obj._groups))
        obj._group_view = [s.store.means for s in obj._groups]
        obj._lane_t = np.zeros(len(obj._lane))
        obj._lane_view = obj._lane.means.copy()
        obj._next_label = f._next_label
        obj.scan_index = f.scan_index
        return obj

    def _configure(self, template, split, births, factor_tol, min_weight, adaptive_birth=None, workers=1,
                   parallel="process", measure_transfer=False, lazy=False, gate_out_of_view=True):
        if split not in _SPLITS:
            raise ValueError(f"split must be one of {_SPLITS}, got {split!r}")
        if births not in _BIRTHS:
            raise ValueError(f"births must be one of {_BIRTHS}, got {births!r}")
        factor_tol = check_positive(factor_tol, "factor_tol")
        min_weight = float(min_weight)
        if not 0.0 <= min_weight < 1.0:
            raise ValueError(f"min_weight must lie in [0, 1), got {min_weight!r}")
        if adaptive_birth is not None:
            if not isinstance(adaptive_birth, AdaptiveBirth):
                raise TypeError(f"adaptive_birth must be an AdaptiveBirth or None, got {type(adaptive_birth).__name__}")
            if template.weights.seeded_births:
                raise ValueError("adaptive_birth needs a population with birth terms; HOMHT's seeded births already "
                                 "start objects at returns (use one of the two)")
            if template.population is None or not hasattr(template.population, "birth_densities"):
                raise ValueError("adaptive_birth needs a population (labeled multi-Bernoulli or binomial) whose "
                                 "birth terms it sets each scan")
            if template.population.n_birth_regions:
                raise ValueError("adaptive_birth sets the population's birth terms itself: give a population "
                                 f"with no birth terms, got {template.population.n_birth_regions}")
            template.population = copy.copy(template.population)  # its birth terms change every scan
            template.population._undetected_cache = {}
        if parallel not in _PARALLEL:
            raise ValueError(f"parallel must be one of {_PARALLEL}, got {parallel!r}")
        self.workers = check_int(workers, "workers", minimum=1)
        self.parallel, self.measure_transfer, self._pool = parallel, bool(measure_transfer), None
        self.adaptive_birth = adaptive_birth
        self._template = template
        self.rng = template.rng
        self.split, self.births, self.factor_tol, self.min_weight = split, births, factor_tol, min_weight
        self.ndim = template.H.shape[1]
        self.lazy = bool(lazy)
        self.gate_out_of_view = bool(gate_out_of_view)
        # singletons are exactly their Gaussian when a quiet group takes no population event
        self._lane_on = _silent(template.population)

    def _reset(self):
        if getattr(self, "adaptive_birth", None) is not None:
            self._set_birth_terms([])
        self._groups = []
        self._group_t = np.zeros(0)  # the time each group's tracks were last predicted to (lazy: may lag)
        self._group_view = []  # each group's track means at _time (lazy groups: advanced a scan at a time)
        self._lane = _cat([], self.ndim)  # the singletons (module docstring), at the times _lane_t
        self._lane_t = np.zeros(0)
        self._lane_view = np.zeros((0, self.ndim))  # the lane's means at _time (module docstring)
        self._time = 0.0
        self._object = {}  # label -> object id, for labels that are not their own object
        self._next_label = 0
        self.scan_index = 0
        self.last_stats = {}
        self.stats_history = []
        self.split_records = []

    # ------------------------------------------------------------------ state
    def initialise(self, means, covs=None, labels=None):
        """One group per object (``n = 0`` allowed), each with its single hypothesis."""
        self._reset()
        d = self.ndim
        means = np.asarray(means, dtype=float)
        if means.size == 0:
            return
        means = check_finite_array(np.atleast_2d(means), "means", shape=(None, d))
        if covs is None:
            raise ValueError("covs are required with means")
        store = TrackStore.from_arrays(means, covs, labels)
        if len(np.unique(store.labels)) != len(store):
            raise ValueError("labels must be distinct (one per object)")
        if self._lane_on:
            self._lane, self._lane_t, self._lane_view = store, np.zeros(len(store)), store.means.copy()
        else:
            self._groups = [_singleton(store, j) for j in range(len(store))]
            self._group_t = np.zeros(len(store))
            self._group_view = [s.store.means for s in self._groups]
        self._next_label = int(store.labels.max()) + 1

    @property
    def groups(self) -> list:
        """The groups' states (:class:`~.factored_groups.GroupState`): the multi-hypothesis
        groups, then the singletons (predicted to the current scan), as a new list."""
        lane = self._lane_now()
        return self._groups_now() + [_singleton(lane, j) for j in range(len(lane))]

    def _sort_out(self, states):
        """``(groups, lane)``: the singletons of ``states`` moved to a lane store (when the lane is on)."""
        if not self._lane_on:
            return list(states), _cat([], self.ndim)
        single = [_is_singleton(s) for s in states]
        return ([s for s, x in zip(states, single) if not x],
                _cat([s.store for s, x in zip(states, single) if x], self.ndim))

    def _groups_now(self) -> list:
        """The multi-hypothesis groups predicted to the current scan (only lazy ones move)."""
        out = list(self._groups)
        for g in np.flatnonzero(self._group_t != self._time):
            s = out[g]
            x, P = _predict_each(self._template.motion, s.store.means, s.store.covs,
                                 np.full(len(s.store), self._time - self._group_t[g]))
            out[g] = GroupState(TrackStore(x, P, s.store.labels), s.log_w, s.tracks, s.keys)
        return out

    def _lane_now(self) -> TrackStore:
        """The singletons predicted to the current scan (only lazy ones move)."""
        gap = self._time - self._lane_t
        if not np.any(gap):
            return self._lane
        x, P = _predict_each(self._template.motion, self._lane.means, self._lane.covs, gap)
        return TrackStore(x, P, self._lane.labels)

    @property
    def n_objects_held(self) -> int:
        """Objects (labels) held by some hypothesis of some group."""
        return int(sum(len(s.labels) for s in self._groups) + len(self._lane))

    @property
    def n_joint_hypotheses(self) -> int:
        """Hypotheses of the product (``Π_g H_g``, exact integer)."""
        return int(np.prod([len(s.log_w) for s in self._groups], dtype=object)) if self._groups else 1

    # ------------------------------------------------------------------ scan
    def step(self, Z, dt=None) -> FactoredPosterior:
        """Advance one scan with returns ``Z`` (m, p); all-or-nothing like the engine's step."""
        saved = (self._groups, self._group_t, self._group_view, self._lane, self._lane_t, self._lane_view, self._time, self._next_label, self.scan_index,
                 self.rng.bit_generator.state, self.last_stats, len(self.stats_history), len(self.split_records),
                 dict(self._object))
        pop = self._template.population
        terms = pop.birth_densities if self.adaptive_birth is not None else None
        try:
            return self._step(Z, dt)
        except BaseException:
            (self._groups, self._group_t, self._group_view, self._lane, self._lane_t, self._lane_view, self._time, self._next_label, self.scan_index, rng_state,
             self.last_stats, n_hist, n_split, self._object) = saved
            if terms is not None:
                self._set_birth_terms(terms)
            self.rng.bit_generator.state = rng_state
            del self.stats_history[n_hist:], self.split_records[n_split:]
            raise

    def _context(self, Z, rows, scores, birth_ll, regions) -> ScanContext:
        T = self._template
        loglik, allowed, p_detect = scores
        clutter = T.sensor.clutter
        return ScanContext(Z=Z[rows], loglik=loglik[rows], allowed=allowed[rows], p_detect=p_detect,
                           birth_loglik=birth_ll[np.ix_(rows, regions)], p_detect_birth=T.p_D,
                           clutter_rate=float(clutter.rate), clutter_volume=float(clutter.region.area))

    def _step(self, Z, dt):
        t0 = time.perf_counter()
        T = self._template
        dt = T.dt if dt is None else check_positive(dt, "dt")
        Z = check_measurements(Z, "Z", T.H.shape[0])
        m, groups, d = len(Z), self._groups, self.ndim
        now = self._time + dt
        # 1. predict the groups and the singletons that may be observed (lazy: those in view); score them
        groups, group_gap, asleep = self._wake(groups, dt, now)
        G = len(groups)
        sizes = np.array([len(s.store) for s in groups], dtype=np.int64)
        bounds = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        lane, gap, view = self._lane, now - self._lane_t, None
        if self.lazy and len(lane):
            # the lane's means advanced one scan (one batch, one interval): the in-view test costs one
            # short propagation per singleton whatever its gap since its last full prediction
            view, seen = self._advance_view(self._lane_view, dt)
            cand = np.flatnonzero(seen)
        else:
            cand = np.arange(len(lane))
        L = len(cand)
        prior = _cat([s.store for s in groups] + [_take(lane, cand)], d)
        pm, pP = _predict_each(T.motion, prior.means, prior.covs, np.concatenate([np.repeat(group_gap, sizes), gap[cand]]))
        pred = TrackStore(pm, pP, prior.labels)
        scores = self._scores(pred, Z)
        birth_ll = T.population.birth_loglik(Z) if T.population is not None else np.zeros((m, 0))
        B = birth_ll.shape[1]
        # 2. the bipartite graph groups/singletons/birth terms/seeded returns — returns
        col_node = np.concatenate([np.repeat(np.arange(G), sizes), G + np.arange(L)]).astype(np.int64)
        gr, c_a = np.nonzero(scores.allowed)
        gi = col_node[c_a]
        explained = np.zeros(m, dtype=bool)
        explained[gr] = True
        bgate = np.isfinite(birth_ll)
        if self.births == "free":
            bgate &= ~explained[:, None]
        unexplained = ~explained & ~bgate.any(axis=1)
        free = np.flatnonzero(unexplained) if T.weights.seeded_births else np.zeros(0, int)
        bi, br = np.nonzero(bgate.T)
        n_nodes = G + L + B + len(free)
        node = np.concatenate([gi, G + L + bi, G + L + B + np.arange(len(free))])
        ret = np.concatenate([gr, br, free])
        n_comp, lab = components(n_nodes, m, node, ret)
        node_lab, ret_lab = lab[:n_nodes], lab[n_nodes:]
        touched = np.zeros(n_comp, dtype=bool)
        touched[ret_lab] = True
        touched[node_lab[G + L:G + L + B]] = True

        stats = dict(n_touched=0, n_merges=0, n_splits=0, n_exact_splits=0, split_kl=0.0, split_l1=0.0,
                     n_duplicates_merged=0, n_kalman_updates=0, n_predict_only=0, mass_retained_min=1.0,
                     n_predicted=len(pred))
        # 3. plans, in the order of each component's first node (deterministic): a quiet group
        # predicts or takes an empty-scan step; a touched component merges its groups and steps
        first = np.full(n_comp, n_nodes, dtype=np.int64)
        np.minimum.at(first, node_lab, np.arange(n_nodes))
        order_n = np.argsort(node_lab, kind="stable")
        starts_n = np.searchsorted(node_lab[order_n], np.arange(n_comp + 1))
        order_r = np.argsort(ret_lab, kind="stable")
        starts_r = np.searchsorted(ret_lab[order_r], np.arange(n_comp + 1))
        quiet_groups = np.flatnonzero(~touched[node_lab[:G]])
        keyed = [(int(g), None) for g in quiet_groups] + [(int(first[c]), int(c)) for c in np.flatnonzero(touched)]
        keyed.sort(key=lambda kc: kc[0])
        plans = []
        for key, c in keyed:
            if c is None:
                cols = np.arange(bounds[key], bounds[key + 1])
                plans.append(self._quiet(groups[key], _take(pred, cols), scores.columns(cols), Z, birth_ll, stats))
                continue
            nodes = order_n[starts_n[c]:starts_n[c + 1]]  # ascending: the stable sort keeps node order
            members = nodes[nodes < G + L]
            regions = nodes[(nodes >= G + L) & (nodes < G + L + B)] - (G + L)
            rows = order_r[starts_r[c]:starts_r[c + 1]]
            plans.append(self._touched(members, regions, rows, groups, bounds, pred, scores, Z, birth_ll, stats))
        # the engine steps of the components are independent: run them (in a pool when workers > 1),
        # each with its own random stream and labels counted from the scan's first free label
        jobs = [p for p in plans if p[0] != "done"]
        seeds = self.rng.integers(0, 2**63 - 1, size=len(jobs)) if jobs else np.zeros(0, np.int64)
        base = self._next_label
        results = iter(self._run([(p[1], p[2], p[3], p[4], base, int(s)) for p, s in zip(jobs, seeds)], stats))
        new_groups = []
        for plan in plans:
            if plan[0] == "done":
                state, parts = plan[1], plan[2]
            else:
                state, parts = self._finish(plan, next(results), base, stats)
            new_groups.extend(self._split(state, parts, stats))
        # 4. singletons back to the lane: the untouched ones (the quiet candidates predicted),
        # then those the steps produced, in plan order
        quiet_c = ~touched[node_lab[G:G + L]]
        keep = np.ones(len(lane), dtype=bool)
        keep[cand] = False
        lane_t = self._lane_t.copy()
        lane_t[cand] = now
        moved = TrackStore(lane.means.copy(), lane.covs.copy(), lane.labels)
        moved.means[cand], moved.covs[cand] = pred.means[bounds[-1]:], pred.covs[bounds[-1]:]
        keep[cand[quiet_c]] = True
        stats["n_predict_only"] += int(keep.sum()) + len(asleep[0])
        stats["n_asleep"] = len(asleep[0])
        groups_new, lane_new = self._sort_out([s for s in (self._prune(s) for s in new_groups) if s is not None])
        # the groups left for later first (unpredicted, their means advanced), then the scan's
        self._groups = asleep[0] + groups_new
        self._group_t = np.concatenate([asleep[1], np.full(len(groups_new), now)])
        self._group_view = asleep[2] + [s.store.means for s in groups_new]
        self._lane = _cat([_take(moved, np.flatnonzero(keep)), lane_new], d)
        self._lane_t = np.concatenate([lane_t[keep], np.full(len(lane_new), now)])
        view = (moved.means if view is None else view).copy()
        view[cand] = pred.means[bounds[-1]:]
        self._lane_view = np.concatenate([view[keep], lane_new.means])
        self._time = now
        if self._object:
            held = np.concatenate([s.store.labels for s in self._groups] + [self._lane.labels])
            ks = np.fromiter(self._object, dtype=np.int64, count=len(self._object))
            self._object = {int(k): self._object[int(k)] for k in ks[np.isin(ks, held)]}
        self.scan_index += 1
        sizes = [len(np.unique(self._objects(s.labels))) for s in self._groups]
        stats.update(n_groups=len(self._groups) + len(self._lane), n_singletons=len(self._lane),
                     largest_group=max(sizes, default=int(len(self._lane) > 0)),
                     largest_group_hypotheses=max((len(s.log_w) for s in self._groups), default=int(len(self._lane) > 0)),
                     time_total=time.perf_counter() - t0)
        if self.adaptive_birth is not None:
            # the next scan's birth terms: one at each return no group or birth term explained
            terms = self.adaptive_birth.terms(Z[unexplained], T.H, T.R, T.motion, dt)
            self._set_birth_terms(terms)
            stats["n_adaptive_terms"] = len(terms)
        self.last_stats = stats
        self.stats_history.append(stats)
        return self.posterior()

    def _wake(self, groups, dt, now):
        """``(groups to predict, their gaps, (groups left for later, their times, their means))``.

        Without ``lazy`` every group is predicted. With it (and a silent population, as for the
        lane) a group is predicted only when the mean of one of its tracks, advanced one scan, is in
        the field of view; the others keep their moments and are only advanced in their means
        (one batch), like the lane's singletons: a group whose tracks are all out of view takes no
        return and, with no population event, changes in nothing but its prediction."""
        t = self._group_t
        if not (self.lazy and self._lane_on and groups):
            return groups, now - t, ([], np.zeros(0), [])
        n = np.array([len(v) for v in self._group_view], dtype=np.int64)  # >= 1: _prune drops empty groups
        view, seen = self._advance_view(np.concatenate(self._group_view), dt)
        awake = np.logical_or.reduceat(seen, np.concatenate([[0], np.cumsum(n)[:-1]]))
        if awake.all():
            return groups, now - t, ([], np.zeros(0), [])
        views = np.split(view, np.cumsum(n)[:-1])
        sleep = np.flatnonzero(~awake)
        return ([groups[g] for g in np.flatnonzero(awake)], now - t[awake],
                ([groups[g] for g in sleep], t[sleep], [views[g] for g in sleep]))

    def _advance_view(self, means, dt):
        """Means ``(n, d)`` advanced by ``dt`` (means only, one batch) and whether each is in the field of view."""
        T = self._template
        view = T.motion.propagate(means, dt)
        return view, T.sensor.detection.in_view(view @ T.H.T)

    def _scores(self, pred, Z) -> _Scores:
        """Every return against every predicted track (the engine's
        :meth:`~.filter.HypothesisFilter._track_scores`, each (return, track) pair once); without
        ``gate_out_of_view`` a track with ``p_D = 0`` gates nothing."""
        loglik, allowed, p_detect = self._template._track_scores(pred, Z)
        if not self.gate_out_of_view:
            allowed = allowed & (p_detect > 0)[None, :]
        return _Scores(loglik, allowed, p_detect)

    def _set_birth_terms(self, terms):
        pop = self._template.population
        pop.birth_densities = tuple(terms)
        if isinstance(pop, LabeledMultiBernoulliPopulation):
            pop.r_birth = np.full(len(terms), self.adaptive_birth.r_birth)
        if hasattr(pop, "_undetected_cache"):
            pop._undetected_cache = {}

    def _objects(self, labels) -> np.ndarray:
        """Object id of each label. The engine gives every (birth term, return) pair of a scan its
        own label, but a birth term yields at most one object per scan: all its newborn labels
        of that scan are one object (id: the smallest of them), which a split keeps in one part.
        Other labels are their own object."""
        get = self._object.get
        return np.array([get(int(x), int(x)) for x in labels], dtype=np.int64)

    def _register_births(self, store, sources, n_regions):
        born = np.flatnonzero((sources[:, 0] < 0) & (sources[:, 0] != -1 - n_regions))
        for r in np.unique(sources[born, 0]):
            labels = store.labels[born[sources[born, 0] == r]]
            for x in labels:
                self._object[int(x)] = int(labels.min())

    def _touched(self, members, regions, rows, groups, bounds, pred, scores, Z, birth_ll, stats):
        """Merge the component's groups and singletons; the plan of one engine step on its
        returns and birth terms. ``members``: graph nodes (``< len(groups)``: a group; else a
        singleton, its track the column ``bounds[-1] + node − len(groups)`` of ``pred``)."""
        T = self._template
        G = len(groups)
        if len(members) == 0:
            state, cols = _empty_state(self.ndim), np.zeros(0, dtype=np.int64)
        else:
            states, col_sets = [], []
            for g in members:
                if g < G:
                    states.append(groups[g])
                    col_sets.append(np.arange(bounds[g], bounds[g + 1]))
                else:
                    col = bounds[-1] + g - G
                    states.append(_singleton(pred, col))
                    col_sets.append(np.array([col]))
            if len(states) == 1:
                state, cols = states[0], col_sets[0]
            else:
                state, used = product(states, T.max_hypotheses, T.cap, self.rng)
                cols = np.concatenate(col_sets)[used]
                stats["n_merges"] += len(states) - 1
        sc = scores.columns(cols)
        return ("touched", state, _take(pred, cols), self._context(Z, rows, sc, birth_ll, regions), regions)

    def _quiet(self, state, pred, sc, Z, birth_ll, stats):
        """A group no return or birth term reaches: predict, or plan an empty-scan step when needed."""
        log_miss = np.log1p(-sc[2])
        miss = np.array([log_miss[t].sum() for t in state.tracks])
        if self._lane_on and np.ptp(miss) <= 1e-12:
            stats["n_predict_only"] += 1
            new = GroupState(pred, state.log_w, state.tracks, state.keys)
            return ("done", new, self._objects(new.store.labels))  # no interaction: every object its own part
        none = np.zeros(0, dtype=np.int64)
        return ("quiet", state, pred, self._context(Z, none, sc, birth_ll, none), none)

    def _finish(self, plan, result, base, stats):
        """A planned step's result in component order: its new labels moved past the labels
        already given this scan (the serial numbering), births registered, interaction parts."""
        kind, _, pred, ctx, regions = plan
        new, sources, n_new, st = result
        if n_new:
            labels = new.store.labels.copy()
            labels[labels >= base] += self._next_label - base
            new = GroupState(TrackStore(new.store.means, new.store.covs, labels), new.log_w, new.tracks, new.keys)
        self._next_label += n_new
        stats["n_duplicates_merged"] += st["n_duplicates_merged"]
        if kind == "quiet":
            return new, self._objects(new.store.labels)
        stats["n_touched"] += 1
        stats["mass_retained_min"] = min(stats["mass_retained_min"], st["mass_retained"])
        stats["n_kalman_updates"] += st["n_kalman_updates"]
        self._register_births(new.store, sources, len(regions))
        return new, self._interaction_parts(self._objects(pred.labels), ctx, sources, len(regions))

    def _run(self, jobs, stats):
        """Run the planned engine steps, in this process (``workers = 1``) or split into
        ``workers`` contiguous chunks of similar cost, the first run here and the others in the pool."""
        t0 = time.perf_counter()
        try:
            return self._run_jobs(jobs, stats)
        finally:
            stats["time_steps"] = time.perf_counter() - t0

    def _run_jobs(self, jobs, stats):
        stats["n_jobs"] = len(jobs)
        if self.workers == 1 or len(jobs) < 2:
            if self.measure_transfer:
                stats["bytes_to_workers"] = sum(len(pickle.dumps(j, protocol=pickle.HIGHEST_PROTOCOL)) for j in jobs)
            out = _run_jobs(self._template, jobs)
            if self.measure_transfer:
                stats["bytes_from_workers"] = sum(len(pickle.dumps(r, protocol=pickle.HIGHEST_PROTOCOL)) for r in out)
            return out
        cost = np.array([len(j[0].log_w) * (j[2].n_returns + 1) for j in jobs], dtype=float)
        cuts = np.searchsorted(np.cumsum(cost), cost.sum() * np.arange(1, self.workers) / self.workers)
        chunks = [c for c in np.split(np.arange(len(jobs)), np.unique(cuts)) if len(c)]
        pool = self._get_pool()
        if self.parallel == "process":
            model = pickle.dumps(self._model(), protocol=pickle.HIGHEST_PROTOCOL)
            blobs = [pickle.dumps([jobs[i] for i in c], protocol=pickle.HIGHEST_PROTOCOL) for c in chunks[1:]]
            futures = [pool.submit(_run_pickled, model, b) for b in blobs]
            stats["bytes_model"] = len(model) * len(blobs)
            stats["bytes_to_workers"] = sum(map(len, blobs))
        else:
            futures = [pool.submit(_run_jobs, self._template, [jobs[i] for i in c]) for c in chunks[1:]]
        out = _run_jobs(self._template, [jobs[i] for i in chunks[0]])
        for f in futures:
            r = f.result()
            if self.parallel == "process":
                stats["bytes_from_workers"] = stats.get("bytes_from_workers", 0) + len(r)
                r, cpu = pickle.loads(r)
                stats["worker_cpu_s"] = stats.get("worker_cpu_s", 0.0) + cpu
            out.extend(r)
        return out

    def _model(self) -> HypothesisFilter:
        """The template without hypotheses: the models, the population (this scan's birth terms)
        and the settings — what a worker needs besides the groups' states."""
        m = object.__new__(HypothesisFilter)
        m.__dict__.update(self._template.__dict__)
        m._store = m._log_w = m._tracks = m._keys = m.last_kept = m.last_track_sources = None
        m.last_stats = {}
        return m

    def _get_pool(self):
        if self._pool is None:
            cls = ProcessPoolExecutor if self.parallel == "process" else ThreadPoolExecutor
            self._pool = cls(max_workers=self.workers - 1)
        return self._pool

    def warm_up(self):
        """Start the pool's workers now and set up numba's typing in each (about a second of CPU on
        a worker's first compiled call otherwise), so the first scans do not pay for it; no-op for
        ``workers = 1``."""
        if self.workers > 1:
            pool = self._get_pool()
            for f in [pool.submit(_warm_worker) for _ in range(self.workers - 1)]:
                f.result()

    def close(self):
        """Shut the worker pool down (a later parallel step starts a new one)."""
        if getattr(self, "_pool", None) is not None:
            self._pool.shutdown()
            self._pool = None

    def __getstate__(self):
        state = self.__dict__.copy()
        state["_pool"] = None
        return state

    @staticmethod
    def _interaction_parts(pred_objects, ctx, sources, n_regions):
        """Part of each new store entry: objects linked by a return they both gated this scan,
        newborn objects with their birth term (or, seeded, their return)."""
        m = ctx.n_returns
        objects = np.unique(pred_objects)
        L = len(objects)
        col_node = np.searchsorted(objects, pred_objects)
        r_a, c_a = np.nonzero(ctx.allowed)
        r_b, b_b = np.nonzero(np.isfinite(ctx.birth_loglik))
        node = np.concatenate([col_node[c_a], L + b_b, L + n_regions + np.arange(m)])
        ret = np.concatenate([r_a, r_b, np.arange(m)])
        n_nodes = L + n_regions + m
        _, lab = components(n_nodes, m, node, ret)
        src, r = sources[:, 0], sources[:, 1]
        tnode = np.empty(len(src), dtype=np.int64)
        old = src >= 0
        tnode[old] = col_node[src[old]]
        seeded = src == -1 - n_regions
        tnode[seeded] = L + n_regions + r[seeded]
        born = ~old & ~seeded
        tnode[born] = L + (-1 - src[born])
        return lab[tnode]

    def _split(self, state, parts, stats):
        if self.split == "never" or len(state.store) == 0 or len(np.unique(parts)) < 2:
            return [state]
        if self.split == "marginal":
            record, pieces = factorise(state, parts, self.factor_tol, self.scan_index + 1)
            self._record(record, stats)
            return pieces
        # "exact": peel off every part that is exactly independent of the rest of the group
        pieces, rest, rest_parts = [], state, np.asarray(parts)
        for c in np.unique(parts)[:-1]:
            record, (rest_new, piece) = factorise(rest, (rest_parts == c).astype(np.int64), self.factor_tol,
                                                  self.scan_index + 1)
            if record.exact:
                self._record(record, stats)
                pieces.append(piece)
                rest, rest_parts = rest_new, rest_parts[rest_parts != c]
        if not pieces:
            record, _ = factorise(state, parts, self.factor_tol, self.scan_index + 1)
            self.split_records.append(SplitRecord(record.scan, record.parts, False, record.kl, record.l1,
                                                  record.n_joint, record.n_parts, applied=False))
        return [rest, *pieces]

    def _record(self, record, stats):
        self.split_records.append(record)
        stats["n_splits"] += 1
        stats["n_exact_splits"] += int(record.exact)
        stats["split_kl"] += record.kl
        stats["split_l1"] += record.l1

    def _prune(self, state):
        """Drop hypotheses below ``min_weight`` and groups holding no object in any hypothesis."""
        if self.min_weight > 0 and len(state.log_w) > 1:
            keep = np.exp(state.log_w) >= self.min_weight
            keep[np.argmax(state.log_w)] = True
            if not keep.all():
                idx = np.flatnonzero(keep)
                lw = state.log_w[idx]
                store, tracks, _ = compact(state.store, [state.tracks[i] for i in idx])
                state = GroupState(store, lw - np.logaddexp.reduce(lw), tracks, [state.keys[i] for i in idx])
        if not any(len(t) for t in state.tracks):
            return None
        return state

    # ------------------------------------------------------------------ output
    def posterior(self, n_top: int = 1) -> FactoredPosterior:
        """Per-group posteriors, the convolved cardinality distribution and the union of MAPs."""
        n_top = check_int(n_top, "n_top", minimum=1)
        return FactoredPosterior(self._groups_now, self._lane_now, len(self._lane), n_top=n_top,
                                 n_states=len(self._groups))

    def map_means(self) -> tuple[np.ndarray, np.ndarray]:
        """``(labels, means)`` of the MAP joint hypothesis: :attr:`posterior`'s ``map_estimate``
        without covariances, so the lane's singletons are not predicted (their means at the current
        scan are kept; with ``lazy``, advanced a scan at a time rather than over their whole gap,
        equal to rounding for the Kepler model and to the integrator's error for a numerical one).
        """
        maps = [summarise(s.log_w, s.tracks, TrackStore(v, s.store.covs, s.store.labels)).map_estimate
                for s, v in zip(self._groups, self._group_view)]
        return (np.concatenate([e.labels for e in maps] + [self._lane.labels]).astype(np.int64),
                np.concatenate([e.means for e in maps] + [self._lane_view]).reshape(-1, self.ndim))

    def estimates(self) -> np.ndarray:
        """Means ``(n, d)`` of the objects of the MAP joint hypothesis (union of the groups' MAPs)."""
        return self.map_means()[1]

    def joint_hypotheses(self, limit: int = 100_000) -> list:
        """The product expanded into joint hypotheses (for checks), heaviest first.

        Raises ``ValueError`` when there are more than ``limit`` (>= 1).
        """
        limit = check_int(limit, "limit", minimum=1)
        if self.n_joint_hypotheses > limit:
            raise ValueError(f"the product has {self.n_joint_hypotheses} joint hypotheses, more than limit = {limit}")
        groups = self.groups
        if not groups:
            d = self.ndim
            return [HypothesisEstimate(1.0, 0.0, np.zeros(0, np.int64), np.zeros((0, d)), np.zeros((0, d, d)))]
        joint, _ = product(groups, limit, "top")
        post = summarise(joint.log_w, joint.tracks, joint.store, n_top=len(joint.log_w))
        return list(post.top)

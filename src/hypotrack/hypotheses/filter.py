"""The hypothesis-level filter: one recursion for H-FISST, R-FISST and HOMHT.

Document 000 Sec. II shows that the multi-object Bayes filter is a Bayes filter on a discrete,
growing hypothesis space (Eq. 11, 19): every parent splits into children (population event ×
data association), each child's weight is the parent's times a transition probability times
the likelihood of the scan under the child, and the pdfs under a child are Kalman updates of
the parent's tracks. :class:`HypothesisFilter` runs that recursion with two plug-ins:

* a weight model (:mod:`.weights`): ``hfisst``, ``fisst_poisson`` or ``reid``;
* a child generator (:mod:`.generators`): exhaustive, Murty k-best or the R-FISST MCMC search.

One ``step(Z)``:

1. predict every track of the shared store once (:mod:`.tracks`);
2. compute, once for the scan, the log-likelihood of every (return, track) pair, the gate and
   the detection probability of every track (:class:`.ScanContext`);
3. for each parent: its association problem (weight model + population event probabilities),
   the generated association children, and their undetected-birth / death *twins*
   (:mod:`.population_events`), keeping the best ``H∞`` per parent (on a scan of one return, with no birth
   term, on Python floats: :mod:`.one_return_children`, the same children);
4. merge identical children of different parents (same tracks, e.g. after deaths) by adding
   their weights (:mod:`.duplicates`; a step with few children by their pair sets, :func:`.duplicates.merge_few`),
   then cap the children at ``H∞`` — the top by weight, or a weighted sample without replacement
   (Gumbel-top-k with the filter's seeded generator) — and normalise with log-sum-exp;
5. build the next store from the distinct ``(track, return)`` pairs of the survivors: each pair
   is one Joseph-form Kalman update however many hypotheses share it.
"""

from __future__ import annotations

import copy
import time as _clock

import numpy as np
from .._logspace import logsumexp

from .._validation import (
    check_covariance,
    check_finite_array,
    check_finite_float,
    check_int,
    check_measurements,
    check_positive,
    check_probability,
    check_seed,
    check_state_dimension,
)
from ..association import gate_threshold, validation_matrix
from ..models.measurement import LinearMeasurement
from .detection import state_p_detect
from .duplicates import merge_few, pairs_function
from .children import candidates, gumbel_keys, heavy_entries, null_event, twins_never_heavier
from .generators import ChildGenerator, top_k
from .hypothesis import ChildSet, Hypothesis
from .one_return_children import applies, one_return_children
from .posterior import summarise
from ..protocol import TrackEstimates
from .scan_context import ScanContext
from .state import FilterState, StepResult, scan_interval
from .tracks import TrackStore, update_pairs
from .validity import NoValidChild, PairMemo, advance_with_fallbacks, valid_top_k
from .weights import WeightModel, prime_scan, seeded_moments

__all__ = ["HypothesisFilter"]


_CHUNK = 1 << 15


class HypothesisFilter:
    """Multi-object filter on the hypothesis space (document 000 Algorithm/Prop. 1–2).

    Parameters
    ----------
    motion : motion model
        ``transition(x, dt)`` and ``Q(dt)`` (:mod:`hypotrack.models.motion`, orbit models).
    sensor : hypotrack.models.sensors.Sensor
        Measurement model (``H``, ``R``), detection (``p_D`` in (0, 1) and field of view) and
        clutter (its region's area is the clutter volume ``V``; its rate is ``λV``).
    weights : WeightModel
    generator : ChildGenerator
    population : SingleEventPopulation, BinomialPopulation or LabeledMultiBernoulliPopulation, optional
        Birth/death model; ``None`` keeps the number of objects fixed (apart from HOMHT's
        seeded births). A population with a ``children`` method (the labeled multi-Bernoulli)
        generates each parent's children itself from the weight model and the generator.
    dt : float
        Default time between scans.
    max_hypotheses : int
        ``H∞``, hypotheses kept after each scan.
    cap : {"top", "sample"}
        Keep the ``H∞`` heaviest children, or draw ``H∞`` without replacement with probability
        proportional to weight (document 000 Sec. III-A offers both).
    gate_probability : float, optional
        Validation gate ``P_G`` in (0, 1); a return outside a track's gate cannot be assigned to
        it. ``None``: no gating.
    seed : int or numpy.random.Generator, optional
        Source of every random draw (MCMC chains, weighted capping).
    means, covs, labels : array_like, optional
        The initial hypothesis: ``n`` objects with Gaussian pdfs (``n = 0`` allowed), weight 1.
    merge_duplicates : bool
        Merge identical children (the same tracks, from different parents) by adding their weights
        before the cap (:mod:`.duplicates`); on by default. ``False`` keeps every copy (the engine
        before duplicate merging; a comparison only).
    validity : callable, optional
        ``validity(means (n, d)) -> bool (n,)``: a child holding a track whose mean fails it gets weight 0
        before the cap (:mod:`.validity`; e.g. ``hypotrack.models.plausibility.plausible_orbits``).
        ``None`` (default): every child is valid.

    Attributes
    ----------
    time : float
        Time of the last scan (or of :meth:`initialise`); :meth:`step` predicts from it.
    state : FilterState
        The hypotheses (:mod:`.state`); :meth:`advance` maps a state to the next.
    """

    def __init__(self, motion, sensor, weights: WeightModel, generator: ChildGenerator, *, population=None,
                 dt=1.0, max_hypotheses=100, cap="top", gate_probability=None, seed=None,
                 means=None, covs=None, labels=None, merge_duplicates=True, validity=None):
        if not isinstance(weights, WeightModel):
            raise TypeError(f"weights must be a WeightModel, got {type(weights).__name__}")
        if not isinstance(generator, ChildGenerator):
            raise TypeError(f"generator must be a ChildGenerator, got {type(generator).__name__}")
        if getattr(sensor, "clutter", None) is None:
            raise ValueError("sensor.clutter must be a PoissonClutter: its region's area is the clutter volume V")
        try:
            p_D = check_probability(sensor.detection.p_D, "p_D", low_open=True, high_open=True)
        except ValueError as err:
            raise ValueError(f"{err}: hypothesis weights hold log(1 - p_D) for every missed object") from None
        if population is not None and weights.seeded_births and population.n_birth_regions:
            raise ValueError("HOMHT's seeded births and population birth regions are two birth models; use one")
        if cap not in ("top", "sample"):
            raise ValueError(f"cap must be 'top' or 'sample', got {cap!r}")
        self.motion = motion
        self.sensor = sensor
        self.weights = weights
        self.generator = generator
        self.population = population
        self.dt = check_positive(dt, "dt")
        self.max_hypotheses = check_int(max_hypotheses, "max_hypotheses", minimum=1)
        self.cap = cap
        # Identical children (same tracks, e.g. after deaths: two parents that differ only in an object
        # that dies give the same child) are one hypothesis: their weights are added before the cap, so
        # the cap keeps H∞ distinct hypotheses instead of copies (13-19 % of the GLMB benchmark's).
        self.merge_duplicates = bool(merge_duplicates)
        if validity is not None and not callable(validity):
            raise TypeError(f"validity must be callable (means -> bool per track) or None, got {type(validity).__name__}")
        self.validity = validity
        self.gate_probability = (
            None if gate_probability is None
            else check_probability(gate_probability, "gate_probability", low_open=True, high_open=True)
        )
        self.p_D = p_D
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(check_seed(seed))
        # a linear sensor's H and R as before, or an extended model (the catalogue radar's, in the sensor frame)
        if getattr(sensor.measurement, "linear", True):
            self.H = check_finite_array(sensor.measurement.H, "sensor H", ndim=2)
            self.R = check_covariance(sensor.measurement.R, "sensor R", dim=self.H.shape[0])
            self.measurement = LinearMeasurement(self.H, self.R)
            self.meas_dim, self.state_dim = self.H.shape
            what = f"the sensor (H of shape {self.H.shape})"
        else:
            self.measurement, self.H, self.R = sensor.measurement, None, check_covariance(sensor.measurement.R, "sensor R")
            self.meas_dim, self.state_dim = self.measurement.dim, self.measurement.ndim_state
            what = f"the sensor ({self.meas_dim}-dimensional returns of a {self.state_dim}-dimensional state)"
        check_state_dimension(motion, self.state_dim, what)
        self.last_stats = {}
        self.initialise(np.zeros((0, self.state_dim)) if means is None else means, covs, labels)

    _OPTIONS = ("motion", "sensor", "weights", "generator", "population", "dt", "max_hypotheses", "cap",
                "gate_probability", "seed", "merge_duplicates", "validity")

    def configuration(self) -> dict:
        """The constructor's keywords that configure this filter (everything but the initial objects
        and ``seed``): ``HypothesisFilter(**f.configuration(), seed=...)`` is a filter configured as ``f``."""
        return dict(motion=self.motion, sensor=self.sensor, weights=self.weights, generator=self.generator,
                    population=self.population, dt=self.dt, max_hypotheses=self.max_hypotheses, cap=self.cap,
                    gate_probability=self.gate_probability, merge_duplicates=self.merge_duplicates,
                    validity=self.validity)

    def with_options(self, **changes) -> "HypothesisFilter":
        """A filter with this one's configuration, ``changes`` applied, and no hypotheses yet.

        ``changes``: any keyword of :meth:`configuration`, or ``seed`` (default: a copy of this
        filter's random generator, so the copy draws what this one would). The copy starts from the
        empty hypothesis at time 0 (give it a state with :attr:`state` or :meth:`initialise`); this
        filter is not changed. Only the changed options are validated (the others were), so a copy
        is cheap: the factored engine makes one per group and scan.
        """
        unknown = set(changes) - set(self._OPTIONS)
        if unknown:
            raise ValueError(f"unknown options {sorted(unknown)}; allowed: {', '.join(self._OPTIONS)}")
        if {"motion", "sensor", "weights", "generator", "dt", "max_hypotheses", "cap", "gate_probability",
                "validity"} & set(changes):
            options = {**self.configuration(), "seed": copy.deepcopy(self.rng), **changes}
            return HypothesisFilter(**options)
        new = copy.copy(self)  # the models are shared, never written: only the options below change
        if "population" in changes:
            new.set_population(changes["population"])
        if "merge_duplicates" in changes:
            new.merge_duplicates = bool(changes["merge_duplicates"])
        seed = changes.get("seed")
        new.rng = copy.deepcopy(self.rng) if "seed" not in changes else (
            seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed))
        new.last_stats = {}
        new.initialise(np.zeros((0, self.state_dim)))
        return new

    def set_population(self, population) -> None:
        """Use ``population`` (birth/death model, or ``None``) from the next scan on."""
        if population is not None and self.weights.seeded_births and population.n_birth_regions:
            raise ValueError("HOMHT's seeded births and population birth regions are two birth models; use one")
        self.population = population

    # ------------------------------------------------------------------ state
    def initialise(self, means, covs=None, labels=None, *, time: float = 0.0):
        """Start from one hypothesis holding ``n`` objects (``n = 0`` allowed), weight 1, at ``time``."""
        d = self.state_dim
        means = np.asarray(means, dtype=float)
        if means.size:
            means = check_finite_array(np.atleast_2d(means), "means", shape=(None, d))
        self.time = check_finite_float(time, "time")
        self._state = FilterState.initial(means, covs, labels, ndim=d)
        self.scan_index = 0
        self.last_kept = None  # ChildSet of the current hypotheses: parent, event, kind, arg
        self.last_track_sources = None

    @property
    def state(self) -> FilterState:
        """The hypotheses (:class:`~.state.FilterState`; immutable: a step makes a new one).

        Assigning a state (e.g. one saved earlier, or a group's) makes it the filter's."""
        return self._state

    @state.setter
    def state(self, state: FilterState) -> None:
        if not isinstance(state, FilterState):
            raise TypeError(f"state must be a FilterState, got {type(state).__name__}")
        if state.store.ndim != self.state_dim or not len(state.tracks) == len(state.log_w) == len(state.keys):
            raise ValueError("state must hold one track list and key per weight, tracks of the sensor's dimension")
        self._state = state

    @property
    def hypotheses(self) -> list[Hypothesis]:
        return [Hypothesis(float(w), tuple(int(j) for j in t)) for w, t in zip(self._state.log_w, self._state.tracks)]

    @property
    def sensor_parameters(self) -> tuple:
        """The sensor parameters this filter's weights use (:attr:`WeightModel.sensor_parameters`), e.g.
        H-FISST/R-FISST: the clutter region but not ``clutter.rate``, which changes none of their weights."""
        return self.weights.sensor_parameters

    @property
    def store(self) -> TrackStore:
        return self._state.store

    @property
    def log_weights(self) -> np.ndarray:
        """Normalised log-weights of the current hypotheses (internal order)."""
        return self._state.log_w.copy()

    @property
    def track_lists(self) -> list:
        """Per hypothesis, the indices of its tracks in :attr:`store` (internal order)."""
        return [t.copy() for t in self._state.tracks]

    @property
    def lineage_keys(self) -> list:
        """Per hypothesis, a hashable key of its whole history (the population event and
        association event of every scan), identical across filters that generated the same
        hypothesis — e.g. to compare H-FISST and HOMHT hypothesis by hypothesis."""
        return list(self._state.keys)

    @property
    def next_label(self) -> int:
        """The label the next newborn track gets."""
        return self._state.next_label

    # ------------------------------------------------------------------ scan
    def track_scores(self, pred: TrackStore, Z):
        """``(loglik (m, n), allowed (m, n), p_detect (n,))`` of returns ``Z`` against the predicted
        tracks: the track columns of the scan's :class:`ScanContext` (also used, group by group,
        by :class:`~.factored.FactoredFilter`)."""
        n, m = len(pred), len(Z)
        if n:
            z_pred, S, _, _ = (meas := self.measurement).innovation(pred.means, pred.covs)
            d2, logdet = meas.mahalanobis2(Z, z_pred, S)
            loglik = -0.5 * (d2 + logdet[None, :] + self.meas_dim * np.log(2 * np.pi))
            in_view = np.asarray(self.sensor.detection.in_view(meas.view_points(pred.means, z_pred)), dtype=bool)
        else:
            d2 = loglik = np.zeros((m, 0))
            in_view = np.zeros(0, dtype=bool)
        if self.gate_probability is None:
            allowed = np.ones((m, n), dtype=bool)
        else:
            allowed = validation_matrix(d2, gate_threshold(self.gate_probability, self.meas_dim))
        return loglik, allowed, np.where(in_view, self.p_D, 0.0)

    def scan_context(self, pred: TrackStore, Z) -> ScanContext:
        """The :class:`ScanContext` of returns ``Z`` against the predicted tracks ``pred`` and the
        population's birth terms (document 000 Eq. 8, 18, 30)."""
        m = len(Z)
        loglik, allowed, p_detect = self.track_scores(pred, Z)
        p_detect = state_p_detect(self.sensor.detection, pred.means, p_detect, pred.covs)
        clutter = self.sensor.clutter
        birth_loglik = (
            self.population.birth_loglik(Z) if self.population is not None else np.zeros((m, 0))
        )
        track_survival = getattr(self.population, "track_survival", None)
        return ScanContext(
            Z=Z, loglik=loglik, allowed=allowed, p_detect=p_detect,
            birth_loglik=birth_loglik, p_detect_birth=self.p_D,
            clutter_rate=float(clutter.rate), clutter_volume=float(clutter.region.area),
            p_survive=None if track_survival is None else track_survival(pred),
        )

    def predict(self, store: TrackStore, interval: float) -> TrackStore:
        """``store`` predicted over ``interval`` (batched EKF); a zero interval is no prediction at
        all — the moments are returned as they are (no motion, no process noise)."""
        return store if interval == 0 else store.predict(self.motion, interval)

    # ------------------------------------------------------------ extension points
    def parent_generators(self, state: FilterState) -> list:
        """Extension point: the child generator of each parent of ``state`` (called once per scan
        by :meth:`advance`). Default: the filter's generator for every parent. Override to give
        parents different budgets, e.g. the GLMB demo's Gibbs samples allotted by ``√w``
        (:class:`hypotrack.experiments.glmb_benchmark.reference.SqrtAllocationFilter`)."""
        return [self.generator] * len(state.log_w)

    def children_of(self, ctx: ScanContext, state: FilterState, h: int, keep, keys_rng, generator=None,
                    with_null: bool = False):
        """Extension point: association children and twins of parent ``h`` of ``state``, reduced to the best ``keep``.

        "Best" is by log-weight, or by Gumbel-perturbed log-weight (``keys_rng`` given) for the
        weighted sample; the keys are returned so that the global cap uses the same draw. Returns
        ``(ChildSet, keys, n_generated, log mass generated, n_twins)``. ``generator``: the parent's
        child generator (default the filter's; see :meth:`parent_generators`). ``with_null``: the null
        association (every return clutter) alone in place of the generator's events, when it is feasible
        (:meth:`advance`'s fallback).
        """
        generator = self.generator if generator is None else generator
        tr = state.tracks[h]
        pop = self.population
        if hasattr(pop, "children"):
            # Population models that generate whole children themselves (labeled multi-Bernoulli).
            ev, kind, arg, lw = pop.children(self.weights, generator, ctx, tr, float(state.log_w[h]), self.rng,
                                             keep=keep if keys_rng is None else None,
                                             **({"with_null": True} if with_null else {}))
            keys = gumbel_keys(lw, keys_rng)
            mass = np.logaddexp.reduce(lw) if len(lw) else -np.inf
            if keep is not None and len(lw) > keep:
                sel = top_k(keys, keep)
                ev, kind, arg, lw, keys = ev[sel], kind[sel], arg[sel], lw[sel], keys[sel]
            return ChildSet(np.full(len(lw), h, np.int64), ev, kind, arg, lw), keys, len(lw), mass, 0
        if applies(pop, ctx, keys_rng, with_null):  # one return, no birth term: Python floats (.one_return_children)
            return one_return_children(self, ctx, state, h, keep, generator)
        p = ctx.p_detect[tr]
        in_view = p > 0
        n_view = int(in_view.sum())
        ps = None if ctx.p_survive is None else ctx.p_survive[tr]  # per-track survival (population's survival)
        pop_lp = pop.log_event_prob(n_view, len(tr), ps) if pop is not None else None
        problem = self.weights.problem(ctx, tr, float(state.log_w[h]), pop_lp)
        gen_keep = None
        if keep is not None and keys_rng is None and (pop is None or twins_never_heavier(pop, ctx, p, in_view, ps)):
            gen_keep = keep
        # the fallback (advance): the null association alone, no search
        events, lw = null_event(problem) if with_null else generator.generate(problem, self.rng, keep=gen_keep)
        events = np.asarray(events, dtype=np.int32)
        n_generated = len(lw)
        mass = [np.logaddexp.reduce(lw)] if len(lw) else []
        parts = [candidates(events, lw[:, None], ChildSet.ASSOCIATION, keep, keys_rng, None)]
        if pop is not None and len(lw):
            M = problem.n_objects
            _, b = problem.counts(events)
            B = pop.n_birth_regions
            if B:
                ub = pop.undetected_birth_log_ratio(n_view, M)[b] + np.log1p(-ctx.p_detect_birth)
                for start in range(0, len(lw), _CHUNK):
                    sl = slice(start, start + _CHUNK)
                    ev = events[sl]
                    used = np.zeros((len(ev), B), dtype=bool)  # birth regions each event detects
                    rows, cols = np.nonzero(ev >= M)
                    used[rows, ev[rows, cols] - M] = True
                    tw = np.where(used, -np.inf, (lw[sl] + ub[sl])[:, None])
                    parts.append(candidates(ev, tw, ChildSet.UNDETECTED_BIRTH, keep, keys_rng, mass))
            elig = pop.death_eligible(in_view)
            if M and elig.any():
                de = pop.death_log_ratio(n_view, M, ps)[b]  # (E,) or, per track, (E, M)
                for start in range(0, len(lw), _CHUNK):
                    sl = slice(start, start + _CHUNK)
                    ev = events[sl]
                    tw = (lw[sl, None] + de[sl].reshape(len(ev), -1)) - np.log1p(-p)[None, :]
                    tw = np.where(problem.detected(ev) | ~elig[None, :], -np.inf, tw)
                    parts.append(candidates(ev, tw, ChildSet.DEATH, keep, keys_rng, mass))
        ev_all, kind, arg, lw_all, keys = (np.concatenate([q[f] for q in parts]) for f in range(5))
        n_twins = sum(len(q[3]) for q in parts[1:])
        if keep is not None and len(lw_all) > keep:
            sel = top_k(keys, keep)
            ev_all, kind, arg, lw_all, keys = ev_all[sel], kind[sel], arg[sel], lw_all[sel], keys[sel]
        cs = ChildSet(np.full(len(lw_all), h, np.int64), ev_all, kind, arg, lw_all)
        return cs, keys, n_generated, (np.logaddexp.reduce(mass) if mass else -np.inf), n_twins

    def expand(self, Z, dt=None) -> ChildSet:
        """All children of the current hypotheses for scan ``Z``, unnormalised, nothing kept.

        For inspection and tests: the filter's state is not changed (MCMC generators do use the
        filter's random generator). ``dt``: the interval (default the filter's ``dt``; 0: no prediction).
        """
        interval, _ = scan_interval(self.time, dt=dt, default=self.dt)
        state = self._state
        pred = self.predict(state.store, interval)
        Z = check_measurements(Z, "Z", self.meas_dim)
        ctx = self.scan_context(pred, Z)
        gens = self.parent_generators(state)
        parts = [self.children_of(ctx, state, h, None, None, gens[h])[0] for h in range(len(state.log_w))]
        return ChildSet.concatenate(parts, len(Z))

    def step(self, Z, time=None, *, dt=None):
        """Advance one scan with returns ``Z`` (m, p) observed at ``time``; ``m = 0`` is a scan with no returns.

        ``time``: the scan's absolute time; the filter predicts over ``time − self.time`` (``dt``:
        give the interval instead; neither: the filter's ``dt``). A zero interval is an update
        without prediction: the tracks' moments enter the update as they are — no motion, no
        process noise (:meth:`predict`). The population events are those of a scan all the same:
        the population models of this package have no interval in them (a death or birth
        probability is per scan, :mod:`.population_events`, :mod:`.population_lmb`), so with a
        population a zero-interval scan is still a scan for births and deaths (a first scan at the
        priors' epoch can start an object; a second sensor's scan at the same time weighs another
        survival). A negative interval raises ``ValueError``.

        Returns the :class:`Posterior` after the scan. All-or-nothing: if the step raises (bad
        scan, a generator over its budget, no child left), the filter — hypotheses, tracks,
        time, scan index and the random generator's state — is as before, so the scan can be retried.
        """
        rng_state = self.rng.bit_generator.state
        try:
            return self._step(Z, time, dt)
        except BaseException:
            self.rng.bit_generator.state = rng_state
            raise

    def _step(self, Z, time, dt):
        t0 = _clock.perf_counter()
        interval, now = scan_interval(self.time, time, dt, self.dt)
        Z = check_measurements(Z, "Z", self.meas_dim)
        prime_scan(self.weights, Z)  # a mixture birth density's per-return mixtures, in one batch
        pred = self.predict(self._state.store, interval)
        result = self.advance(self._state, pred, self.scan_context(pred, Z))
        result.stats["time_total"] = _clock.perf_counter() - t0
        self._state, self.time = result.state, now
        self.scan_index += 1
        self.last_stats, self.last_kept, self.last_track_sources = result.stats, result.kept, result.sources
        return self.posterior()

    def advance(self, state: FilterState, pred: TrackStore, ctx: ScanContext, light: float = 0.0) -> StepResult:
        """The state after one scan: children of every hypothesis of ``state`` for the scan of
        ``ctx`` (their tracks predicted in ``pred``, entry for entry of ``state.store``), duplicates
        merged, capped and materialised (module docstring, steps 3–5; document 000 Eq. 11, 19).

        Draws from the filter's random generator and changes nothing else: the filter's own state
        is the :meth:`step`'s business. Newborn tracks are labelled from ``state.next_label``.

        With a validity test and no valid child, the fallbacks of :func:`.validity.advance_with_fallbacks`:
        each parent's null association, then the deletion of predictions that fail the test. ``light`` (> 0): a store
        entry whose kept children weigh less than it in all is left without moments (NaN; :func:`.children.heavy_entries`).
        """
        return advance_with_fallbacks(lambda st, with_null: self._advance(st, pred, ctx, with_null, light), state, pred,
                                      self.validity)

    def _advance(self, state: FilterState, pred: TrackStore, ctx: ScanContext, with_null: bool, light=0.0) -> StepResult:
        t0 = _clock.perf_counter()
        keys_rng = self.rng if self.cap == "sample" else None
        gens = self.parent_generators(state)
        parts, all_keys, n_gen, n_twins, masses = [], [], 0, 0, []
        t1 = _clock.perf_counter()
        for h in range(len(state.log_w)):
            cs, keys, ng, mass, nt = self.children_of(ctx, state, h, self.max_hypotheses, keys_rng, gens[h],
                                                      **({"with_null": True} if with_null else {}))
            parts.append(cs)
            all_keys.append(keys)
            n_gen += ng
            n_twins += nt
            masses.append(mass)
        t2 = _clock.perf_counter()
        children = ChildSet.concatenate(parts, ctx.n_returns)
        if len(children) == 0:
            raise RuntimeError("no child hypothesis has a positive weight (every event was gated out or forbidden)")
        all_keys, n_dup, known = np.concatenate(all_keys), 0, None
        if self.merge_duplicates:  # (few children: grouped by their pairs, kept for the memo; duplicates.merge_few)
            children, all_keys, n_dup, known = merge_few(children, all_keys, state.tracks, ctx.n_birth_regions)
        n_invalid, memo = 0, PairMemo(pairs_function(children, state.tracks, ctx.n_birth_regions), known)
        if self.validity is None:
            sel = top_k(all_keys, self.max_hypotheses)
        else:
            sel, n_invalid = valid_top_k(all_keys, self.max_hypotheses, memo.pairs,
                                         lambda src, ret: self.pair_moments(pred, ctx, src, ret, False), self.validity)
            if len(sel) == 0:
                raise NoValidChild("no child hypothesis is valid: every child holds a track that fails validity")
        kept = children.take(sel)
        new, sources, n_updates = self._materialise(state, kept, memo, sel, pred, ctx, light)
        log_total = logsumexp(masses)
        stats = {
            "n_parents": len(parts), "n_association_children": n_gen, "n_twin_children": n_twins,
            "n_duplicates_merged": n_dup, "n_invalid_pruned": n_invalid,
            "n_kept": len(kept), "log_mass_generated": float(log_total),
            "mass_retained": float(np.exp(logsumexp(kept.log_weights) - log_total)),
            "n_kalman_updates": n_updates, "time_generate": t2 - t1, "time_total": _clock.perf_counter() - t0,
        }
        return StepResult(new, sources, kept, stats, new.next_label - state.next_label)

    def _materialise(self, state: FilterState, kept: ChildSet, memo: PairMemo, sel, pred: TrackStore, ctx: ScanContext,
                     light=0.0):
        """The new state from the kept children (``kept``: children ``sel`` of the step's, whose pairs ``memo``
        holds); returns ``(state, track sources, Kalman updates)``; the moments of the entries lighter than ``light``
        in all are NaN (:meth:`advance`)."""
        pair_index, pairs, new_lists = {}, [], []
        for c in sel.tolist():
            idx = []
            for key in memo.pairs(c):
                if key not in pair_index:
                    pair_index[key] = len(pairs)
                    pairs.append(key)
                idx.append(pair_index[key])
            new_lists.append(np.asarray(idx, dtype=np.int64))
        labels = np.zeros(len(pairs), dtype=np.int64)
        src = np.array([s for s, _ in pairs], dtype=np.int64)
        ret = np.array([r for _, r in pairs], dtype=np.int64)
        old = src >= 0
        n_updates = int(np.sum(old & (ret >= 0)))
        log_w = kept.log_weights - logsumexp(kept.log_weights)
        need = heavy_entries(new_lists, log_w, len(pairs), light)
        means, covs = np.full((len(pairs), pred.ndim), np.nan), np.full((len(pairs), pred.ndim, pred.ndim), np.nan)
        means[need], covs[need] = self.pair_moments(pred, ctx, src[need], ret[need])
        labels[old] = pred.labels[src[old]]
        next_label = state.next_label
        for q in np.flatnonzero(~old):
            labels[q] = next_label
            next_label += 1
        # (source, return) of each store entry: source >= 0 a predicted track, -1 - r birth term r,
        # -1 - B - c a seeded birth in component c (read by the factored engine to place newborn objects)
        sources = np.stack([src, ret], axis=1) if len(pairs) else np.zeros((0, 2), np.int64)
        ev = np.ascontiguousarray(kept.events)  # each child's row of bytes (its event), cut from one buffer
        row, buf = ev.shape[1] * ev.itemsize, ev.tobytes()
        keys = [(state.keys[p], int(k), int(a), buf[c * row:(c + 1) * row])
                for c, (p, k, a) in enumerate(zip(kept.parent.tolist(), kept.kind.tolist(), kept.arg.tolist()))]
        return FilterState(TrackStore(means, covs, labels), log_w, new_lists, keys, next_label), sources, n_updates

    def pair_moments(self, pred: TrackStore, ctx: ScanContext, src, ret, covariances: bool = True):
        """Means ``(P, d)`` and covariances of next-store entries given as ``(source, return)`` pairs
        (:func:`.child_pairs`): a predicted track updated with a return (or missed), a birth term's first
        update (or prior, born undetected), a seeded birth at its return (:func:`.seeded.seeded_moments`). Without
        ``covariances`` (the validity test reads the means) they are ``None`` and a seeded birth's are not mapped."""
        src, ret = np.asarray(src, dtype=np.int64), np.asarray(ret, dtype=np.int64)
        d, old, seeded_src = pred.ndim, src >= 0, -1 - ctx.n_birth_regions
        seeded = np.flatnonzero(src <= seeded_src)  # component seeded_src − src of a (mixture) seeded birth
        parts = [(old, update_pairs(pred, ctx.Z, self.measurement, None, src[old], ret[old]) if old.any() else None),
                 (seeded, seeded_moments(self.weights.birth_density, ctx.Z, self.R, ret[seeded], seeded_src - src[seeded],
                                         d, covariances) if len(seeded) else None)]
        parts += [([q], self.population.birth_track(int(-1 - src[q]), ctx.Z[ret[q]] if ret[q] >= 0 else None, self.R))
                  for q in np.flatnonzero(~old & (src > seeded_src))]
        means, covs = np.zeros((len(src), d)), (np.zeros((len(src), d, d)) if covariances else None)
        for rows, mc in parts:
            if mc is not None:
                means[rows] = mc[0]
                if covariances:
                    covs[rows] = mc[1]
        return means, covs

    # ------------------------------------------------------------------ output
    def posterior(self, n_top: int = 10):
        """Cardinality distribution, expected number of objects and the top hypotheses."""
        s = self._state
        return summarise(s.log_w, s.tracks, s.store, n_top=n_top)

    def estimates(self) -> TrackEstimates:
        """The maximum-a-posteriori hypothesis's tracks at :attr:`time`: labels, means and covariances."""
        e = self.posterior(n_top=1).map_estimate
        return TrackEstimates(self.time, e.labels, e.means, e.covs)

"""The factored filter itself: :class:`FactoredFilter` (package docstring) and its state, :class:`FactoredState`."""

from __future__ import annotations

import copy
import time as _clock
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..._validation import check_finite_array, check_finite_float, check_int, check_measurements
from ...protocol import TrackEstimates
from ..factored_groups import factorise, product
from ..filter import HypothesisFilter
from ..posterior import HypothesisEstimate, summarise
from ..state import scan_interval
from ..tracks import TrackStore
from .born_detected import birth_step, born_detected_applies, born_detected_plan
from .seeded_birth import lone_seeded_applies, lone_seeded_plan, map_lone_returns
from .births import birth_loglik
from .fast_path import FastBatch, birth_existence, born_template, fast_components, fast_rule
from .lane import (GroupSet, Lane, admitted, bernoulli_existence, bernoulli_lane, cat, is_singleton, lane_existence,
                   lane_survival, one_hypothesis_lane, predict_each, scan_existence, silent, singleton, sort_out,
                   survival_lane, take)
from .options import FactoredOptions
from .planner import (ObjectIds, ScanData, interaction_parts, prune, quiet_plan, scan_graph, score_scorable, split_group,
                      touched_plan)
from .pool import WorkerPool, engine_step
from .scores import Scores
from .summary import FactoredPosterior

__all__ = ["FactoredFilter", "FactoredState"]

_BIRTHS = ("born", "born_detected", "seeded")  # closed-form birth steps
_NO_JOB = ("done", "dropped", "slept") + _BIRTHS  # plans with no engine step to run (slept: a closed form)


@dataclass(frozen=True, eq=False)
class FactoredState:
    """The factored posterior as held: the multi-hypothesis groups (:class:`~.lane.GroupSet`), the
    lane of singletons (:class:`~.lane.Lane`), each as kept (lazy ones at the time they were last
    predicted to), the scan's time, the next label and the label → object map of this scan's births."""

    groups: GroupSet
    lane: Lane
    time: float
    next_label: int
    objects: dict

    def same_as(self, other: "FactoredState") -> bool:
        """Bit-for-bit the same posterior: groups (weights, labels, track moments, hypotheses), lane,
        the times each was predicted to, their means at the scan, and the next label."""
        return (self.next_label == other.next_label and self.groups.same_as(other.groups)
                and self.lane.same_as(other.lane))


_STATS0 = dict(n_touched=0, n_merges=0, n_splits=0, n_exact_splits=0, split_kl=0.0, split_l1=0.0,
               n_duplicates_merged=0, n_kalman_updates=0, n_predict_only=0, mass_retained_min=1.0, n_fast_path=0,
               n_fast_births=0, n_fast_clutter=0, n_fast_quiet=0, n_fast_born=0, n_fast_born_detected=0, n_fast_seeded=0)


class FactoredFilter:
    """Hypothesis filter whose posterior is a product of independent groups (package docstring).

    Parameters
    ----------
    motion, sensor, weights, generator, population, dt, max_hypotheses, cap, gate_probability, seed, merge_duplicates :
        As :class:`~..filter.HypothesisFilter`; ``max_hypotheses`` caps each group (and each merge).
    validity : callable, optional
        As :class:`~..filter.HypothesisFilter` (:mod:`..validity`): applied in every group step, so every
        newborn is tested; a quiet singleton (no return, no event) is only predicted and keeps its one track.
    means, covs, labels : array_like, optional
        Initial objects, one group each.
    options : FactoredOptions, optional
        How the filter factors, prunes and parallelises (:class:`~.options.FactoredOptions`: every
        option, its default and its allowed values, stated once). The keywords ``split``,
        ``births``, ``factor_tol``, ``min_weight``, ``adaptive_birth``, ``workers``, ``parallel``,
        ``measure_transfer``, ``lazy``, ``gate_out_of_view``, ``fast_path``, ``replay`` override single options (``lazy``
        is off by default; the SSA catalogue experiment's configuration turns it on).

    Attributes
    ----------
    options : FactoredOptions
        The options (``workers``, ``parallel`` and ``measure_transfer`` may be set between scans;
        they are validated like the options and change no posterior).
    time : float
        Time of the last scan (or of :meth:`initialise`).
    last_stats : dict
        Of the last scan: ``n_groups``, ``largest_group`` (objects), ``largest_group_hypotheses``,
        ``n_touched`` (groups stepped with returns or birth terms), ``n_predict_only`` (groups
        only predicted, or with ``lazy`` left for later), ``n_singletons`` (groups in the lane),
        ``n_predicted`` (tracks predicted this scan), ``n_asleep`` (groups left unpredicted, ``lazy``),
        ``n_merges`` (groups merged away), ``n_splits``, ``n_exact_splits``, ``split_kl`` and
        ``split_l1`` (summed losses of this scan's splits), ``n_duplicates_merged``,
        ``n_kalman_updates``, ``mass_retained_min`` (smallest share of its children's mass a
        touched group kept under the cap), ``n_fast_path``, ``n_fast_births``, ``n_fast_clutter``
        (components the fast path took: lone tracks updated, lone birth terms and returns dropped;
        they count in ``n_touched``, not in ``n_jobs``), ``n_fast_quiet`` (quiet groups the fast path
        found to keep no object after their empty-scan step: dropped, not in ``n_jobs``), ``n_fast_born`` (lone
        birth terms keeping both children, stepped from a template: in ``n_touched``, not in ``n_jobs``), ``n_fast_born_detected``
        (birth terms with one return, born detected in closed form, :mod:`.born_detected`: likewise), ``n_fast_seeded`` (returns in no gate, HOMHT's seeded births in closed form, :mod:`.seeded_birth`: likewise), ``n_jobs`` (engine steps), ``time_steps`` (wall seconds running them), ``time_total``; with a process
        pool or ``measure_transfer``, ``bytes_to_workers``/``bytes_from_workers`` (and
        ``bytes_model``, the template sent to the pool; ``worker_cpu_s``, the pool processes' CPU seconds).
    stats_history : list of the ``last_stats`` of every scan.
    split_records : list of :class:`~..factored_groups.SplitRecord`, every split (and, with
        ``split="exact"``, every rejected one), with its KL and L1 loss.
    """

    def __init__(self, motion, sensor, weights, generator, *, population=None, dt=1.0, max_hypotheses=100,
                 cap="top", gate_probability=None, seed=None, means=None, covs=None, labels=None,
                 merge_duplicates=True, validity=None, options: FactoredOptions | None = None, **option_changes):
        engine = HypothesisFilter(motion, sensor, weights, generator, population=population, dt=dt,
                                  max_hypotheses=max_hypotheses, cap=cap, gate_probability=gate_probability,
                                  seed=seed, merge_duplicates=merge_duplicates, validity=validity)
        self._configure(engine, options, option_changes)
        self.initialise(np.zeros((0, self.ndim)) if means is None else means, covs, labels)

    @classmethod
    def from_filter(cls, f: HypothesisFilter, options: FactoredOptions | None = None, **option_changes):
        """The factored form of a configured engine (e.g. a preset) and its current posterior.

        ``f``'s configuration is used and its random generator copied (``f`` is not changed).
        Its hypotheses become one group, split exactly into one group per object where the
        joint factorises (a single hypothesis always does). ``options``/``option_changes``: as the
        constructor's (:class:`~.options.FactoredOptions`).
        """
        if not isinstance(f, HypothesisFilter):
            raise TypeError(f"f must be a HypothesisFilter, got {type(f).__name__}")
        unknown = set(option_changes) - set(FactoredOptions.names())
        if unknown:
            raise ValueError(f"unknown options {sorted(unknown)}; allowed: {', '.join(FactoredOptions.names())}")
        obj = cls(**f.configuration(), seed=copy.deepcopy(f.rng), options=options, **option_changes)
        obj.initialise(np.zeros((0, obj.ndim)), time=f.time)
        state = f.state.with_next_label(0)
        groups = [state] if any(len(t) for t in state.tracks) else []
        lone = one_hypothesis_lane(state) if obj._silent and groups else None
        if lone is not None:  # one singleton per object, as the exact split gives them (without it)
            obj._groups, obj._lane = GroupSet.at((), f.time), Lane.at(lone, f.time)
            groups = None
        elif groups and len(state.labels) > 1:
            record, parts = factorise(state, np.searchsorted(state.labels, state.store.labels), obj.options.factor_tol)
            if record.exact:
                groups = parts
        if groups is not None:
            states, lane, r = sort_out(groups, obj._mode, obj._engine.population, obj.ndim)
            obj._groups, obj._lane = GroupSet.at(states, f.time), Lane.at(lane, f.time, *lane_existence(obj._bern_pop, lane, r))
        obj._next_label = f.next_label
        obj.scan_index = f.scan_index
        return obj

    def _configure(self, engine: HypothesisFilter, options, changes):
        options = FactoredOptions() if options is None else options
        if not isinstance(options, FactoredOptions):
            raise TypeError(f"options must be a FactoredOptions, got {type(options).__name__}")
        options = options.with_changes(**changes) if changes else options
        ab = options.adaptive_birth
        if ab is not None:
            if engine.weights.seeded_births:
                raise ValueError("adaptive_birth needs a population with birth terms; HOMHT's seeded births already "
                                 "start objects at returns (use one of the two)")
            if engine.population is None or not hasattr(engine.population, "birth_densities"):
                raise ValueError("adaptive_birth needs a population (labeled multi-Bernoulli or binomial) whose "
                                 "birth terms it sets each scan")
            if engine.population.n_birth_regions:
                raise ValueError("adaptive_birth sets the population's birth terms itself: give a population "
                                 f"with no birth terms, got {engine.population.n_birth_regions}")
        self._options = options
        self._engine = engine  # the template of every group's step: models, population, settings; no hypotheses
        self._pool = WorkerPool()
        self._born_templates = {}  # r_B -> the fast path's lone birth term step (:func:`.born_detected.birth_step`)
        self._detected = {}  # the kept key of a born-detected step, once checked (:func:`.born_detected.born_detected_plan`)
        self.rng = engine.rng
        self.ndim = engine.state_dim
        # singletons are exactly their Gaussian when a quiet group takes no population event, or (per-track
        # survival) when their track surely survives (lane.survival_lane)
        self._silent = silent(engine.population)
        self._bern = bernoulli_lane(engine.population, options.bernoulli_lane)  # (lane module docstring)
        self._bern_pop = engine.population if self._bern else None
        self._lane_on = self._silent or survival_lane(engine.population) or self._bern
        self._mode = "off" if not self._lane_on else "silent" if self._silent else "bernoulli" if self._bern else "survival"

    # ------------------------------------------------------------------ options
    @property
    def options(self) -> FactoredOptions:
        return self._options

    def set_options(self, **changes) -> None:
        """Change ``workers``, ``parallel`` or ``measure_transfer`` between scans (validated)."""
        bad = set(changes) - {"workers", "parallel", "measure_transfer"}
        if bad:
            raise ValueError(f"only workers, parallel and measure_transfer can change after construction, got {sorted(bad)}")
        self._options = self._options.with_changes(**changes)

    @property
    def workers(self) -> int:
        return self._options.workers

    @workers.setter
    def workers(self, value):
        self.set_options(workers=value)

    @property
    def parallel(self) -> str:
        return self._options.parallel

    @parallel.setter
    def parallel(self, value):
        self.set_options(parallel=value)

    @property
    def measure_transfer(self) -> bool:
        return self._options.measure_transfer

    @measure_transfer.setter
    def measure_transfer(self, value):
        self.set_options(measure_transfer=value)

    @property
    def engine(self) -> HypothesisFilter:
        """The engine every group's step runs (its configuration; it holds no hypotheses)."""
        return self._engine

    def _reset(self, time: float = 0.0):
        if self._options.adaptive_birth is not None:
            self._set_birth_terms([])
        self._groups = GroupSet.at((), time)
        self._lane = Lane.empty(self.ndim, self._bern)
        self.time = float(time)
        self._objects = ObjectIds()
        self._next_label = 0
        self.scan_index = 0
        self.last_stats = {}
        self.stats_history = []
        self.split_records = []

    # ------------------------------------------------------------------ state
    def initialise(self, means, covs=None, labels=None, *, time: float = 0.0):
        """One group per object (``n = 0`` allowed), each with its single hypothesis, at ``time``."""
        self._reset(check_finite_float(time, "time"))
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
        if self._bern:
            self._lane = Lane.at(store, self.time, *lane_existence(self._bern_pop, store, np.ones(len(store))))
        elif self._lane_on:
            ok = admitted(self._engine.population, store)
            self._lane = Lane.at(store if ok.all() else take(store, np.flatnonzero(ok)), self.time)
            self._groups = GroupSet.at([singleton(store, j) for j in np.flatnonzero(~ok)], self.time)
        else:
            self._groups = GroupSet.at([singleton(store, j) for j in range(len(store))], self.time)
        self._next_label = int(store.labels.max()) + 1

    def state(self) -> FactoredState:
        """The posterior as held (:class:`FactoredState`; lazy groups and singletons not predicted)."""
        return FactoredState(self._groups, self._lane, self.time, self._next_label, dict(self._objects.mapping))

    def same_posterior(self, other: "FactoredFilter") -> bool:
        """Whether ``other`` holds bit-for-bit the same posterior (:meth:`FactoredState.same_as`)."""
        return self.state().same_as(other.state())

    @property
    def next_label(self) -> int:
        """The label the next newborn object gets."""
        return self._next_label

    @property
    def groups(self) -> list:
        """The groups' states (:class:`~..state.FilterState`): the multi-hypothesis groups, then the
        singletons (predicted to the current scan), as a new list."""
        lane = self._lane.now(self.time, self._engine.motion)
        return self._groups.now(self.time, self._engine.motion) + self._lane.bernoulli_states(lane)

    @property
    def n_objects_held(self) -> int:
        """Objects (labels) held by some hypothesis of some group."""
        return int(sum(len(s.labels) for s in self._groups.states) + len(self._lane))

    @property
    def n_joint_hypotheses(self) -> int:
        """Hypotheses of the product (``Π_g H_g``, exact integer; a Bernoulli singleton of ``r < 1`` holds two)."""
        n = [len(s.log_w) for s in self._groups.states] + [2] * int(np.sum(self._lane.r < 1) if self._bern else 0)
        return int(np.prod(n, dtype=object)) if n else 1

    # ------------------------------------------------------------------ scan
    def step(self, Z, time=None, *, dt=None) -> FactoredPosterior:
        """Advance one scan with returns ``Z`` (m, p) observed at ``time`` (package docstring, steps 1–4).

        ``time``/``dt`` as :meth:`HypothesisFilter.step <..filter.HypothesisFilter.step>`: a zero interval advances no
        lane mean and predicts only the tracks another sensor's scan woke (scan by scan with ``replay``; the population's
        per-scan events are those of any scan) and updates; a negative one raises ``ValueError``.
        All-or-nothing like the engine's step: if it raises, the filter is as before.
        """
        saved = (self._groups, self._lane, self.time, self._next_label, self.scan_index, self.rng.bit_generator.state,
                 self.last_stats, len(self.stats_history), len(self.split_records), self._objects.copy(),
                 self._engine.population)
        try:
            return self._step(Z, time, dt)
        except BaseException:
            (self._groups, self._lane, self.time, self._next_label, self.scan_index, rng_state, self.last_stats,
             n_hist, n_split, self._objects, population) = saved
            self._engine.set_population(population)
            self.rng.bit_generator.state = rng_state
            del self.stats_history[n_hist:], self.split_records[n_split:]
            raise

    def _step(self, Z, time, dt):
        t0, E = _clock.perf_counter(), self._engine
        interval, now = scan_interval(self.time, time, dt, E.dt)
        Z = check_measurements(Z, "Z", E.meas_dim)
        scan = self._predict_and_score(Z, interval, now)
        graph = scan_graph(scan.col_node, scan.G, scan.L, scan.scores, scan.birth_ll, self._options.births,
                           E.weights.seeded_births)
        if not self._silent and self._lane_on and not self._bern:  # a lane track that may die this scan takes its step (lane.survival_lane)
            graph = graph.touching(scan.G + np.flatnonzero(scan.scores.p_survive[scan.bounds[-1]:] < 1))
        stats = dict(_STATS0, n_predicted=len(scan.pred))
        fast = self._fast(scan, graph, Z, stats)
        plans, keys = self._plan(scan, graph, Z, stats, None if fast is None else fast.comps)
        new_groups = self._run_plans(plans, keys, fast, stats)
        self._keep(scan, graph, new_groups, fast, now, stats)
        self.time = now
        self._objects.keep_held(np.concatenate([s.store.labels for s in self._groups.states] + [self._lane.labels]))
        self.scan_index += 1
        sizes = [len(np.unique(self._objects.of(s.labels))) for s in self._groups.states]
        states = self._groups.states
        stats.update(n_groups=len(states) + len(self._lane), n_singletons=len(self._lane),
                     largest_group=max(sizes, default=int(len(self._lane) > 0)),
                     largest_group_hypotheses=max((len(s.log_w) for s in states), default=int(len(self._lane) > 0)),
                     time_total=_clock.perf_counter() - t0)
        if self._options.adaptive_birth is not None:
            stats["n_adaptive_terms"] = self._births_after(Z[graph.unexplained], interval)
        self.last_stats = stats
        self.stats_history.append(stats)
        return self.posterior()

    def _predict_and_score(self, Z, interval, now) -> "ScanData":
        """Step 1: predict the groups and the singletons that may be observed (``lazy``: those whose
        mean, advanced a scan, is in view), score every return against them."""
        E, lazy = self._engine, self._options.lazy
        groups, group_gap, asleep = self._groups.wake(lazy and self._silent, interval, now, self._advance_view)
        sizes = np.array([len(s.store) for s in groups], dtype=np.int64)
        bounds = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        cand, view = self._lane.candidates(lazy, interval, self._advance_view)
        lane = self._lane
        prior = cat([s.store for s in groups] + [lane.take(cand)], self.ndim)
        pm, pP = predict_each(E.motion, prior.means, prior.covs,
                              np.concatenate([np.repeat(group_gap, sizes), (now - lane.times)[cand]]),
                              step=(interval or E.dt) if self._options.replay else None)
        pred = TrackStore(pm, pP, prior.labels)
        G, L = len(groups), len(cand)
        birth_ll = birth_loglik(E.population, Z) if E.population is not None else np.zeros((len(Z), 0))
        col_node = np.concatenate([np.repeat(np.arange(G), sizes), G + np.arange(L)]).astype(np.int64)
        return ScanData(groups, asleep, bounds, cand, view, pred, self._scores(pred, Z), birth_ll, col_node, G, L)

    def _fast(self, scan, graph, Z, stats) -> FastBatch | None:
        """The fast path (``fast_path``, :mod:`.fast_path`): the components that are one lane singleton with one return
        and nothing else, whose general step keeps only the detected child, stepped in one batch; ``None``: off/not exact."""
        rule, E = self._fast_rule(), self._engine
        if rule is None:
            return None
        r_birth = None if E.population is None or E.max_hypotheses < 2 else birth_existence(E.population)
        c0, rp = int(scan.bounds[-1]), None  # Bernoulli singletons: r p_S ("not": 1 - r p_S, "died" merged into it)
        if self._bern:  # (duplicates not merged: 0, none taken)
            rp = self._lane.r[scan.cand] * lane_survival(E.population, take(scan.pred, np.arange(c0, len(scan.pred)))) * E.merge_duplicates
        fast = fast_components(rule, graph, scan.scores, scan.pred, c0, Z, E.H if E.H is not None else E.measurement, E.R,
                               E.weights.seeded_births, r_birth, E.population, lane_exist=rp)
        n = len(fast.store)
        stats.update(n_fast_path=n, n_fast_births=fast.n_births, n_fast_clutter=fast.n_clutter,
                     n_touched=stats["n_touched"] + len(fast), n_kalman_updates=stats["n_kalman_updates"] + n)
        return fast

    def _fast_rule(self):
        """The fast path's :class:`~.fast_path.FastRule`, or ``None`` (off, or not exact for this engine)."""
        return fast_rule(self._engine, self._lane_on, self._options.min_weight) if self._options.fast_path else None

    def _plan(self, scan, graph, Z, stats, skip=None) -> tuple:
        """Step 2–3: one plan per component, in the order of its first node (deterministic): a quiet
        group predicts or takes an empty-scan step; a touched component merges its groups and steps.
        Returns the plans and their keys (first nodes); ``skip``: components the fast path took."""
        E, plans, keys, bounds = self._engine, [], [], scan.bounds
        lane_r = self._lane.r[scan.cand] if self._bern else None  # a woken Bernoulli enters as its two hypotheses
        rule = self._fast_rule()
        born_det, seeded = born_detected_applies(E, rule, self._mode), lone_seeded_applies(E, rule)
        r_birth = None if rule is None or E.population is None or E.max_hypotheses < 2 else birth_existence(E.population)
        for key, c, members, regions, rows in graph.components(skip):
            keys.append(key)
            general = partial(touched_plan, E, self.rng, members, regions, rows, scan.groups, bounds, scan.pred,
                              scan.scores, Z, scan.birth_ll, stats, lane_r)  # the plan of the component's engine step
            if c is None:
                cols = np.arange(bounds[key], bounds[key + 1])
                state = scan.groups[key]
                plan = quiet_plan(E, self._silent, self._objects, state, take(scan.pred, cols),
                                  scan.scores.block(np.zeros(0, np.int64), cols), Z, scan.birth_ll, stats, rule)
                if (plan[0] == "quiet" and rule is not None and self._silent and len(np.unique(self._objects.of(state.labels))) == 1
                        and rule.quiet_group_dies(state.log_w, state.tracks, scan.scores.p_detect[cols])):
                    # the fast path: its step would keep no object (one object: no split, no record)
                    plan = ("dropped",)
                    stats["n_fast_quiet"] += 1
                plans.append(plan)
            elif (r_birth is not None and len(members) == 0 and len(rows) == 0 and len(regions) == 1
                  and rule.keeps_born(r_birth[regions[0]])):
                # a lone birth term keeping both children: one engine step of such a term (no return: one
                # association, nothing drawn) is the template of every term of its r_B (FastRule.keeps_born)
                r_b = float(r_birth[regions[0]])
                if r_b not in self._born_templates:
                    self._born_templates[r_b] = born_template(engine_step(E, *general()[1:], 0, 0))
                if self._born_templates[r_b] is None:
                    plans.append(general())
                else:
                    plans.append(("born", int(regions[0]), self._born_templates[r_b]))
                    stats["n_fast_born"] += 1
            else:
                plan = None
                if born_det and len(members) == 0 and len(rows) == 1 and len(regions) == 1:  # a birth term, its return
                    plan = born_detected_plan(E, rule, self._options.min_weight, int(regions[0]), int(rows[0]), Z,
                                              scan.birth_ll, self._detected, general)
                elif seeded and len(members) == 0 and len(regions) == 0 and len(rows) == 1:  # a return in no gate
                    plan = lone_seeded_plan(E, general(), self._options.min_weight)
                plans.append(plan or general())
        map_lone_returns(E, plans)  # their covariances mapped in one call
        return plans, np.array(keys, dtype=np.int64)

    def _run_plans(self, plans, keys, fast, stats) -> list:
        """The engine steps of the components are independent: run them (in a pool when workers > 1),
        each with its own random stream and labels counted from the scan's first free label; then
        each result in component order, split by its objects' interaction (step 4). Returns
        ``(key, state)`` of every resulting group, in plan order.

        The fast path's components keep their places: a random stream is drawn for each (unused)
        and the labels each uses are counted where its plan would have run, so the other steps
        draw and number exactly as without it."""
        n_fast = 0 if fast is None else len(fast)
        # a dropped quiet group (the fast path's) keeps its step's place: it draws its stream, unused
        steps = np.array([p[0] != "done" for p in plans], dtype=bool)
        run = np.array([p[0] not in _NO_JOB for p in plans], dtype=bool)
        jobs = [p for p, r in zip(plans, run) if r]
        # each step's place among the steps and the fast components (both in key order)
        fast_before = np.searchsorted(fast.keys, keys) if n_fast else np.zeros(len(plans), np.int64)
        slot = (np.cumsum(steps) - 1 + fast_before)[run]
        n_draw = int(steps.sum()) + n_fast
        seeds = self.rng.integers(0, 2**63 - 1, size=n_draw)[slot] if n_draw else np.zeros(0, np.int64)
        base, light = self._next_label, min(self._options.min_weight, 1.0 / self._engine.max_hypotheses) * (1 - 1e-9)
        results = iter(self._pool.run(self._engine, [(p[1], p[2], p[3], p[4], base, int(s), light) for p, s in zip(jobs, seeds)],
                                      self._options, stats))  # (light: _keep's pruning drops it, children.heavy_entries)
        new_groups, opts, counted = [], self._options, 0
        for plan, key, before in zip(plans, keys, fast_before):
            if n_fast:  # the labels the fast path's components before this plan used
                self._next_label += int(fast.labels_before(before) - fast.labels_before(counted))
                counted = before
            if plan[0] == "dropped":
                continue
            if plan[0] in ("done", "slept"):
                state, parts = plan[1], plan[2]
            elif plan[0] in _BIRTHS:  # a closed-form birth step (:mod:`.born_detected`)
                state, parts, used = birth_step(plan, self._engine, self._next_label, self._objects, stats, self.ndim)
                self._next_label += used
            else:
                state, parts = self._finish(plan, next(results), base, stats)
            new_groups.extend((key, s) for s in split_group(state, parts, opts.split, opts.factor_tol,
                                                           self.scan_index + 1, self.split_records, stats))
        if n_fast:
            self._next_label += int(fast.labels_before(n_fast) - fast.labels_before(counted))
        return new_groups

    def _finish(self, plan, result, base, stats):
        """A planned step's result in component order: its new labels moved past the labels
        already given this scan (the serial numbering), births registered, interaction parts."""
        kind, _, pred, ctx, regions = plan
        new, sources, n_new, st = result
        if n_new:
            labels = new.store.labels.copy()
            labels[labels >= base] += self._next_label - base
            new = new.with_store(TrackStore(new.store.means, new.store.covs, labels))
        self._next_label += n_new
        stats["n_duplicates_merged"] += st["n_duplicates_merged"]
        if kind == "quiet":
            return new, self._objects.of(new.store.labels)
        stats["n_touched"] += 1
        stats["mass_retained_min"] = min(stats["mass_retained_min"], st["mass_retained"])
        stats["n_kalman_updates"] += st["n_kalman_updates"]
        self._objects.register_births(new.store, sources, len(regions))
        return new, interaction_parts(self._objects.of(pred.labels), ctx, sources, len(regions))

    def _keep(self, scan, graph, new_groups, fast, now, stats):
        """Step 4's end: singletons back to the lane — the untouched candidates predicted, then those
        the steps (and the fast path) produced, in plan order; the groups left for later first, then the scan's."""
        tail = take(scan.pred, np.arange(scan.bounds[-1], len(scan.pred)))
        kept = [(k, s) for k, s in ((k, prune(s, self._options.min_weight)) for k, s in new_groups) if s is not None]
        states = [s for _, s in kept]
        groups_new, lane_new, r_new = sort_out(states, self._mode, self._engine.population, self.ndim)
        if fast is not None and len(fast.store):
            # the fast path's singletons between the steps' ones, by plan key (stable: a step's own stay in order)
            one = (lambda s: bernoulli_existence(s) is not None) if self._bern else is_singleton
            step_keys = np.array([k for k, s in kept if one(s)], dtype=np.int64)
            order = np.argsort(np.concatenate([step_keys, fast.store_keys]), kind="stable")
            lane_new = take(cat([lane_new, fast.store], self.ndim), order)
            r_new = None if r_new is None else np.concatenate([r_new, np.ones(len(fast.store))])[order]  # detected: r = 1
        quiet, q = graph.quiet_singletons(), np.flatnonzero(graph.quiet_singletons())
        exist = None if not self._bern else scan_existence(  # Bernoulli singletons: empty-scan steps in closed form
            self._lane, scan.cand, scan.view, quiet, take(tail, q), scan.scores.p_detect[scan.bounds[-1] + q],
            self._engine, lane_new, r_new, self._options.min_weight)
        self._lane, n_kept = self._lane.after_scan(scan.cand, quiet, tail, now, scan.view, lane_new, exist)
        stats["n_predict_only"] += n_kept + len(scan.asleep)
        stats["n_asleep"] = len(scan.asleep)
        self._groups = scan.asleep.then(groups_new, now)

    def _advance_view(self, means, interval):
        """Means ``(n, d)`` advanced by ``interval`` (means only, one batch; a zero interval leaves them)
        and whether each is in the field of view."""
        E = self._engine
        view = means if interval == 0 else E.motion.propagate(means, interval)
        return view, E.sensor.detection.in_view(view @ E.H.T if E.H is not None else E.measurement.view_points(view))

    def _scores(self, pred, Z) -> Scores:
        """Every return against every predicted track (:func:`~.planner.score_scorable`: the engine's
        ``track_scores``, at scale the gated pairs alone, :func:`~.scores.score_tracks`; a track whose
        prediction diverged takes no return and is not missed); without ``gate_out_of_view`` a track with
        ``p_D = 0`` gates nothing."""
        return score_scorable(self._engine, pred, Z, gate_out_of_view=self._options.gate_out_of_view,
                              survival=getattr(self._engine.population, "track_survival", None))

    def _births_after(self, Z, interval) -> int:
        """The next scan's birth terms, one at each return ``Z`` no group or birth term explained, predicted over this scan's
        interval (the next one's if evenly spaced; :mod:`.multisensor` waits for the next scan's time and sensor); their number."""
        E = self._engine
        terms = self._options.adaptive_birth.terms(Z, E.H, E.R, E.motion, interval, measurement=E.measurement)
        self._set_birth_terms(terms)
        return len(terms)

    def _set_birth_terms(self, terms):
        r_birth = self._options.adaptive_birth.r_birth
        if any(getattr(t, "weight", 1.0) != 1.0 for t in terms):  # an admissible-region mixture's components
            r_birth = r_birth * np.array([t.weight for t in terms])
        pop = self._engine.population.with_birth_terms(terms, r_birth=r_birth)
        self._engine.set_population(pop)

    # ------------------------------------------------------------------ pool
    def warm_up(self):
        """Start the pool's workers now and set up numba's typing in each (about a second of CPU on
        a worker's first compiled call otherwise), so the first scans do not pay for it; no-op for
        ``workers = 1``."""
        self._pool.warm_up(self._options)

    def close(self):
        """Shut the worker pool down (a later parallel step starts a new one)."""
        self._pool.close()

    # ------------------------------------------------------------------ output
    def posterior(self, n_top: int = 1) -> FactoredPosterior:
        """Per-group posteriors, the convolved cardinality distribution and the union of MAPs."""
        n_top = check_int(n_top, "n_top", minimum=1)
        motion, t, groups, lane = self._engine.motion, self.time, self._groups, self._lane
        states, singles, n_singles, n_unsure = lane.summary_parts(lambda: groups.now(t, motion), t, motion)
        return FactoredPosterior(states, singles, n_singles, n_top=n_top, n_states=len(groups) + n_unsure)

    def map_means(self) -> tuple[np.ndarray, np.ndarray]:
        """``(labels, means)`` of the MAP joint hypothesis: :attr:`posterior`'s ``map_estimate``
        without covariances, so the lane's singletons are not predicted (their means at the current
        scan are kept; with ``lazy``, advanced a scan at a time rather than over their whole gap,
        equal to rounding for the Kepler model and to the integrator's error for a numerical one).
        """
        maps = [summarise(s.log_w, s.tracks, TrackStore(v, s.store.covs, s.store.labels)).map_estimate
                for s, v in zip(self._groups.states, self._groups.views)]
        lane = self._lane
        if lane.r is not None:  # a Bernoulli singleton is in the MAP when "exists" is the heavier (first on a tie)
            lane = lane.where(lane.r >= 1.0 - lane.r)
        return (np.concatenate([e.labels for e in maps] + [lane.labels]).astype(np.int64),
                np.concatenate([e.means for e in maps] + [lane.view]).reshape(-1, self.ndim))

    def estimates(self) -> TrackEstimates:
        """The MAP joint hypothesis (the union of the groups' MAPs) at :attr:`time`: labels and means
        (:meth:`map_means`), ``P = None`` — the lazy lane's and lazy groups' covariances are not
        predicted to the scan (:attr:`posterior`'s ``map_estimate`` has them, at that cost)."""
        labels, means = self.map_means()
        return TrackEstimates(self.time, labels, means, None)

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


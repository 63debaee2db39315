"""The singleton lane and lazy prediction (package docstring, "Singletons and lazy prediction").

At catalogue scale nearly every group is a singleton: one object, one hypothesis, one track. With
a population that takes no event in a quiet group (:func:`silent`) a singleton is exactly its
Gaussian, so the factored filter keeps all of them in one batched :class:`Lane` (moments, the time
each was last predicted to, its mean at the current scan) instead of one Python object each; the
multi-hypothesis groups are a :class:`GroupSet` (the same times and means per group). With ``lazy``
only what may be in view is predicted in full (:meth:`Lane.candidates`, :meth:`GroupSet.wake`):
a track out of view takes no return, and one EKF prediction over a gap of ``k`` scans replaces
``k`` predictions (equal for a linear constant-velocity model).

Bernoulli singletons (``bernoulli_lane``)
-----------------------------------------
With a labeled multi-Bernoulli population whose tracks may die, the general engine holds a lone
track of existence ``r < 1`` as a group of two hypotheses over one track: "exists" (weight ``r``,
the track) and "not" (``1 − r``, no track) (:func:`bernoulli`). A scan in which no return or birth term
reaches it is the engine's empty-scan step (Vo, Vo & Hoang 2017, Eq. 12; the labeled problem's
rows, :mod:`..population_lmb`): children "exists, missed" ``r p_S (1 − p_D)``, "died" ``r (1 − p_S)`` and
"not" ``1 − r``, the last two the same hypothesis (no track: merged), so the posterior is again
one Bernoulli. Document 001's binomial population (R-FISST's, HOMHT's deaths; Eq. 59, per-track ``p_S``
allowed) gives a group of one track and no birth term the same three children (its "at most one death per
child" loses nothing with one object; the H-FISST and Reid weights' clutter and count factors are the
scan's, common to the three), so the lane holds its lone tracks alike,

    ``r' = r p_S (1 − p_D) / (1 − r p_S p_D)``                 (:func:`missed`)

(out of view ``p_D = 0``: ``r' = p_S r``), and the engine's pruning of its two hypotheses deletes the
track when ``r' < min_weight`` (and "not" is the heavier) or sets ``r' = 1`` when ``1 − r' < min_weight``
(:func:`bernoulli_prune`). So the lane carries ``r`` and each singleton's per-scan survival
``p_S`` (of its moments when last predicted): a quiet candidate takes :func:`missed` with its
predicted ``p_S`` and ``p_D``, a singleton out of view ``r ← p_S r`` each scan (one multiplication over
the lane; over ``k`` scans asleep ``p_S^k r``, exact for a constant ``p_S``, and for a per-track
``survival`` the value at its last prediction, which for :class:`~..population_lmb.UnconfirmedDecay`
changes only where the track turns tentative out of view), and a singleton a return or birth term
reaches enters the engine's step as its two hypotheses (:func:`bernoulli`), its results of one track
coming back with their ``r``. ``r = 1`` is the single hypothesis of a lone track, as without.
The survival is per scan, as the engine's (``p_S^k`` over ``k`` scans: ``p_S^{Δt/dt}`` for evenly spaced
scans); "died" and "not" are one hypothesis when the engine merges duplicates (its default; the fast path
takes no Bernoulli singleton otherwise); with the engine's ``validity`` test a track failing it leaves, as its
"missed" child weighs 0 there (:func:`scan_existence`: a quiet candidate at its prediction, a singleton asleep
at its mean at the scan).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...gaussian import predict_with_unchecked, symmetrize
from ..population_events import BinomialPopulation
from ..population_lmb import LabeledMultiBernoulliPopulation
from ..state import FilterState
from ..tracks import TrackStore
from .lane_kernels import rebuild

__all__ = ["Lane", "GroupSet", "silent", "survival_lane", "admitted", "predict_each", "singleton", "is_singleton", "take", "cat", "empty_state",
           "one_hypothesis_lane", "bernoulli", "bernoulli_existence", "bernoulli_lane", "lane_survival", "missed",
           "bernoulli_prune", "lane_existence", "scan_existence", "sort_out"]


def silent(population) -> bool:
    """Whether a group without birth terms can take no population event: no population, or the
    labeled multi-Bernoulli or binomial population with ``p_S = 1`` and no per-track survival (its only child of an empty scan is "every object
    missed", as with no population)."""
    return population is None or (isinstance(population, (LabeledMultiBernoulliPopulation, BinomialPopulation))
                                  and population.p_survive == 1.0 and getattr(population, "survival", None) is None)


def survival_lane(population) -> bool:
    """Whether the lane may hold the tracks that surely survive a scan although the population has per-track
    survival: the labeled multi-Bernoulli population with ``p_S = 1`` and a ``survival`` callable (e.g.
    :class:`~..population_lmb.UnconfirmedDecay`: 1 for a confirmed track). A track of ``p_S = 1`` has no
    "died" child (weight ``1 − p_S = 0``), so as a singleton it is exactly its Gaussian, as with a silent
    population. The factored filter keeps there only tracks of ``p_S = 1`` (:func:`admitted`), checks each
    again whenever it predicts it (a candidate of ``p_S < 1`` is stepped on the empty scan: it may die) and
    predicts every group each scan (a group may hold a track that can die out of view). Lazy prediction takes
    a lane track out of view as surviving surely until it is next predicted (its ``p_S`` is not evaluated
    at the scans it sleeps through): exact when ``p_S`` stays 1 along the prediction, as a confirmed track's
    velocity spread (``UnconfirmedDecay``) does over an orbit's gap with the catalogue's process noise."""
    return (type(population) in _BERNOULLI_POPULATIONS and population.p_survive == 1.0
            and population.survival is not None)


def admitted(population, store: TrackStore) -> np.ndarray:
    """Whether each track of ``store`` may be a lane singleton: every one with a :func:`silent` population,
    those whose per-track survival is exactly 1 with a :func:`survival_lane` one (bool ``(n,)``)."""
    if silent(population) or len(store) == 0:
        return np.ones(len(store), dtype=bool)
    return population.track_survival(store) == 1.0


#: the populations whose lone track's posterior is exactly one Bernoulli (module docstring): the labeled
#: multi-Bernoulli and document 001's binomial one — with one object and no birth term in the group the binomial
#: population's "at most one death per child" loses nothing, and its children are the labeled problem's
#: ("missed" ``p_S (1 − p_D)``, "died" ``1 − p_S``, "not" ``1 − r``; the H-FISST and Reid weights' other factors
#: — count term, clutter — are those of the scan's returns, common to the three)
_BERNOULLI_POPULATIONS = (LabeledMultiBernoulliPopulation, BinomialPopulation)


def bernoulli_lane(population, requested: bool) -> bool:
    """Whether the lane holds Bernoulli singletons (module docstring): ``requested`` (the ``bernoulli_lane``
    option) with a labeled multi-Bernoulli or binomial population that is not :func:`silent`."""
    return bool(requested) and type(population) in _BERNOULLI_POPULATIONS and not silent(population)


def lane_survival(population, store: TrackStore) -> np.ndarray:
    """Per-scan ``p_S`` ``(n,)`` of the tracks of ``store`` (labeled multi-Bernoulli or binomial): its ``survival`` of their
    moments, else its one ``p_survive`` (:meth:`~..population_lmb.LabeledMultiBernoulliPopulation.log_existence`)."""
    p = population.track_survival(store)
    return np.full(len(store), float(population.p_survive)) if p is None else p


def missed(r, p_s, p_d) -> np.ndarray:
    """Existence after a scan with no return for the track (module docstring):
    ``r p_S (1 − p_D) / (1 − r p_S p_D)``; ``r = p_S = 1`` stays exactly 1."""
    a = np.asarray(r, dtype=float) * p_s
    return a * (1.0 - p_d) / (1.0 - a * p_d)


def bernoulli_prune(r, min_weight: float):
    """``(alive, r)``: the engine's pruning (:func:`~.planner.prune`: below ``min_weight`` dropped, the heavier
    always kept, "exists" first on a tie) of the Bernoulli groups of existences ``r``: "exists" dropped (the
    track deleted: ``alive`` False) or "not" dropped (``r = 1``)."""
    r = np.asarray(r, dtype=float)
    if min_weight <= 0:
        return r > 0, r
    alive = (r > 0) & ((r >= min_weight) | (r >= 1.0 - r))
    return alive, np.where(((1.0 - r) >= min_weight) | (1.0 - r > r), r, 1.0)


def bernoulli(store: TrackStore, j, r: float) -> FilterState:
    """The group of store entry ``j`` of existence ``r``: :func:`singleton` for ``r = 1``, else the two
    hypotheses the general engine holds for it, "exists" (``log r``, the track) and "not" (``log(1 − r)``)."""
    if r == 1.0:
        return singleton(store, j)
    return FilterState(TrackStore(store.means[[j]], store.covs[[j]], store.labels[[j]]),
                       np.array([np.log(r), np.log1p(-r)]),
                       [np.zeros(1, dtype=np.int64), np.zeros(0, dtype=np.int64)], [("lane", 1), ("lane", 0)])


def bernoulli_existence(state: FilterState) -> float | None:
    """The existence ``r`` of a group that is one track's Bernoulli (:func:`bernoulli`; a singleton: 1),
    or ``None`` for any other group."""
    if len(state.store) != 1:
        return None
    if len(state.log_w) == 1:
        return 1.0 if len(state.tracks[0]) == 1 else None
    if len(state.log_w) == 2 and sorted(len(t) for t in state.tracks) == [0, 1]:
        h = 0 if len(state.tracks[0]) == 1 else 1
        return float(np.exp(state.log_w[h] - np.logaddexp(state.log_w[0], state.log_w[1])))
    return None


def lane_existence(population, store: TrackStore, r):
    """``(r, p_s)`` of new Bernoulli singletons ``store`` of existences ``r``: their per-scan survival at these
    moments (:func:`lane_survival` of ``population``); ``(None, None)`` without Bernoulli singletons (``population``
    ``None``)."""
    if population is None:
        return None, None
    return np.asarray(r, dtype=float), lane_survival(population, store)


def scan_existence(lane: "Lane", cand, view, quiet, pred: TrackStore, p_detect, engine, new: TrackStore, r_new,
                   min_weight: float):
    """The ``exist`` of :meth:`Lane.after_scan` for Bernoulli singletons. The quiet candidates ``cand[quiet]``
    (predicted to ``pred``, no return or birth term) take the engine's empty-scan step in closed form (:func:`missed`
    with the predicted ``p_S`` and the scan's ``p_D``, the ones its step takes from the scores); the singletons
    ``new`` the steps produced keep their existences ``r_new``; each one's survival (:func:`lane_survival`) and
    ``min_weight``. With the engine's ``validity`` test a track failing it gets ``r' = 0``, as its "missed" child
    weighs 0 in the engine's step: a quiet candidate at its prediction, a singleton asleep at its mean at the scan
    (``view``, lazy) — unless ``r = p_S = 1`` (a lone track the general path only predicts)."""
    population, validity = engine.population, engine.validity
    r = lane.r[cand[quiet]]
    p_s = lane_survival(population, pred)
    out = missed(r, p_s, p_detect)
    ok = None
    if validity is not None:
        check = (lane.r < 1) | (lane.p_s < 1)
        check[cand] = False
        if len(pred):
            v = np.asarray(validity(pred.means), dtype=bool)
            out = np.where(((r < 1) | (p_s < 1)) & ~v, 0.0, out)
        if view is not None and bool(check.any()):
            # the test is row by row: every singleton's mean at the scan in one call (the few candidates' verdicts
            # unused), not a copy of the asleep ones (nearly all of the lane: a decaying p_S is below 1 for every track)
            ok = np.where(check & ~np.asarray(validity(view), dtype=bool), 0.0, 1.0)
    return out, p_s, np.asarray(r_new, dtype=float), lane_survival(population, new), min_weight, ok


def sort_out(states, mode: str, population, ndim: int):
    """``(groups, lane store, r)``: the singletons of ``states`` moved to a lane store — ``mode`` ``"off"`` (none),
    ``"silent"`` (every singleton), ``"survival"`` (those whose track surely survives, :func:`admitted`) or
    ``"bernoulli"`` (every one-track Bernoulli, ``r`` their existences, :func:`bernoulli_existence`; else
    ``r`` is ``None``)."""
    if mode == "off":
        return list(states), cat([], ndim), None
    if mode == "bernoulli":
        r = [bernoulli_existence(s) for s in states]
        return ([s for s, x in zip(states, r) if x is None], cat([s.store for s, x in zip(states, r) if x is not None], ndim),
                np.array([x for x in r if x is not None], dtype=float))
    single = [is_singleton(s) for s in states]
    if mode == "survival" and any(single):  # per-track survival: only the tracks surviving surely
        ok = iter(admitted(population, cat([s.store for s, x in zip(states, single) if x], ndim)))
        single = [x and bool(next(ok)) for x in single]
    return ([s for s, x in zip(states, single) if not x], cat([s.store for s, x in zip(states, single) if x], ndim), None)


def predict_each(motion, x, P, dt, step=None):
    """EKF prediction of ``(x, P)`` by their own intervals ``dt`` (n,): the motion model's
    ``transition_each``/``Q_each`` where it has them (one batch), else one batch per distinct
    interval (a zero interval leaves a track as it is).

    ``step`` (> 0, optional): each interval is cut into ``k = max(1, round(dt / step))`` equal steps,
    predicted one after the other, ``P ← sym(Φ P Φᵀ + Q(dt / k))`` — the predictions an eager filter
    scanning every ``step`` makes (``Σ Φ Q Φᵀ``), where one step over the interval adds ``Q(dt)``
    (package docstring: far apart over an orbit's gap between passes). All tracks take their ``j``-th
    step in one batch; with a motion model that has ``replay_each`` (:class:`~...models.orbit3d.J2Orbit3D`: a
    compiled kernel) every track takes all its steps in one call (the same numbers: bit for bit where numpy and its BLAS
    round with fused multiply-adds, :func:`~...models.orbit3d_replay.rounds_as_numpy`; else to rounding)."""
    if step is not None and len(dt):
        k = np.where(dt > 0, np.maximum(np.rint(np.asarray(dt) / float(step)), 1), 0).astype(np.int64)
        if getattr(motion, "replay_each", None) is not None:
            return motion.replay_each(x, P, np.where(k > 0, dt / np.maximum(k, 1), 0.0), k)
        if k.max() > 1:
            h = np.where(k > 0, dt / np.maximum(k, 1), 0.0)
            xo, Po = x.copy(), P.copy()
            for j in range(int(k.max())):
                sel = np.flatnonzero(k > j)
                xo[sel], Po[sel] = predict_each(motion, xo[sel], Po[sel], h[sel])
            return xo, Po
    if len(dt) and np.all(dt == dt[0]):
        return predict_with_unchecked(motion, x, P, float(dt[0])) if dt[0] != 0 else (x.copy(), P.copy())
    if hasattr(motion, "transition_each"):  # one batch for every interval (a zero one is the identity)
        xo, F = motion.transition_each(x, dt)
        return xo, symmetrize(F @ P @ np.swapaxes(F, -1, -2) + motion.Q_each(dt))
    xo, Po = x.copy(), P.copy()
    for u in np.unique(dt):
        if u != 0:
            sel = dt == u
            xo[sel], Po[sel] = predict_with_unchecked(motion, x[sel], P[sel], float(u))
    return xo, Po


def singleton(store: TrackStore, j) -> FilterState:
    """The group of store entry ``j`` alone: one hypothesis holding one track."""
    return FilterState(TrackStore(store.means[[j]], store.covs[[j]], store.labels[[j]]), np.zeros(1),
                       [np.zeros(1, dtype=np.int64)], [()])


def is_singleton(state: FilterState) -> bool:
    return len(state.log_w) == 1 and len(state.store) == 1 and len(state.tracks[0]) == 1


def take(store: TrackStore, idx) -> TrackStore:
    return TrackStore(store.means[idx], store.covs[idx], store.labels[idx])


def cat(stores, ndim) -> TrackStore:
    stores = [s for s in stores if len(s)]
    if not stores:
        return TrackStore(np.zeros((0, ndim)), np.zeros((0, ndim, ndim)), np.zeros(0, dtype=np.int64))
    if len(stores) == 1:
        return stores[0]
    return TrackStore(*(np.concatenate([getattr(s, f) for s in stores]) for f in ("means", "covs", "labels")))


def one_hypothesis_lane(state: FilterState) -> TrackStore | None:
    """The lane that :func:`~..factored_groups.factorise` and the factored filter's sorting make of a state
    with one hypothesis holding every store entry once, of distinct labels: one singleton per object, in
    label order (stably); ``None`` for any other state. Without one Python group per object, which at
    10⁶ objects costs gigabytes and minutes."""
    if len(state.log_w) != 1 or len(state.tracks[0]) != len(state.store):
        return None
    labels = state.store.labels
    if not (np.array_equal(np.sort(state.tracks[0]), np.arange(len(labels))) and len(np.unique(labels)) == len(labels)):
        return None
    return take(state.store, np.argsort(labels, kind="stable"))


def empty_state(ndim: int) -> FilterState:
    return FilterState(TrackStore.from_arrays(np.zeros((0, ndim)), None, ndim=ndim), np.zeros(1),
                       [np.zeros(0, dtype=np.int64)], [()])


class _Moments:
    """The lane's moments (:class:`Lane`): ``means`` ``(capacity, d)``, ``covs`` ``(capacity, d, d)``, of which the first
    ``used`` rows are written; rows are only ever appended, so a lane's rows stay as they were."""

    __slots__ = ("means", "covs", "used")

    def __init__(self, means, covs, used: int):
        self.means, self.covs, self.used = means, covs, int(used)


#: garbage (rows no lane of the newest scan holds) up to which :meth:`Lane.after_scan` appends to its moments before it
#: compacts them: ``COMPACT_SHARE`` of the rows held plus ``COMPACT_ROWS``
COMPACT_SHARE, COMPACT_ROWS = 0.25, 4096


class Lane:
    """The singletons: ``store`` (each at its own time ``times``) and ``view``, their means at the
    current scan (with ``lazy``, advanced a scan at a time); with Bernoulli singletons (module docstring)
    ``r``, each one's existence after the last scan, and ``p_s``, its per-scan survival while not
    predicted (both ``None``: every singleton exists surely); ``labels``, the store's.

    The moments are held as rows of an append-only :class:`_Moments` (``_rows``: each singleton's row, in lane
    order) and ``store`` is gathered from them when first read. A scan changes a few hundred of ~10⁴–10⁶ singletons:
    :meth:`after_scan` appends the changed and new moments and writes the lane's 1-D arrays (rows, times, labels,
    existences) and means at the scan, where rebuilding the moments would copy every covariance each scan (the
    lane's bulk: 36 of its 43 numbers a row). It compacts the moments when their garbage passes ``COMPACT_SHARE``
    of the rows held (plus ``COMPACT_ROWS``), when they are full, or when another lane appended to them since this one
    was made (a lane restored after a failed step, or two lanes stepped from one): appending is the newest lane's."""

    def __init__(self, store: TrackStore | None, times, view, r=None, p_s=None, *, moments: _Moments | None = None,
                 rows=None, labels=None):
        # (``moments``, ``rows``, ``labels``: a lane of rows of existing moments, its store gathered when read)
        if moments is None:
            moments, rows, labels = _Moments(store.means, store.covs, len(store)), np.arange(len(store)), store.labels
        self._buf, self._rows, self._end, self._store = moments, rows, moments.used, store
        self.labels, self.times, self.view, self.r, self.p_s = labels, times, view, r, p_s

    @property
    def store(self) -> TrackStore:
        if self._store is None:
            rows = self._rows
            self._store = TrackStore(self._buf.means[rows], self._buf.covs[rows], self.labels)
        return self._store

    def take(self, idx) -> TrackStore:
        """The singletons ``idx`` (as :func:`take` of :attr:`store`, without gathering the whole store)."""
        rows = self._rows[idx]
        return TrackStore(self._buf.means[rows], self._buf.covs[rows], self.labels[idx])

    @classmethod
    def empty(cls, ndim: int, bernoulli: bool = False) -> "Lane":
        z = np.zeros(0) if bernoulli else None
        return cls(cat([], ndim), np.zeros(0), np.zeros((0, ndim)), z, z)

    @classmethod
    def at(cls, store: TrackStore, time: float, r=None, p_s=None) -> "Lane":
        """Singletons ``store``, all predicted to ``time`` (with Bernoulli singletons: existences ``r``, survivals ``p_s``)."""
        return cls(store, np.full(len(store), float(time)), store.means.copy(), r, p_s)

    def where(self, keep) -> "Lane":
        """The singletons ``keep`` (bool mask), in order."""
        idx = np.flatnonzero(keep)
        return Lane(None, self.times[idx], self.view[idx], None if self.r is None else self.r[idx],
                    None if self.p_s is None else self.p_s[idx], moments=self._buf, rows=self._rows[idx],
                    labels=self.labels[idx])

    def summary_parts(self, groups, time: float, motion):
        """``(states, singles, n_singles, n_unsure)`` for :class:`~.summary.FactoredPosterior`: ``groups()`` (the
        multi-hypothesis groups predicted to ``time``) followed by the singletons of ``r < 1`` as their two
        hypotheses (:func:`bernoulli`), and the singletons that surely exist, all predicted when read."""
        if self.r is None or not np.any(self.r < 1):
            return groups, lambda: self.now(time, motion), len(self), 0
        unsure, sure = np.flatnonzero(self.r < 1), np.flatnonzero(self.r == 1)
        return (lambda: groups() + [bernoulli(self.now(time, motion), j, float(self.r[j])) for j in unsure],
                lambda: take(self.now(time, motion), sure), len(sure), len(unsure))

    def bernoulli_states(self, store: TrackStore) -> list:
        """Each singleton of ``store`` (this lane's, e.g. predicted) as the engine's group (:func:`bernoulli`)."""
        if self.r is None:
            return [singleton(store, j) for j in range(len(store))]
        return [bernoulli(store, j, float(r)) for j, r in enumerate(self.r)]

    def __len__(self) -> int:
        return len(self._rows)

    def now(self, time: float, motion) -> TrackStore:
        """The singletons predicted to ``time`` (only lazy ones move)."""
        gap = time - self.times
        if not np.any(gap):
            return self.store
        x, P = predict_each(motion, self.store.means, self.store.covs, gap)
        return TrackStore(x, P, self.store.labels)

    def candidates(self, lazy: bool, interval: float, advance_view):
        """``(cand, view)``: the singletons to predict in full this scan and, with ``lazy``, every
        singleton's mean advanced one scan (``advance_view(means, interval)`` → ``(means, in view)``:
        one short propagation per singleton whatever its gap since its last full prediction)."""
        if lazy and len(self):
            view, seen = advance_view(self.view, interval)
            return np.flatnonzero(seen), view
        return np.arange(len(self)), None

    def after_scan(self, cand, quiet, pred: TrackStore, now: float, view, new: TrackStore, exist=None):
        """``(lane, n_kept)``: the lane after a scan whose candidates ``cand`` were predicted to
        ``pred`` (their order), the ``quiet`` ones (no return, no birth term) kept here, the others
        stepped; then the singletons ``new`` the scan's steps produced, at ``now``.

        ``exist`` (Bernoulli singletons): ``(r_quiet, p_s_quiet, r_new, p_s_new, min_weight, ok)``, the quiet
        candidates' existences after the scan (:func:`missed`) and survivals at their prediction, the new
        singletons' existences and survivals, whether each singleton passes the validity test (``None``: all,
        :func:`scan_existence`); the singletons not predicted take ``r ← p_S r`` (0 failing it), and every
        existence the engine's pruning (:func:`bernoulli_prune`: a singleton whose track it drops leaves)."""
        # one compiled pass over the lane's rows (:mod:`.lane_kernels`): the kept singletons (the quiet candidates
        # replaced by their prediction, appended to the moments), then the new ones; with Bernoulli singletons only
        # those the pruning keeps (the same rows as building every row and then dropping the pruned ones)
        f8, no = np.float64, np.zeros(0)
        r_quiet = p_quiet = r_new = p_new = ok = no
        min_weight, bern = 0.0, exist is not None
        if bern:
            r_quiet, p_quiet, r_new, p_new, min_weight, ok = exist
        use_ok = ok is not None
        cand, quiet = np.asarray(cand, np.int64), np.asarray(quiet, np.bool_)
        order = np.argsort(cand, kind="stable")  # the rows in lane order (the candidates come ascending)
        rank = np.cumsum(quiet) - 1  # a quiet candidate's place in r_quiet, p_quiet and among the appended rows
        n, n_quiet, d = len(self), int(quiet.sum()), self._buf.means.shape[1]
        n_keep = n - (len(cand) - n_quiet)
        total, extra = n_keep + len(new), n_quiet + len(new)
        buf, rows = self._appendable(extra)
        if buf.used + extra > len(buf.means):  # (the compiled pass writes there unchecked)
            raise RuntimeError(f"the lane's moments hold {len(buf.means)} rows, {buf.used + extra} needed")
        out = (np.empty(total, np.int64), np.empty((total, d)), np.empty(total), np.empty(total, self.labels.dtype),
               np.empty(total if bern else 0), np.empty(total if bern else 0))
        m = rebuild(rows, self.view if view is None else view, view is not None, self.times, self.labels,
                    self.r if bern else no, self.p_s if bern else no, ok if use_ok else no, cand[order], quiet[order],
                    order, rank[order], pred.means, pred.covs, np.asarray(r_quiet, f8), np.asarray(p_quiet, f8),
                    new.means, new.covs, np.asarray(new.labels, self.labels.dtype), np.asarray(r_new, f8),
                    np.asarray(p_new, f8), float(now), float(min_weight), bern, use_ok, buf.means, buf.covs, buf.used,
                    *out)
        buf.used += extra
        o_rows, lane_view, times, labels, r, p_s = (a[:m] if m < total else a for a in out)
        return Lane(None, times, lane_view, r if bern else None, p_s if bern else None, moments=buf, rows=o_rows,
                    labels=labels), n_keep

    def _appendable(self, extra: int):
        """``(moments, rows)`` to which ``extra`` rows may be appended: this lane's own, unless another lane appended
        to them since, they lack the room, or their garbage passed the bound (class docstring); then the rows held,
        compacted into new moments with room for ``extra`` and the garbage of the scans to come."""
        buf, n = self._buf, len(self)
        fits = buf.used == self._end and buf.used + extra <= len(buf.means)
        if fits and buf.used + extra - n <= COMPACT_SHARE * n + COMPACT_ROWS:
            return buf, self._rows
        cap = n + extra + max(int(COMPACT_SHARE * n) + COMPACT_ROWS, 0)
        d = buf.means.shape[1]
        means, covs = np.empty((cap, d)), np.empty((cap, d, d))
        # mode="clip": the rows are in range, and numpy buffers ``out`` in its default mode (a second copy)
        np.take(buf.means, self._rows, axis=0, out=means[:n], mode="clip")
        np.take(buf.covs, self._rows, axis=0, out=covs[:n], mode="clip")
        return _Moments(means, covs, n), np.arange(n)

    def same_as(self, other: "Lane") -> bool:
        """Bit-for-bit the same singletons, times and means at the scan."""
        a, b = self.store, other.store
        return all(np.array_equal(x, y) for x, y in ((a.means, b.means), (a.covs, b.covs), (a.labels, b.labels),
                                                      (self.times, other.times), (self.view, other.view),
                                                      (self.r, other.r), (self.p_s, other.p_s)))


@dataclass(frozen=True, eq=False)
class GroupSet:
    """The multi-hypothesis groups: their states, the time each was last predicted to, and each
    one's track means at the current scan (lazy groups: advanced a scan at a time)."""

    states: tuple
    times: np.ndarray
    views: tuple

    @classmethod
    def at(cls, states, time: float) -> "GroupSet":
        states = tuple(states)
        return cls(states, np.full(len(states), float(time)), tuple(s.store.means for s in states))

    def __len__(self) -> int:
        return len(self.states)

    def now(self, time: float, motion) -> list:
        """The groups predicted to ``time`` (only lazy ones move)."""
        out = list(self.states)
        for g in np.flatnonzero(self.times != time):
            s = out[g]
            x, P = predict_each(motion, s.store.means, s.store.covs, np.full(len(s.store), time - self.times[g]))
            out[g] = s.with_store(TrackStore(x, P, s.store.labels))
        return out

    def wake(self, lazy: bool, interval: float, now: float, advance_view):
        """``(groups to predict, their gaps, the groups left for later as a GroupSet)``.

        Without ``lazy`` every group is predicted. With it a group is predicted only when the mean
        of one of its tracks, advanced one scan, is in the field of view; the others keep their
        moments and are only advanced in their means (one batch), like the lane's singletons: a
        group whose tracks are all out of view takes no return and, with no population event (the
        caller turns ``lazy`` off otherwise), changes in nothing but its prediction."""
        groups, t = list(self.states), self.times
        nobody = GroupSet((), np.zeros(0), ())
        if not (lazy and groups):
            return groups, now - t, nobody
        n = np.array([len(v) for v in self.views], dtype=np.int64)  # >= 1: pruning drops empty groups
        view, seen = advance_view(np.concatenate(self.views), interval)
        awake = np.logical_or.reduceat(seen, np.concatenate([[0], np.cumsum(n)[:-1]]))
        if awake.all():
            return groups, now - t, nobody
        views = np.split(view, np.cumsum(n)[:-1])
        sleep = np.flatnonzero(~awake)
        return ([groups[g] for g in np.flatnonzero(awake)], now - t[awake],
                GroupSet(tuple(groups[g] for g in sleep), t[sleep], tuple(views[g] for g in sleep)))

    def then(self, states, time: float) -> "GroupSet":
        """These groups followed by ``states``, predicted to ``time``."""
        states = tuple(states)
        return GroupSet(self.states + states, np.concatenate([self.times, np.full(len(states), float(time))]),
                        self.views + tuple(s.store.means for s in states))

    def same_as(self, other: "GroupSet") -> bool:
        """Bit-for-bit the same groups (weights, tracks, moments, labels), times and means at the scan."""
        return (len(self) == len(other) and np.array_equal(self.times, other.times)
                and all(np.array_equal(x, y) for x, y in zip(self.views, other.views))
                and all(s.same_as(t) for s, t in zip(self.states, other.states)))

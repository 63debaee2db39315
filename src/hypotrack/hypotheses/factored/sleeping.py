"""A quiet group of one-track hypotheses under per-track deaths: its engine step on the empty scan in closed form.

With document 001's binomial deaths (Eq. 59: each track its own ``p_S``, at most one death per child; HOMHT k-best
and R-FISST's ``unconfirmed_decay``) a group no return reaches is not a prediction: its hypotheses reweigh. When
every hypothesis ``h`` (log-weight ``w_h``) holds at most one track ``t_h`` — e.g. an object born at a return as one
hypothesis per admissible-region component, plus "no object" — the general step
(:meth:`~..filter.HypothesisFilter.advance` on a scan without returns nor birth terms, Reid's weights: no count
term) makes, parent by parent in order,

* ``h`` holds ``t_h``: "missed", ``w_h + log(1 − p_D,t) + log p_S,t`` (the predicted track), then its death twin
  "died", that plus ``log((1 − p_S,t) / p_S,t) − log(1 − p_D,t)`` (no track; none when ``p_S,t = 1``);
* ``h`` holds nothing: "nothing", ``w_h`` (no track);

then merges the children holding the same tracks (:func:`~..duplicates.merge_duplicates`: every trackless child
into the heaviest of them, its weight their log-sum-exp, only when a death twin is among the children), visits
them best first keeping the first ``H∞`` whose track passes the validity test
(:func:`~..validity.valid_top_k`), and materialises them (:meth:`~..filter.HypothesisFilter._materialise`): the
predicted tracks themselves (no update), the weights normalised, each hypothesis keyed by its parent's key, the
child's kind and argument and its (empty) event. :func:`sleeping_step` computes exactly that with array
operations — no association problem, generator or Kalman update — in the same order (ties broken by position as
the stable sorts do), so the state is the general step's: the same hypotheses in the same order, tracks, labels and
keys, the weights to rounding (the tests compare to 1e-12 scan by scan on the catalogue). The factored filter then
prunes, splits and files the state as it does the general step's.

Anything else — a population with birth terms or its own children (labeled multi-Bernoulli), a sampled cap, no
duplicate merging, another weight model, generator or filter class, a hypothesis holding two tracks, a ``p_D`` of 1,
no valid child (the general step raises) — returns ``None``: the general step.
"""

from __future__ import annotations

import numpy as np

from ..._logspace import logsumexp
from ..filter import HypothesisFilter
from ..generators import ExhaustiveGenerator, MurtyGenerator
from ..hypothesis import ChildSet
from ..population_events import BinomialPopulation
from ..state import FilterState
from ..tracks import TrackStore
from ..weights import ReidWeights

__all__ = ["sleeping_step"]


def sleeping_step(engine, state: FilterState, pred: TrackStore, ctx):
    """The engine step of quiet group ``state`` (its tracks predicted in ``pred``; ``ctx`` its
    :class:`~..scan_context.ScanContext`, no return nor birth term) in closed form (module docstring):
    ``(new state, duplicates merged)``, or ``None`` where the closed form is not the general step."""
    pop = engine.population
    if (type(engine) is not HypothesisFilter or engine.cap != "top" or not engine.merge_duplicates
            or type(engine.weights) is not ReidWeights or type(pop) is not BinomialPopulation
            or pop.n_birth_regions or type(engine.generator) not in (ExhaustiveGenerator, MurtyGenerator)
            or engine.max_hypotheses < 2 or ctx.n_returns or ctx.n_birth_regions
            or any(len(t) > 1 for t in state.tracks)):  # (H∞ >= 2: no parent's children trimmed and reordered)
        return None
    p = np.asarray(ctx.p_detect, dtype=float)
    if np.any(p >= 1):
        return None
    n_pred = len(p)
    p_s = np.full(n_pred, pop.p_survive) if ctx.p_survive is None else np.asarray(ctx.p_survive, dtype=float)
    with np.errstate(divide="ignore"):
        log_ps = np.log(p_s)
        death = np.log1p(-p_s) - log_ps  # death_log_ratio's
    log_miss = np.log1p(-p)
    # the children, parent by parent: (log-weight, parent, kind, argument, track or -1)
    lw, parent, kind, arg, track = [], [], [], [], []
    for h, tr in enumerate(state.tracks):
        w = float(state.log_w[h])
        if len(tr) == 0:
            lw.append(w + 0.0)
            parent.append(h), kind.append(ChildSet.ASSOCIATION), arg.append(-1), track.append(-1)
            continue
        t = int(tr[0])
        missed = (w + float(log_miss[t])) + log_ps[t]
        if not np.isfinite(missed):
            return None
        lw.append(missed)
        parent.append(h), kind.append(ChildSet.ASSOCIATION), arg.append(-1), track.append(t)
        died = (missed + death[t]) - log_miss[t]
        if np.isfinite(died):
            lw.append(died)
            parent.append(h), kind.append(ChildSet.DEATH), arg.append(0), track.append(-1)
    lw, track, kind = np.array(lw), np.array(track, dtype=np.int64), np.array(kind, dtype=np.int64)
    keys = lw.copy()
    keep = np.ones(len(lw), dtype=bool)
    n_dup = 0
    if np.any(kind == ChildSet.DEATH):  # merge_duplicates: children holding the same tracks, in position order
        for t in np.unique(track):
            members = np.flatnonzero(track == t)
            if len(members) < 2:
                continue
            rep = members[np.argmax(lw[members])]
            total = float(logsumexp(lw[members]))
            keys[rep] += total - lw[rep]
            lw[rep] = total
            keep[members[members != rep]] = False
            n_dup += len(members) - 1
    idx = np.flatnonzero(keep)
    lw, keys, track = lw[idx], keys[idx], track[idx]
    # valid_top_k: best key first (stable), the first H∞ whose track passes the test
    held = np.unique(track[track >= 0])
    ok = np.ones(n_pred, dtype=bool)
    if engine.validity is not None and len(held):
        verdict = np.asarray(engine.validity(pred.means[held]), dtype=bool)
        if verdict.shape != (len(held),):
            return None  # (the general step raises its error)
        ok[held] = verdict
    sel = []
    for c in np.argsort(-keys, kind="stable"):
        if len(sel) == engine.max_hypotheses or not np.isfinite(keys[c]):
            break
        if track[c] < 0 or ok[track[c]]:
            sel.append(int(c))
    if not sel:
        return None
    sel = np.asarray(sel, dtype=np.int64)
    # _materialise: the predicted tracks in order of first appearance, one label each
    src, lists = [], []
    for t in track[sel]:
        if t >= 0:
            if t not in src:
                src.append(int(t))
            lists.append(np.array([src.index(t)], dtype=np.int64))
        else:
            lists.append(np.zeros(0, dtype=np.int64))
    src = np.asarray(src, dtype=np.int64)
    store = TrackStore(pred.means[src].copy(), pred.covs[src].copy(), pred.labels[src].astype(np.int64))
    par = np.asarray(parent, dtype=np.int64)[idx][sel]
    kd, ag = np.asarray(kind, dtype=np.int64)[idx][sel], np.asarray(arg, dtype=np.int64)[idx][sel]
    hyp_keys = [(state.keys[int(h)], int(k), int(a), b"") for h, k, a in zip(par, kd, ag)]
    log_w = lw[sel] - logsumexp(lw[sel])
    return FilterState(store, log_w, lists, hyp_keys, 0), n_dup

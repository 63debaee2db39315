"""The quiet group's closed-form step (:mod:`hypotrack.hypotheses.factored.sleeping`) written with array
operations: the tests' second form of it. The package computes the step on Python floats (numpy's per-call overhead
dominates on groups of a few hypotheses); this form, itself compared with the general engine's step
(``tests/unit/hypotheses/factored/test_sleeping.py`` does the same for the package's), checks it bit for bit on
random groups (``test_sleeping_scalar.py``) and stands in for it in the catalogue run of
``test_one_return_catalogue.py``. The derivation is the package module's docstring."""


from __future__ import annotations

import numpy as np

from hypotrack._logspace import logsumexp
from hypotrack.hypotheses.filter import HypothesisFilter
from hypotrack.hypotheses.generators import ExhaustiveGenerator, MurtyGenerator
from hypotrack.hypotheses.hypothesis import ChildSet
from hypotrack.hypotheses.population_events import BinomialPopulation
from hypotrack.hypotheses.state import FilterState
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.hypotheses.weights import ReidWeights

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

"""The closed-form empty-scan step of a quiet group of one-track hypotheses (:mod:`.sleeping`) as array operations.

Over a long run HOMHT's quiet groups accumulate in view: an object born at a return as one hypothesis per
admissible-region component plus "no object" whose components the radar barely sees (an SNR-driven ``p_D`` near 0)
loses little weight a scan and stays a group for hundreds of scans. Measured on the whole catalogue (N = 10,855,
300 scans of HOMHT k-best) their steps grew from ~14 to ~87 a scan and from a fifth to half of the scan's CPU, the
cost per scan doubling over the run. :func:`sleeping_step` computes the same step as
:func:`.sleeping.sleeping_step` — the same children (document 001 Eq. 59's "missed" ``w_h + log(1 − p_D,t) + log
p_S,t`` and "died" twin), the same duplicate merging, validity test, cap and materialisation, with the same floating
point operations on the same operands — but parent by parent only where Python must (the hypotheses' keys), so that
the state is bit for bit the one of :func:`.sleeping.sleeping_step` (``tests/unit/hypotheses/factored/
test_sleeping_arrays.py``), itself the general engine step's to 1e-12.
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

_EMPTY = np.zeros(0, dtype=np.int64)


def _applies(engine, state, ctx) -> bool:
    """:func:`.sleeping.sleeping_step`'s cases (its module docstring): anything else is the general step."""
    pop = engine.population
    return not (type(engine) is not HypothesisFilter or engine.cap != "top" or not engine.merge_duplicates
                or type(engine.weights) is not ReidWeights or type(pop) is not BinomialPopulation
                or pop.n_birth_regions or type(engine.generator) not in (ExhaustiveGenerator, MurtyGenerator)
                or engine.max_hypotheses < 2 or ctx.n_returns or ctx.n_birth_regions
                or any(len(t) > 1 for t in state.tracks))


def sleeping_step(engine, state: FilterState, pred: TrackStore, ctx):
    """:func:`.sleeping.sleeping_step` (the engine step of quiet group ``state``, its tracks predicted in ``pred``,
    ``ctx`` its context with no return nor birth term): ``(new state, duplicates merged)`` or ``None``, the same
    state bit for bit (module docstring)."""
    if not _applies(engine, state, ctx):
        return None
    p = np.asarray(ctx.p_detect, dtype=float)
    if np.any(p >= 1):
        return None
    n_pred, H = len(p), len(state.log_w)
    p_s = np.full(n_pred, engine.population.p_survive) if ctx.p_survive is None else np.asarray(ctx.p_survive, float)
    with np.errstate(divide="ignore"):
        log_ps = np.log(p_s)
        death = np.log1p(-p_s) - log_ps
    log_miss = np.log1p(-p)
    th = np.array([tr[0] if len(tr) else -1 for tr in state.tracks], dtype=np.int64)  # each parent's track or -1
    has = th >= 0
    t = th[has]
    w = np.asarray(state.log_w, dtype=float)
    missed = (w[has] + log_miss[t]) + log_ps[t]
    if not np.all(np.isfinite(missed)):
        return None
    died = (missed + death[t]) - log_miss[t]
    # the children parent by parent: slot 2h its "missed" (or "nothing", w_h + 0.0), slot 2h + 1 its finite "died"
    lw2 = np.empty(2 * H)
    lw2[0::2] = w + 0.0
    lw2[0::2][has] = missed
    present = np.zeros(2 * H, dtype=bool)
    present[0::2] = True
    dslot = 2 * np.flatnonzero(has) + 1
    fin = np.isfinite(died)
    lw2[dslot[fin]] = died[fin]
    present[dslot[fin]] = True
    track2 = np.full(2 * H, -1, dtype=np.int64)
    track2[0::2] = th
    kind2 = np.full(2 * H, ChildSet.ASSOCIATION, dtype=np.int64)
    kind2[1::2] = ChildSet.DEATH
    pos = np.flatnonzero(present)
    lw, track, kind = lw2[pos], track2[pos], kind2[pos]
    parent = pos // 2
    keys = lw.copy()
    keep = np.ones(len(lw), dtype=bool)
    n_dup = 0
    if fin.any():  # merge_duplicates: children holding the same tracks (a death twin is among them)
        values, counts = np.unique(track, return_counts=True)
        for v in values[counts > 1]:
            members = np.flatnonzero(track == v)
            rep = members[np.argmax(lw[members])]
            total = float(logsumexp(lw[members]))
            keys[rep] += total - lw[rep]
            lw[rep] = total
            keep[members[members != rep]] = False
            n_dup += len(members) - 1
    idx = np.flatnonzero(keep)
    lw, keys, track = lw[idx], keys[idx], track[idx]
    held = np.unique(track[track >= 0])
    ok = np.ones(n_pred, dtype=bool)
    if engine.validity is not None and len(held):
        verdict = np.asarray(engine.validity(pred.means[held]), dtype=bool)
        if verdict.shape != (len(held),):
            return None
        ok[held] = verdict
    order = np.argsort(-keys, kind="stable")
    finite = np.isfinite(keys[order])
    if not finite.all():  # valid_top_k stops at the first key that is not finite
        order = order[:int(np.argmin(finite))]
    tr_o = track[order]
    sel = order[(tr_o < 0) | ok[np.maximum(tr_o, 0)]][:engine.max_hypotheses]
    if len(sel) == 0:
        return None
    # _materialise: the predicted tracks in order of first appearance, one store entry each
    ts = track[sel]
    src, first = np.unique(ts[ts >= 0], return_index=True)
    src = src[np.argsort(first, kind="stable")]
    slot = np.full(n_pred, -1, dtype=np.int64)
    slot[src] = np.arange(len(src))
    entry = np.where(ts >= 0, slot[np.maximum(ts, 0)], -1)
    lists = [np.array([e], dtype=np.int64) if e >= 0 else _EMPTY.copy() for e in entry.tolist()]
    store = TrackStore(pred.means[src].copy(), pred.covs[src].copy(), pred.labels[src].astype(np.int64))
    sk = state.keys
    hyp_keys = [(sk[h], k, a, b"") for h, k, a in zip(parent[idx][sel].tolist(), kind[idx][sel].tolist(),
                                                         np.where(kind[idx][sel] == ChildSet.DEATH, 0, -1).tolist())]
    log_w = lw[sel] - logsumexp(lw[sel])
    return FilterState(store, log_w, lists, hyp_keys, 0), n_dup

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
child's kind and argument and its (empty) event. :func:`sleeping_step` computes exactly that — no association
problem, generator or Kalman update — in the same order (ties broken by position as the stable sorts do), so the state is the general step's: the same hypotheses in the same order, tracks, labels and
keys, the weights to rounding (the tests compare to 1e-12 scan by scan on the catalogue). The factored filter then
prunes, splits and files the state as it does the general step's.

Anything else — a population with birth terms or its own children (labeled multi-Bernoulli), a sampled cap, no
duplicate merging, another weight model, generator or filter class, a hypothesis holding two tracks, a ``p_D`` of 1,
no valid child (the general step raises) — returns ``None``: the general step.

On Python floats, not arrays: over a long run HOMHT's quiet groups accumulate in view (an object born at a return as
one hypothesis per admissible-region component whose ``p_D``, from the signal-to-noise ratio, is near 0 loses
little weight a scan), and on arrays of a few entries numpy's per-call overhead is the step's cost. The operations
are the array form's on the same operands (Python's float arithmetic is the same IEEE double arithmetic; the
logarithms and log-sum-exps are numpy's calls on the same arrays): ``tests/unit/hypotheses/factored/
test_sleeping_scalar.py`` compares the two bit for bit on random groups (the array form: ``tests/sleeping_arrays.py``).
"""

from __future__ import annotations

from math import isfinite

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

ASSOCIATION, DEATH = int(ChildSet.ASSOCIATION), int(ChildSet.DEATH)


def _applies(engine, state, ctx) -> bool:
    """The closed form's cases (the module docstring): anything else is the general step."""
    pop = engine.population
    return not (type(engine) is not HypothesisFilter or engine.cap != "top" or not engine.merge_duplicates
                or type(engine.weights) is not ReidWeights or type(pop) is not BinomialPopulation
                or pop.n_birth_regions or type(engine.generator) not in (ExhaustiveGenerator, MurtyGenerator)
                or engine.max_hypotheses < 2 or ctx.n_returns or ctx.n_birth_regions
                or any(len(t) > 1 for t in state.tracks))


def sleeping_step(engine, state: FilterState, pred: TrackStore, ctx):
    """The closed form (the engine step of quiet group ``state``, its tracks predicted in ``pred``,
    ``ctx`` its context with no return nor birth term): ``(new state, duplicates merged)`` or ``None``, the same
    state bit for bit (module docstring)."""
    if not _applies(engine, state, ctx):
        return None
    p = np.asarray(ctx.p_detect, dtype=float)
    if np.any(p >= 1):
        return None
    n_pred = len(p)
    p_s = np.full(n_pred, engine.population.p_survive) if ctx.p_survive is None else np.asarray(ctx.p_survive, float)
    if np.all((p_s > 0) & (p_s < 1)):  # (numpy's error-state context costs more than the logarithms)
        log_ps = np.log(p_s)
        death = np.log1p(-p_s) - log_ps
    else:
        with np.errstate(divide="ignore"):
            log_ps = np.log(p_s)
            death = np.log1p(-p_s) - log_ps
    log_miss = np.log1p(-p)
    # the same operations as the closed form's on Python floats (IEEE doubles: the same roundings), numpy only for
    # the logarithms and log-sum-exps, which it computes as the closed form does
    lm, lps, dth = log_miss.tolist(), log_ps.tolist(), death.tolist()
    lw, parent, kind, track = [], [], [], []  # the children, parent by parent
    for h, (w, tr) in enumerate(zip(state.log_w.tolist(), state.tracks)):
        if len(tr) == 0:
            lw.append(w + 0.0)
            parent.append(h), kind.append(ASSOCIATION), track.append(-1)
            continue
        t = int(tr[0])
        missed = (w + lm[t]) + lps[t]
        if not isfinite(missed):
            return None
        lw.append(missed)
        parent.append(h), kind.append(ASSOCIATION), track.append(t)
        died = (missed + dth[t]) - lm[t]
        if isfinite(died):
            lw.append(died)
            parent.append(h), kind.append(DEATH), track.append(-1)
    keys = list(lw)
    keep = [True] * len(lw)
    n_dup = 0
    if DEATH in kind:  # merge_duplicates: children holding the same tracks, into the heaviest (the first of equals)
        members = {}
        for c, t in enumerate(track):
            members.setdefault(t, []).append(c)
        for ms in members.values():
            if len(ms) < 2:
                continue
            rep = max(ms, key=lw.__getitem__)  # (max returns the first of equal maxima, as argmax)
            total = float(logsumexp(np.array([lw[c] for c in ms])))
            keys[rep] += total - lw[rep]
            lw[rep] = total
            for c in ms:
                if c != rep:
                    keep[c] = False
            n_dup += len(ms) - 1
    idx = [c for c in range(len(lw)) if keep[c]]
    ok = None
    if engine.validity is not None:
        held = sorted({track[c] for c in idx if track[c] >= 0})
        if held:
            verdict = np.asarray(engine.validity(pred.means[held]), dtype=bool)
            if verdict.shape != (len(held),):
                return None
            ok = dict(zip(held, verdict.tolist()))
    sel = []
    for c in sorted(idx, key=lambda c: -keys[c]):  # valid_top_k: best key first (stable), the first H∞ valid
        if len(sel) == engine.max_hypotheses or not isfinite(keys[c]):
            break
        if ok is None or track[c] < 0 or ok[track[c]]:
            sel.append(c)
    if not sel:
        return None
    # _materialise: the predicted tracks in order of first appearance, one store entry each
    slot, lists = {}, []
    for c in sel:
        t = track[c]
        if t >= 0:
            lists.append(np.array([slot.setdefault(t, len(slot))], dtype=np.int64))
        else:
            lists.append(np.zeros(0, dtype=np.int64))
    src = np.array(list(slot), dtype=np.int64)
    store = TrackStore(pred.means[src], pred.covs[src], pred.labels[src].astype(np.int64))
    sk = state.keys
    hyp_keys = [(sk[parent[c]], kind[c], 0 if kind[c] == DEATH else -1, b"") for c in sel]
    lw_sel = np.array([lw[c] for c in sel])
    return FilterState(store, lw_sel - logsumexp(lw_sel), lists, hyp_keys, 0), n_dup

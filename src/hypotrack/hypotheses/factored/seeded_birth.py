"""A return in no gate under HOMHT's seeded births: its engine step without the engine (``fast_path``).

With Reid's seeded births (:mod:`..seeded`) a return no track gates is a component of its own: no group, no
singleton, no birth term, one return. About half of HOMHT k-best's engine steps on the catalogue are such
components. The general step (:meth:`~..filter.HypothesisFilter.advance` from the empty hypothesis, log-weight 0,
no track) has one parent and one row of options — "clutter" and, for each admissible-region component ``c`` of the
return, "a new object in component ``c``" — so its children are Murty's one-row k best
(:func:`~..one_return.one_return_k_best`, on Python floats), no death twin (no track), no duplicate (each child holds
a different pair), the first ``H∞`` valid (:func:`~..validity.valid_top_k`) materialised: the seeded tracks of the
kept children in their order, one new label each, the weights normalised, each hypothesis keyed by the parent's
key, its kind, argument and event. :func:`lone_seeded_plan` computes that — the same calls on the same operands
(the children, the validity visit, :func:`~..children.heavy_entries`, :meth:`~..filter.HypothesisFilter.pair_moments`)
without the engine copy, the child sets, the duplicate pass, the memo and the generic materialisation — and
:func:`lone_seeded_step` gives the state, the labels from the scan's running label as the engine's would be
renumbered (:meth:`~.engine.FactoredFilter._finish`), the newborn components one object
(:meth:`~.planner.ObjectIds.register_births`) and one part (every entry seeded at the one return).

The covariances are mapped when the scan's steps run, after :func:`map_lone_returns` has asked the birth density
to map those of all the scan's lone returns in one call (``map_covariances``,
:meth:`hypotrack.scenarios.catalogue.admissible.SeededAdmissibleBirth.map_covariances`, the per-return map row by
row: the same numbers), instead of one call per step.

Anything else — another filter class, weight model or generator, a one-Gaussian birth density, a sampled cap, a population with birth terms
or its own children, a one-row problem whose k best the solver's tie order decides — keeps the general step
(``tests/unit/hypotheses/factored/test_seeded_birth.py`` steps the catalogue both ways and compares bit for bit).
"""

from __future__ import annotations

import numpy as np

from ..._logspace import logsumexp
from ..factored_groups import restrict_population
from .. import filter as engine_filter
from ..filter import HypothesisFilter
from ..generators import MurtyGenerator, top_k
from ..hypothesis import ChildSet
from ..one_return_children import _reid_k_best
from ..seeded import is_mixture, seeded_moments
from ..state import FilterState
from ..tracks import TrackStore
from ..weights import ReidWeights

__all__ = ["lone_seeded_applies", "lone_seeded_plan", "map_lone_returns", "lone_seeded_step"]

_ASSOCIATION = int(ChildSet.ASSOCIATION)


def lone_seeded_applies(engine, rule) -> bool:
    """Whether a lone return's step has the closed form's children (module docstring): the fast path on (``rule``),
    the plain engine, Reid's weights with seeded births from a mixture density (one child per component: a
    one-Gaussian birth's step has two children and keeps the general step), Murty's generator, the cap by weight, a
    population with no birth term and no children of its own (or none)."""
    pop = engine.population
    return (rule is not None and type(engine) is HypothesisFilter and type(engine.weights) is ReidWeights
            and engine.weights.seeded_births and is_mixture(engine.weights.birth_density)
            and type(engine.generator) is MurtyGenerator and engine.cap == "top"
            and (pop is None or (not hasattr(pop, "children") and pop.n_birth_regions == 0)))


def lone_seeded_plan(engine, general, min_weight: float):
    """The plan ``("seeded", pred, ctx, sel log-weights…)`` of a lone return's step (``general``: its general plan,
    :func:`~.planner.touched_plan`, ``("touched", state, pred, ctx, regions)``), or ``None`` where the general step
    must decide (module docstring). ``min_weight``: the factored filter's, for the light entries' bound."""
    _, state, pred, ctx, regions = general
    if len(state.log_w) != 1 or len(state.store) or len(state.tracks[0]) or ctx.n_returns != 1 or len(regions):
        return None
    tr = state.tracks[0]
    keep = engine.max_hypotheses
    pop = restrict_population(engine.population, regions)  # engine_step's population (no birth term: the same)
    # the general step's own helpers are looked up where it looks them up (filter.applies, filter.valid_top_k,
    # filter.heavy_entries): one form of each, whoever replaces it (the tests that step the general path do)
    if not engine_filter.applies(pop, ctx, None, False):
        return None  # the general step's children are not the one-return ones
    pop_lp = None
    if pop is not None:  # one_return_children's population terms for a parent of no track
        ps = None if ctx.p_survive is None else ctx.p_survive[tr]
        pop_lp = pop.log_event_prob(0, 0, ps)
    out = _reid_k_best(engine.weights, engine.generator, ctx, tr, float(state.log_w[0]), pop_lp, keep)
    if out is None:
        return None  # the solver's tie order: the general step's generator decides
    events, lw = out
    E = len(lw)
    if E == 0:
        return None  # (the general step raises its error)
    log_total = logsumexp([np.logaddexp.reduce(lw)])  # one parent: its generated mass (advance's log_total)
    keys = lw.copy()
    if E > keep:
        return None  # (one_return_k_best keeps at most min(k, H∞): not reached)
    if engine.merge_duplicates:  # (no death among the children: none merged, the merge's own early return)
        kids = ChildSet(np.zeros(E, np.int64), events, np.full(E, _ASSOCIATION, np.int64), np.full(E, -1, np.int64), lw)
        kids, keys, _, _ = engine_filter.merge_few(kids, keys, state.tracks, 0)
        events, lw = kids.events, kids.log_weights
    ev0 = events[:, 0].tolist()
    pairs = [[] if a > -2 else [(a + 1, 0)] for a in ev0]  # child_pairs: clutter none; component c: (−1 − c, 0)
    if engine.validity is None:
        sel = top_k(keys, keep)
    else:
        means_of = lambda src, ret: _seeded_pairs(engine, ctx, src, ret, False)  # noqa: E731
        sel, _ = engine_filter.valid_top_k(keys, keep, pairs.__getitem__, means_of, engine.validity)
    if len(sel) == 0:
        return None  # (the general step's fallbacks)
    kept_lw = lw[sel]
    log_w = kept_lw - logsumexp(kept_lw)
    src = [p[0][0] for p in (pairs[c] for c in sel.tolist()) if p]  # every kept component's own entry, in order
    lists, q = [], 0
    for c in sel.tolist():
        if pairs[c]:
            lists.append(np.array([q], dtype=np.int64))
            q += 1
        else:
            lists.append(np.zeros(0, dtype=np.int64))
    light = min(min_weight, 1.0 / keep) * (1 - 1e-9)  # the engine's bound (:meth:`~.engine.FactoredFilter._run_plans`)
    need = engine_filter.heavy_entries(lists, log_w, len(src), light)
    hyp = [(state.keys[0], _ASSOCIATION, -1, np.array([ev0[c]], dtype=np.int32).tobytes()) for c in sel.tolist()]
    mass = float(np.exp(logsumexp(kept_lw) - log_total))
    return ("seeded", pred, ctx, np.array(src, dtype=np.int64), need, log_w, lists, hyp, mass)


def _seeded_pairs(engine, ctx, src, ret, covariances: bool):
    """:meth:`~..filter.HypothesisFilter.pair_moments` of pairs that are all seeded births (``src <= −1``, no birth
    term): its :func:`~..seeded.seeded_moments` call itself, whose rows it copies unchanged (the same numbers)."""
    src = np.asarray(src, dtype=np.int64)
    return seeded_moments(engine.weights.birth_density, ctx.Z, engine.R, np.asarray(ret, dtype=np.int64), -1 - src,
                          engine.state_dim, covariances)


def map_lone_returns(engine, plans) -> None:
    """Ask the birth density to map, in one call, the covariances of the returns of the scan's lone-return plans
    that keep a component (``map_covariances(Z)``, when it has one; module docstring)."""
    density = getattr(engine.weights, "birth_density", None)
    if not hasattr(density, "map_covariances"):
        return
    Z = [p[2].Z[0] for p in plans if p[0] == "seeded" and p[4].any()]
    if Z:
        density.map_covariances(np.array(Z))


def lone_seeded_step(plan, engine, label: int, objects, stats, ndim: int):
    """``(state, parts, labels used)`` of a lone return's plan (:func:`lone_seeded_plan`): the seeded tracks (NaN
    moments for the light ones, as the engine leaves them), labels from ``label``, the newborn registered as one
    object, its stats counted as :meth:`~.engine.FactoredFilter._finish` counts the general step's."""
    _, pred, ctx, src, need, log_w, lists, keys, mass = plan
    n = len(src)
    means, covs = np.full((n, ndim), np.nan), np.full((n, ndim, ndim), np.nan)
    if need.any():
        means[need], covs[need] = _seeded_pairs(engine, ctx, src[need], np.zeros(int(need.sum()), np.int64), True)
    store = TrackStore(means, covs, np.arange(label, label + n, dtype=np.int64))
    new = FilterState(store, log_w, lists, keys, 0)
    stats["n_touched"] += 1
    stats["n_fast_seeded"] += 1
    stats["mass_retained_min"] = min(stats["mass_retained_min"], mass)
    sources = np.stack([src, np.zeros(n, np.int64)], axis=1) if n else np.zeros((0, 2), np.int64)
    objects.register_births(store, sources, 0)
    return new, np.zeros(n, dtype=np.int64), n

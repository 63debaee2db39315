"""A parent's children on a scan of one return, without the general path's array machinery.

:meth:`HypothesisFilter.children_of <.filter.HypothesisFilter.children_of>` builds every parent's children
(document 000 Eq. 11, 19; :mod:`.population_events`) from matrices: the association children as an ``(E, 1)``
column, the death twins as an ``(E, M)`` matrix of ``log w_e + log r_d,j − log(1 − p_D,j)`` (``−inf`` where object
``j`` is detected by event ``e`` or may not die), each reduced to its finite entries in row-major order
(:func:`~.children.candidates`) and trimmed to the best ``keep``. With one return a parent has a handful of children and the
cost is numpy's per-call overhead, about forty calls a parent. :func:`one_return_children` computes the same
children with the same IEEE operations on Python floats:

* the association children are the generator's (its events, order and log-weights, unchanged);
* with no birth term (``B = 0``) every event has ``b = 0`` detected births, so each death twin's population
  factor is row 0 of :meth:`~.population_events.BinomialPopulation.death_log_ratio` (one value, or one per
  object), asked once — the general path asks twice (also in :func:`~.children.twins_never_heavier`);
* each twin's log-weight is ``(log w_e + r_j) − log(1 − p_D,j)``, the matrix's operations in its order, its
  ``log(1 − p_D,j)`` the same ``numpy.log1p`` of the parent's ``p_D`` array;
* the twins are visited row by row, object by object (``numpy.nonzero``'s order), the masses and trims are the
  general path's calls (``numpy.logaddexp.reduce``, :func:`~.generators.top_k`) on the same arrays.

So the children, their order, log-weights, keys, mass and counts are the general path's bit for bit
(``tests/unit/hypotheses/test_one_return_children.py``). It applies to a parent scored by the weight model's
association problem (not a population that generates its children itself), on a scan of one return, with no
birth term and the cap by weight (``keys_rng`` ``None``: the sampled cap's Gumbel draws stay the general path's);
otherwise :func:`applies` is false and the general path runs.
"""

from __future__ import annotations

from math import inf as _INF
from typing import NamedTuple

import numpy as np

from .generators import MurtyGenerator, top_k
from .hypothesis import ChildSet
from .one_return import one_return_k_best
from .weights import ReidWeights

__all__ = ["applies", "one_return_children"]

_ASSOCIATION, _DEATH = ChildSet.ASSOCIATION, ChildSet.DEATH
_CHUNK = 1 << 15  # the general path's rows per chunk of death twins (filter._CHUNK)


def applies(pop, ctx, keys_rng, with_null: bool) -> bool:
    """Whether :func:`one_return_children` gives this parent's children (module docstring)."""
    return (keys_rng is None and not with_null and ctx.n_returns == 1 and ctx.n_birth_regions == 0
            and (pop is None or (not hasattr(pop, "children") and pop.n_birth_regions == 0)))


def one_return_children(f, ctx, state, h: int, keep, generator):
    """``(ChildSet, keys, n_generated, log mass generated, n_twins)`` of parent ``h`` of ``state`` — the value of
    :meth:`~.filter.HypothesisFilter.children_of` — for a parent :func:`applies` accepts (module docstring)."""
    tr = state.tracks[h]
    pop = f.population
    p = ctx.p_detect[tr]
    in_view = p > 0
    n_view = int(in_view.sum())
    M = len(tr)
    ps = None if ctx.p_survive is None else ctx.p_survive[tr]
    pop_lp = pop.log_event_prob(n_view, M, ps) if pop is not None else None
    elig = de_row = log_miss = None
    gen_keep = None
    if pop is not None:
        elig = pop.death_eligible(in_view)
        if M and elig.any():
            ratio = pop.death_log_ratio(n_view, M, ps)
            de_row = ratio[0].tolist() if ratio.ndim == 2 else [float(ratio[0])] * M  # b = 0: row 0
            log_miss = np.log1p(-p)
    if keep is not None:
        # twins_never_heavier with B = 0: the death twins' largest log-ratio, with its detection factor
        if pop is None or de_row is None:
            gen_keep = keep
        else:
            lm = log_miss.tolist()
            el = elig.tolist()
            if max(de_row) - min(lm[j] for j in range(M) if el[j]) <= 0:
                gen_keep = keep
    gen = f.generator if generator is None else generator
    out = None
    if type(gen) is MurtyGenerator and type(f.weights) is ReidWeights:
        out = _reid_k_best(f.weights, gen, ctx, tr, float(state.log_w[h]), pop_lp, gen_keep)
    if out is None:
        out = gen.generate(f.weights.problem(ctx, tr, float(state.log_w[h]), pop_lp), f.rng, keep=gen_keep)
    events, lw = out
    events = np.asarray(events, dtype=np.int32)
    E = len(lw)
    mass = [np.logaddexp.reduce(lw)] if E else []
    lw = np.asarray(lw, dtype=float)
    a_rows = np.flatnonzero(np.isfinite(lw))  # (a generator returns feasible events: all of them, as a rule)
    a_lw = lw[a_rows]
    if keep is not None and len(a_lw) > keep:
        sel = top_k(a_lw, keep)
        a_rows, a_lw = a_rows[sel], a_lw[sel]
    a_ev, n_assoc = events[a_rows], len(a_lw)
    d_rows, d_cols, d_vals = [], [], []
    if de_row is not None and E:
        lm, el = log_miss.tolist(), elig.tolist()
        ev0 = events[:, 0].tolist()
        for e, w in enumerate(lw.tolist()):
            hit = ev0[e]
            for j in range(M):
                if j != hit and el[j]:
                    v = (w + de_row[j]) - lm[j]
                    if -_INF < v < _INF:
                        d_rows.append(e)
                        d_cols.append(j)
                        d_vals.append(v)
    # the general path's death twins come in chunks of rows (_CHUNK events), each chunk's entries reduced to
    # their mass and trimmed on their own: one chunk but for a parent of tens of thousands of children
    parts_ev, parts_lw, parts_col = [a_ev], [a_lw], []
    d_rows, d_cols = np.array(d_rows, dtype=np.int64), np.array(d_cols, dtype=np.int64)
    d_vals = np.array(d_vals, dtype=float)
    for start in range(0, E if len(d_vals) else 0, _CHUNK):
        inside = (d_rows >= start) & (d_rows < start + _CHUNK)
        rows, cols, vals = d_rows[inside], d_cols[inside], d_vals[inside]
        if not len(vals):
            continue
        mass.append(np.logaddexp.reduce(vals))
        if keep is not None and len(vals) > keep:
            sel = top_k(vals, keep)
            rows, cols, vals = rows[sel], cols[sel], vals[sel]
        parts_ev.append(events[rows])
        parts_lw.append(vals)
        parts_col.append(cols)
    n_twins = sum(len(c) for c in parts_col)
    if parts_col:
        ev_all, lw_all = np.concatenate(parts_ev), np.concatenate(parts_lw)
        kind = np.concatenate([np.full(n_assoc, _ASSOCIATION, np.int64), np.full(n_twins, _DEATH, np.int64)])
        arg = np.concatenate([np.full(n_assoc, -1, np.int64), *parts_col])
    else:
        ev_all, lw_all = a_ev, a_lw
        kind, arg = np.full(n_assoc, _ASSOCIATION, np.int64), np.full(n_assoc, -1, np.int64)
    keys = lw_all.copy()
    if keep is not None and len(lw_all) > keep:
        sel = top_k(keys, keep)
        ev_all, kind, arg, lw_all, keys = ev_all[sel], kind[sel], arg[sel], lw_all[sel], keys[sel]
    cs = ChildSet(np.full(len(lw_all), h, np.int64), ev_all, kind, arg, lw_all)
    return cs, keys, E, (np.logaddexp.reduce(mass) if mass else -np.inf), n_twins


class _Row(NamedTuple):
    """The fields of an :class:`~.association_problem.AssociationProblem` that :func:`~.one_return.one_return_k_best`
    reads, for a one-return problem whose arrays are already floats of the right shapes (no validation pass)."""

    target_scores: np.ndarray
    option_scores: np.ndarray
    n_objects: int
    count_term: np.ndarray
    constant: float


def _reid_k_best(weights, generator, ctx, tracks, constant: float, pop_lp, keep):
    """:class:`~.generators.MurtyGenerator`'s children of the one-return problem :meth:`ReidWeights.problem
    <.weights.WeightModel.problem>` builds for ``tracks`` — its arrays (:meth:`~.weights.WeightModel.problem_fields`)
    without the validation pass, handed to :func:`~.one_return.one_return_k_best` as the generator hands them (``k``
    the smaller of its own and ``keep``); ``None`` where that declines (ties: the generator's solver decides)."""
    row = _Row(**weights.problem_fields(ctx, tracks, constant, pop_lp))
    return one_return_k_best(row, generator.k if keep is None else min(generator.k, keep))

"""Helpers of :meth:`HypothesisFilter.children_of <.filter.HypothesisFilter.children_of>`: the keys the cap ranks
children by, whether pre-trimming a parent's association children is exact, and the null association used when a
search found no valid child (:meth:`~.filter.HypothesisFilter.advance`'s fallback)."""

from __future__ import annotations

import numpy as np

from .generators import top_k
from .hypothesis import ChildSet

__all__ = ["candidates", "feasible_events", "gumbel_keys", "heavy_entries", "null_event", "twins_never_heavier"]


def gumbel_keys(lw, rng):
    """Log-weights ``lw``, Gumbel-perturbed with ``rng`` (the weighted sample's keys) or as they are (``rng`` None)."""
    return lw if rng is None else lw + rng.gumbel(size=lw.shape)


def candidates(events, tw, kind, keep, keys_rng, mass):
    """Children from an (E, K) matrix ``tw`` of log-weights (−inf = no such child), with their keys: ``(events,
    kind, arg, log-weights, keys)``, the finite entries in row-major order, the best ``keep`` by key when more.

    Column ``c`` of ``tw`` is the child's argument (birth region, dead object); association children come as a
    single column with argument −1. ``mass`` (a list, or ``None``): the entries' log-sum-exp appended to it.
    """
    finite = np.isfinite(tw)
    rows, cols = np.nonzero(finite)
    vals = tw[rows, cols]
    if mass is not None and len(vals):
        mass.append(np.logaddexp.reduce(vals))  # diagnostics only; ufunc, no per-call overhead
    keys = gumbel_keys(vals, keys_rng)
    if keep is not None and len(vals) > keep:
        sel = top_k(keys, keep)
        rows, cols, vals, keys = rows[sel], cols[sel], vals[sel], keys[sel]
    arg = np.full(len(vals), -1, np.int64) if kind == ChildSet.ASSOCIATION else cols.astype(np.int64)
    return events[rows], np.full(len(vals), kind, np.int64), arg, vals, keys


def twins_never_heavier(pop, ctx, p, in_view, p_survive=None) -> bool:
    """Whether every twin weighs at most its association child, for the twins actually made.

    Then a child outside a parent's best ``keep`` association children cannot have a twin
    inside the best ``keep`` children overall, and asking the generator for the best ``keep``
    only (pre-trimming) is exact. The twins' full log-ratios are checked, with the detection
    factors the twin changes: an undetected birth adds ``log(1 − p_D)``; a death removes the
    dead object's miss factor, i.e. adds ``−log(1 − p_D,j)`` > 0 (e.g. β = 0.2, p_D = 0.99:
    the population ratio is < 0 but the twin outweighs its child).
    """
    n_view, M = int(in_view.sum()), len(p)
    if pop.n_birth_regions:
        ub = np.max(pop.undetected_birth_log_ratio(n_view, M)) + np.log1p(-ctx.p_detect_birth)
        if ub > 0:
            return False
    elig = pop.death_eligible(in_view)
    if M and elig.any():
        de = np.max(pop.death_log_ratio(n_view, M, p_survive)) - np.min(np.log1p(-p[elig]))
        if de > 0:
            return False
    return True


def feasible_events(problem, events):
    """``(events, lw)``: the rows of ``events`` (int events of association problem ``problem``) whose log-weight
    under ``problem.log_weights`` is finite, and those log-weights."""
    events = np.asarray(events)
    lw = np.asarray(problem.log_weights(events), dtype=float)
    ok = np.isfinite(lw)
    return events[ok], lw[ok]


def null_event(problem):
    """``(events, lw)`` of the null association alone (every return clutter; none on an empty scan), when it is
    feasible (:meth:`~.filter.HypothesisFilter.advance`'s fallback)."""
    return feasible_events(problem, np.full((1, problem.n_returns), -1, dtype=np.int32))


def heavy_entries(lists, log_w, n_entries: int, light: float) -> np.ndarray:
    """Whether each of a step's ``n_entries`` new store entries weighs at least ``light`` in all: the sum of the
    normalised weights ``exp(log_w)`` of the hypotheses whose track lists ``lists`` hold it (all True for
    ``light <= 0``).

    The factored engine prunes each group after its step (and split) at ``min_weight``, the heaviest hypothesis
    always kept (:func:`~.factored.planner.prune`). A marginal hypothesis of a split holding an entry weighs at most
    that entry's mass, and the heaviest weighs at least ``1/H∞``: an entry of mass below ``min(min_weight, 1/H∞)``
    is in no hypothesis the pruning keeps, so the step need not compute its moments (a Kalman update, a seeded
    birth's covariance mapping) — the factored engine passes that bound, less a relative margin, as ``light``."""
    need = np.ones(n_entries, dtype=bool)
    if light > 0 and n_entries:
        idx = np.concatenate([np.asarray(t, dtype=np.int64) for t in lists]) if lists else np.zeros(0, np.int64)
        w = np.repeat(np.exp(np.asarray(log_w, dtype=float)), [len(t) for t in lists])
        need = np.bincount(idx, weights=w, minlength=n_entries) >= light
    return need

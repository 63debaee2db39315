"""Helpers of :meth:`HypothesisFilter.children_of <.filter.HypothesisFilter.children_of>`: the keys the cap ranks
children by, whether pre-trimming a parent's association children is exact, and the null association used when a
search found no valid child (:meth:`~.filter.HypothesisFilter.advance`'s fallback)."""

from __future__ import annotations

import numpy as np

__all__ = ["feasible_events", "gumbel_keys", "null_event", "twins_never_heavier"]


def gumbel_keys(lw, rng):
    """Log-weights ``lw``, Gumbel-perturbed with ``rng`` (the weighted sample's keys) or as they are (``rng`` None)."""
    return lw if rng is None else lw + rng.gumbel(size=lw.shape)


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

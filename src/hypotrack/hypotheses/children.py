"""Helpers of :meth:`HypothesisFilter.children_of <.filter.HypothesisFilter.children_of>`: the keys the cap ranks
children by, whether pre-trimming a parent's association children is exact, and the null association used when a
search found no valid child (:meth:`~.filter.HypothesisFilter.advance`'s fallback)."""

from __future__ import annotations

import numpy as np

__all__ = ["gumbel_keys", "twins_never_heavier", "with_events", "with_null_event"]


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


def with_events(problem, events, lw, extra):
    """``(events, lw)`` with the rows of ``extra`` (events of ``problem``, int) appended that are feasible (finite
    log-weight under ``problem.log_weights``) and not among ``events`` already."""
    events = np.asarray(events)
    extra = np.asarray(extra, dtype=events.dtype).reshape(-1, events.shape[1] if events.ndim == 2 else len(extra[0]))
    if extra.shape[1] == 0:
        return events, lw
    lw_extra = problem.log_weights(extra)
    new = [i for i in range(len(extra)) if np.isfinite(lw_extra[i])
           and not (len(events) and np.any(np.all(events == extra[i], axis=1)))]
    if not new:
        return events, lw
    return np.concatenate([events.reshape(-1, extra.shape[1]), extra[new]]), \
        np.concatenate([np.asarray(lw, dtype=float), lw_extra[new]])


def with_null_event(problem, events, lw):
    """``(events, lw)`` with the null association (every return clutter) appended when it is feasible and not
    among ``events`` already (``(E, m)`` int32 events of association problem ``problem``, log-weights ``lw``)."""
    return with_events(problem, events, lw, np.full((1, problem.n_returns), -1, dtype=np.int32))

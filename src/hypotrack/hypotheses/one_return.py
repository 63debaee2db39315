"""Murty's k best of a one-return association problem, without the assignment solver.

With one return the extended assignment matrix of :func:`~.generators._murty_matrix` is a single row: the
return's exclusive columns (the parent's objects, then birth regions), one column per seeded option
``t = 1 … T−1`` (HOMHT's seeded birth, or each component of a seeded mixture, :mod:`.seeded`), then its
clutter column. An assignment is one finite entry of that row and its total is the entry, so
:func:`~hypotrack.association.murty_k_best` returns entries of the row in non-increasing order; only the
order among *equal* entries is the solver's:

* at most ``k`` finite entries (:func:`~hypotrack.association.assignment._all_assignments`): the solver's
  optimum first, then the others by total, ties in column order (a stable sort);
* more than ``k``: Murty's partition of a one-row problem is a chain, each child forbidding the previous
  columns, and each entry is the solver's optimum of the columns left.

So the k best are the row's entries sorted (stably, by column) whenever the solver never has to choose between
equal entries: at most ``k`` entries and a unique maximum, or more than ``k`` and the ``k + 1`` largest all
distinct. :func:`one_return_k_best` returns ``None`` otherwise (and on a malformed row, which the general path
rejects with its own error) so that the caller takes the solver's path and its tie order, unchanged
(``tests/unit/hypotheses/test_one_return.py`` compares both on rows with and without ties).
"""

from __future__ import annotations

import numpy as np

__all__ = ["one_return_k_best"]


def one_return_k_best(problem, k: int):
    """``(events (E, 1) int32, log-weights (E,))`` of the ``k`` best children of a one-return problem whose count term
    is constant, in Murty's order (module docstring) and weighed as :meth:`~.association_problem.AssociationProblem.
    log_weights` weighs them (``constant + ((0.0 + score) + φ[k, b])``, its gather-sum's operations), the infeasible
    dropped — :class:`~.generators.MurtyGenerator`'s answer; ``None`` when the solver's tie order would decide it or
    the problem is malformed (the general path raises its error)."""
    ts, os_ = problem.target_scores[0], problem.option_scores[0]
    row = np.concatenate([ts, os_[1:], os_[:1]])  # the Murty matrix's columns: exclusive, seeded options, clutter
    ct = problem.count_term
    if np.isnan(row).any() or np.isposinf(row).any() or not os_[0] > -np.inf or not ct.flat[0] < np.inf:
        return None
    cols = np.flatnonzero(row > -np.inf)
    v = row[cols]
    order = np.argsort(-v, kind="stable")
    if len(cols) <= k:
        if len(cols) > 1 and v[order[0]] == v[order[1]]:
            return None  # the solver's pick among equal optima leads
    else:
        top = v[order[:k + 1]]
        if np.any(top[1:] == top[:-1]):
            return None  # the chain's next pick among equal entries is the solver's
        order = order[:k]
    n_excl, n_opt, n_obj = ts.shape[0], os_.shape[0], problem.n_objects
    codes = np.concatenate([np.arange(n_excl), -1 - np.arange(1, n_opt), [-1]]).astype(np.int32)[cols[order]]
    on_object = ((codes >= 0) & (codes < n_obj)).astype(np.int64)
    on_birth = (codes >= n_obj).astype(np.int64)
    lw = problem.constant + ((0.0 + v[order]) + ct[on_object, on_birth])
    ok = np.isfinite(lw)
    events, lw = codes[ok][:, None], lw[ok]
    sel = np.argsort(-lw, kind="stable")  # the generator's top_k of at most k children
    return events[sel], lw[sel]

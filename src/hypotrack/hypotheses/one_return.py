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
    """``(events (E, 1) int32, row totals)`` of the ``k`` best assignments of a one-return problem in
    Murty's order (module docstring), or ``None`` when the solver's tie order would decide it."""
    ts, os_ = problem.target_scores[0], problem.option_scores[0]
    row = np.concatenate([ts, os_[1:], os_[:1]])  # the Murty matrix's columns: exclusive, seeded options, clutter
    if np.isnan(row).any() or np.isposinf(row).any():
        return None
    cols = np.flatnonzero(row > -np.inf)
    if len(cols) == 0:
        return None
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
    n_excl, n_opt = ts.shape[0], os_.shape[0]
    codes = np.concatenate([np.arange(n_excl), -1 - np.arange(1, n_opt), [-1]]).astype(np.int32)
    picked = cols[order]
    return codes[picked][:, None], v[order]

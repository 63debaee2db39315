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

from math import inf as _INF
from math import isfinite

import numpy as np

__all__ = ["one_return_k_best"]


def one_return_k_best(problem, k: int):
    """``(events (E, 1) int32, log-weights (E,))`` of the ``k`` best children of a one-return problem whose count term
    is constant, in Murty's order (module docstring) and weighed as :meth:`~.association_problem.AssociationProblem.
    log_weights` weighs them (``constant + ((0.0 + score) + φ[k, b])``, its gather-sum's operations), the infeasible
    dropped — :class:`~.generators.MurtyGenerator`'s answer; ``None`` when the solver's tie order would decide it or
    the problem is malformed (the general path raises its error). On Python floats (the same IEEE double arithmetic):
    a row holds a few entries, where numpy's per-call overhead would be the cost."""
    ts, opts = problem.target_scores[0].tolist(), problem.option_scores[0].tolist()
    row = ts + opts[1:] + opts[:1]  # the Murty matrix's columns: exclusive, seeded options, clutter
    ct = problem.count_term
    if any(v != v or v == _INF for v in row) or not opts[0] > -_INF or not float(ct.flat[0]) < _INF:
        return None
    cols = [j for j, v in enumerate(row) if v > -_INF]
    cols.sort(key=lambda j: -row[j])  # stable: equal entries in column order
    if len(cols) <= k:
        if len(cols) > 1 and row[cols[0]] == row[cols[1]]:
            return None  # the solver's pick among equal optima leads
    else:
        top = [row[j] for j in cols[:k + 1]]
        if any(a == b for a, b in zip(top, top[1:])):
            return None  # the chain's next pick among equal entries is the solver's
        cols = cols[:k]
    n_excl, n_obj, phi, const = len(ts), problem.n_objects, ct.tolist(), problem.constant
    events, lw = [], []
    for j in cols:
        code = j if j < n_excl else -2 - (j - n_excl) if j < len(row) - 1 else -1
        w = const + ((0.0 + row[j]) + phi[int(0 <= code < n_obj)][int(code >= n_obj)])
        if isfinite(w):
            events.append(code)
            lw.append(w)
    sel = sorted(range(len(lw)), key=lambda i: -lw[i])  # the generator's top_k of at most k children (stable)
    return (np.array([events[i] for i in sel], dtype=np.int32).reshape(-1, 1),
            np.array([lw[i] for i in sel], dtype=float))

"""The lane's end-of-scan rebuild in one compiled pass (:meth:`~.lane.Lane.after_scan`).

A scan changes a few hundred of the lane's ~10⁴–10⁶ rows: the candidates a return or birth term reached leave
(their steps' singletons come back at the end), the quiet candidates take their prediction in place, and with
Bernoulli singletons every row's existence moves (``r ← p_S r`` asleep, :func:`~.lane.missed` for a quiet
candidate) and the engine's pruning (:func:`~.lane.bernoulli_prune`) may drop a row or round its ``r`` up to 1.
Written as numpy this is a dozen passes over the lane's 1-D arrays (masks, cumulative sums, concatenations, the
pruning's comparisons) and a gather of its moments; :func:`rebuild` makes them one pass that decides each row and
one that writes the kept rows, with the same arithmetic (``(r p_S) · ok``, the pruning's comparisons), so the lane
is the numpy construction's bit for bit (``tests/unit/hypotheses/factored/test_lane_after_scan.py``).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["rebuild"]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def rebuild(means, covs, view, times, labels, r, p_s, ok, cand, quiet, pred_means, pred_covs, r_quiet, p_quiet,
            new_means, new_covs, new_labels, r_new, p_new, now, min_weight, bern, use_ok, o_means, o_covs, o_view,
            o_times, o_labels, o_r, o_ps):
    """The lane after a scan (:meth:`~.lane.Lane.after_scan`): rows ``means`` ``(n, d)``, ``covs``, ``view``,
    ``times``, ``labels`` (and with ``bern`` their existences ``r`` and survivals ``p_s``; with ``use_ok`` the
    validity verdicts ``ok``, 0 or 1); candidates ``cand`` (ascending rows), the ``quiet`` ones replaced by their
    prediction (row ``k`` of ``pred_means``/``pred_covs`` for ``cand[k]``; existences ``r_quiet``, survivals
    ``p_quiet`` in the order of the quiet ones), the others dropped; then the new singletons at ``now``.

    The rows the pruning keeps are written to the first rows of ``o_means``, ``o_covs``, ``o_view``, ``o_times``,
    ``o_labels`` (and with ``bern`` ``o_r``, ``o_ps``), each with a row for every old row kept and every new one
    (allocated by the caller: numpy backs large arrays with huge pages, numba's allocator does not — at 10⁶ rows
    the page faults of fresh 4-KiB pages tripled the pass). Returns how many rows it wrote."""
    n, d = means.shape[0], means.shape[1]
    src = np.full(n, -1, np.int64)  # -1: kept as it is; -2: stepped (leaves); k >= 0: quiet, its prediction row
    q_of = np.full(n, -1, np.int64)  # a quiet candidate's rank among the quiet ones (r_quiet, p_quiet)
    n_quiet = 0
    for k in range(cand.shape[0]):
        if quiet[k]:
            src[cand[k]] = k
            q_of[cand[k]] = n_quiet
            n_quiet += 1
        else:
            src[cand[k]] = -2
    n_keep = n - (cand.shape[0] - n_quiet)
    n_new = new_means.shape[0]
    total = n_keep + n_new
    alive = np.ones(total, np.bool_)
    r_all = np.empty(total if bern else 0)
    ps_all = np.empty(total if bern else 0)
    if bern:
        j = 0
        for i in range(n):
            if src[i] == -2:
                continue
            if src[i] >= 0:
                r_all[j], ps_all[j] = r_quiet[q_of[i]], p_quiet[q_of[i]]
            else:  # asleep: r <- p_S r (p_D = 0), 0 when its mean fails the validity test
                x = r[i] * p_s[i]
                r_all[j] = x * ok[i] if use_ok else x
                ps_all[j] = p_s[i]
            j += 1
        for t in range(n_new):
            r_all[j], ps_all[j] = r_new[t], p_new[t]
            j += 1
        for j in range(total):  # the engine's pruning of each Bernoulli's two hypotheses (lane.bernoulli_prune)
            x = r_all[j]
            if min_weight <= 0:
                alive[j] = x > 0
            else:
                alive[j] = (x > 0) and ((x >= min_weight) or (x >= 1.0 - x))
                if not (((1.0 - x) >= min_weight) or (1.0 - x > x)):
                    r_all[j] = 1.0
    j = o = 0
    for i in range(n):
        s = src[i]
        if s == -2:
            continue
        if alive[j]:
            if s >= 0:  # a quiet candidate: its prediction, at the scan
                for a in range(d):
                    o_means[o, a] = pred_means[s, a]
                    o_view[o, a] = pred_means[s, a]
                    for b in range(d):
                        o_covs[o, a, b] = pred_covs[s, a, b]
                o_times[o] = now
            else:
                for a in range(d):
                    o_means[o, a] = means[i, a]
                    o_view[o, a] = view[i, a]
                    for b in range(d):
                        o_covs[o, a, b] = covs[i, a, b]
                o_times[o] = times[i]
            o_labels[o] = labels[i]
            if bern:
                o_r[o], o_ps[o] = r_all[j], ps_all[j]
            o += 1
        j += 1
    for t in range(n_new):
        if alive[j]:
            for a in range(d):
                o_means[o, a] = new_means[t, a]
                o_view[o, a] = new_means[t, a]
                for b in range(d):
                    o_covs[o, a, b] = new_covs[t, a, b]
            o_times[o] = now
            o_labels[o] = new_labels[t]
            if bern:
                o_r[o], o_ps[o] = r_all[j], ps_all[j]
            o += 1
        j += 1
    return o

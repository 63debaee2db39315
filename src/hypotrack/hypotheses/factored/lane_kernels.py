"""The lane's end-of-scan rebuild in one compiled pass (:meth:`~.lane.Lane.after_scan`).

A scan changes a few hundred of the lane's ~10⁴–10⁶ rows: the candidates a return or birth term reached leave
(their steps' singletons come back at the end), the quiet candidates take their prediction in place, and with
Bernoulli singletons every row's existence moves (``r ← p_S r`` asleep, :func:`~.lane.missed` for a quiet
candidate) and the engine's pruning (:func:`~.lane.bernoulli_prune`) may drop a row or round its ``r`` up to 1.
Written as numpy this is a dozen passes over the lane's 1-D arrays (masks, cumulative sums, concatenations, the
pruning's comparisons) and a gather of its moments; :func:`rebuild` makes them one pass that decides and writes each
row, with the same arithmetic (``(r p_S) · ok``, the pruning's comparisons), so the lane
is the numpy construction's bit for bit (``tests/unit/hypotheses/factored/test_lane_after_scan.py``).
"""

from __future__ import annotations

import numba

__all__ = ["rebuild"]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def rebuild(means, covs, view, times, labels, r, p_s, ok, cand, quiet, pred_row, quiet_rank, pred_means, pred_covs,
            r_quiet, p_quiet, new_means, new_covs, new_labels, r_new, p_new, now, min_weight, bern, use_ok, o_means,
            o_covs, o_view, o_times, o_labels, o_r, o_ps):
    """The lane after a scan (:meth:`~.lane.Lane.after_scan`): rows ``means`` ``(n, d)``, ``covs``, ``view``,
    ``times``, ``labels`` (and with ``bern`` their existences ``r`` and survivals ``p_s``; with ``use_ok`` the
    validity verdicts ``ok``, 0 or 1); candidates ``cand`` (strictly ascending rows), the ``quiet`` ones replaced by
    their prediction (row ``pred_row[k]`` of ``pred_means``/``pred_covs`` for ``cand[k]``; existence and survival
    ``r_quiet``/``p_quiet`` at ``quiet_rank[k]``), the others dropped; then the new singletons at ``now``.

    The rows the pruning keeps are written to the first rows of ``o_means``, ``o_covs``, ``o_view``, ``o_times``,
    ``o_labels`` (and with ``bern`` ``o_r``, ``o_ps``), each with a row for every old row kept and every new one.
    They are allocated by the caller, and the pass itself allocates nothing: numpy backs large arrays with huge
    pages, numba's allocator does not, and at 10⁶ rows the page faults of fresh 4-KiB pages cost more than the
    copy. Returns how many rows it wrote."""
    n, d, n_cand = means.shape[0], means.shape[1], cand.shape[0]
    o = k = 0
    for i in range(n + new_means.shape[0]):
        new = i >= n
        s = -1  # -1: kept as it is; k >= 0: quiet candidate k (its prediction)
        if not new and k < n_cand and cand[k] == i:
            s = k
            k += 1
            if not quiet[s]:  # stepped: its step's singletons come back among the new ones
                continue
        if bern:
            if new:
                x, ps = r_new[i - n], p_new[i - n]
            elif s >= 0:
                x, ps = r_quiet[quiet_rank[s]], p_quiet[quiet_rank[s]]
            else:  # asleep: r <- p_S r (p_D = 0), 0 when its mean fails the validity test
                x, ps = r[i] * p_s[i], p_s[i]
                if use_ok:
                    x = x * ok[i]
            # the engine's pruning of the Bernoulli's two hypotheses (lane.bernoulli_prune)
            if min_weight <= 0:
                if not x > 0:
                    continue
            else:
                if not ((x > 0) and ((x >= min_weight) or (x >= 1.0 - x))):
                    continue
                if not (((1.0 - x) >= min_weight) or (1.0 - x > x)):
                    x = 1.0
            o_r[o], o_ps[o] = x, ps
        if new:
            t = i - n
            for a in range(d):
                o_means[o, a] = new_means[t, a]
                o_view[o, a] = new_means[t, a]
                for b in range(d):
                    o_covs[o, a, b] = new_covs[t, a, b]
            o_times[o] = now
            o_labels[o] = new_labels[t]
        elif s >= 0:  # a quiet candidate: its prediction, at the scan
            q = pred_row[s]
            for a in range(d):
                o_means[o, a] = pred_means[q, a]
                o_view[o, a] = pred_means[q, a]
                for b in range(d):
                    o_covs[o, a, b] = pred_covs[q, a, b]
            o_times[o] = now
            o_labels[o] = labels[i]
        else:
            for a in range(d):
                o_means[o, a] = means[i, a]
                o_view[o, a] = view[i, a]
                for b in range(d):
                    o_covs[o, a, b] = covs[i, a, b]
            o_times[o] = times[i]
            o_labels[o] = labels[i]
        o += 1
    return o

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
def rebuild(rows, view, has_view, times, labels, r, p_s, ok, cand, quiet, pred_row, quiet_rank, pred_means, pred_covs,
            r_quiet, p_quiet, new_means, new_covs, new_labels, r_new, p_new, now, min_weight, bern, use_ok, buf_means,
            buf_covs, used, o_rows, o_view, o_times, o_labels, o_r, o_ps):
    """The lane after a scan (:meth:`~.lane.Lane.after_scan`): its rows ``rows`` (of the moments ``buf_means``,
    ``buf_covs``), ``view`` (``has_view``; else their means), ``times``, ``labels`` (and with ``bern`` their
    existences ``r`` and survivals ``p_s``; with ``use_ok`` the validity verdicts ``ok``, 0 or 1); candidates
    ``cand`` (strictly ascending), the ``quiet`` ones replaced by their prediction (row ``pred_row[k]`` of
    ``pred_means``/``pred_covs`` for ``cand[k]``; existence and survival ``r_quiet``/``p_quiet`` at
    ``quiet_rank[k]``), the others dropped; then the new singletons at ``now``.

    The quiet candidates' predictions and the new singletons' moments are appended to the moments from row ``used``
    on (the quiet ones in rank order, then the new ones); the lane's rows the pruning keeps are written to the first
    rows of ``o_rows``, ``o_view``, ``o_times``, ``o_labels`` (and with ``bern`` ``o_r``, ``o_ps``), each with a row
    for every old row kept and every new one. Every array is the caller's: numpy backs large ones with huge pages,
    numba's allocator does not, and at 10⁶ rows fresh 4-KiB pages cost more than the pass. Returns how many rows
    it wrote."""
    n, d, n_cand = rows.shape[0], buf_means.shape[1], cand.shape[0]
    n_quiet = 0
    for k in range(n_cand):  # the appended moments, whether or not the pruning keeps the row
        if quiet[k]:
            q, b_row = pred_row[k], used + quiet_rank[k]
            n_quiet += 1
            for a in range(d):
                buf_means[b_row, a] = pred_means[q, a]
                for b in range(d):
                    buf_covs[b_row, a, b] = pred_covs[q, a, b]
    for t in range(new_means.shape[0]):
        b_row = used + n_quiet + t
        for a in range(d):
            buf_means[b_row, a] = new_means[t, a]
            for b in range(d):
                buf_covs[b_row, a, b] = new_covs[t, a, b]
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
        if new or s >= 0:  # its prediction (or new moments), at the scan
            b_row = used + n_quiet + (i - n) if new else used + quiet_rank[s]
            o_rows[o] = b_row
            for a in range(d):
                o_view[o, a] = buf_means[b_row, a]
            o_times[o] = now
            o_labels[o] = new_labels[i - n] if new else labels[i]
        else:
            o_rows[o] = rows[i]
            for a in range(d):
                o_view[o, a] = view[i, a] if has_view else buf_means[rows[i], a]
            o_times[o] = times[i]
            o_labels[o] = labels[i]
        o += 1
    return o

"""Which events a search keeps: the ``k`` heaviest, with ties at the ``k``-th weight decided by order of first visit.

:func:`top_k_first` is the selection the MCMC search (:mod:`.chain`) returns when asked for the ``keep`` heaviest;
:func:`heaviest_heap` seeds the min-heap of the heaviest weights held that the completion's last round compares each
move with (:func:`.chain._complete`).
"""

from __future__ import annotations

import numpy as np

from ..._validation import check_int

__all__ = ["heaviest_heap", "top_k_first"]


def heaviest_heap(logw, k):
    """A min-heap (an ascending array is one) of the ``k`` heaviest of ``logw``, in a buffer of length ``k``,
    and how many it holds."""
    heap = np.empty(k)
    top = np.sort(logw if len(logw) <= k else np.partition(logw, len(logw) - k)[len(logw) - k:])
    heap[: len(top)] = top
    return heap, len(top)


def top_k_first(log_weights, k):
    """Indices of the ``k`` largest log-weights, best first; ties (at the ``k``-th weight too) keep the first.

    Unlike an ``argpartition``, which of several events tied at the ``k``-th weight are kept is defined: the
    lowest indices (for a search, the first visited), so that the ``k`` best of a set and of any subset holding
    every event at least as heavy as its ``k``-th are the same indices of the same events."""
    lw = np.asarray(log_weights, dtype=float)
    if k is None or k >= len(lw):
        return np.argsort(-lw, kind="stable")
    k = check_int(k, "k", minimum=0)
    if k == 0:
        return np.zeros(0, dtype=np.int64)
    kth = np.partition(lw, len(lw) - k)[len(lw) - k]
    above = np.flatnonzero(lw > kth)
    idx = np.sort(np.concatenate([above, np.flatnonzero(lw == kth)[: k - len(above)]]))
    return idx[np.argsort(-lw[idx], kind="stable")]

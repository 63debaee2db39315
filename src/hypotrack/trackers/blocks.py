"""A large scan cut into independent blocks of tracks and returns, for the single-hypothesis trackers.

Gating every predicted track against every return makes ``(m, n)`` matrices: at 10⁶ catalogued objects
(about 8,000 tracks in view and as many returns) that is 6×10⁷ pairs, half a gigabyte per matrix and
seconds a scan, where each track gates a handful of returns. GNN's assignment and JPDA's marginals
decompose over the connected components of the gate graph (returns and tracks joined by a gated pair): a
pair outside every gate takes no part in either (GNN's gain is ``−∞`` there, JPDA's weight 0). So a scan
can be solved block by block, each block a set of whole components, with the trackers' own dense code on
each block's small matrices — the same numbers as the whole matrix, without it.

:func:`gate_blocks` finds the blocks without the matrix. A pair in the gate, ``d² = νᵀ S⁻¹ ν ≤ γ``, has
``|ν_a| ≤ √(γ S_aa)`` for every component ``a`` (Cauchy–Schwarz in the ``S⁻¹`` inner product, as the
factored engine's :func:`~hypotrack.hypotheses.factored.scores.sensor_frame_pairs`): the returns within that
half-width of a track's predicted first component are found by binary search on the sorted returns, the
other components checked as a box. The candidate pairs so found contain every gated pair (a margin of
10⁻⁶ covers rounding), so components of the candidate graph are unions of components of the gate graph:
blocks of whole candidate components never split a gated pair. Tracks and returns with no candidate pair
are in no block: such a track is missed (GNN leaves it unassigned, JPDA's PDA update with ``β₀ = 1``
leaves it as predicted) and such a return is unused.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..association.gating import box_candidates

__all__ = ["candidate_pairs", "gate_blocks", "SPARSE_PAIRS", "BLOCK_TRACKS"]

#: Scans with more (return, track) pairs than this are solved block by block (:func:`gate_blocks`); smaller
#: ones keep the whole matrices (at the catalogue's 10,855 objects a scan has ~10⁴ pairs).
SPARSE_PAIRS = 200_000
#: Tracks per block (whole components are added until a block holds at least this many): blocks large enough
#: that the per-block Python overhead is spread, small enough that a block's matrices stay small.
BLOCK_TRACKS = 64


def _innovation_moments(x, P, model):
    """Predicted measurements ``(n, p)`` and the innovation covariances' diagonals ``(n, p)``."""
    if model.measurement is not None:
        z_pred, S, _, _ = model.measurement.innovation(x, P)
        return z_pred, np.diagonal(S, axis1=1, axis2=2)
    H = model.H
    z_pred = x @ H.T
    S = H @ P @ H.T + model.R
    return z_pred, np.diagonal(S, axis1=1, axis2=2)


def candidate_pairs(x, P, Z, model) -> tuple[np.ndarray, np.ndarray]:
    """``(rows, cols)``: every (return, track) pair that may lie in the track's gate (module docstring), a
    superset of the gated pairs; ``model`` a :class:`~._sht_common.ScanModel`."""
    n, m = len(x), len(Z)
    if n == 0 or m == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    z_pred, S_diag = _innovation_moments(x, P, model)
    return box_candidates(Z, z_pred, np.sqrt(model.gate * S_diag) * (1.0 + 1e-6), model.residual_rows)


def gate_blocks(x, P, Z, model, *, block_tracks: int | None = None) -> list[tuple[np.ndarray, np.ndarray]]:
    """The scan's blocks: ``[(tracks, returns), ...]``, index arrays (ascending) into ``x`` and ``Z``, each
    block a union of whole components of the candidate graph (:func:`candidate_pairs`) holding at least one
    pair, with at least ``block_tracks`` (default :data:`BLOCK_TRACKS`) tracks except the last; every candidate pair
    lies in one block."""
    block_tracks = BLOCK_TRACKS if block_tracks is None else int(block_tracks)
    rows, cols = candidate_pairs(x, P, Z, model)
    if len(rows) == 0:
        return []
    n, m = len(x), len(Z)
    graph = coo_matrix((np.ones(len(rows), np.int8), (cols, n + rows)), shape=(n + m, n + m))
    _, comp = connected_components(graph, directed=False)
    tcomp = comp[:n]
    touched = np.zeros(n + m, dtype=bool)
    touched[cols], touched[n + rows] = True, True
    live = np.unique(comp[touched])  # components holding a pair, in label order
    # whole components in label order, a block closed once it holds block_tracks tracks (one pass over the
    # components: ~10⁴ at 10⁶ objects, milliseconds)
    per = np.bincount(tcomp[touched[:n]], minlength=comp.max() + 1)[live]
    bid, b, held = np.empty(len(live), dtype=np.int64), 0, 0
    for i, c in enumerate(per.tolist()):
        if held >= block_tracks:
            b, held = b + 1, 0
        bid[i], held = b, held + c
    block_of = np.full(comp.max() + 1, -1, dtype=np.int64)
    block_of[live] = bid
    tb = np.where(touched[:n], block_of[tcomp], -1)
    rb = np.where(touched[n:], block_of[comp[n:]], -1)
    t_order, r_order = np.argsort(tb, kind="stable"), np.argsort(rb, kind="stable")
    edges = np.arange(int(bid.max()) + 2)
    t_cuts, r_cuts = np.searchsorted(tb[t_order], edges), np.searchsorted(rb[r_order], edges)
    out = [(t_order[t_cuts[b]:t_cuts[b + 1]], r_order[r_cuts[b]:r_cuts[b + 1]]) for b in range(len(edges) - 1)]
    return out

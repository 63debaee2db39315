"""Global nearest neighbour (GNN) association and update (lecture notes 004, "GNN Algorithm").

The lecture writes the log-probability of an association hypothesis θ as a sum of entries of
the *assignment matrix* ``A`` (rows: returns ``y_i``; columns: targets ``T_j`` then one
external-source column ``EX_i`` per return):

* ``A[i, j] = ℓ_ij = log( P_D p_j(y_i) / (1 − P_D P_G) )`` when ``y_i`` is in target j's gate,
  ``−∞`` otherwise, with ``p_j(y) = N(y; ẑ_j, S_j)`` the predicted measurement density;
* ``A[i, n + i] = log β_EX``, ``β_EX = β_FA + β_NT`` (false alarms and new targets merged into
  one Poisson source); ``−∞`` off the diagonal.

(Fundamental theorem of TT with the constant ``Π_j (1 − P_D P_G)`` divided out.) GNN keeps the
single best hypothesis: the assignment of every row to a distinct column maximising
``Σ_i A[i, a_i]``. Subtracting ``log β_EX`` from every row changes every hypothesis by the same
``m log β_EX``, so this is the same as maximising the summed *gains* ``ℓ_ij − log β_EX`` of the
target pairs chosen, a return left to EX (and a target left undetected) gaining 0. That is how
it is solved here: per cluster of the validation matrix (the problem separates), with
:func:`hypotrack.association.best_assignment` (``scipy.optimize.linear_sum_assignment``) on
the cluster's own assignment matrix (solved in its rectangular form, the EX columns' zero gains
implicit); isolated tracks take their best positive-gain return
directly, and a few small clusters are solved together in one assignment (same optimum, less
overhead than finding them). Returns assigned to EX go to the initiation logic.

A second score reproduces Stone Soup's ``GNNWith2DAssignment`` with a ``DistanceHypothesiser``
(Mahalanobis measure, ``missed_distance = g``): it *minimises* the summed **unsquared**
Mahalanobis distances of the chosen pairs plus ``g`` per detected-in-gate target left
unassigned, only pairs with ``d < g`` allowed — i.e. gains ``g − d_ij``. That is not the
lecture's criterion (no determinant term, no ``P_D`` or clutter density); it exists so the
cross-check compares like with like.
"""

from __future__ import annotations

import numpy as np

from scipy.optimize import linear_sum_assignment

from ..association import association_score_matrix
from ..association.clustering import component_labels
from ..gaussian import joseph_covariance_unchecked
from ._sht_common import GatedTracks, ScanModel

_JOINT_LIMIT = 128

__all__ = [
    "assignment_matrix",
    "gnn_gains",
    "mahalanobis_gains",
    "gnn_associate",
    "gnn_update",
]


def assignment_matrix(gated: GatedTracks, model: ScanModel) -> np.ndarray:
    """The lecture's assignment matrix ``A`` of shape ``(m, n + m)`` (lecture 004, "GNN Algorithm").

    Parameters
    ----------
    gated : GatedTracks
        Predicted tracks gated against the scan.
    model : ScanModel

    Returns
    -------
    A : (m, n + m) ndarray
        ``A[i, j] = ℓ_ij`` for gated pairs, ``A[i, n + i] = log β_EX``, ``−∞`` elsewhere.
    """
    ell = np.log(model.p_D) + gated.log_likelihood() - model.log_missed
    ell = np.where(gated.valid, ell, -np.inf)
    return association_score_matrix(ell, np.full(gated.n_meas, np.log(model.external_density)))


def gnn_gains(gated: GatedTracks, model: ScanModel) -> np.ndarray:
    """Gains ``ℓ_ij − log β_EX`` of the lecture's criterion, ``−∞`` outside the gates; shape (m, n)."""
    gain = np.log(model.p_D) + gated.log_likelihood() - model.log_missed - np.log(model.external_density)
    return np.where(gated.valid, gain, -np.inf)


def mahalanobis_gains(gated: GatedTracks, missed_distance: float) -> np.ndarray:
    """Gains ``g − d_ij`` (unsquared Mahalanobis ``d``) for pairs with ``d < g``; Stone Soup's criterion.

    ``GNNWith2DAssignment`` with a ``DistanceHypothesiser(measure=Mahalanobis(),
    missed_distance=g)`` minimises ``Σ_assigned d_ij + g · #(unassigned targets that had a
    candidate)``, which equals ``const − Σ_assigned (g − d_ij)``.
    """
    g = float(missed_distance)
    if not (np.isfinite(g) and g > 0):
        raise ValueError(f"missed_distance must be a finite number > 0, got {missed_distance!r}")
    d = np.sqrt(gated.d2)
    return np.where(d < g, g - d, -np.inf)


def gnn_associate(gain) -> np.ndarray:
    """Best single association hypothesis for pair gains (a return left to EX gains 0).

    Parameters
    ----------
    gain : (m, n) array_like
        Gain of assigning return ``i`` to target ``j`` relative to leaving both unassigned;
        ``−∞`` for pairs outside the gate.

    Returns
    -------
    a : (m,) int64
        Event vector (project convention): ``a[i] = j`` if return i updates target j, ``−1`` if
        it goes to external sources (initiation).

    Examples
    --------
    Return 0 is in both targets' gates, return 1 only in target 0's. Giving each its own best
    target gains 3.0 and leaves return 1 unused; crossing them gains ``1.0 + 2.5 = 3.5``:

    >>> gnn_associate([[3.0, 1.0], [2.5, -np.inf]]).tolist()
    [1, 0]

    A pair with a negative gain is worse than leaving both unassigned (return to initiation,
    target missed):

    >>> gnn_associate([[-0.5, -np.inf], [0.2, -np.inf]]).tolist()
    [-1, 0]
    """
    gain = np.asarray(gain, dtype=float)
    if gain.ndim != 2:
        raise ValueError(f"gain must have shape (m, n), got {gain.shape}")
    if np.isnan(gain).any() or np.isposinf(gain).any():
        raise ValueError("gain must not contain NaN or +inf")
    return _associate(gain)


def _associate(gain) -> np.ndarray:
    """:func:`gnn_associate` without its input checks (the tracker's own, finite gains)."""
    m, n = gain.shape
    a = np.full(m, -1, dtype=np.int64)
    if m == 0 or n == 0:
        return a
    # Only pairs that beat leaving both unassigned can be in an optimal assignment.
    useful = gain > 0
    if n <= _JOINT_LIMIT:
        # One assignment over all returns and tracks (a row or column without a useful pair
        # just stays unassigned): no cluster bookkeeping for a small problem.
        r, c = linear_sum_assignment(np.where(useful, gain, 0.0), maximize=True)
        hit = useful[r, c]
        a[r[hit]] = c[hit]
        return a
    # A track none of whose useful returns is wanted by another track decides alone; the
    # others are solved in groups of whole clusters.
    contested = useful.sum(axis=1) > 1
    track_contested = (useful & contested[:, None]).any(axis=0)
    alone = np.flatnonzero(~track_contested & useful.any(axis=0))
    if len(alone):
        best = np.argmax(np.where(useful[:, alone], gain[:, alone], -np.inf), axis=0)
        a[best] = alone
    for cols in _cluster_groups(useful, np.flatnonzero(track_contested)):
        rows = np.flatnonzero(useful[:, cols].any(axis=1))
        ix = np.ix_(rows, cols)
        block = useful[ix]
        # Rectangular assignment on the gains, a pair outside ``useful`` gaining 0: the same optimum
        # as the square (rows, cols + EX) matrix of the module docstring, without building it.
        r, c = linear_sum_assignment(np.where(block, gain[ix], 0.0), maximize=True)
        hit = block[r, c]
        a[rows[r[hit]]] = cols[c[hit]]
    return a


def _cluster_groups(useful, tracks):
    """Contested tracks in groups of whole clusters, each group at most ``_JOINT_LIMIT`` tracks
    (a larger cluster is a group of its own).

    Clusters are independent, so one assignment over several of them has the same optimum as
    one per cluster; packing small clusters together saves the per-call overhead, while
    keeping groups small bounds the cubic cost of the assignment solver. Below the limit no
    clustering is needed at all.
    """
    if len(tracks) <= _JOINT_LIMIT:
        return [tracks] if len(tracks) else []
    m = useful.shape[0]
    _, labels = component_labels(useful[:, tracks])
    col_lab = labels[m:]
    order = np.argsort(col_lab, kind="stable")
    members = tracks[order]
    # Cluster boundaries in ``members`` (sorted by cluster label), then greedy packing.
    starts = np.flatnonzero(np.diff(col_lab[order], prepend=-1))
    sizes = np.diff(starts, append=len(members)).tolist()
    groups, begin, size = [], 0, 0
    for s0, sz in zip(starts.tolist(), sizes):
        if size and size + sz > _JOINT_LIMIT:
            groups.append(members[begin:s0])
            begin, size = s0, 0
        size += sz
    groups.append(members[begin:])
    return groups


def gnn_update(gated: GatedTracks, a, model: ScanModel):
    """Kalman (Joseph-form) update of each target with its assigned return; others stay predicted.

    Parameters
    ----------
    gated : GatedTracks
    a : (m,) int
        Event vector from :func:`gnn_associate`.
    model : ScanModel

    Returns
    -------
    x, P : (n, d), (n, d, d)
        Updated means and covariances.
    detected : (n,) bool
        Which targets received a return.
    """
    a = np.asarray(a, dtype=np.int64)
    x, P = gated.x.copy(), gated.P.copy()
    detected = np.zeros(gated.n_tracks, dtype=bool)
    rows = np.flatnonzero(a >= 0)
    if len(rows):
        tracks = a[rows]
        K = gated.K[tracks]
        nu = model.residual_rows(gated.Z[rows], gated.z_pred[tracks])
        x[tracks] = gated.x[tracks] + np.einsum("ndp,np->nd", K, nu)
        P[tracks] = joseph_covariance_unchecked(gated.P[tracks], K, model.H_of(gated, tracks), model.R)
        detected[tracks] = True
    return x, P, detected

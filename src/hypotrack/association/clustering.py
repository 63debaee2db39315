"""Clusters: connected components of the bipartite track–return gating graph.

Tracks that share no gated return are independent in the association problem, so JPDA
probabilities, enumerations and assignments can be computed cluster by cluster (paper 004,
"JPDAF": "the calculations can be done separately for the clusters of targets that do not
share gated measurements"). The graph has an edge between return ``i`` and track ``j`` whenever
``validation[i, j]``; its components are found with :func:`scipy.sparse.csgraph.connected_components`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

__all__ = ["Cluster", "find_clusters", "unassociated_measurements", "check_validation", "graph_components"]


def check_validation(validation, name: str = "validation") -> np.ndarray:
    """Return ``validation`` as a 2-D ``(m, n)`` boolean array, or raise naming ``name``."""
    arr = np.asarray(validation)
    if arr.dtype != bool:
        raise TypeError(f"{name} must be a boolean (m, n) array, got dtype {arr.dtype}")
    if arr.ndim != 2:
        raise ValueError(f"{name} must be a 2-D (m, n) boolean array, got shape {arr.shape}")
    return arr


def _frozen_indices(values) -> np.ndarray:
    arr = np.array(sorted(int(v) for v in values), dtype=np.intp)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Cluster:
    """One connected group of tracks and the returns gated by them.

    Attributes
    ----------
    tracks : ndarray of int
        Sorted track (column) indices; never empty.
    measurements : ndarray of int
        Sorted return (row) indices gated by at least one of the tracks; may be empty.
    """

    tracks: np.ndarray
    measurements: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "tracks", _frozen_indices(self.tracks))
        object.__setattr__(self, "measurements", _frozen_indices(self.measurements))

    def __eq__(self, other):
        if not isinstance(other, Cluster):
            return NotImplemented
        return np.array_equal(self.tracks, other.tracks) and np.array_equal(
            self.measurements, other.measurements
        )

    def __hash__(self):
        return hash((tuple(self.tracks.tolist()), tuple(self.measurements.tolist())))

    def __repr__(self):
        return f"Cluster(tracks={self.tracks.tolist()}, measurements={self.measurements.tolist()})"

    def submatrix(self, matrix: np.ndarray) -> np.ndarray:
        """The rows (returns) and columns (tracks) of an ``(m, n)`` matrix that belong to this cluster."""
        return np.asarray(matrix)[np.ix_(self.measurements, self.tracks)]


SMALL_GRAPH = 256
"""Graphs up to this many vertices are labelled by union–find in Python: a gated problem or a group's
interaction graph has a few dozen, where building a sparse matrix for scipy costs ~0.5 ms and
union–find ~20 µs."""


def graph_components(n: int, a, b) -> tuple[int, np.ndarray]:
    """Connected components of the undirected graph on vertices ``0..n-1`` with edges ``(a[k], b[k])``.

    Returns ``(count, labels)`` as :func:`scipy.sparse.csgraph.connected_components` does: components
    numbered in the order of their smallest vertex (small graphs by union–find, the same labels).
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    if n > SMALL_GRAPH:
        graph = csr_array((np.ones(a.size, dtype=np.int8), (a, b)), shape=(n, n))
        return connected_components(graph, directed=False)
    parent = list(range(n))

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for u, v in zip(a.tolist(), b.tolist()):
        ru, rv = root(u), root(v)
        if ru != rv:
            parent[rv] = ru
    # numbered in the order of their first vertex, whichever vertex is the root
    number, labels = {}, np.empty(n, dtype=np.int32)
    for x in range(n):
        labels[x] = number.setdefault(root(x), len(number))
    return len(number), labels


def component_labels(validation: np.ndarray) -> tuple[int, np.ndarray]:
    """Component label of every node of the gating graph: returns ``0..m-1``, then tracks."""
    m, n = validation.shape
    rows, cols = np.nonzero(validation)
    return graph_components(m + n, rows, m + cols)


def find_clusters(validation) -> list[Cluster]:
    """Partition the tracks into clusters that share gated returns.

    Parameters
    ----------
    validation : (m, n) array of bool
        Validation matrix: ``validation[i, j]`` when return ``i`` lies in track ``j``'s gate.

    Returns
    -------
    list of Cluster
        Every track is in exactly one cluster (a track gating no return forms a cluster of its
        own with no measurements). Returns gated by no track belong to no cluster; see
        :func:`unassociated_measurements`. Clusters are ordered by their smallest track index.

    Examples
    --------
    The lecture's example (paper 004): y1 gated by T3, y2 by none, y3 by T1 and T2, y4 by T2.

    >>> V = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)
    >>> find_clusters(V)
    [Cluster(tracks=[0, 1], measurements=[2, 3]), Cluster(tracks=[2], measurements=[0])]
    """
    arr = check_validation(validation)
    m, n = arr.shape
    if n == 0:
        return []
    _, labels = component_labels(arr)
    row_lab, col_lab = labels[:m], labels[m:]
    clusters = []
    for lab in dict.fromkeys(col_lab.tolist()):  # first-seen order = smallest track index
        clusters.append(Cluster(np.flatnonzero(col_lab == lab), np.flatnonzero(row_lab == lab)))
    return clusters


def unassociated_measurements(validation) -> np.ndarray:
    """Indices of the returns gated by no track (they go to track initiation)."""
    arr = check_validation(validation)
    return np.flatnonzero(~arr.any(axis=1))

"""Data association: counting, enumeration, assignment, gating and clustering.

Event convention (used by the whole project): for ``n`` objects (tracks) and ``m`` returns an
association event is an int vector ``a`` of length ``m``; ``a[i] = j`` (``0 <= j < n``) assigns
return ``i`` to object ``j`` and ``a[i] = -1`` makes it clutter (or, in a hypothesis filter, a
birth handled by the caller's extra columns). Non-negative entries are distinct; objects not
named in ``a`` are missed detections.

The samplers that search the events of one parent hypothesis (R-FISST's MCMC chain, the Gibbs sweeps
of the δ-GLMB filter) are :mod:`hypotrack.association.samplers`, imported on their own (compiled with
numba).
"""

from .assignment import (
    association_score_matrix,
    best_assignment,
    columns_to_event,
    k_best_events,
    murty_k_best,
)
from .cardinality_assignment import cardinality_k_best, cardinality_map
from .clustering import Cluster, find_clusters, unassociated_measurements
from .counting import count_associations, count_children, count_gated_associations
from .enumeration import EnumerationBudgetError, enumerate_associations, event_dtype, iter_association_chunks
from .gating import gate_measurements, gate_threshold, validation_matrix

__all__ = [
    "count_associations",
    "count_children",
    "count_gated_associations",
    "EnumerationBudgetError",
    "enumerate_associations",
    "iter_association_chunks",
    "event_dtype",
    "best_assignment",
    "murty_k_best",
    "association_score_matrix",
    "columns_to_event",
    "k_best_events",
    "cardinality_k_best",
    "cardinality_map",
    "gate_threshold",
    "validation_matrix",
    "gate_measurements",
    "Cluster",
    "find_clusters",
    "unassociated_measurements",
]

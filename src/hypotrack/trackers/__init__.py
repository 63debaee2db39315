"""Single-hypothesis and special-purpose trackers.

* GNN and JPDA/PDAF with M-of-N initiation (lecture notes 004): :class:`SingleHypothesisTracker`
  driven by :class:`ScanModel`, with the association steps in :mod:`.gnn` and :mod:`.jpda`;
* the closely-spaced-target filters of document 003 (ideal, GNNF/MHT, PDAF, ECMHT), vectorised
  over Monte Carlo runs, in :mod:`.ecmht`;
* cardinality tracking (document 003 §4): :class:`CardinalityTracker` (Tetris extraction),
  :class:`ClassicalCountMHT` and the exact count dynamic programme, in :mod:`.cardinality`.
"""

from ._sht_common import GatedTracks, ScanModel
from .cardinality import CardinalityTracker, ClassicalCountMHT, CountModel, exact_count_dp, tetris_extract
from .ecmht import ECMHTFilter, GNNFilter, IdealFilter, PDAFilter
from .gnn import gnn_associate, gnn_update
from .initiation import MOfNInitiator
from .jpda import jpda_probabilities, pda_update
from .tracker import SingleHypothesisTracker, TrackEstimates

__all__ = [
    "ScanModel",
    "GatedTracks",
    "SingleHypothesisTracker",
    "TrackEstimates",
    "MOfNInitiator",
    "gnn_associate",
    "gnn_update",
    "jpda_probabilities",
    "pda_update",
    "IdealFilter",
    "GNNFilter",
    "PDAFilter",
    "ECMHTFilter",
    "CountModel",
    "CardinalityTracker",
    "ClassicalCountMHT",
    "exact_count_dp",
    "tetris_extract",
]

"""Adapters between hypotrack and other tracking libraries.

* :mod:`hypotrack.interop.stonesoup` — run any hypotrack tracker (GNN, JPDA/PDAF, H-FISST,
  R-FISST, HOMHT) as a Stone Soup ``Tracker``: Stone Soup detections in, Stone Soup ``Track``s
  out, so Stone Soup's simulators, metric generators (OSPA, GOSPA, SIAP) and plotters work with
  them. Stone Soup is an optional dependency (``pip install 'hypotrack[stonesoup]'``), imported
  only when the adapter is used.
"""

"""Deterministic scenario generators (ground truth and scans from parameters and a seed).

Every generator returns tidy tables in the schema of :mod:`hypotrack.scenarios.tables`.
:mod:`hypotrack.scenarios.catalogue` (the real TLE catalogue propagated by SGP4, ground radars) is
imported on its own, as it needs the ``sgp4`` package.
"""

from . import tables
from .ssa import SSAParams, SSAScenario, simulate_ssa
from .tables import scans_by_sensor, scans_to_list, truth_to_list, validate_scans, validate_truth

__all__ = [
    "tables",
    "scans_to_list",
    "scans_by_sensor",
    "truth_to_list",
    "validate_truth",
    "validate_scans",
    "SSAParams",
    "SSAScenario",
    "simulate_ssa",
]

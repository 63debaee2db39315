"""The set-up the catalogue's side-by-side timings share (:mod:`.fast_path`, :mod:`.lazy_sht`): one scenario, its
tracking problem and its scans, so that every variant a timing compares steps the very same returns."""

from __future__ import annotations

from dataclasses import dataclass

import pandas as pd

from .run import build_scenario, initial_tracks, make_motion, make_problem, tracker_sensor

__all__ = ["SameScans", "same_scans"]


@dataclass(frozen=True)
class SameScans:
    """``scenario`` (its scans and GMSTs: ``scenario.scan_list(0)``, ``scenario.theta``), the radar as the trackers
    see it (``tsensor``), the tracking problem every variant is built on, the objects in view per scan
    (``in_view``, indexed by scan) and the ``scans`` to step (``(time, returns)``, the first ``n_scans``)."""

    scenario: object
    tsensor: object
    problem: object
    in_view: pd.Series
    scans: list

    def returns(self, k: int):
        """Scan ``k``'s ``(time, returns)`` in the trackers' frame (the radar set to the scan's GMST)."""
        t_k, Z = self.scans[k]
        self.tsensor.at(self.scenario.theta[k])
        return float(t_k), self.tsensor.returns(Z)


def same_scans(cfg, n: int, seed: int, scenario=None, n_scans: int | None = None) -> SameScans:
    """The :class:`SameScans` of ``cfg`` (an ``ssa_catalogue`` section) at population ``n`` and ``seed``
    (:func:`~.run.build_scenario`; ``scenario``, its result, when already built), ``n_scans`` scans (default all)."""
    _, unknown, sc, init_seed = scenario if scenario is not None else build_scenario(cfg, n, seed)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    problem = make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels)
    scans = sc.scan_list(0)
    scans = scans if n_scans is None else scans[:int(n_scans)]
    return SameScans(sc, tsensor, problem, sc.truth[sc.truth["in_view"]].groupby("scan").size(), scans)

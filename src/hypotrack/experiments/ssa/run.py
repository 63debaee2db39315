"""SSA experiments, step 2b: run a tracker over every scan and record its posterior as tables.

:func:`run_tracker` records, per scan, the posterior summaries (expected number of objects,
cardinality distribution, MAP estimates, hypothesis weights at snapshot scans) as a
:class:`TrackingRun`; :func:`run_and_save` is the pipeline's run step (config and scenario
tables in, tracker tables out).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from ..._validation import check_finite_array, check_int
from ...association import count_children
from ...scenarios.ssa import SSAScenario
from ...scenarios.tables import state_columns, write_table
from ..stepping import Clocks
from .scenario import scenario_from_files, truth_arrays
from .trackers import TrackerSettings, make_tracker, tracker_seed

__all__ = [
    "POS_COV",
    "TrackingRun",
    "percent_of_run",
    "run_and_save",
    "run_configured_tracker",
    "run_tracker",
    "snapshot_scans",
]

# The packed position covariance (x-x, x-y, y-y) of every MAP estimate table.
POS_COV = ["cov_0_0", "cov_0_1", "cov_1_1"]


def snapshot_scans(n_scans: int, fractions: Sequence[float]) -> np.ndarray:
    """Scan indices at the given fractions of the run (document 000 Figs 6, 8–10: 10, 50, 75, 100 %).

    Fraction ``f`` is scan ``round(f (K − 1))``, but at least scan 1: scan 0 is the initial
    hypothesis, so the "beginning" of a run is its first processed scan.
    """
    K = check_int(n_scans, "n_scans", minimum=1)
    f = check_finite_array(fractions, "fractions", ndim=1)
    if np.any((f < 0) | (f > 1)):
        raise ValueError(f"fractions must lie in [0, 1], got {f.tolist()}")
    idx = np.rint(f * (K - 1)).astype(np.int64)
    return np.unique(np.maximum(idx, min(1, K - 1)))


def percent_of_run(scan, n_scans):
    """Scan index as a percentage of a run of ``n_scans`` scans (scan 0 = 0 %, last = 100 %)."""
    return 100.0 * np.asarray(scan) / max(n_scans - 1, 1)


@dataclass(frozen=True, eq=False)
class TrackingRun:
    """What :func:`run_tracker` records (every table deterministic given the seed).

    Attributes
    ----------
    summary : DataFrame
        One row per scan: ``scan, time, n_returns, expected_number, map_n_objects,
        map_weight, n_hypotheses, effective_hypotheses, n_children, mass_retained,
        log10_possible_children`` (children of a parent holding the objects truly in view:
        ``A(M, m) + M_b A(M + 1, m) + M_d A(M − 1, m)``, document 000 Sec. II-C).
    cardinality : DataFrame
        ``scan, n_objects, probability`` for every cardinality with positive probability.
    map_estimates : DataFrame
        ``scan, label, state_0..3, cov_0_0, cov_0_1, cov_1_1``: the MAP hypothesis's objects.
    weights : DataFrame
        ``scan, time, rank, weight, n_objects``: every hypothesis at the snapshot scans.
    seconds, cpu_seconds : (K,) float
        Wall-clock and CPU (process) time of each scan: the :meth:`timing_table`, never part
        of the deterministic tables (on a shared machine the CPU time is the steadier one).
    """

    summary: pd.DataFrame
    cardinality: pd.DataFrame
    map_estimates: pd.DataFrame
    weights: pd.DataFrame
    seconds: np.ndarray = field(repr=False)
    cpu_seconds: np.ndarray = field(repr=False, default=None)

    TABLES = ("summary", "cardinality", "map_estimates", "weights")

    def timing_table(self) -> pd.DataFrame:
        """``scan, seconds, cpu_seconds``: the run time of every scan (scan 0: the initial hypothesis)."""
        cpu = np.full(len(self.seconds), np.nan) if self.cpu_seconds is None else self.cpu_seconds
        return pd.DataFrame({"scan": np.arange(len(self.seconds)), "seconds": self.seconds, "cpu_seconds": cpu})

    def write(self, paths: Mapping) -> None:
        """Write each table to ``paths[name]`` as CSV with fixed float formatting (and the
        :meth:`timing_table` to ``paths["timing"]`` when given)."""
        for name in self.TABLES:
            write_table(getattr(self, name), paths[name])
        if "timing" in paths:
            write_table(self.timing_table(), paths["timing"])

    def timing(self) -> str:
        """One line of wall-clock times (total and per scan)."""
        s = self.seconds[1:] if len(self.seconds) > 1 else self.seconds
        return (f"{self.seconds.sum():.1f} s in total (CPU {np.nansum(self.timing_table()['cpu_seconds']):.1f} s); per scan median {np.median(s):.3f} s, "
                f"95th percentile {np.quantile(s, 0.95):.3f} s, max {s.max():.3f} s")


def _log10_children(n_in_view: int, m: int, n_birth_regions: int, deaths: bool) -> float:
    # math.log10 takes the exact (possibly > 64-bit) integer count.
    return math.log10(count_children(n_in_view, m, n_birth_regions, n_in_view if deaths else 0))


def run_tracker(tracker, scenario: SSAScenario, *, snapshots: Sequence[int] = (), name: str = "",
                progress: Callable[[str], None] | None = print, n_progress: int = 20,
                n_scans: int | None = None) -> TrackingRun:
    """Run a hypothesis filter over every scan of an SSA scenario and record its posterior.

    Parameters
    ----------
    tracker : HypothesisFilter
        Started from the scenario's initial hypothesis (:func:`make_tracker`).
    scenario : SSAScenario
    snapshots : sequence of int
        Scans at which every hypothesis's weight is recorded (:func:`snapshot_scans`).
    name : str
        Prefix of the progress lines.
    progress : callable, optional
        Receives about ``n_progress`` progress lines; ``None`` is silent.
    n_scans : int, optional
        Stop after the first ``n_scans`` scans (scan 0, the initial hypothesis, included); ``None``: all.

    Returns
    -------
    TrackingRun
    """
    scans = scenario.scan_list()
    if n_scans is not None:
        scans = scans[:check_int(n_scans, "n_scans", minimum=1)]
    K = len(scans)
    _, in_view = truth_arrays(scenario)
    snapshots = {int(k) for k in snapshots}
    population = getattr(tracker, "population", None)
    n_regions = population.n_birth_regions if population is not None else 0
    every = max(1, (K - 1) // max(1, n_progress))
    rows, card, est, weights = [], [], [], []
    seconds, cpu_seconds = np.zeros(K), np.zeros(K)
    start = time.perf_counter()
    for k, (t, Z) in enumerate(scans):
        with Clocks() as clocks:
            post = tracker.step(Z, t) if k else tracker.posterior(n_top=1)
        seconds[k], cpu_seconds[k] = clocks.wall, clocks.cpu
        w = post.weights
        stats = tracker.last_stats if k else {}
        top = post.map_estimate
        rows.append({
            "scan": k, "time": t, "n_returns": len(Z), "expected_number": post.expected_number,
            "map_n_objects": top.n_objects, "map_weight": top.weight, "n_hypotheses": len(w),
            "effective_hypotheses": 1.0 / float(np.sum(w**2)),
            "n_children": stats.get("n_association_children", 0) + stats.get("n_twin_children", 0),
            "mass_retained": stats.get("mass_retained", 1.0),
            "log10_possible_children": _log10_children(int(in_view[k].sum()), len(Z), n_regions,
                                                       population is not None),
        })
        nz = np.flatnonzero(post.cardinality > 0)
        card.append(pd.DataFrame({"scan": k, "n_objects": nz, "probability": post.cardinality[nz]}))
        e = pd.DataFrame(top.means, columns=state_columns(4))
        e.insert(0, "label", top.labels.astype(np.int64))
        e.insert(0, "scan", k)
        for c, (i, j) in zip(POS_COV, [(0, 0), (0, 1), (1, 1)]):
            e[c] = top.covs[:, i, j]
        est.append(e)
        if k in snapshots:
            weights.append(pd.DataFrame({"scan": k, "time": t, "rank": np.arange(1, len(w) + 1),
                                         "weight": w, "n_objects": post.n_objects}))
        if progress is not None and (k % every == 0 or k == K - 1):
            el = time.perf_counter() - start
            eta = el / max(k, 1) * (K - 1 - k)
            progress(f"{name} scan {k}/{K - 1} ({100 * k / max(K - 1, 1):.0f} %): {len(Z)} returns, "
                     f"E[N] = {post.expected_number:.3f}, MAP weight {top.weight:.3f}, {len(w)} hypotheses; "
                     f"{el:.0f} s elapsed, ~{eta:.0f} s to go")
    empty_w = pd.DataFrame(columns=["scan", "time", "rank", "weight", "n_objects"])
    return TrackingRun(
        summary=pd.DataFrame(rows),
        cardinality=pd.concat(card, ignore_index=True),
        map_estimates=pd.concat(est, ignore_index=True),
        weights=pd.concat(weights, ignore_index=True) if weights else empty_w,
        seconds=seconds,
        cpu_seconds=cpu_seconds,
    )


def run_configured_tracker(config: Mapping, experiment: str, name: str, scenario: SSAScenario, *,
                           snapshot_key: str, progress=print) -> TrackingRun:
    """Build tracker ``name`` from the pipeline config's ``experiment`` section and run it.

    The section gives the tracker settings (:meth:`TrackerSettings.from_config`) and, under
    ``snapshot_key``, the fractions of the run at which all hypothesis weights are recorded; the
    random stream comes from the config's master ``seed`` (:func:`tracker_seed`).
    """
    section = config[experiment]
    settings = TrackerSettings.from_config(section, name)
    tracker = make_tracker(scenario, settings, tracker_seed(config["seed"], experiment, name))
    snaps = snapshot_scans(len(scenario.times), section[snapshot_key])
    return run_tracker(tracker, scenario, snapshots=snaps, name=f"{experiment} {settings.label}",
                       progress=progress)


def run_and_save(config: Mapping, experiment: str, name: str, inputs: Mapping, outputs: Mapping, log_path, *,
                 snapshot_key: str) -> TrackingRun:
    """The pipeline's run step: scenario tables in, tracker tables out, progress to stdout and log.

    ``inputs`` has the ``truth``, ``scans`` and ``prior`` paths of the scenario ``experiment``
    (``"ssa50"`` / ``"ssa15"``); ``outputs`` one path per :attr:`TrackingRun.TABLES` entry
    (and optionally ``timing``).
    """
    scenario = scenario_from_files(config, experiment, inputs["truth"], inputs["scans"], inputs["prior"])
    with open(log_path, "w") as log:

        def progress(line):
            print(line, flush=True)
            print(line, file=log, flush=True)

        run = run_configured_tracker(config, experiment, name, scenario, snapshot_key=snapshot_key,
                                     progress=progress)
        run.write(dict(outputs.items()))  # a Snakemake output list or a mapping
        progress(f"{experiment} {name}: {run.timing()}")
    return run

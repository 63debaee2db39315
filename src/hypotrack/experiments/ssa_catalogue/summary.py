"""Tables, ledger rows and macros of the ``ssa_catalogue`` experiment.

Accuracy (byte-reproducible: same config and seed, same numbers) and timing (machine-dependent)
are kept apart: ``summary.csv``/``claims.csv``/``macros.csv`` hold GOSPA, OSPA, groups,
continuity and births; ``summary_timing.csv``/``timing_claims.csv``/``timing_macros.csv`` hold the
CPU seconds, the cost slope and the peak memory.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim
from .run import FACTORED, REENTRY_GAP_SCANS, continuity

__all__ = ["cost_slope", "accuracy_table", "timing_table", "catalogue_claims", "timing_claims", "catalogue_macros",
           "timing_macros", "parallel_claims", "parallel_macros", "peer_claims", "peer_macros", "TRACKER_NAMES",
           "full_record_macros", "full_record_markdown"]

EXPERIMENT = "ssa_catalogue"
SOURCE = "extension (SSA at catalogue scale)"
TRACKER_NAMES = {"glmb": "δ-GLMB (Gibbs), factored", "homht_kbest": "HOMHT k-best, factored",
                 "rfisst": "R-FISST, factored", "gnn": "GNN", "jpda": "JPDA"}


def cost_slope(n, cost) -> float:
    """Least-squares slope of ``log cost`` on ``log n`` (the exponent ``b`` of ``cost ∝ n^b``).

    Needs at least two distinct positive sizes and positive costs.
    """
    n, cost = np.asarray(n, dtype=float), np.asarray(cost, dtype=float)
    if n.shape != cost.shape or n.ndim != 1:
        raise ValueError(f"n and cost must be 1-D of one length, got shapes {n.shape} and {cost.shape}")
    if len(np.unique(n)) < 2:
        raise ValueError("n must hold at least two distinct sizes for a slope")
    if np.any(n <= 0) or np.any(cost <= 0) or not np.all(np.isfinite(cost)):
        raise ValueError("n and cost must be finite and > 0 (a log-log slope)")
    return float(np.polyfit(np.log(n), np.log(cost), 1)[0])


def accuracy_table(per_scan: pd.DataFrame, assign: pd.DataFrame) -> pd.DataFrame:
    """Per (tracker, size): mean GOSPA (and its missed/false parts) and OSPA over the scans, mean
    objects in view, groups, and the continuity/birth measures of :func:`continuity`."""
    rows = []
    for (name, n), g in per_scan.groupby(["tracker", "n_objects"], sort=False):
        a = assign[(assign["tracker"] == name) & (assign["n_objects"] == n)]
        rows.append(dict(tracker=name, n_objects=int(n), n_scans=len(g), mean_in_view=g["n_in_view"].mean(),
                         gospa_km=g["gospa_km"].mean(), gospa_missed=g["gospa_missed"].mean(),
                         gospa_false=g["gospa_false"].mean(), ospa_km=g["ospa_km"].mean(),
                         groups_mean=g["n_groups"].mean(), largest_group_max=g["largest_group"].max(),
                         **continuity(a)))
    return pd.DataFrame(rows)


#: Scans left out of the CPU averages: scan 0 is at the tracks' epoch (an update with a negligible
#: prediction) and pays the process's one-off costs (loading the compiled kernels, ~0.3 s).
WARM_UP_SCANS = 1


def timing_table(per_scan: pd.DataFrame, memory: pd.DataFrame | None = None) -> pd.DataFrame:
    """Per (tracker, size), over the scans after :data:`WARM_UP_SCANS`: mean CPU seconds per scan,
    CPU ms per object in view per scan, the largest CPU seconds of a scan, the CPU ms per object in
    view over the first and the last quarter of those scans (does the cost grow through the run?);
    peak memory (bytes, from the separate traced pass) when given."""
    rows = []
    for (name, n), g in per_scan.groupby(["tracker", "n_objects"], sort=False):
        g = g[g["scan"] >= WARM_UP_SCANS].sort_values("scan")
        view = g["n_in_view"].to_numpy(float)
        cpu = g["cpu_s"].to_numpy(float)
        q = max(len(g) // 4, 1)
        rows.append(dict(tracker=name, n_objects=int(n), scans_timed=len(g), cpu_s_per_scan=cpu.mean(),
                         cpu_s_max=cpu.max(), mean_in_view=view.mean(),
                         cpu_ms_per_object_in_view=1e3 * cpu.sum() / max(view.sum(), 1.0),
                         cpu_ms_per_object_first_quarter=1e3 * cpu[:q].sum() / max(view[:q].sum(), 1.0),
                         cpu_ms_per_object_last_quarter=1e3 * cpu[-q:].sum() / max(view[-q:].sum(), 1.0)))
    out = pd.DataFrame(rows)
    if memory is not None and len(memory):
        out = out.merge(memory[["tracker", "n_objects", "peak_bytes"]], on=["tracker", "n_objects"], how="left")
    return out


def _fmt(x, digits=3):
    return f"{x:.{digits}g}"


def catalogue_claims(acc: pd.DataFrame, reference: str = "gnn") -> list[Claim]:
    """Extension rows at the largest size: each factored tracker's GOSPA against ``reference``'s,
    and the unknown objects it born from the data with their mean latency."""
    n = acc["n_objects"].max()
    big = acc[acc["n_objects"] == n].set_index("tracker")
    ref = big.loc[reference] if reference in big.index else None
    out = []
    for name in [t for t in FACTORED if t in big.index]:
        r = big.loc[name]
        note = (f"mean GOSPA (c, p from the config) over {int(r.n_scans)} scans of {int(n)} objects; "
                f"{TRACKER_NAMES[reference]}: {_fmt(ref.gospa_km)} km" if ref is not None else "")
        out.append(Claim(EXPERIMENT, f"GOSPA of the in-view estimates, {TRACKER_NAMES[name]}, N = {int(n)}", SOURCE,
                         "--", f"{_fmt(r.gospa_km)} km", "--", "extension", note, "measurement",
                         key=f"gospa_{name}"))
        lat = "no unknown object born" if not np.isfinite(r.latency_mean) else f"mean latency {_fmt(r.latency_mean)} scans"
        out.append(Claim(EXPERIMENT, f"unknown objects born from the data, {TRACKER_NAMES[name]}, N = {int(n)}",
                         SOURCE, "--", f"{int(r.born)} of {int(r.unknown_in_view)}", "--", "extension",
                         f"{lat}; {int(r.label_switches)} label switches, {int(r.fragmentations)} fragmentations",
                         "measurement", key=f"born_{name}"))
        if r.get("reentries", 0) > 0:  # custody through a pass out of view (runs longer than a pass apart)
            ref_txt = (f"; {TRACKER_NAMES[reference]}: {int(ref.reacquired)} of {int(ref.reentries)}"
                       if ref is not None and "reentries" in ref else "")
            out.append(Claim(EXPERIMENT, f"tracks kept through a pass out of view, {TRACKER_NAMES[name]}, N = {int(n)}",
                             SOURCE, "--", f"{int(r.reacquired)} of {int(r.reentries)} re-entries", "--", "extension",
                             f"an object back in view after more than {REENTRY_GAP_SCANS} scans out of it is "
                             f"re-acquired when its first label of the new pass is its last of the previous ones; "
                             f"{int(r.objects_in_view)} distinct objects in view over the run{ref_txt}",
                             "measurement", key=f"reacquired_{name}"))
    return out


def slopes(timing: pd.DataFrame) -> dict:
    """Cost slope (CPU per scan vs N, log-log) per tracker with at least two sizes."""
    out = {}
    for name, g in timing.groupby("tracker", sort=False):
        if g["n_objects"].nunique() >= 2:
            out[name] = cost_slope(g["n_objects"], g["cpu_s_per_scan"])
    return out


def timing_claims(timing: pd.DataFrame, goal: float, per_object_goal_ms: float | None = None) -> list[Claim]:
    """The cost slope of each factored tracker (goal ``≤ goal``) and, with ``per_object_goal_ms``,
    its CPU per object in view per scan at the largest size, as extension rows."""
    out = []
    sl = slopes(timing)
    sizes = ", ".join(str(int(x)) for x in sorted(timing["n_objects"].unique()))
    for name in [t for t in FACTORED if t in sl]:
        out.append(Claim(EXPERIMENT, f"log–log slope of CPU per scan against N, {TRACKER_NAMES[name]}", SOURCE,
                         f"goal ≤ {goal:g}", _fmt(sl[name]), "--", "extension",
                         f"N ∈ {{{sizes}}}; {'meets' if sl[name] <= goal else 'misses'} the goal",
                         "measurement", key=f"slope_{name}"))
    if per_object_goal_ms is not None:
        n = timing["n_objects"].max()
        for _, r in timing[(timing["n_objects"] == n) & timing["tracker"].isin(FACTORED)].iterrows():
            ok = r.cpu_ms_per_object_in_view <= per_object_goal_ms
            out.append(Claim(EXPERIMENT, f"CPU per object in view per scan, {TRACKER_NAMES[r.tracker]}, N = {int(n)}",
                             SOURCE, f"goal ≤ {per_object_goal_ms:g} ms", f"{_fmt(r.cpu_ms_per_object_in_view)} ms",
                             "--", "extension",
                             f"{_fmt(r.cpu_s_per_scan)} CPU s per scan with {_fmt(r.mean_in_view)} "
                             f"object{'' if _fmt(r.mean_in_view) == '1' else 's'} in view, "
                             f"mean of {int(r.scans_timed)} scans (largest {_fmt(r.cpu_s_max)} s); "
                             f"{'meets' if ok else 'misses'} the goal", "measurement",
                             key=f"cpu_object_{r.tracker}"))
    return out


def catalogue_macros(acc: pd.DataFrame) -> dict:
    """Macros of the accuracy table at the largest size."""
    n = acc["n_objects"].max()
    big = acc[acc["n_objects"] == n].set_index("tracker")
    v = {"NLargest": int(n), "InViewLargest": f"{big['mean_in_view'].iloc[0]:.3g}", "ReentryGapScans": REENTRY_GAP_SCANS}
    if "objects_in_view" in big:
        v["ObjectsSeenLargest"] = int(big["objects_in_view"].iloc[0])
    for name, r in big.iterrows():
        k = name.replace("_", "")
        if "reentries" in r:
            v[f"Reentries{k}"], v[f"Reacquired{k}"] = int(r.reentries), int(r.reacquired)
        v[f"Gospa{k}"] = f"{r.gospa_km:.3g}"
        v[f"Ospa{k}"] = f"{r.ospa_km:.3g}"
        v[f"Born{k}"] = int(r.born)
        v[f"Unknown{k}"] = int(r.unknown_in_view)
        v[f"Switches{k}"] = int(r.label_switches)
        v[f"Frags{k}"] = int(r.fragmentations)
        if np.isfinite(r.latency_mean):
            v[f"Latency{k}"] = f"{r.latency_mean:.3g}"
        if np.isfinite(r.largest_group_max):
            v[f"LargestGroup{k}"] = int(r.largest_group_max)
            v[f"Groups{k}"] = f"{r.groups_mean:.4g}"
    return v


def timing_macros(timing: pd.DataFrame) -> dict:
    v = {}
    n = timing["n_objects"].max()
    for name, s in slopes(timing).items():
        v[f"Slope{name.replace('_', '')}"] = f"{s:.2f}"
    for _, r in timing[timing["n_objects"] == n].iterrows():
        k = r.tracker.replace("_", "")
        v[f"CpuScan{k}"] = f"{r.cpu_s_per_scan:.3g}"
        v[f"CpuObj{k}"] = f"{r.cpu_ms_per_object_in_view:.3g}"
        if "peak_bytes" in r and np.isfinite(r.peak_bytes):
            v[f"PeakMB{k}"] = f"{r.peak_bytes / 1e6:.3g}"
    return v


_POOLS = {"process": "process pool", "thread": "thread pool"}


def parallel_claims(par: pd.DataFrame) -> list[Claim]:
    """One extension row per pool kind: the wall-clock speed-up of ``workers`` over one on the
    same scans, with the Amdahl ceiling, whether the posterior stayed identical, and the bytes a
    distributed scheduler would move."""
    serial = par[par["pool"] == "serial"].iloc[0]
    out = []
    for _, r in par[par["pool"] != "serial"].iterrows():
        note = (f"same {int(r.n_scans)} scans in lockstep; {_fmt(r.steps_per_scan)} engine steps a scan take "
                f"{100 * r.steps_share_serial:.2g} % of the serial wall time, so the ceiling is "
                f"{r.speedup_ceiling:.2f}×; CPU per scan {_fmt(serial.cpu_s_per_scan)} s serial, "
                f"{_fmt(r.cpu_s_per_scan)} s here (+{_fmt(r.worker_cpu_s_per_scan)} s in the pool); posterior "
                f"{'identical' if r.identical else 'DIFFERENT'} to workers = 1; pickled state per scan "
                f"{serial.bytes_in_per_scan / 1e3:.3g} kB in, {serial.bytes_out_per_scan / 1e3:.3g} kB out")
        out.append(Claim(EXPERIMENT, f"wall-clock speed-up with {int(r.workers)} workers ({_POOLS[r.pool]}), "
                         f"{TRACKER_NAMES[r.tracker]}, N = {int(r.n_objects)}", SOURCE, "--",
                         f"{r.speedup_wall:.2f}×", "--", "extension", note, "measurement",
                         key=f"speedup_{r.pool}"))
    return out


def parallel_macros(par: pd.DataFrame) -> dict:
    """Macros of the parallel timing table (speed-ups, ceiling, step share, bytes moved)."""
    serial = par[par["pool"] == "serial"].iloc[0]
    v = {"ParN": int(serial.n_objects), "ParWorkers": int(par["workers"].max()),
         "ParStepsScan": f"{serial.steps_per_scan:.3g}", "ParStepShare": f"{100 * serial.steps_share_serial:.2g}",
         "ParCeiling": f"{par['speedup_ceiling'].max():.2f}", "ParWallSerial": f"{serial.wall_s_per_scan:.3g}",
         "ParKBInScan": f"{serial.bytes_in_per_scan / 1e3:.3g}", "ParKBOutScan": f"{serial.bytes_out_per_scan / 1e3:.3g}",
         "ParKBInStep": f"{serial.bytes_in_per_step / 1e3:.3g}", "ParKBOutStep": f"{serial.bytes_out_per_step / 1e3:.3g}",
         "ParIdentical": "yes" if bool(par["identical"].all()) else "no"}
    for _, r in par[par["pool"] != "serial"].iterrows():
        v[f"ParSpeedup{r.pool}"] = f"{r.speedup_wall:.2f}"
    return v


def peer_claims(peers: pd.DataFrame) -> list[Claim]:
    """One extension row per (algorithm, Stone Soup peer, size): hypotrack's per-scan speed-up over
    the peer on the same scans, with how many timed scans gave the same associations."""
    out = []
    rank = {n: i + 1 for i, n in enumerate(sorted(peers["n_objects"].unique()))}  # keys never embed a config value
    for _, r in peers[peers["implementation"] != "hypotrack"].iterrows():
        ref = peers[(peers["algorithm"] == r.algorithm) & (peers["n_objects"] == r.n_objects)
                    & (peers["implementation"] == "hypotrack")].iloc[0]
        agree = ("same associations and states on every timed scan" if r.scans_same_association == r.scans_compared
                 else f"same associations on {int(r.scans_same_association)} of {int(r.scans_compared)} timed scans "
                      f"(largest difference {_fmt(r.max_output_diff)})")
        out.append(Claim(EXPERIMENT, f"per-scan speed-up of hypotrack's {r.algorithm.upper()} over Stone Soup "
                         f"{r.implementation}, catalogue N = {int(r.n_objects)}", SOURCE, "--",
                         f"{r.peer_over_hypotrack:.3g}×", "--", "extension",
                         f"{int(r.n_tracks)} known tracks, EKF (hypotrack's dynamics on both sides), "
                         f"median of {int(r.scans_timed)} scans: {_fmt(ref.median_ms)} ms against "
                         f"{_fmt(r.median_ms)} ms; {agree}", "measurement",
                         key=f"peer_{r.algorithm}_{r.implementation}_size{rank[r.n_objects]}"))
    return out


def peer_macros(peers: pd.DataFrame) -> dict:
    """Speed-up macros per (algorithm, peer) at the smallest size timed."""
    v = {}
    n = peers["n_objects"].min()
    for _, r in peers[(peers["implementation"] != "hypotrack") & (peers["n_objects"] == n)].iterrows():
        v[f"Peer{r.algorithm}{r.implementation}"] = f"{r.peer_over_hypotrack:.3g}"
        v[f"PeerSame{r.algorithm}{r.implementation}"] = int(r.scans_same_association)
        v[f"PeerScans{r.algorithm}{r.implementation}"] = int(r.scans_compared)
    if len(peers):
        v["PeerN"] = int(n)
    return v


def full_record_macros(table: pd.DataFrame, goal_ms: float = 1.0) -> dict:
    """Macros of the committed full-catalogue record (``paper/record/ssa_catalogue_full.csv``, the
    joined accuracy and timing table of a ``full.yaml`` run): at its largest size, objects in view,
    and per tracker CPU per scan (ms), per object in view (ms, and whether it meets ``goal_ms``),
    peak memory (MB), GOSPA (km), objects born of the unknown ones in view; the cost slopes over
    all its sizes."""
    n = int(table["n_objects"].max())
    big = table[table["n_objects"] == n].set_index("tracker")
    v = {"FullN": n, "FullSizes": ", ".join(str(int(x)) for x in sorted(table["n_objects"].unique())),
         "FullInView": f"{big['mean_in_view'].iloc[0]:.3g}", "FullScans": int(big["n_scans"].iloc[0])}
    if "objects_in_view" in big:  # a record from before the re-entry measures lacks them
        v["FullObjectsSeen"] = int(big["objects_in_view"].iloc[0])
    for name, r in big.iterrows():
        k = name.replace("_", "")
        if "reentries" in r and np.isfinite(r.reentries):
            v[f"FullReentries{k}"], v[f"FullReacquired{k}"] = int(r.reentries), int(r.reacquired)
        v[f"FullCpuScan{k}"] = f"{1e3 * r.cpu_s_per_scan:.3g}"
        v[f"FullCpuObj{k}"] = f"{r.cpu_ms_per_object_in_view:.3g}"
        if "cpu_ms_per_object_last_quarter" in r and np.isfinite(r.cpu_ms_per_object_last_quarter):
            v[f"FullCpuObjFirst{k}"] = f"{r.cpu_ms_per_object_first_quarter:.3g}"
            v[f"FullCpuObjLast{k}"] = f"{r.cpu_ms_per_object_last_quarter:.3g}"
        v[f"FullPeakMB{k}"] = f"{r.peak_bytes / 1e6:.3g}"
        v[f"FullGospa{k}"] = f"{r.gospa_km:.3g}"
        v[f"FullBorn{k}"] = int(r.born)
        v[f"FullUnknown{k}"] = int(r.unknown_in_view)
        if name in FACTORED:
            v[f"FullGoal{k}"] = "meets" if r.cpu_ms_per_object_in_view <= goal_ms else "misses"
    for name, s in slopes(table).items():
        v[f"FullSlope{name.replace('_', '')}"] = f"{s:.2f}"
    return v


def full_record_markdown(table: pd.DataFrame) -> str:
    """The full-catalogue record at its largest size as a Markdown table (the README's block)."""
    n = int(table["n_objects"].max())
    sl = slopes(table)
    big = table[table["n_objects"] == n]
    custody = "reentries" in big and bool(np.isfinite(big["reentries"]).all())
    quarters = "cpu_ms_per_object_last_quarter" in big
    lines = [f"Whole catalogue, N = {n:,} objects, {int(table['n_scans'].max())} scans of the radar, one run "
             "(`full.yaml`, recorded in `paper/record/ssa_catalogue_full.csv`):", "",
             "| tracker | CPU per scan (ms) | CPU per object in view (ms) "
             + ("| first → last quarter of the run (ms) " if quarters else "")
             + "| cost slope in N | peak memory (MB) "
             "| GOSPA (km) | unknown objects born |" + (" tracks kept through a pass out of view |" if custody else ""),
             "|---|---|---|---|---|---|---|" + ("---|" if quarters else "") + ("---|" if custody else "")]
    for _, r in big.iterrows():
        growth = (f"| {r.cpu_ms_per_object_first_quarter:.3g} → {r.cpu_ms_per_object_last_quarter:.3g} "
                  if quarters else "")
        lines.append(f"| {TRACKER_NAMES[r.tracker]} | {1e3 * r.cpu_s_per_scan:.3g} | {r.cpu_ms_per_object_in_view:.3g} "
                     + growth +
                     f"| {sl.get(r.tracker, float('nan')):.2f} | {r.peak_bytes / 1e6:.3g} | {r.gospa_km:.3g} "
                     f"| {int(r.born)} of {int(r.unknown_in_view)} |"
                     + (f" {int(r.reacquired)} of {int(r.reentries)} |" if custody else ""))
    sizes = ", ".join(f"{int(x):,}" for x in sorted(table["n_objects"].unique()))
    seen = f"{int(big['objects_in_view'].iloc[0]):,} distinct objects in view over the run; " if custody else ""
    lines += ["", f"Objects in view per scan: {big['mean_in_view'].iloc[0]:.3g} on average; {seen}"
              f"slopes over N ∈ {{{sizes}}}; peak memory traced over the first scans (tracemalloc)."]
    return "\n".join(lines)

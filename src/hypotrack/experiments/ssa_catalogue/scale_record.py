"""The timing-at-scale part of the whole-catalogue record: its check, macros and README block.

The scale harness (:mod:`.scale`) under ``workflows/config/full.yaml`` writes ``scale_summary_timing.csv``
(per tracker and cloned population size N: the median of the runs with their spread, the machine's mean load)
and ``scale_runs_timing.csv`` (one row per run). :mod:`.record` commits them beside the whole-catalogue table
(``paper/record/ssa_catalogue_scale.csv`` and ``ssa_catalogue_scale_runs.csv``) after
:func:`scale_config_differences` has found them to be the full configuration's; the report quotes them
through :func:`scale_record_macros` and the README through :func:`scale_record_markdown`:

* at the smallest size (the catalogue itself, N = 10,855), µs of CPU per object in view per scan;
* at the largest size (10⁶ objects), the real-time factor (simulated seconds per CPU second: above 1 the
  tracker keeps up with the radar on one core) and the peak resident memory;

each the median of the runs with its minimum and maximum, and the machine's load average over those runs
(the machine is shared: a loaded machine slows a run down, the load says by how much to distrust it).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from .summary import TRACKER_NAMES

__all__ = ["scale_config_differences", "scale_record_macros", "scale_record_markdown"]


def scale_config_differences(table: pd.DataFrame, scale: dict) -> list[str]:
    """What in the summary ``table`` differs from the ``scale`` config block it should be a run of: its sizes,
    trackers, runs per (tracker, N), timed scans per run (``n_scans − warm_scans``) and the start after the priors'
    epoch (``start_after_s``, 0 for a table without it); empty when none."""
    out = []
    if sorted(int(n) for n in table["n_objects"].unique()) != sorted(int(float(n)) for n in scale["sizes"]):
        out.append(f"sizes {sorted(table['n_objects'].unique().tolist())} (config {scale['sizes']})")
    if sorted(table["tracker"].unique()) != sorted(scale["trackers"]):
        out.append(f"trackers {sorted(table['tracker'].unique())} (config {scale['trackers']})")
    planned = table["runs"] + table.get("runs_timed_out", 0) + table.get("runs_failed", 0) + table.get("runs_skipped", 0)
    if not (planned == int(scale["runs"])).all():
        out.append(f"runs {sorted(planned.unique().tolist())} (config {scale['runs']})")
    timed = int(scale["n_scans"]) - int(scale.get("warm_scans", 1))
    if not (table["n_scans"].dropna() == timed).all():
        out.append(f"timed scans {sorted(table['n_scans'].unique().tolist())} (config {timed})")
    after = float(scale.get("start_after_s", 0.0))  # tables from before the harness recorded it started at the epoch
    had = table["start_after_s"].dropna().unique().tolist() if "start_after_s" in table else [0.0]
    if had != [after]:
        out.append(f"start_after_s {had} (config {after:g})")
    return out


def _three(r, figure: str, scale: float = 1.0, fmt: str = ".3g"):
    """``(median, min, max)`` formatted; ``None`` when no run finished (NaN)."""
    if not np.isfinite(r[f"{figure}_median"]):
        return None
    return tuple(format(scale * r[f"{figure}_{q}"], fmt) for q in ("median", "min", "max"))


def _cell(three, r) -> str:
    if three is None:
        failed = int(r.get("runs_failed", 0)) if np.isfinite(r.get("runs_failed", 0)) else 0
        timed_out = int(r.get("runs_timed_out", 0))
        if not failed and not timed_out and int(r.get("runs_skipped", 0)):
            return "not run (stopped at a smaller N)"
        return f"not finished ({f'{failed} failed' if failed else f'{timed_out} timed out'})"
    return f"{three[0]} [{three[1]}, {three[2]}]"


def scale_record_macros(table: pd.DataFrame) -> dict:
    """Macros of the committed scale table (module docstring): ``ScaleSmallN``, ``ScaleLargeN``, ``ScaleRuns``,
    ``ScaleScans``; per tracker ``k`` (underscores dropped) ``ScaleUs{k}`` with ``ScaleUsMin{k}``,
    ``ScaleUsMax{k}`` (µs per object in view at the smallest size), ``ScaleRtf{k}`` and ``ScalePeakGB{k}``
    with their ``Min``/``Max`` (at the largest size), ``ScaleSlope{k}`` (log-log slope of CPU per scan
    against N); ``ScaleLoadSmall``, ``ScaleLoadLarge`` the mean load average over the runs at each."""
    small, large = int(table["n_objects"].min()), int(table["n_objects"].max())
    v = {"ScaleSmallN": small, "ScaleLargeN": large, "ScaleRuns": int(table["runs"].max()),
         "ScaleScans": int(table["n_scans"].min())}
    for name, g in table.groupby("tracker", sort=False):
        k = name.replace("_", "")
        s = g[g["n_objects"] == small].iloc[0]
        b = g[g["n_objects"] == large].iloc[0]
        for key, row, figure, scale in (("Us", s, "us_per_object_in_view", 1.0), ("Rtf", b, "real_time_factor", 1.0),
                                        ("PeakGB", b, "peak_rss_mb", 1e-3)):
            three = _three(row, figure, scale)
            if three is not None:  # no macro for a figure no run gave (the report says so)
                v[f"Scale{key}{k}"], v[f"Scale{key}Min{k}"], v[f"Scale{key}Max{k}"] = three
        if np.isfinite(b["slope_cpu_vs_n"]):
            v[f"ScaleSlope{k}"] = f"{b['slope_cpu_vs_n']:.2f}"
    v["ScaleLoadSmall"] = f"{table.loc[table['n_objects'] == small, 'load_mean'].mean():.2g}"
    v["ScaleLoadLarge"] = f"{table.loc[table['n_objects'] == large, 'load_mean'].mean():.2g}"
    return v


def scale_record_markdown(table: pd.DataFrame) -> str:
    """The README's scale block: per tracker the macros' figures as a Markdown table (median [min, max])."""
    small, large = int(table["n_objects"].min()), int(table["n_objects"].max())
    runs, scans = int(table["runs"].max()), int(table["n_scans"].min())
    threads = ({f"{t:g}" if isinstance(t, float) else str(t) for t in table["blas_threads"].dropna()} - {""}
               if "blas_threads" in table else {"default"})  # read back from CSV, "1" is 1.0
    blas = "BLAS on one thread" if threads == {"1"} else f"BLAS threads: {', '.join(sorted(threads))}"
    lines = [f"Timing at scale (the catalogue cloned to N objects, `full.yaml`'s `ssa_catalogue.scale`, recorded in "
             f"`paper/record/ssa_catalogue_scale.csv`): median [min, max] of {runs} runs of {scans} timed scans each, "
             f"one process per run ({blas}):", "",
             f"| tracker | µs of CPU per object in view per scan, N = {small:,} | real-time factor, N = {large:,} "
             f"| peak memory (GB), N = {large:,} | cost slope in N |", "|---|---|---|---|---|"]
    for name, g in table.groupby("tracker", sort=False):
        s = g[g["n_objects"] == small].iloc[0]
        b = g[g["n_objects"] == large].iloc[0]
        us, rtf, gb = _three(s, "us_per_object_in_view"), _three(b, "real_time_factor"), _three(b, "peak_rss_mb", 1e-3)
        slope = f"{b['slope_cpu_vs_n']:.2f}" if np.isfinite(b["slope_cpu_vs_n"]) else "—"
        lines.append(f"| {TRACKER_NAMES.get(name, name)} | {_cell(us, s)} | {_cell(rtf, b)} | {_cell(gb, b)} | {slope} |")
    sizes = ", ".join(f"{int(x):,}" for x in sorted(table["n_objects"].unique()))
    load_s = table.loc[table["n_objects"] == small, "load_mean"].mean()
    load_b = table.loc[table["n_objects"] == large, "load_mean"].mean()
    stopped = ("runs_timed_out" in table) and bool(table["runs_timed_out"].sum())
    failed = ("runs_failed" in table) and bool(table["runs_failed"].fillna(0).sum())
    lines += ["", ("A run not finished within the wall-time limit (`timeout_s`) was stopped, and its tracker not run "
                   "again at that N or above. " if stopped else "") +
              ("A run whose process failed (e.g. out of memory) is recorded as failed, and its "
               "tracker not run again at that N or above. " if failed else "") +
              f"Real-time factor: simulated seconds per CPU second (above 1 the tracker keeps up with the radar); "
              f"slopes over N ∈ {{{sizes}}}; the machine's load average over the runs {load_s:.2g} at N = {small:,} "
              f"and {load_b:.2g} at N = {large:,} (a shared 2-core machine)."]
    return "\n".join(lines)

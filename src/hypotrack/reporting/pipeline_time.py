"""What a pipeline run cost: wall clock and CPU time per rule, from Snakemake's job benchmarks.

Every job of the workflow writes a Snakemake benchmark file (``{results}/benchmarks/<rule>[_<wildcards>].tsv``:
wall seconds, CPU seconds, peak memory; the Snakefile attaches one to every rule with outputs). At the
end of a successful invocation the Snakefile calls :func:`write_run_record`, which keeps the jobs that
this invocation ran (benchmark written after it started) and writes ``{results}/paper/pipeline_timing.csv``::

    rule, jobs, wall_s, cpu_s, max_rss_mib

one row per rule, sorted by CPU time, and a first row ``(whole run)`` whose ``wall_s`` is the
invocation's elapsed time, ``cpu_s`` the sum over its jobs, ``jobs`` their number and ``cores`` the
cores it was given (empty for a run through an executor, e.g. a cluster profile). The README's run-time sentence is generated from that file
(:mod:`hypotrack.reporting.readme`), so the budget it states is the one measured by the last full run.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

__all__ = ["WHOLE_RUN", "assembled_run_record", "job_benchmarks", "run_summary", "runtime_sentence", "write_run_record"]

WHOLE_RUN = "(whole run)"
COLUMNS = ["rule", "jobs", "wall_s", "cpu_s", "max_rss_mib", "cores"]


def job_benchmarks(results, since: float | None = None) -> pd.DataFrame:
    """One row per job benchmark under ``{results}/benchmarks``: rule, wall_s, cpu_s, max_rss_mib.

    ``since`` (a POSIX time) keeps only files written at or after it, i.e. the jobs one invocation ran.
    """
    rows = []
    root = Path(results) / "benchmarks"
    for path in sorted(root.glob("*/*.tsv")) if root.is_dir() else []:
        if since is not None and path.stat().st_mtime < since:
            continue
        table = pd.read_csv(path, sep="\t")
        if table.empty:
            continue
        last = table.iloc[-1]  # a benchmark file has one row per repeat; the pipeline runs one
        rss = pd.to_numeric(last.get("max_rss"), errors="coerce")
        rows.append({"rule": path.parent.name, "wall_s": float(last["s"]),
                     "cpu_s": float(pd.to_numeric(last.get("cpu_time"), errors="coerce")),
                     "max_rss_mib": None if pd.isna(rss) else float(rss)})
    return pd.DataFrame(rows, columns=["rule", "wall_s", "cpu_s", "max_rss_mib"])


def run_summary(jobs: pd.DataFrame, elapsed_s: float, cores: int | None) -> pd.DataFrame:
    """Per-rule totals of ``jobs`` (sorted by CPU time, largest first) under a ``(whole run)`` row."""
    if elapsed_s < 0 or (cores is not None and cores < 1):
        raise ValueError(f"elapsed_s must be >= 0 and cores >= 1 (None on an executor), got {elapsed_s} and {cores}")
    per_rule = (jobs.groupby("rule")
                .agg(jobs=("rule", "size"), wall_s=("wall_s", "sum"), cpu_s=("cpu_s", "sum"),
                     max_rss_mib=("max_rss_mib", "max"))
                .reset_index().sort_values(["cpu_s", "rule"], ascending=[False, True]))
    per_rule["cores"] = pd.NA
    whole = pd.DataFrame([{"rule": WHOLE_RUN, "jobs": len(jobs), "wall_s": elapsed_s,
                           "cpu_s": jobs["cpu_s"].sum(), "max_rss_mib": jobs["max_rss_mib"].max(),
                           "cores": cores}])
    out = pd.concat([whole, per_rule], ignore_index=True)[COLUMNS]
    return out.round({"wall_s": 1, "cpu_s": 1, "max_rss_mib": 1})


def write_run_record(results, started: float, finished: float, cores: int | None,
                     elapsed_s: float | None = None) -> Path | None:
    """Write ``{results}/paper/pipeline_timing.csv`` for the jobs run since ``started``; ``None`` if none ran.

    ``elapsed_s`` (default ``finished - started``) is for a run completed by a second invocation
    (``--rerun-incomplete`` after an interruption): the sum of the invocations' elapsed times, so the
    pause between them is not counted.
    """
    jobs = job_benchmarks(results, since=started)
    if jobs.empty:
        return None
    path = Path(results) / "paper" / "pipeline_timing.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    run_summary(jobs, finished - started if elapsed_s is None else elapsed_s, cores).to_csv(path, index=False)
    return path


def assembled_run_record(results, cores: int) -> Path | None:
    """Write ``{results}/paper/pipeline_timing.csv`` from every job benchmark under ``{results}/benchmarks``, for
    results assembled by several invocations of one configuration (jobs whose code did not change kept from an
    earlier run, the others rerun): each job's wall and CPU time are measured, the whole run's wall clock is not
    (``wall_s`` empty; :func:`runtime_sentence` then gives the CPU time and the bound it sets on ``cores``)."""
    jobs = job_benchmarks(results)
    if jobs.empty:
        return None
    out = run_summary(jobs, 0.0, cores)
    out["wall_s"] = out["wall_s"].astype(float)
    out.loc[out["rule"] == WHOLE_RUN, "wall_s"] = float("nan")
    path = Path(results) / "paper" / "pipeline_timing.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    out.to_csv(path, index=False)
    return path


def runtime_sentence(record: pd.DataFrame) -> str:
    """``72 minutes measured (2 cores; 141 CPU-minutes over 95 jobs, most in ssa_seeds_shard)``; for a record
    assembled from several invocations (no whole-run wall clock), the CPU time and the least wall time it
    implies on the cores given."""
    whole = record[record["rule"] == WHOLE_RUN]
    if whole.empty:
        raise ValueError(f"pipeline time record has no {WHOLE_RUN!r} row")
    w = whole.iloc[0]
    rules = record[record["rule"] != WHOLE_RUN]
    top = ", ".join(f"{r.rule} {r.cpu_s / 60:.0f}" for r in rules.head(3).itertuples())
    where = "through an executor (a cluster)" if pd.isna(w.cores) else f"on {int(w.cores)} cores"
    cpu = f"{w.cpu_s / 60:.0f} CPU-minutes over {int(w.jobs)} jobs; largest, in CPU-minutes: {top}"
    if pd.isna(w.wall_s):
        bound = "" if pd.isna(w.cores) else f"; at least {w.cpu_s / 60 / int(w.cores):.0f} minutes {where}"
        return f"not measured as one run ({cpu}{bound})"
    return f"{w.wall_s / 60:.0f} minutes measured {where} ({cpu})"

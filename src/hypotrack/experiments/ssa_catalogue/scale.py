"""Honest timing at scale: CPU, real-time factor and peak memory per tracker and population size.

Populations (config ``ssa_catalogue.scale``): the catalogue cloned to ``N`` objects
(:func:`hypotrack.scenarios.catalogue.clones.simulate_clones`: every ``N`` the same mix of the
catalogue's groups, so a slope of cost against ``N`` compares like with like), the radar, motion model
and trackers of the ``ssa_catalogue`` section, the known objects and the unknown share of the debris as
in :func:`~.run.build_scenario`.

One **run** (:func:`measure_run`) is one tracker over ``n_scans`` scans of one population, in a fresh
Python process (:func:`run_isolated`), so that its peak resident memory (``ru_maxrss``, over the
whole run: simulation included) is its own. Per run: CPU seconds of the tracker's steps
(``time.process_time``; the first ``warm_scans`` scans stepped untimed: scan 0 is at the priors' epoch, and a
fresh process compiles each numba kernel on its first call, ~0.1 s of CPU in the first scan with a general
engine step, which over a few timed scans would swamp the steady cost; the association samplers' kernels are loaded
before the first scan, untimed, since a tracker's first Gibbs or MCMC step may fall in a timed scan), and from them µs per
object in view per scan, per catalogued object per scan and per return; the **real-time factor**
(simulated seconds per CPU second: above 1 the tracker keeps up with the radar on one core); the
load average of the machine before and after; ``blas_threads``, the ``OPENBLAS_NUM_THREADS`` the process started with (one in :func:`run_isolated`: :data:`ONE_THREAD`). :func:`scale_summary`: per (tracker, N) the median of the
runs with its spread (min, max), and per tracker the log-log slope of CPU per scan against ``N``.

A run not finished within ``scale.timeout_s`` seconds of wall time (when set) is stopped and recorded as
``timed_out``, a run whose process fails (e.g. out of memory) as ``failed`` with its reason; either way its
tracker is not run again at that ``N`` or above (``skipped``), and the summary takes the
finished runs only. Each run's process has BLAS on one thread (:data:`ONE_THREAD`). A numba kernel a tracker
first calls after the untimed scans (e.g. JPDA's first large cluster) is compiled inside a timed scan when the
kernel cache is cold: a fresh checkout's first run can be seconds dearer than the next.

Steady state (``scale.start_after_s``). The priors are the known objects' states at the catalogue's epoch; the scans
begin ``start_after_s`` seconds later (the population simulated from there, the tracker's clock still counted from
the epoch). A lazy tracker predicts only what may be in view, so each object it first sees in the run is predicted
over at least that gap — with ``replay`` scan by scan, ``start_after_s / revisit_s`` EKF steps — as a track
re-acquired on its next pass is in a long run (a LEO object is back in the radar's view about an orbit later:
~5,700 s, ~570 scans of 10 s). Started at the epoch instead (``start_after_s`` 0, the default) every gap is at
most ``n_scans`` scans, and the timed scans leave out the cost that grows with the gap: the figures are then of
a run's first minutes only. The warm (untimed) scans hold the first predictions of the objects already in view
at the start. GNN and JPDA replay a deferred track over the scans they were given only, so from priors at the
epoch they would predict each object over the whole gap in one EKF step (far too wide: measured, JPDA's clusters
then cost ~2 s a scan at N = 10,855); their priors are instead replayed to the first scan scan by scan, untimed
(:func:`~...hypotheses.factored.lane.predict_each` with the revisit interval as step), and their clock starts
there: their figures hold steady-state covariances but not the replay of a pass gap, which the factored trackers'
figures include.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time

import numpy as np
import pandas as pd

from ...hypotheses.factored.lane import predict_each
from ...scenarios.catalogue import load_catalogue, reference_epoch
from ...scenarios.catalogue.clones import simulate_clones
from ...hypotheses.warm import warm_engine, warm_samplers
from .run import initial_tracks, make_motion, make_problem, make_radar, make_tracker, tracker_sensor

__all__ = ["FIGURES", "ONE_THREAD", "ScaleRunFailed", "clone_scenario", "measure_run", "run_isolated", "scale_runs", "scale_summary"]

class ScaleRunFailed(RuntimeError):
    """A run's process ended with an error (``reason``: its last line of error output, or the signal that killed
    it: an out-of-memory kill has none)."""

    def __init__(self, message: str, reason: str):
        super().__init__(message)
        self.reason = reason


#: The per-run figures :func:`scale_summary` takes the median and spread of.
FIGURES = ("cpu_s_per_scan", "us_per_object_in_view", "us_per_object", "us_per_return", "real_time_factor",
           "peak_rss_mb")


def clone_scenario(cfg, n: int, seed: int, *, n_scans: int, chunk: int, start_after_s: float = 0.0):
    """``(objects, unknown NORAD numbers, scenario, init seed)`` of a cloned population of ``n`` objects
    (the tuple :func:`~.run.build_scenario` returns): a seeded ``unknown_share`` of its debris unknown; the scans
    from ``start_after_s`` seconds after the catalogue's epoch (module docstring)."""
    ss = np.random.SeedSequence([int(seed), int(n), 1])
    pop_seed, sim_seed, init_seed = (int(s.generate_state(1)[0]) for s in ss.spawn(3))
    cat = load_catalogue()
    sc = simulate_clones(cat, n, make_radar(cfg), n_scans=n_scans, seed=sim_seed, clone_seed=pop_seed,
                         chunk=chunk, start=reference_epoch(cat) + pd.Timedelta(seconds=float(start_after_s)))
    pop = sc.catalogue
    debris = (pop["group"] != "active").to_numpy()
    unk = debris & (np.random.default_rng(pop_seed).random(len(pop)) < cfg["unknown_share"])
    return pop, np.sort(pop["norad"].to_numpy(np.int64)[unk]), sc, init_seed


def measure_run(cfg, tracker: str, n: int, seed: int) -> dict:
    """One run (module docstring) in this process; ``cfg`` the ``ssa_catalogue`` section."""
    s = cfg["scale"]
    load0 = os.getloadavg()[0]
    wall0 = time.perf_counter()
    after = float(s.get("start_after_s", 0.0))
    if not after >= 0:
        raise ValueError(f"scale.start_after_s must be >= 0 (seconds from the priors' epoch to the first scan), got {after}")
    objects, unknown, sc, init_seed = clone_scenario(cfg, n, seed, n_scans=s["n_scans"], chunk=s["chunk"],
                                                     start_after_s=after)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed, at=-after)  # the priors at the epoch
    motion, is_factored = make_motion(cfg), cfg["trackers"][tracker].get("factored") is not None
    clock = after if is_factored else 0.0
    if after and not is_factored:  # GNN/JPDA: their priors replayed to the first scan here, untimed (docstring)
        means, covs = predict_each(motion, means, covs, np.full(len(means), after), step=cfg["radar"]["revisit_s"])
    problem = make_problem(cfg, tsensor, motion, means, covs, labels)
    factored = s.get("factored") or {}
    kw = factored if is_factored else {}
    tr = make_tracker(tracker, cfg, problem, int(seed), **kw)
    in_view = sc.truth.groupby("scan").size()
    # the association samplers' compiled kernels loaded now, untimed: a tracker's first Gibbs or MCMC step may come
    # after the warm scans, and loading its kernels from numba's cache (~10 ms) would then be timed as a scan's work
    warm_samplers()
    warm_engine()  # the factored engine's kernels likewise (the birth band test is first called in a timed scan)
    warm = int(s.get("warm_scans", 1))
    if not 1 <= warm < s["n_scans"]:
        raise ValueError(f"scale.warm_scans must lie in [1, n_scans = {s['n_scans']}), got {warm}")
    cpu, view, returns, timed, per_scan = 0.0, 0, 0, 0, []
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        Zt = tsensor.returns(Z)
        c0 = time.process_time()
        tr.step(Zt, float(t_k) + clock)  # a factored tracker's clock from the priors' epoch
        c = time.process_time() - c0
        if k >= warm:  # scan 0 is at the priors' epoch (an update without prediction); first compiled calls
            cpu += c
            per_scan.append(c)
            view += int(in_view.get(k, 0))
            returns += len(Z)
            timed += 1
    if hasattr(tr, "close"):
        tr.close()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    sim_s = timed * cfg["radar"]["revisit_s"]
    return dict(tracker=tracker, n_objects=int(n), n_scans=timed, in_view_per_scan=view / max(timed, 1),
                returns_per_scan=returns / max(timed, 1), cpu_s=cpu, cpu_s_per_scan=cpu / max(timed, 1),
                us_per_object_in_view=1e6 * cpu / view if view else np.nan, us_per_object=1e6 * cpu / max(n * timed, 1),
                us_per_return=1e6 * cpu / returns if returns else np.nan, real_time_factor=sim_s / max(cpu, 1e-12),
                start_after_s=after, peak_rss_mb=rss,
                # the dearest timed scan over the median one: near 1, no start-up burst left in the timed scans
                slowest_scan_ratio=max(per_scan) / max(float(np.median(per_scan)), 1e-12) if per_scan else np.nan,
                wall_s=time.perf_counter() - wall0, load_before=load0, load_after=os.getloadavg()[0],
                blas_threads=os.environ.get("OPENBLAS_NUM_THREADS", "default"))


def _child():
    """Entry of :func:`run_isolated`'s process: a JSON request on stdin, the run's JSON on stdout."""
    req = json.load(sys.stdin)
    limit = req["cfg"]["scale"].get("memory_limit_gb")
    if limit is not None:  # an allocation past it fails with MemoryError (the run: failed) instead of the machine's OOM kill
        resource.setrlimit(resource.RLIMIT_AS, (int(float(limit) * 2**30), resource.RLIM_INFINITY))
    print(json.dumps(measure_run(req["cfg"], req["tracker"], req["n"], req["seed"])))


#: The child's environment: BLAS and OpenMP on one thread. The figures are of one core (the real-time factor is
#: simulated seconds per CPU second), and a multi-threaded BLAS spends CPU on nothing here: the tracker's large
#: products are (n, 3) by (3, 3), and on a shared machine the library's threads spin waiting for a core (measured:
#: a (10⁶, 3) @ (3, 3) product ~250 ms of CPU with two OpenBLAS threads on the loaded 2-core machine, ~3 ms on one).
ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def run_isolated(cfg, tracker: str, n: int, seed: int, timeout: float | None = None) -> dict | None:
    """:func:`measure_run` in a fresh Python process (its own peak memory; BLAS on one thread,
    :data:`ONE_THREAD`); ``None`` when it has not finished after ``timeout`` seconds of wall time (the process
    is killed); a failed run raises ``RuntimeError`` with the process's error output."""
    code = "from hypotrack.experiments.ssa_catalogue.scale import _child; _child()"
    try:
        res = subprocess.run([sys.executable, "-c", code], input=json.dumps(dict(cfg=cfg, tracker=tracker, n=int(n),
                                                                                 seed=int(seed))),
                             capture_output=True, text=True, env={**os.environ, **ONE_THREAD}, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None
    if res.returncode != 0:
        why = res.stderr.strip().splitlines()[-1] if res.stderr.strip() else f"killed by signal {-res.returncode}" \
            if res.returncode < 0 else f"exit status {res.returncode}"
        raise ScaleRunFailed(f"scale run {tracker} at N = {n} failed: {why}", why)
    return json.loads(res.stdout.strip().splitlines()[-1])


def scale_runs(cfg, seed: int, *, log=print) -> pd.DataFrame:
    """Every run of ``cfg["scale"]``: for each repetition, each size and each tracker (repetitions
    outermost, so that a change of the machine's load spreads over all); one row per run, its ``status``
    ``done``, ``timed_out`` (not finished within ``scale.timeout_s`` seconds of wall time, when set), ``failed``
    (the process ended with an error, ``error`` its reason) or
    ``skipped``: a tracker that timed out at N is not run again at N or above (a run there would only
    time out again), its figures NaN."""
    s = cfg["scale"]
    timeout = s.get("timeout_s")
    if timeout is not None and not float(timeout) > 0:
        raise ValueError(f"scale.timeout_s must be > 0 (seconds of wall time per run) or absent, got {timeout!r}")
    rows, gave_up = [], {}  # tracker -> the smallest N at which one of its runs timed out
    for rep in range(s["runs"]):
        for n in s["sizes"]:
            for name in s["trackers"]:
                if n >= gave_up.get(name, np.inf):
                    rows.append(dict(tracker=name, n_objects=int(n), run=rep, status="skipped"))
                    log(f"{name} N={n} run {rep}: skipped (stopped at N={gave_up[name]})")
                    continue
                load0 = os.getloadavg()[0]
                try:
                    r = run_isolated(cfg, name, n, seed, timeout=timeout)
                except ScaleRunFailed as e:  # e.g. out of memory: recorded, the tracker not run again at N or above
                    gave_up[name] = min(gave_up.get(name, np.inf), n)
                    rows.append(dict(tracker=name, n_objects=int(n), run=rep, status="failed", error=e.reason,
                                     load_before=load0, load_after=os.getloadavg()[0]))
                    log(f"{name} N={n} run {rep}: failed ({e.reason})")
                    continue
                if r is None:
                    gave_up[name] = min(gave_up.get(name, np.inf), n)
                    rows.append(dict(tracker=name, n_objects=int(n), run=rep, status="timed_out", load_before=load0,
                                     load_after=os.getloadavg()[0], wall_s=float(timeout)))
                    log(f"{name} N={n} run {rep}: not finished within {timeout} s of wall time")
                    continue
                r["run"], r["status"] = rep, "done"
                rows.append(r)
                log(f"{name} N={n} run {rep}: {r['us_per_object_in_view']:.1f} µs/object in view, RTF "
                    f"{r['real_time_factor']:.1f}, peak {r['peak_rss_mb']:.0f} MB, load {r['load_before']:.2f}")
    return pd.DataFrame(rows)


def scale_summary(runs: pd.DataFrame) -> pd.DataFrame:
    """Per (tracker, N): runs finished (``runs``), timed out and skipped, objects in view and returns per scan, and
    for each of :data:`FIGURES` the median, min and max over the finished runs (NaN when none finished); the mean load average; the runs' ``blas_threads``; per tracker ``slope_cpu_vs_n``, the
    least-squares slope of log median CPU per scan against log N (NaN with one size)."""
    out = []
    for (name, n), g_all in runs.groupby(["tracker", "n_objects"], sort=False):
        status = g_all["status"] if "status" in g_all else pd.Series("done", index=g_all.index)
        g = g_all[status == "done"]
        r = dict(tracker=name, n_objects=int(n), runs=len(g), runs_timed_out=int((status == "timed_out").sum()),
                 runs_failed=int((status == "failed").sum()),
                 runs_skipped=int((status == "skipped").sum()),
                 n_scans=int(g["n_scans"].iloc[0]) if len(g) else np.nan,
                 in_view_per_scan=g["in_view_per_scan"].iloc[0] if len(g) else np.nan,
                 returns_per_scan=g["returns_per_scan"].iloc[0] if len(g) else np.nan)
        for f in FIGURES:
            x = g[f] if f in g else pd.Series(dtype=float)
            r[f"{f}_median"], r[f"{f}_min"], r[f"{f}_max"] = x.median(), x.min(), x.max()
        if "start_after_s" in g:  # runs from before the harness recorded it started at the epoch
            r["start_after_s"] = float(g["start_after_s"].iloc[0]) if len(g) else np.nan
        ran = g_all[status != "skipped"]
        r["load_mean"] = float(np.mean(np.r_[ran["load_before"], ran["load_after"]])) if len(ran) else np.nan
        if "blas_threads" in g:  # runs from before the harness recorded it lack it
            r["blas_threads"] = "/".join(sorted(set(g["blas_threads"].dropna().astype(str))))
        out.append(r)
    table = pd.DataFrame(out)
    slopes = {}
    for name, g in table.groupby("tracker", sort=False):
        g = g[np.isfinite(g["cpu_s_per_scan_median"])]  # the sizes at which some run finished
        if g["n_objects"].nunique() > 1:
            slopes[name] = float(np.polyfit(np.log(g["n_objects"]), np.log(g["cpu_s_per_scan_median"]), 1)[0])
    table["slope_cpu_vs_n"] = table["tracker"].map(slopes).astype(float)
    return table

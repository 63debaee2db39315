"""The factored filter's engine steps and the pool that runs them (``workers``, ``parallel``).

A scan's components are independent problems: each is one engine step
(:meth:`~..filter.HypothesisFilter.advance`) of one group with the returns of its gate and its
birth terms — :func:`engine_step`, the unit of work. :class:`WorkerPool` runs a scan's steps here
(``workers = 1``) or split into ``workers`` contiguous chunks of similar cost (hypotheses ×
returns), the first run here and the others in a process or thread pool. Each step draws from its
own random stream and numbers its new labels from the scan's first free label, so the results do
not depend on where a step ran.
"""

from __future__ import annotations

import pickle
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np

from ..factored_groups import restrict_population

__all__ = ["engine_step", "run_jobs", "WorkerPool"]

_STEP_STATS = ("n_duplicates_merged", "mass_retained", "n_kalman_updates")


def engine_step(template, state, pred, ctx, regions, base, seed, light=0.0):
    """One group's engine step (the unit of work of a scan, run in any worker).

    ``template``: the filter's engine without hypotheses (models, population); ``state``: the
    group's hypotheses; ``pred``: its predicted tracks; ``ctx``: the returns of its gate and their
    scores; ``regions``: its birth terms; new labels count from ``base``; ``seed`` seeds the step's
    own random stream; ``light``: the mass below which a new store entry is left without moments (the pruning
    drops it, :func:`~..children.heavy_entries`; 0: every entry's). Returns ``(new state, track sources, number of
    new labels, stats)``.
    """
    engine = template.with_options(population=restrict_population(template.population, regions),
                                   seed=np.random.Generator(np.random.PCG64(seed)))
    result = engine.advance(state.with_next_label(base), pred, ctx, light)
    new = result.state.with_next_label(0)
    return new, result.sources, result.n_new_labels, {k: result.stats[k] for k in _STEP_STATS}


def run_jobs(template, jobs):
    """:func:`engine_step` of every job, in order."""
    return [engine_step(template, *job) for job in jobs]


def _warm_worker():
    """Initialise numba's typing and target contexts in this worker (done once per process)."""
    from numba.core.registry import cpu_target  # noqa: PLC0415 (only in a worker)

    cpu_target.typing_context.refresh()
    cpu_target.target_context.refresh()
    time.sleep(0.05)  # every worker gets a task


def _run_pickled(model, blob):
    """A process worker's chunk: the pickled template and jobs in, the pickled results and the
    worker's CPU seconds out."""
    t0 = time.process_time()
    out = run_jobs(pickle.loads(model), pickle.loads(blob))
    return pickle.dumps((out, time.process_time() - t0), protocol=pickle.HIGHEST_PROTOCOL)


def _size(obj) -> int:
    return len(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))


class WorkerPool:
    """Runs a scan's engine steps with ``workers`` processes or threads (``parallel``); the pool
    is started on first use and stopped by :meth:`close`."""

    def __init__(self):
        self._executor = None
        self._kind = None

    def run(self, template, jobs, options, stats) -> list:
        """The results of ``jobs`` (in order), recording ``n_jobs``, ``time_steps`` and, with a process
        pool or ``options.measure_transfer``, the bytes moved in ``stats``."""
        t0 = time.perf_counter()
        try:
            return self._run(template, jobs, options, stats)
        finally:
            stats["time_steps"] = time.perf_counter() - t0

    def _run(self, template, jobs, options, stats):
        stats["n_jobs"] = len(jobs)
        if options.workers == 1 or len(jobs) < 2:
            if options.measure_transfer:
                stats["bytes_to_workers"] = sum(_size(j) for j in jobs)
            out = run_jobs(template, jobs)
            if options.measure_transfer:
                stats["bytes_from_workers"] = sum(_size(r) for r in out)
            return out
        cost = np.array([len(j[0].log_w) * (j[2].n_returns + 1) for j in jobs], dtype=float)
        cuts = np.searchsorted(np.cumsum(cost), cost.sum() * np.arange(1, options.workers) / options.workers)
        chunks = [c for c in np.split(np.arange(len(jobs)), np.unique(cuts)) if len(c)]
        pool = self.executor(options)
        if options.parallel == "process":
            model = pickle.dumps(template, protocol=pickle.HIGHEST_PROTOCOL)
            blobs = [pickle.dumps([jobs[i] for i in c], protocol=pickle.HIGHEST_PROTOCOL) for c in chunks[1:]]
            futures = [pool.submit(_run_pickled, model, b) for b in blobs]
            stats["bytes_model"] = len(model) * len(blobs)
            stats["bytes_to_workers"] = sum(map(len, blobs))
        else:
            futures = [pool.submit(run_jobs, template, [jobs[i] for i in c]) for c in chunks[1:]]
        out = run_jobs(template, [jobs[i] for i in chunks[0]])
        for f in futures:
            r = f.result()
            if options.parallel == "process":
                stats["bytes_from_workers"] = stats.get("bytes_from_workers", 0) + len(r)
                r, cpu = pickle.loads(r)
                stats["worker_cpu_s"] = stats.get("worker_cpu_s", 0.0) + cpu
            out.extend(r)
        return out

    def executor(self, options):
        """The pool for ``options`` (``workers − 1`` workers of kind ``parallel``), started if needed;
        a pool of another size or kind is stopped first."""
        kind = (options.parallel, options.workers)
        if self._executor is not None and self._kind != kind:
            self.close()
        if self._executor is None:
            cls = ProcessPoolExecutor if options.parallel == "process" else ThreadPoolExecutor
            self._executor, self._kind = cls(max_workers=options.workers - 1), kind
        return self._executor

    def warm_up(self, options):
        """Start the workers now and set up numba's typing in each (about a second of CPU on a
        worker's first compiled call otherwise); no-op for ``workers = 1``."""
        if options.workers > 1:
            pool = self.executor(options)
            for f in [pool.submit(_warm_worker) for _ in range(options.workers - 1)]:
                f.result()

    def close(self):
        """Shut the pool down (a later parallel step starts a new one)."""
        if self._executor is not None:
            self._executor.shutdown()
            self._executor, self._kind = None, None

    def __getstate__(self):
        return {"_executor": None, "_kind": None}

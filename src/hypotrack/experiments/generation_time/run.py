"""Hypothesis-generation timing (document 000 Fig. 15) and throughput benchmarks.

:func:`generation_time_point` times one method generating the children of one synthetic parent
(:mod:`hypotrack.hypotheses.problems`) and records whether the true association was among them and its rank;
:func:`generation_time_sweep` runs the sweep M = m = 1..N (plus optional rectangular sizes) for
one method until its budget breaks it. :func:`mcmc_throughput`, :func:`exhaustive_throughput`
and :func:`exhaustive_memory` measure the engine's performance targets (proposals per
second, children per second, bounded memory).

Methods (the papers' pairing of weights and generator):

``homht``        Reid weights, exhaustive enumeration + weighting, best ``keep`` kept (streamed)
``rfisst``       H-FISST weights, MCMC search (document 000 Sec. III-B)
``homht_kbest``  Reid weights, Murty's ``keep`` best
"""

from __future__ import annotations

import math
import time
import tracemalloc

import numpy as np
import pandas as pd

from ..._validation import check_int
from ...association import EnumerationBudgetError, count_associations
from ...association.mcmc import mcmc_search
from ...hypotheses.generators import ExhaustiveGenerator, MCMCGenerator, MurtyGenerator
from ...hypotheses.problems import synthetic_problem, truth_rank
from ..stepping import best_time

__all__ = [
    "METHODS",
    "make_generator",
    "generation_time_point",
    "generation_time_sweep",
    "mcmc_throughput",
    "exhaustive_throughput",
    "exhaustive_memory",
    "throughput_table",
]

METHODS = {"homht": "reid", "rfisst": "hfisst", "homht_kbest": "reid"}


def make_generator(method: str, params: dict):
    """The child generator of a method from a config mapping (see the generation_time schema)."""
    if method == "homht":
        return ExhaustiveGenerator(max_events=int(params["exhaustive_max_events"]),
                                   chunk_size=int(params["exhaustive_chunk_size"]))
    if method == "rfisst":
        return MCMCGenerator(n_steps=int(params["mcmc_steps"]), burn_in=params.get("mcmc_burn_in"),
                             variant=params["mcmc_variant"], init=params["mcmc_init"],
                             completion_rounds=int(params["mcmc_completion_rounds"]))
    if method == "homht_kbest":
        return MurtyGenerator(k=int(params["keep"]))
    raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")


def generation_time_point(method, n_objects, n_returns, params, seed):
    """Time one method on one synthetic parent; a dict row of the Fig. 15 table.

    The problem is drawn from ``seed`` (the same problem for every method at a given size);
    the generator's own randomness comes from a stream derived from it. The time is the
    fastest of ``params["repeats"]`` runs of ``generate`` (problem construction excluded).
    """
    weights = METHODS[method]
    problem_seed, gen_seed = np.random.SeedSequence(seed).spawn(2)
    sp = synthetic_problem(n_objects, n_returns, np.random.default_rng(problem_seed), weights=weights,
                           p_D=params["p_D"], clutter_rate=params["clutter_rate"], spacing=params["spacing"])
    generator = make_generator(method, params)
    row = _row(method, n_objects, n_returns)
    from .difficulty import linear_assignment_event  # the negative control: one assignment, no search

    row["lsa_is_truth"] = bool(np.all(linear_assignment_event(sp.problem) == sp.truth))
    best = np.inf
    for _ in range(int(params["repeats"])):
        rng = np.random.default_rng(gen_seed)  # every repeat does the same work
        t0 = time.perf_counter()
        try:
            events, lw = generator.generate(sp.problem, rng, keep=int(params["keep"]))
        except EnumerationBudgetError:
            row["broken"] = True
            return row
        best = min(best, time.perf_counter() - t0)
    rank = truth_rank(events, lw, sp.truth)
    row.update(seconds=best, n_generated=len(lw), truth_found=rank is not None,
               truth_rank=np.nan if rank is None else rank, map_is_truth=rank == 1)
    return row


def _row(method, n_objects, n_returns, broken=False):
    return {"method": method, "n_objects": n_objects, "n_returns": n_returns,
            "log10_hypotheses": math.log10(count_associations(n_objects, n_returns)), "broken": broken,
            "seconds": np.nan, "n_generated": 0, "truth_found": False, "truth_rank": np.nan, "map_is_truth": False,
            "lsa_is_truth": np.nan}


def _sizes(params):
    """M = m = 1..max_size, then the larger square sizes ``beyond``, then ``rectangular`` pairs."""
    sizes = [(n, n) for n in range(1, int(params["max_size"]) + 1)]
    sizes += [(int(n), int(n)) for n in params.get("beyond", [])]
    sizes += [tuple(int(v) for v in pair) for pair in params.get("rectangular", [])]
    return sizes


def generation_time_sweep(method, params, seed, progress=print):
    """All sizes for one method; once the exhaustive budget breaks, larger sizes are skipped
    (recorded as broken) instead of being attempted."""
    rows = []
    limit = int(params.get("method_max_size", {}).get(method, 10**9))
    ss = np.random.SeedSequence(seed)
    generation_time_point(method, 2, 2, params, 0)  # compile / load the numba kernels before timing
    for (M, m) in _sizes(params):
        point_seed = int(np.random.SeedSequence([ss.entropy, M, m]).generate_state(1)[0])
        too_big = max(M, m) > limit
        broken_before = method == "homht" and any(
            r["broken"] and count_associations(M, m) >= 10 ** r["log10_hypotheses"] for r in rows)
        if too_big or broken_before:
            row = _row(method, M, m, broken=broken_before)
        else:
            row = generation_time_point(method, M, m, params, point_seed)
        rows.append(row)
        progress(f"[generation_time] {method:12s} M={M:3d} m={m:3d} log10A={row['log10_hypotheses']:7.2f} "
                 f"t={row['seconds']:.4g}s broken={row['broken']} truth_found={row['truth_found']}")
    return rows


def mcmc_throughput(n, n_steps=100_000, repeats=5, seed=0, variant="paper"):
    """Proposals per second of the compiled chain alone at M = m = ``n`` (best of ``repeats``)."""
    n = check_int(n, "n", minimum=1)
    sp = synthetic_problem(n, n, np.random.default_rng(seed), weights="hfisst")
    p = sp.problem
    mcmc_search(p.score, p.n_objects, p.n_exclusive, p.count_term, n_steps=10, seed=0, variant=variant)  # warm-up
    best = np.inf
    for r in range(repeats):
        t0 = time.perf_counter()
        mcmc_search(p.score, p.n_objects, p.n_exclusive, p.count_term, n_steps=n_steps, seed=r, variant=variant)
        best = min(best, time.perf_counter() - t0)
    return {"n_objects": n, "n_returns": n, "n_steps": n_steps, "seconds": best, "per_second": n_steps / best}


def exhaustive_throughput(n_objects, n_returns, repeats=3, seed=0, keep=None, chunk_size=1 << 20):
    """Children enumerated *and* weighted per second (best of ``repeats``).

    ``keep=None`` materialises every child with its weight; ``keep=k`` streams blocks and keeps
    the best ``k`` (the bounded-memory mode HOMHT uses in the Fig. 15 sweep).
    """
    sp = synthetic_problem(n_objects, n_returns, np.random.default_rng(seed), weights="reid")
    gen = ExhaustiveGenerator(max_events=10**9, chunk_size=chunk_size)
    gen.generate(synthetic_problem(2, 2, np.random.default_rng(0), weights="reid").problem)  # warm-up
    _, best = best_time(lambda: gen.generate(sp.problem, keep=keep), repeats)
    A = count_associations(n_objects, n_returns)
    return {"n_objects": n_objects, "n_returns": n_returns, "children": A, "mode": "all" if keep is None else f"top{keep}",
            "seconds": best, "per_second": A / best}


def exhaustive_memory(n_objects, n_returns, max_events, chunk_size=1 << 18, keep=100, seed=0):
    """Peak traced memory of one exhaustive generation, or the budget error it raises instead.

    Returns a dict with ``peak_bytes`` (``tracemalloc``), ``seconds`` and ``outcome`` —
    ``"ok"`` or the :class:`EnumerationBudgetError` message (raised before any allocation).
    """
    sp = synthetic_problem(n_objects, n_returns, np.random.default_rng(seed), weights="reid")
    gen = ExhaustiveGenerator(max_events=max_events, chunk_size=chunk_size)
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        gen.generate(sp.problem, keep=keep)
        outcome = "ok"
    except EnumerationBudgetError as err:
        outcome = str(err)
    seconds = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return {"n_objects": n_objects, "n_returns": n_returns, "children": count_associations(n_objects, n_returns),
            "max_events": max_events, "chunk_size": chunk_size, "peak_bytes": peak, "seconds": seconds,
            "outcome": outcome}


def throughput_table(params, progress=print):
    """The engine's performance table against its targets: MCMC proposals/s, exhaustive children/s, bounded memory.

    Rows: one per MCMC variant at M = m = ``mcmc_size``; exhaustive enumeration + weighting at
    each of ``exhaustive_sizes`` (every child materialised, and streamed keeping the best 100);
    the peak memory of a streamed generation at ``memory_size``; and the budget error raised for
    ``budget_size`` (far more events than ``max_events``) with the time it took to refuse.
    """
    targets = params["targets"]
    repeats = int(params["repeats"])
    rows = []
    for variant in params["mcmc_variants"]:
        r = mcmc_throughput(int(params["mcmc_size"]), int(params["mcmc_steps"]), repeats=repeats, variant=variant)
        rows.append({"benchmark": "mcmc", "label": f"MCMC '{variant}', M = m = {r['n_objects']}, {r['n_steps']:,} steps",
                     "variant": variant, "n_objects": r["n_objects"], "n_returns": r["n_returns"],
                     "work": r["n_steps"], "seconds": r["seconds"], "per_second": r["per_second"],
                     "target_per_second": targets["mcmc_per_second"] if variant == "paper" else np.nan})
        progress(f"[perf_hypotheses] {rows[-1]['label']}: {r['per_second']:.3g} proposals/s")
    for n in params["exhaustive_sizes"]:
        for keep in (None, 100):
            r = exhaustive_throughput(int(n), int(n), repeats=repeats, keep=keep)
            mode = "every child" if keep is None else "streamed, best 100 kept"
            rows.append({"benchmark": "exhaustive", "label": f"exhaustive, M = m = {n} ({mode})", "variant": r["mode"],
                         "n_objects": n, "n_returns": n, "work": r["children"], "seconds": r["seconds"],
                         "per_second": r["per_second"], "target_per_second": targets["exhaustive_per_second"]})
            progress(f"[perf_hypotheses] {rows[-1]['label']}: {r['per_second']:.3g} children/s")
    for n, budget in ((int(params["memory_size"]), int(params["max_events"])),
                      (int(params["budget_size"]), int(params["max_events"]))):
        r = exhaustive_memory(n, n, budget, chunk_size=int(params["memory_chunk_size"]))
        rows.append({"benchmark": "memory", "label": f"exhaustive memory, M = m = {n}, budget {budget:.0e}",
                     "variant": r["outcome"], "n_objects": n, "n_returns": n, "work": r["children"],
                     "seconds": r["seconds"], "per_second": np.nan, "target_per_second": np.nan,
                     "peak_bytes": r["peak_bytes"]})
        progress(f"[perf_hypotheses] {rows[-1]['label']}: peak {r['peak_bytes'] / 2**20:.1f} MiB, {r['outcome'][:60]}")
    table = pd.DataFrame(rows)
    has_target = table["target_per_second"].notna()
    table["meets_target"] = (table["per_second"] >= table["target_per_second"]).astype(object).where(has_target, "")
    return table



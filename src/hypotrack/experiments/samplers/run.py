"""R-FISST's chain, the GLMB Gibbs sampler and Murty's ranked assignment on identical problems.

Each problem is one parent's association problem of the difficulty axis of
:mod:`hypotrack.hypotheses.problems` (``M`` objects ``1σ … 8σ`` apart, ``p_D = 0.9``, Poisson
clutter) under Reid's / FISST-Poisson weights, whose count term is constant — the weight under
which R-FISST's return-indexed search and the GLMB's object-indexed Gibbs sampler target the
*same* posterior (:func:`object_indexed` writes the one problem both ways; the events map one to
one). Per budget ``B`` (proposals):

* ``rfisst_chain`` — document 000's proposal, ``B`` steps, the chain alone (``completion_rounds = 0``);
* ``rfisst_completion`` — the same chain plus the neighbour completion (2 rounds);
* ``gibbs`` — Vo, Vo & Hoang's systematic scan over objects, ``⌈B / M⌉`` sweeps (``B`` conditional draws);
* ``murty`` — the ``⌈B / M⌉`` best events (one ranked assignment per full event, like one sweep).

Measured: posterior mass captured by the distinct children found (exact: the exhaustive total),
whether the MAP child is found, distinct children per second, wall time. One more difficulty,
``recorded``, holds association problems recorded from the GLMB benchmark's scans
(:mod:`.recorded`), where all four samplers run on the δ-GLMB's own object-indexed problem.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pandas as pd

from ...hypotheses import AssociationProblem, ExhaustiveGenerator, GibbsGenerator, MCMCGenerator, MurtyGenerator
from ...hypotheses.problems import synthetic_problem
from ...hypotheses.warm import warm_samplers
from .recorded import run_recorded_problem

__all__ = ["object_indexed", "to_return_indexed", "SAMPLERS", "run_problem", "timed_run", "samplers_sweep", "summarise"]

SAMPLERS = ("rfisst_chain", "rfisst_completion", "gibbs", "murty")


def object_indexed(problem: AssociationProblem) -> AssociationProblem:
    """The same children with the objects as rows (the GLMB form): row ``j``, column ``i`` scores
    "object ``j`` made return ``i``" relative to return ``i`` being clutter; row option 0 is
    "missed". Needs a constant count term, clutter as the only row option and no birth column."""
    if not problem.count_term_is_constant or problem.n_options != 1 or problem.n_birth_columns:
        raise ValueError("object_indexed needs a constant count term, one row option (clutter) and no births")
    M, m = problem.n_objects, problem.n_returns
    clutter = problem.option_scores[:, 0]
    return AssociationProblem(
        target_scores=(problem.target_scores - clutter[:, None]).T.reshape(M, m),
        option_scores=np.zeros((M, 1)), n_objects=m, count_term=np.zeros((m + 1, 1)),
        constant=problem.constant + float(clutter.sum()) + float(problem.count_term.flat[0]),
    )


def to_return_indexed(gammas, n_returns: int) -> np.ndarray:
    """Object-indexed events (E, M) → return-indexed events (E, m) (clutter −1)."""
    gammas = np.asarray(gammas, dtype=np.int64).reshape(len(gammas), -1)
    ev = np.full((len(gammas), n_returns), -1, dtype=np.int32)
    rows, objs = np.nonzero(gammas >= 0)
    ev[rows, gammas[rows, objs]] = objs
    return ev


def _run(name, problem, obj_problem, budget, rng):
    M = max(problem.n_objects, 1)
    per_event = math.ceil(budget / M)
    if name.startswith("rfisst"):
        gen = MCMCGenerator(n_steps=budget, completion_rounds=0 if name == "rfisst_chain" else 2)
        return gen.generate(problem, rng)
    if name == "gibbs":
        g, lw = GibbsGenerator(n_sweeps=per_event).generate(obj_problem, rng)
    else:
        g, lw = MurtyGenerator(k=per_event).generate(obj_problem)
    return to_return_indexed(g, problem.n_returns), lw


def timed_run(fn, rng):
    """``fn(rng)`` -> (events, log-weights); returns them with the wall time. Short runs (< 50 ms)
    are timed twice more on side streams and the least time kept (shared CPU); the results and the
    main stream are those of the first run, so the tables stay deterministic."""
    t0 = time.perf_counter()
    ev, lw = fn(rng)
    dt = time.perf_counter() - t0
    if dt < 0.05:
        for rep in range(2):
            t0 = time.perf_counter()
            fn(np.random.default_rng(rep))
            dt = min(dt, time.perf_counter() - t0)
    return ev, lw, dt


def run_problem(sp, budgets, rng) -> list:
    """Rows (sampler, budget, mass captured, MAP found, distinct children, time) for one problem."""
    problem = sp.problem
    obj_problem = object_indexed(problem)
    ev_all, lw_all = ExhaustiveGenerator().generate(problem)
    log_total = np.logaddexp.reduce(lw_all)
    map_key = ev_all[np.argmax(lw_all)].astype(np.int32).tobytes()
    rows = []
    for budget in budgets:
        for name in SAMPLERS:
            ev, lw, dt = timed_run(lambda r, name=name, b=int(budget): _run(name, problem, obj_problem, b, r), rng)
            keys = {e.astype(np.int32).tobytes() for e in ev}
            rows.append({"sampler": name, "budget": int(budget), "n_children_total": len(lw_all),
                         "mass_captured": float(np.exp(np.logaddexp.reduce(lw) - log_total)) if len(lw) else 0.0,
                         "map_found": map_key in keys, "n_distinct": len(keys), "time_s": dt})
    return rows


def samplers_sweep(cfg, seed_seq, recorded=None) -> pd.DataFrame:
    """Every difficulty × problem × budget × sampler; one seed stream per difficulty. ``recorded``
    (problems recorded from the GLMB benchmark, :mod:`.recorded`) adds the difficulty
    ``recorded`` with ``cfg["recorded"]``'s ``max_events`` and ``reference_k``."""
    warm_samplers()  # every sampler's kernels compiled once, so the first timed problem does not pay for it
    parts = []
    streams = seed_seq.spawn(len(cfg["difficulties"]) + 1)
    for difficulty, ss in zip(cfg["difficulties"], streams[:-1]):
        for p, child in enumerate(ss.spawn(cfg["n_problems"])):
            prob_seed, run_seed = child.spawn(2)
            sp = synthetic_problem(cfg["n_objects"], difficulty=difficulty, rng=np.random.default_rng(prob_seed),
                                   weights="reid")
            print(f"samplers {difficulty} problem {p}: M = {cfg['n_objects']}, m = {sp.problem.n_returns}", flush=True)
            rows = run_problem(sp, cfg["budgets"], np.random.default_rng(run_seed))
            parts.append(pd.DataFrame(rows).assign(difficulty=difficulty, problem=p, n_returns=sp.problem.n_returns,
                                                   mass_exact=True))
    if recorded:
        rec_cfg = cfg["recorded"]
        for p, (problem, child) in enumerate(zip(recorded, streams[-1].spawn(len(recorded)))):
            print(f"samplers recorded problem {p}: {problem.n_returns} rows, {problem.n_exclusive} returns",
                  flush=True)
            rows = run_recorded_problem(problem, cfg["budgets"], np.random.default_rng(child),
                                        max_events=int(rec_cfg["max_events"]), reference_k=int(rec_cfg["reference_k"]),
                                        timed_run=timed_run)
            parts.append(pd.DataFrame(rows).assign(difficulty="recorded", problem=p, n_returns=problem.n_exclusive))
    return pd.concat(parts, ignore_index=True)


def summarise(raw: pd.DataFrame):
    """Per difficulty × sampler × budget: mean mass captured (± s.e.), MAP found rate, mean
    distinct children. Returns (deterministic table, timing table with children per second)."""
    keys = ["difficulty", "sampler", "budget"]
    if "mass_exact" not in raw:
        raw = raw.assign(mass_exact=True)
    g = raw.groupby(keys, sort=False)
    det = g.agg(n_problems=("problem", "size"), mass_mean=("mass_captured", "mean"),
                mass_se=("mass_captured", lambda x: x.std(ddof=1) / np.sqrt(len(x)) if len(x) > 1 else np.nan),
                map_found=("map_found", "mean"), distinct_mean=("n_distinct", "mean"),
                mass_exact=("mass_exact", "all")).reset_index()
    timing = g.agg(time_mean_s=("time_s", "mean"), distinct_mean=("n_distinct", "mean")).reset_index()
    timing["children_per_s"] = timing.distinct_mean / timing.time_mean_s
    return det, timing

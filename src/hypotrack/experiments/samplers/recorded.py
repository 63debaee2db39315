"""The samplers on association problems recorded from the GLMB benchmark's scans.

The problems are the δ-GLMB tracker's own, recorded by the ``glmb_benchmark_record`` rule
(:mod:`hypotrack.experiments.glmb_benchmark.recorded`, which saves and loads them); this module
only scores the samplers on them. All four samplers of :mod:`.run` run on the *same* matrix:
R-FISST's chain and completion move one row at a time (here a row is an object, the event space of
the δ-GLMB joint prediction–update), the Gibbs sampler sweeps the rows, Murty ranks whole events.
Budgets are proposals as in :mod:`.run` (chain steps; ``⌈B / rows⌉`` Gibbs sweeps or
Murty events). Mass captured is exact when the problem has at most ``max_events`` children;
beyond, it is relative to a reference: the union of Murty's ``reference_k`` best children and
every child any sampler found (a lower bound of the total, so the fractions are upper bounds).
"""

from __future__ import annotations

import numpy as np

from ...association.enumeration import EnumerationBudgetError
from ...hypotheses import AssociationProblem, ExhaustiveGenerator, GibbsGenerator, MCMCGenerator, MurtyGenerator

__all__ = ["run_recorded_problem"]


def _keys(ev) -> set:
    return {e.tobytes() for e in np.asarray(ev, dtype=np.int32).reshape(len(ev), -1)}


def run_recorded_problem(problem: AssociationProblem, budgets, rng, *, max_events: int, reference_k: int,
                         timed_run) -> list:
    """Rows as :func:`.run.run_problem` for one recorded problem; ``timed_run(make, rng)`` runs
    a sampler (``make()`` returns its events and log-weights) and returns (events, log-weights, seconds)."""
    rows_per_event = max(problem.n_returns, 1)
    makers = {
        "rfisst_chain": lambda b, r: MCMCGenerator(n_steps=b, completion_rounds=0).generate(problem, r),
        "rfisst_completion": lambda b, r: MCMCGenerator(n_steps=b, completion_rounds=2).generate(problem, r),
        "gibbs": lambda b, r: GibbsGenerator(n_sweeps=-(-b // rows_per_event)).generate(problem, r),
        "murty": lambda b, r: MurtyGenerator(k=-(-b // rows_per_event)).generate(problem),
    }
    found = []
    for budget in budgets:
        for name, make in makers.items():
            ev, lw, dt = timed_run(lambda r, make=make, b=int(budget): make(b, r), rng)
            found.append((name, int(budget), _keys(ev), ev, np.asarray(lw, dtype=float), dt))
    try:
        ev_all, lw_all = ExhaustiveGenerator(max_events=max_events).generate(problem)
        exact = True
    except EnumerationBudgetError:
        ev_ref, lw_ref = MurtyGenerator(k=reference_k).generate(problem)
        pool = {}
        for ev, lw in [(ev_ref, lw_ref)] + [(f[3], f[4]) for f in found]:
            for e, w in zip(np.asarray(ev, dtype=np.int32).reshape(len(lw), -1), lw):
                pool[e.tobytes()] = w
        ev_all = np.array([np.frombuffer(k, dtype=np.int32) for k in pool])
        lw_all = np.array(list(pool.values()))
        exact = False
    log_total = np.logaddexp.reduce(lw_all)
    map_key = np.asarray(ev_all[np.argmax(lw_all)], dtype=np.int32).tobytes()
    rows = []
    for name, budget, keys, _, lw, dt in found:
        rows.append({"sampler": name, "budget": budget, "n_children_total": len(lw_all),
                     "mass_captured": float(np.exp(np.logaddexp.reduce(lw) - log_total)) if len(lw) else 0.0,
                     "map_found": map_key in keys, "n_distinct": len(keys), "time_s": dt, "mass_exact": exact})
    return rows

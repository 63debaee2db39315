"""Association problems recorded from the benchmark's scans, for the sampler head-to-head (rule
``glmb_benchmark_record``; the ``samplers`` rule reads the file).

One seeded realisation of the benchmark (:mod:`.run`) is run by the δ-GLMB tracker; every time
the engine builds a parent's association problem (the object-indexed labeled problem of
:meth:`GLMBWeights.labeled_problem`: one row per track and birth term, a column per return, row
options "missed" and "died / not born"), it is recorded as built. Per scan the problem with the
most children is kept, and the ``n_problems`` scans with the most children are saved
(:func:`save_problems`; :func:`load_problems` reads them back). How the samplers score them is
:mod:`hypotrack.experiments.samplers.recorded`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...association.counting import count_gated_associations
from ...hypotheses import AssociationProblem
from .run import benchmark_model, make_tracker, simulate_scans, truth_states

__all__ = ["RecordingGenerator", "record_problems", "save_problems", "load_problems", "n_children"]


class RecordingGenerator:
    """Wraps the tracker's child generator; keeps every problem it is given, tagged with the scan."""

    def __init__(self, inner):
        self.inner = inner
        self.name = getattr(inner, "name", "recording")
        self.scan = 0
        self.problems: list[tuple[int, AssociationProblem]] = []

    def generate(self, problem, rng=None, keep=None):
        self.problems.append((self.scan, problem))
        return self.inner.generate(problem, rng, keep=keep)


def n_children(problem: AssociationProblem, cap: int | None = None) -> int:
    """Number of children of a problem (exact up to ``cap``): gated exclusive columns plus, per row,
    its second row option as a private column (the enumerator's own convention)."""
    allowed = problem.allowed
    if problem.n_options > 1:
        allowed = np.hstack([allowed, np.diag(np.isfinite(problem.option_scores[:, 1]))])
    return count_gated_associations(allowed, cap=cap)


def record_problems(cfg, tracker_options: dict, seed_seq, n_problems: int, cap: int | None = None):
    """Run the ``glmb`` tracker on one realisation; returns (problems, table) of the ``n_problems``
    scans whose largest problem has the most children (ties: earlier scan), in scan order."""
    model = benchmark_model(cfg)
    truth = truth_states(cfg["truth"], model.n_scans)
    scan_seed, tracker_seed = seed_seq.spawn(2)
    scans = simulate_scans(model, truth, np.random.default_rng(scan_seed))
    tracker = make_tracker("glmb", model, tracker_options, np.random.default_rng(tracker_seed))
    rec = RecordingGenerator(tracker.generator)
    tracker.generator = rec
    for k, Z in enumerate(scans, start=1):
        rec.scan = k
        tracker.step(Z)
    best: dict[int, tuple[int, AssociationProblem]] = {}
    for k, p in rec.problems:
        c = n_children(p, cap)
        if k not in best or c > best[k][0]:
            best[k] = (c, p)
    order = sorted(best, key=lambda k: (-best[k][0], k))[:n_problems]
    chosen = sorted(order)
    rows = [{"problem": i, "scan": k, "n_rows": best[k][1].n_returns, "n_returns": best[k][1].n_exclusive,
             "n_children": best[k][0], "n_children_exact": cap is None or best[k][0] <= cap} for i, k in enumerate(chosen)]
    return [best[k][1] for k in chosen], pd.DataFrame(rows)


def save_problems(problems, path):
    """One ``.npz`` holding every problem's arrays (``p{i}_target``, ``p{i}_options``, ``p{i}_count``, ``p{i}_meta``)."""
    arrays = {}
    for i, p in enumerate(problems):
        arrays[f"p{i}_target"] = p.target_scores
        arrays[f"p{i}_options"] = p.option_scores
        arrays[f"p{i}_count"] = p.count_term
        arrays[f"p{i}_meta"] = np.array([p.n_objects, p.constant])
    np.savez_compressed(path, n_problems=np.array(len(problems)), **arrays)


def load_problems(path) -> list[AssociationProblem]:
    with np.load(path) as f:
        return [AssociationProblem(f[f"p{i}_target"], f[f"p{i}_options"], int(f[f"p{i}_meta"][0]),
                                   f[f"p{i}_count"], float(f[f"p{i}_meta"][1])) for i in range(int(f["n_problems"]))]


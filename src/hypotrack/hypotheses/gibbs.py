"""The Gibbs child generator of the δ-GLMB filter (Vo, Vo & Hoang 2017, Sec. IV, Algorithm 1).

An adapter: :class:`GibbsGenerator` runs the systematic-scan Gibbs sweeps of
:mod:`hypotrack.association.samplers.gibbs` on an :class:`~.AssociationProblem` whose rows are the
objects (:mod:`.weights_glmb`). One sample is a sweep over the rows in order, each row redrawn from
its exact conditional given all the others' current values — every row option (missed, died) and
every return not held by another row — from the published start "every object missed" (row
option 0; the start is the first sample). The distinct samples are returned with their **exact**
weights (the sample frequencies are not used), so the generator is a search like R-FISST's chain
(DESIGN.md §4.3), and its children are a subset of the exhaustive ones.

The conditional is computed for any count term ``φ`` (its change enters the conditional), so
the sampler runs on any :class:`~.AssociationProblem`; on the GLMB problem ``φ`` is constant and
the conditional is the row's ``η`` over the free columns, as published.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int
from ..association.samplers import checked_sweep_search
from .association_problem import AssociationProblem
from .generators import ChildGenerator, top_k

__all__ = ["GibbsGenerator", "gibbs_search"]


def gibbs_search(problem: AssociationProblem, n_sweeps: int, seed: int):
    """The distinct samples of ``n_sweeps`` systematic-scan Gibbs sweeps from the all-option-0
    start (the start included), in public event codes, with exact log-weights (first-visit order)."""
    n_sweeps = check_int(n_sweeps, "n_sweeps", minimum=0)
    if problem.n_returns and not np.all(np.isfinite(problem.option_scores[:, 0])):
        raise ValueError("row option 0 must be finite for every row: it is the sampler's starting point")
    events, lw = checked_sweep_search(*problem.checked, n_sweeps=n_sweeps, seed=seed)
    return events, problem.constant + lw  # problem.log_weights(events): the exact gather-sum, bytewise


@dataclass(frozen=True)
class GibbsGenerator(ChildGenerator):
    """The distinct samples of ``n_sweeps`` systematic Gibbs sweeps, weighted exactly.

    Parameters
    ----------
    n_sweeps : int
        Samples per parent (each a sweep over all rows: ``n_sweeps × rows`` conditional draws), at
        least 1: with none, every child is the all-missed start and no measurement is ever used.
    """

    n_sweeps: int = 1000
    name = "gibbs"

    def __post_init__(self):
        check_int(self.n_sweeps, "n_sweeps", minimum=1)

    def generate(self, problem, rng=None, keep=None):
        rng = np.random.default_rng(rng)
        events, lw = gibbs_search(problem, self.n_sweeps, int(rng.integers(2**31 - 1)))
        ok = np.isfinite(lw)
        events, lw = events[ok], lw[ok]
        sel = top_k(lw, keep)
        return events[sel].astype(np.int32), lw[sel]

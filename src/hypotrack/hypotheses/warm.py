"""The association samplers' and JPDA's compiled kernels loaded (or compiled) now, on three-object problems; the
factored engine's catalogue kernels by :func:`~.warm_factored.warm_engine` (re-exported here).

A timed loop calls this first when a tracker's first Gibbs, MCMC or ranked-assignment step may fall inside a timed
scan: numba loads a kernel from its cache on the kernel's first call in a process (~10 ms for the Gibbs sampler's
two), or compiles it when the cache is cold (seconds), a cost of the process's start and not of the scan.
"""

from __future__ import annotations

import numpy as np

from ..association.lbp import lbp_marginals
from ..association.marginals import jpda_marginals
from .generators import MCMCGenerator, MurtyGenerator
from .gibbs import GibbsGenerator
from .problems import synthetic_problem
from .warm_factored import warm_engine

__all__ = ["warm_engine", "warm_samplers"]


def warm_samplers() -> None:
    """Run R-FISST's chain with its neighbour completion, the Gibbs sampler and Murty's ranking once each on a
    seeded three-object problem (Reid's weights), and JPDA's exact and loopy-belief-propagation marginals on a
    three-track cluster, discarding the results."""
    problem = synthetic_problem(3, difficulty="2sigma", seed=0, weights="reid").problem
    rng = np.random.default_rng(0)
    MCMCGenerator(n_steps=10, completion_rounds=2).generate(problem, rng)
    GibbsGenerator(n_sweeps=4).generate(problem, rng)
    MurtyGenerator(k=4).generate(problem)
    log_weights = np.log([[0.1, 0.5, 0.3, 0.1], [0.2, 0.2, 0.5, 0.1], [0.1, 0.1, 0.3, 0.5]])  # column 0: missed
    jpda_marginals(log_weights)
    lbp_marginals(log_weights)

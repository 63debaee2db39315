"""The association samplers' compiled kernels loaded (or compiled) now, on a three-object problem.

A timed loop calls this first when a tracker's first Gibbs, MCMC or ranked-assignment step may fall inside a timed
scan: numba loads a kernel from its cache on the kernel's first call in a process (~10 ms for the Gibbs sampler's
two), a cost of the process's start and not of the scan.
"""

from __future__ import annotations

import numpy as np

from .generators import MCMCGenerator, MurtyGenerator
from .gibbs import GibbsGenerator
from .problems import synthetic_problem

__all__ = ["warm_samplers"]


def warm_samplers() -> None:
    """Run R-FISST's chain with its neighbour completion, the Gibbs sampler and Murty's ranking once each on a
    seeded three-object problem (Reid's weights), discarding the results."""
    problem = synthetic_problem(3, difficulty="2sigma", seed=0, weights="reid").problem
    rng = np.random.default_rng(0)
    MCMCGenerator(n_steps=10, completion_rounds=2).generate(problem, rng)
    GibbsGenerator(n_sweeps=4).generate(problem, rng)
    MurtyGenerator(k=4).generate(problem)

"""Seed streams of the experiments: one master seed, independent children per experiment and shard."""

from __future__ import annotations

import zlib

import numpy as np

from .._validation import check_int

__all__ = ["experiment_seeds"]


def experiment_seeds(seed: int, experiment: str, n: int) -> list:
    """``n`` independent child seed sequences of the master ``seed`` for one experiment.

    The experiment name is folded into the entropy so that experiments sharing the master seed
    draw independent streams; child ``i`` (one per shard or per grid point) is stable whatever
    the other children are used for.
    """
    seed = check_int(seed, "seed", minimum=0)
    n = check_int(n, "n", minimum=1)
    return np.random.SeedSequence([seed, zlib.crc32(experiment.encode())]).spawn(n)

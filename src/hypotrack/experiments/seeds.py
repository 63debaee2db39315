"""Seed streams and shards of the experiments: one master seed, independent children per experiment and
shard, and how many Monte Carlo runs each shard takes."""

from __future__ import annotations

import zlib

import numpy as np

from .._validation import check_int

__all__ = ["experiment_seeds", "shard_runs"]


def experiment_seeds(seed: int, experiment: str, n: int) -> list:
    """``n`` independent child seed sequences of the master ``seed`` for one experiment.

    The experiment name is folded into the entropy so that experiments sharing the master seed
    draw independent streams; child ``i`` (one per shard or per grid point) is stable whatever
    the other children are used for.
    """
    seed = check_int(seed, "seed", minimum=0)
    n = check_int(n, "n", minimum=1)
    return np.random.SeedSequence([seed, zlib.crc32(experiment.encode())]).spawn(n)


def shard_runs(n_runs: int, n_shards: int, shard: int) -> int:
    """Number of Monte Carlo runs of shard ``shard`` when ``n_runs`` are split over ``n_shards``."""
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    n_shards = check_int(n_shards, "n_shards", minimum=1, maximum=n_runs)
    shard = check_int(shard, "shard", minimum=0, maximum=n_shards - 1)
    return n_runs // n_shards + (1 if shard < n_runs % n_shards else 0)

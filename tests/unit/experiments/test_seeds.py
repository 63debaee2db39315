"""The experiments' shared seeds module: shard sizes."""

from __future__ import annotations

import pytest

from hypotrack.experiments.seeds import shard_runs


@pytest.mark.parametrize("n_runs, n_shards", [(10, 3), (7, 7), (100, 8), (1, 1)])
def test_shards_split_the_runs_as_evenly_as_possible(n_runs, n_shards):
    sizes = [shard_runs(n_runs, n_shards, s) for s in range(n_shards)]
    assert sum(sizes) == n_runs
    assert max(sizes) - min(sizes) <= 1 and sizes == sorted(sizes, reverse=True)  # the first shards take the rest


def test_shard_arguments_are_checked():
    with pytest.raises(ValueError):
        shard_runs(3, 4, 0)  # more shards than runs
    with pytest.raises(ValueError):
        shard_runs(10, 3, 3)  # shard out of range

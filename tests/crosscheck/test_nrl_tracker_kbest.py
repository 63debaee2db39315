"""Murty's k best (hypotrack.association.murty_k_best) against nrl-tracker's (pytcl, a Python port of the
NRL Tracker Component Library; a test extra): the same k best sums on the same costs, square and
rectangular, with ties. Skipped when nrl-tracker is not installed."""

import itertools
import math

import numpy as np
import pytest

from hypotrack.association.assignment import murty_k_best
from hypotrack.experiments.williams2015.kbest import kbest_benchmark

kbest = pytest.importorskip("pytcl.assignment_algorithms.two_dimensional.kbest")


@pytest.mark.parametrize("shape,k,seed", [((3, 3), 6, 0), ((4, 6), 20, 1), ((8, 8), 25, 2), ((20, 25), 25, 3),
                                          ((50, 50), 25, 4)])
def test_same_k_best_sums(shape, k, seed):
    C = np.random.default_rng(seed).uniform(0, 100, shape)
    ours = np.array([-s for s, _ in murty_k_best(-C, k)])
    peer = kbest.murty(C, k)
    assert peer.n_found == len(ours) == min(k, _n_assignments(*shape))
    np.testing.assert_allclose(peer.costs, ours, rtol=0, atol=1e-9)


def _n_assignments(m, n):
    return math.perm(n, m)


def test_same_sums_with_ties_and_brute_force():
    """Integer costs (many equal sums): both give the multiset of the k smallest of all 4! sums."""
    C = np.array([[1, 2, 2, 3], [2, 1, 3, 2], [2, 3, 1, 2], [3, 2, 2, 1]], dtype=float)
    every = sorted(sum(C[i, p[i]] for i in range(4)) for p in itertools.permutations(range(4)))
    ours = [-s for s, _ in murty_k_best(-C, 10)]
    peer = list(kbest.murty(C, 10).costs)
    assert ours == every[:10] == peer


def test_benchmark_rows_agree():
    table = kbest_benchmark(10, 5, 2, 1, np.random.default_rng(0), target_ms=1e9)
    assert table.same_k_best_sums.all() and (table.n_found == 5).all()
    assert (table.max_abs_sum_difference < 1e-9).all() and table.target_met.all()

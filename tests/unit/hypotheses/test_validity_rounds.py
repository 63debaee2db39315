"""The validity test's visit (:func:`hypotrack.hypotheses.validity.valid_top_k`) against the one-child-at-a-time
visit it replaces (the reference below: each child's new pairs updated and tested when the child is reached):
the same children kept, in the same order, the same number rejected, every pair tested once — on random child
sets with shared pairs, rejection streaks, ``−inf`` keys and caps from 1 to past the number of children; and the
rounds: one batch per rejection streak, not one per child."""

import numpy as np
import pytest

from hypotrack.hypotheses.validity import valid_top_k


def _one_by_one(keys, k, pairs_of, moments_of, validity):
    keys = np.asarray(keys, dtype=float)
    order = np.argsort(-keys, kind="stable")
    verdict, sel, n_invalid = {}, [], 0
    for c in order:
        if len(sel) == k or not np.isfinite(keys[c]):
            break
        pairs = pairs_of(int(c))
        new = list(dict.fromkeys(p for p in pairs if p not in verdict))
        if new:
            means, _ = moments_of(np.array([p[0] for p in new]), np.array([p[1] for p in new]))
            verdict.update(zip(new, np.asarray(validity(means), dtype=bool).tolist()))
        if all(verdict[p] for p in pairs):
            sel.append(int(c))
        else:
            n_invalid += 1
    return np.asarray(sel, dtype=np.int64), n_invalid


class Counting:
    """Pairs ``(source, return)`` with a fixed verdict each (its "mean" is ±1); counts calls and pairs tested."""

    def __init__(self, bad):
        self.bad, self.calls, self.tested = bad, 0, []

    def moments_of(self, src, ret):
        self.calls += 1
        self.tested += list(zip(src.tolist(), ret.tolist()))
        means = np.array([[-1.0 if (s, r) in self.bad else 1.0] for s, r in zip(src, ret)]).reshape(len(src), 1)
        return means, None

    @staticmethod
    def validity(means):
        return means[:, 0] > 0


@pytest.mark.parametrize("seed", range(40))
def test_the_same_children_as_one_at_a_time(seed):
    rng = np.random.default_rng(seed)
    E = int(rng.integers(1, 60))
    pool = [(int(s), int(r)) for s, r in rng.integers(-3, 6, (25, 2))]
    pairs = {c: [pool[i] for i in rng.choice(len(pool), rng.integers(0, 5), replace=True)] for c in range(E)}
    bad = {p for p in pool if rng.random() < rng.uniform(0.0, 0.4)}
    keys = rng.normal(size=E)
    keys[rng.random(E) < 0.15] = -np.inf
    keys[rng.integers(E)] = keys[rng.integers(E)]  # a tie: the stable order decides
    k = int(rng.integers(1, E + 3))
    a, b = Counting(bad), Counting(bad)
    got = valid_top_k(keys, k, pairs.__getitem__, a.moments_of, a.validity)
    want = _one_by_one(keys, k, pairs.__getitem__, b.moments_of, b.validity)
    np.testing.assert_array_equal(got[0], want[0])
    assert got[1] == want[1]
    assert len(a.tested) == len(set(a.tested))  # each pair tested once
    # the pairs tested are those of the children visited plus, at most, those of the last round's unvisited ones
    assert set(b.tested) <= set(a.tested) and a.calls <= b.calls


def test_one_batch_per_rejection_streak():
    """Ten children, each with its own pair; children 2 and 3 fail; cap 5: the first round tests children 0-4
    at once (2 and 3 rejected, 3 kept), the second the next two (5, 6), which fill the cap: two calls, not seven."""
    pairs = {c: [(c, 0)] for c in range(10)}
    counting = Counting({(2, 0), (3, 0)})
    sel, n_invalid = valid_top_k(-np.arange(10.0), 5, pairs.__getitem__, counting.moments_of, counting.validity)
    assert sel.tolist() == [0, 1, 4, 5, 6] and n_invalid == 2
    assert counting.calls == 2 and sorted(counting.tested) == [(c, 0) for c in range(7)]
    none = Counting(set())
    sel, n_invalid = valid_top_k(np.full(3, -np.inf), 2, pairs.__getitem__, none.moments_of, none.validity)
    assert sel.tolist() == [] and n_invalid == 0 and none.calls == 0

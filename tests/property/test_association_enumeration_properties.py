"""Property tests: enumeration is complete, feasible and duplicate-free for random gating."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from hypotrack.association import (
    EnumerationBudgetError,
    count_associations,
    count_gated_associations,
    enumerate_associations,
    iter_association_chunks,
)


def recursive_count(allowed, row=0, used=frozenset()):
    """Independent oracle: depth-first count over returns."""
    if row == allowed.shape[0]:
        return 1
    total = recursive_count(allowed, row + 1, used)
    for j in np.flatnonzero(allowed[row]):
        if j not in used:
            total += recursive_count(allowed, row + 1, used | {int(j)})
    return total


@st.composite
def gated_problems(draw):
    n = draw(st.integers(0, 5))
    m = draw(st.integers(0, 5))
    allowed = draw(arrays(np.bool_, (m, n)))
    return n, m, allowed


@settings(max_examples=150, deadline=None)
@given(gated_problems())
def test_gated_enumeration_is_complete_feasible_and_distinct(problem):
    n, m, allowed = problem
    events = enumerate_associations(n, m, allowed=allowed)
    assert len(events) == recursive_count(allowed) == count_gated_associations(allowed)
    assert events.shape[1] == m
    for row in events.astype(int):
        detected = row[row >= 0]
        assert len(set(detected.tolist())) == len(detected)
        assert np.all(row >= -1) and np.all(row < n)
        assert all(allowed[i, j] for i, j in enumerate(row) if j >= 0)
    assert len({tuple(r) for r in events.tolist()}) == len(events)
    if allowed.all():
        assert len(events) == count_associations(n, m)


@settings(max_examples=50, deadline=None)
@given(gated_problems(), st.integers(1, 20))
def test_chunked_stream_equals_enumeration(problem, chunk_size):
    n, m, allowed = problem
    chunks = list(iter_association_chunks(n, m, allowed=allowed, chunk_size=chunk_size))
    np.testing.assert_array_equal(np.concatenate(chunks), enumerate_associations(n, m, allowed=allowed))


@settings(max_examples=50, deadline=None)
@given(gated_problems())
def test_budget_error_iff_count_exceeds_budget(problem):
    n, m, allowed = problem
    count = recursive_count(allowed)
    budget = max(1, count - 1)
    if count > budget:
        try:
            enumerate_associations(n, m, allowed=allowed, max_events=budget)
        except EnumerationBudgetError as err:
            assert err.count == count
        else:
            raise AssertionError("budget not enforced")
    assert len(enumerate_associations(n, m, allowed=allowed, max_events=count)) == count

"""Exhaustive event enumeration against an independent permutation-based oracle."""

import itertools
import tracemalloc

import numpy as np
import pytest

from hypotrack.association import (
    EnumerationBudgetError,
    count_associations,
    enumerate_associations,
    event_dtype,
    iter_association_chunks,
)

LECTURE_VALIDATION = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)


def oracle_events(n_tracks, n_meas, allowed=None):
    """All events built as: choose k detected returns, then an ordered choice of k objects."""
    out = set()
    for k in range(min(n_tracks, n_meas) + 1):
        for rows in itertools.combinations(range(n_meas), k):
            for objs in itertools.permutations(range(n_tracks), k):
                if allowed is not None and not all(allowed[r, o] for r, o in zip(rows, objs)):
                    continue
                a = [-1] * n_meas
                for r, o in zip(rows, objs):
                    a[r] = o
                out.add(tuple(a))
    return out


@pytest.mark.parametrize("M", range(7))
@pytest.mark.parametrize("m", range(7))
def test_count_equals_eq4(M, m):
    events = enumerate_associations(M, m)
    assert events.shape == (count_associations(M, m), m)
    assert events.dtype == np.int8


@pytest.mark.parametrize("M, m", [(0, 0), (0, 3), (3, 0), (1, 1), (2, 3), (3, 2), (4, 4)])
def test_same_events_as_oracle_in_lexicographic_order(M, m):
    events = enumerate_associations(M, m)
    rows = [tuple(r) for r in events.tolist()]
    assert set(rows) == oracle_events(M, m)
    assert len(set(rows)) == len(rows)
    assert rows == sorted(rows)  # -1 sorts first, so the all-clutter event leads
    assert rows[0] == (-1,) * m


def test_lecture_example_events():
    events = enumerate_associations(3, 4, allowed=LECTURE_VALIDATION)
    assert {tuple(r) for r in events.tolist()} == oracle_events(3, 4, LECTURE_VALIDATION)
    assert len(events) == 10
    # y2 is gated by no track, so it is clutter in every event.
    assert np.all(events[:, 1] == -1)


def test_dtype_widens_with_object_count():
    assert enumerate_associations(126, 1).dtype == np.int8
    big = enumerate_associations(127, 1)
    assert big.dtype == np.int16 and big.shape == (128, 1) and big[-1, 0] == 126
    assert enumerate_associations(40000, 1).dtype == np.int32
    assert event_dtype(32766) == np.int16 and event_dtype(32767) == np.int32
    with pytest.raises(ValueError, match="n_tracks"):
        event_dtype(-1)


@pytest.mark.parametrize("chunk_size", [1, 7, 64, 10_000])
def test_chunks_concatenate_to_full_enumeration(chunk_size):
    rng = np.random.default_rng(3)
    allowed = rng.random((5, 6)) < 0.6
    for gate in (None, allowed):
        full = enumerate_associations(6, 5, allowed=gate)
        chunks = list(iter_association_chunks(6, 5, allowed=gate, chunk_size=chunk_size))
        assert all(1 <= len(c) <= chunk_size for c in chunks)
        np.testing.assert_array_equal(np.concatenate(chunks), full)


def test_budget_error_raised_before_allocation():
    # A(7, 7) = 130,922 events (~1 MB); with a budget of 1000 nothing that size may be allocated.
    tracemalloc.start()
    try:
        with pytest.raises(EnumerationBudgetError) as info:
            enumerate_associations(7, 7, max_events=1000)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 100_000
    assert isinstance(info.value, ValueError)
    assert "max_events=1,000" in str(info.value) and "130,922" in str(info.value)
    assert info.value.count == 130_922 and info.value.budget == 1000


def test_budget_error_for_astronomical_count():
    # A(30, 30) ~ 1e33 events: counted exactly, refused instantly.
    with pytest.raises(EnumerationBudgetError, match="max_events"):
        enumerate_associations(30, 30)


def test_budget_error_gated_wide_component():
    with pytest.raises(EnumerationBudgetError, match="more than 10,000"):
        enumerate_associations(30, 30, allowed=~np.eye(30, dtype=bool), max_events=10_000)


def test_budget_exactly_met_is_allowed():
    assert len(enumerate_associations(4, 4, max_events=count_associations(4, 4))) == 209


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(n_tracks=-1, n_meas=2), "n_tracks"),
        (dict(n_tracks=2, n_meas=-3), "n_meas"),
        (dict(n_tracks=2, n_meas=2, max_events=0), "max_events"),
        (dict(n_tracks=2, n_meas=2, allowed=np.ones((2, 3), dtype=bool)), "allowed"),
    ],
)
def test_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        enumerate_associations(**kwargs)


def test_bad_input_types():
    with pytest.raises(TypeError, match="allowed"):
        enumerate_associations(2, 2, allowed=np.ones((2, 2)))
    with pytest.raises(TypeError, match="n_tracks"):
        enumerate_associations(2.0, 2)


def test_chunk_iterator_validates_eagerly():
    with pytest.raises(ValueError, match="chunk_size"):
        iter_association_chunks(2, 2, chunk_size=0)
    with pytest.raises(ValueError, match="allowed"):
        iter_association_chunks(2, 2, allowed=np.ones((3, 3), dtype=bool))


def test_chunks_have_the_enumeration_dtype():
    """Blocks use the same small signed dtype as the full enumeration (int8 below 127 objects)."""
    for n, dtype in ((3, np.int8), (130, np.int16)):
        chunks = list(iter_association_chunks(n, 2, chunk_size=5))
        assert {c.dtype for c in chunks} == {np.dtype(dtype)}
        assert sum(len(c) for c in chunks) == count_associations(n, 2)


def test_budget_error_message_exact_and_capped():
    """The message states the count (or that it exceeds the budget) and what the caller can do."""
    advice = "raise max_events, gate more tightly, or sample instead of enumerating"
    exact = EnumerationBudgetError(130_922, 1000)  # the count is exact unless the caller says otherwise
    assert str(exact) == (
        f"enumeration would produce 130,922 association events, exceeding max_events=1,000; {advice}"
    )
    capped = EnumerationBudgetError(10_001, 10_000, exact=False)
    assert str(capped) == (
        f"enumeration would produce more than 10,000 association events, exceeding max_events=10,000; {advice}"
    )
    assert (capped.count, capped.budget) == (10_001, 10_000)


def test_chunk_size_message_names_argument_and_range():
    with pytest.raises(ValueError, match=r"^chunk_size must be an integer in \[1, inf\], got 0$"):
        iter_association_chunks(2, 2, chunk_size=0)


@pytest.mark.parametrize("call, message", [
    (lambda: enumerate_associations(-1, 2), "n_tracks must be an integer in [0, inf], got -1"),
    (lambda: enumerate_associations(2, -3), "n_meas must be an integer in [0, inf], got -3"),
    (lambda: list(iter_association_chunks(-1, 2)), "n_tracks must be an integer in [0, inf], got -1"),
    (lambda: event_dtype(-2), "n_tracks must be an integer in [0, inf], got -2"),
])
def test_negative_sizes_are_named_exactly(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert str(info.value) == message

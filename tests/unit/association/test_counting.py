"""Exact hypothesis counts (paper 000 Eq. 4, Sec. II-C) against independent brute force."""

import itertools
import math

import numpy as np
import pytest

from hypotrack.association import (
    EnumerationBudgetError,
    count_associations,
    count_children,
    count_gated_associations,
    enumerate_associations,
)


def brute_force_events(n_tracks, n_meas, allowed=None):
    """Every event by itertools: each return picks clutter or an object; keep the injective ones."""
    options = []
    for i in range(n_meas):
        opts = [-1] + [j for j in range(n_tracks) if allowed is None or allowed[i, j]]
        options.append(opts)
    events = []
    for a in itertools.product(*options):
        used = [j for j in a if j >= 0]
        if len(used) == len(set(used)):
            events.append(a)
    return events


def test_published_value_eq4():
    # Paper 000 quotes A(10, 5) = 63,591 under Eq. 4.
    assert count_associations(10, 5) == 63591


def test_returns_exact_python_int_beyond_64_bits():
    value = count_associations(30, 30)
    assert type(value) is int
    assert value > 2**63
    # Closed-form sum recomputed independently with math.comb/math.factorial.
    assert value == sum(math.comb(30, n) ** 2 * math.factorial(n) for n in range(31))


@pytest.mark.parametrize("M", range(7))
@pytest.mark.parametrize("m", range(7))
def test_matches_brute_force_and_is_symmetric(M, m):
    assert count_associations(M, m) == len(brute_force_events(M, m))
    assert count_associations(M, m) == count_associations(m, M)


def test_small_closed_forms():
    # A(M, 0) = 1 (only the empty event); A(M, 1) = M + 1 (the return is clutter or one object).
    for M in range(10):
        assert count_associations(M, 0) == 1
        assert count_associations(M, 1) == M + 1
    # A(2, 2) = 1 + 4 + 2.
    assert count_associations(2, 2) == 7


def test_count_children_birth_death_terms():
    # A(3,2) + 2 A(4,2) + 3 A(2,2) = 13 + 2*21 + 3*7.
    assert count_children(3, 2, n_birth_regions=2, n_deaths=3) == 76
    assert count_children(4, 3) == count_associations(4, 3)
    # With no objects the death term is absent: A(0,2) + 5 A(1,2) = 1 + 5*3.
    assert count_children(0, 2, n_birth_regions=5) == 16


def test_gated_count_lecture_example():
    # Paper 004 validation matrix (rows y1..y4, columns T1..T3).
    allowed = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)
    assert count_gated_associations(allowed) == len(brute_force_events(3, 4, allowed)) == 10


def test_gated_count_random_vs_brute_force():
    rng = np.random.default_rng(1)
    for _ in range(60):
        m, n = rng.integers(0, 6, size=2)
        allowed = rng.random((m, n)) < rng.uniform(0.1, 0.9)
        assert count_gated_associations(allowed) == len(brute_force_events(n, m, allowed))


def test_gated_count_full_matrix_equals_eq4():
    assert count_gated_associations(np.ones((9, 12), dtype=bool)) == count_associations(12, 9)


def band_count(n):
    """Events of an n x n band (return k gates objects k and k+1) by an independent two-state
    transfer recursion along the band, the state being whether object k+1 was already taken by
    return k."""
    free, taken = 1, 0  # counts of partial events after return k with object k+1 free / taken
    for k in range(n):
        # return k: clutter, object k (needs it untaken), or object k+1 (last return has none).
        total = free + taken
        to_own = free
        to_next = total if k + 1 < n else 0
        free, taken = total + to_own, to_next
    return free + taken


def test_gated_count_banded_uses_narrow_frontier():
    # A 40 x 40 band: too many events for brute force, so the oracle is the transfer recursion.
    n = 40
    allowed = np.eye(n, dtype=bool) | np.eye(n, k=1, dtype=bool)
    assert count_gated_associations(allowed) == band_count(n)


def test_gated_count_with_cap_stops_on_wide_component():
    # Fully gated but for the diagonal: 30 open columns at once, so the capped DP is used.
    allowed = ~np.eye(30, dtype=bool)
    capped = count_gated_associations(allowed, cap=10**5)
    assert capped > 10**5
    assert capped < count_associations(30, 30)


@pytest.mark.parametrize(
    "args, name, exc",
    [
        ((-1, 3), "M", ValueError),
        ((3, -2), "m", ValueError),
        ((2.5, 3), "M", TypeError),
        ((3, None), "m", TypeError),
    ],
)
def test_count_associations_bad_input(args, name, exc):
    with pytest.raises(exc, match=name):
        count_associations(*args)


def test_count_children_bad_input():
    with pytest.raises(ValueError, match="n_birth_regions"):
        count_children(2, 2, n_birth_regions=-1)
    with pytest.raises(ValueError, match="n_deaths"):
        count_children(2, 2, n_deaths=3)


def test_gated_count_bad_input():
    with pytest.raises(TypeError, match="allowed"):
        count_gated_associations(np.ones((2, 2)))
    with pytest.raises(ValueError, match="allowed"):
        count_gated_associations(np.ones(3, dtype=bool))
    with pytest.raises(ValueError, match="cap"):
        count_gated_associations(np.ones((2, 2), dtype=bool), cap=-1)


def test_count_children_single_object_that_may_die():
    """M = 1 keeps the death term: A(1,3) + 2 A(2,3) + 1 A(0,3) = 4 + 2*13 + 1 (object dies, all clutter)."""
    assert count_children(1, 3, n_birth_regions=2, n_deaths=1) == 31
    assert count_children(1, 3, n_birth_regions=2, n_deaths=0) == 30
    # An empty scan: every population event has exactly one child (everything undetected).
    assert count_children(2, 0, n_birth_regions=1, n_deaths=2) == 1 + 1 + 2


@pytest.mark.parametrize(
    "args, kwargs, message",
    [
        ((-1, 3), {}, r"^M must be an integer in \[0, inf\], got -1$"),
        ((3, -2), {}, r"^m must be an integer in \[0, inf\], got -2$"),
        ((2, 2), {"n_birth_regions": -1}, r"^n_birth_regions must be an integer in \[0, inf\], got -1$"),
        ((2, 2), {"n_deaths": -1}, r"^n_deaths must be an integer in \[0, 2\], got -1$"),
        ((2, 2), {"n_deaths": 3}, r"^n_deaths must be an integer in \[0, 2\], got 3$"),
    ],
)
def test_count_children_messages_name_argument_and_range(args, kwargs, message):
    with pytest.raises(ValueError, match=message):
        count_children(*args, **kwargs)


@pytest.mark.parametrize(
    "args, message",
    [
        ((-1, 3), r"^M must be an integer in \[0, inf\], got -1$"),
        ((3, -2), r"^m must be an integer in \[0, inf\], got -2$"),
        ((3, None), r"^m must be an integer, got NoneType$"),
    ],
)
def test_count_associations_messages_name_argument_and_range(args, message):
    with pytest.raises((ValueError, TypeError), match=message):
        count_associations(*args)


LECTURE_VALIDATION = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)


def test_budget_error_states_the_exact_count_of_a_narrow_gated_problem():
    """Narrow components are counted exactly even with a budget: the error gives the count."""
    with pytest.raises(EnumerationBudgetError, match="^enumeration would produce 10 association events, "
                                                     "exceeding max_events=5;"):
        enumerate_associations(3, 4, allowed=LECTURE_VALIDATION, max_events=5)
    band = np.eye(40, dtype=bool) | np.eye(40, k=1, dtype=bool)  # frontier of one or two columns
    with pytest.raises(EnumerationBudgetError, match=f"^enumeration would produce {band_count(40):,} "):
        enumerate_associations(40, 40, allowed=band, max_events=1000)


def test_capped_count_stops_only_once_strictly_above_the_cap():
    """~I(30): a wide frontier, so the capped DP is used. Its first row (29 gated objects) already
    gives 1 + 29 = 30 partial events; a budget of exactly 30 is not yet exceeded there, so counting
    goes on and the budget error says "more than 30" (instead of enumerating a wrong 30 events)."""
    allowed = ~np.eye(30, dtype=bool)
    assert count_gated_associations(allowed, cap=30) > 30
    with pytest.raises(EnumerationBudgetError, match="more than 30 association events"):
        enumerate_associations(30, 30, allowed=allowed, max_events=30)


def test_cap_zero_still_counts_a_narrow_problem_exactly():
    assert count_gated_associations(LECTURE_VALIDATION, cap=0) == 10


def test_gated_count_messages_name_the_argument():
    with pytest.raises(TypeError, match=r"^allowed must be a boolean \(m, n\) array, got dtype float64$"):
        count_gated_associations(np.ones((2, 2)))
    with pytest.raises(TypeError, match=r"^allowed must be a boolean \(m, n\) array, got dtype float64$"):
        enumerate_associations(2, 2, allowed=np.ones((2, 2)))
    with pytest.raises(ValueError, match=r"^cap must be an integer in \[0, inf\], got -1$"):
        count_gated_associations(np.ones((2, 2), dtype=bool), cap=-1)


def test_fully_gated_component_is_counted_in_closed_form_next_to_an_ungated_track():
    """A fully gated 25 x 25 block (too wide for the capped DP to count exactly) beside a track
    that gates nothing: the block alone is the component, counted by Eq. 4, so the budget error
    states the exact A(25, 25)."""
    allowed = np.zeros((25, 26), dtype=bool)
    allowed[:, :25] = True
    with pytest.raises(EnumerationBudgetError,
                       match=f"^enumeration would produce {count_associations(25, 25):,} association events"):
        enumerate_associations(26, 25, allowed=allowed, max_events=1000)


def _double_cross_count(n, special=2):
    """Matchings of any size when only the first ``special`` rows and columns of an n x n block
    are gated (each to everything): the special rows pick distinct columns (or none) by loops, then
    each special column still free is left unmatched or taken by a distinct ordinary row."""
    ordinary = n - special
    total = 0
    for picks in itertools.product([None, *range(n)], repeat=special):
        used = [c for c in picks if c is not None]
        if len(used) != len(set(used)):
            continue
        free = sum(c not in used for c in range(special))
        total += sum(math.comb(free, k) * math.perm(ordinary, k) for k in range(free + 1))
    return total


def test_frontier_exactly_at_the_exact_limit_is_counted_exactly_under_a_cap():
    """Two rows and two columns gated to everything in a 20 x 20 block: 20 columns are open at once
    in either orientation, exactly the limit up to which a capped count is still exact, so a cap
    of 5 does not stop it: the exact count (oracle: closed form above) comes back."""
    n = 20
    allowed = np.zeros((n, n), dtype=bool)
    allowed[:2, :] = True
    allowed[:, :2] = True
    small = np.zeros((5, 5), dtype=bool)
    small[:2, :] = True
    small[:, :2] = True
    assert _double_cross_count(5) == len(brute_force_events(5, 5, small))  # the oracle itself, by brute force
    exact = _double_cross_count(n)
    assert count_gated_associations(allowed) == exact
    assert count_gated_associations(allowed, cap=5) == exact
    with pytest.raises(EnumerationBudgetError, match=f"^enumeration would produce {exact:,} association events"):
        enumerate_associations(n, n, allowed=allowed, max_events=5)


def test_frontier_plan_keeps_only_the_columns_later_rows_use():
    """Rows {0,3}, {0,1}, {1,2} of a 3 x 4 block are ordered by (first, last) gated column:
    {0,1}, {0,3}, {1,2}. After the first row every column is still wanted (mask 0b1111); after the
    second only columns 1 and 2 (0b0110; column 3 is used by no later row, though it lies right of
    the next row's first column); after the last none. Open columns: {0,1}, then {1}: width 2."""
    from hypotrack.association.counting import _frontier_plan

    block = np.array([[1, 0, 0, 1], [1, 1, 0, 0], [0, 1, 1, 0]], dtype=bool)
    ordered, keep, width = _frontier_plan(block)
    np.testing.assert_array_equal(ordered, block[[1, 0, 2]])
    assert keep == [0b1111, 0b0110, 0]
    assert width == 2


def test_a_capped_component_keeps_the_whole_count_inexact():
    """~I(30) (wide, counted only up to the cap) followed by a small narrow component (counted
    exactly): the product is a lower bound, so the budget error must say "more than", even
    though the last component counted was exact."""
    allowed = np.zeros((32, 32), dtype=bool)
    allowed[:30, :30] = ~np.eye(30, dtype=bool)
    allowed[30, 30] = allowed[30, 31] = allowed[31, 31] = True
    with pytest.raises(EnumerationBudgetError, match="^enumeration would produce more than 1,000 association events"):
        enumerate_associations(32, 32, allowed=allowed, max_events=1000)

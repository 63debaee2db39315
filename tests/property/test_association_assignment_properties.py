"""Property test: Murty's k best equal the k best of an exhaustive permutation search."""

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hypotrack.association import best_assignment, murty_k_best


@st.composite
def score_matrices(draw):
    m = draw(st.integers(1, 4))
    N = draw(st.integers(m, 6))
    values = draw(
        st.lists(
            st.one_of(st.just(-np.inf), st.integers(-3, 3).map(float), st.floats(-5, 5)),
            min_size=m * N,
            max_size=m * N,
        )
    )
    return np.array(values).reshape(m, N)


@settings(max_examples=200, deadline=None)
@given(score_matrices(), st.integers(1, 30))
def test_murty_k_best_equals_exhaustive_ranking(score, k):
    m, N = score.shape
    all_totals = (score[np.arange(m), perm].sum() for perm in itertools.permutations(range(N), m))
    totals = sorted((t for t in all_totals if np.isfinite(t)), reverse=True)
    ranked = murty_k_best(score, k)
    np.testing.assert_allclose([t for t, _ in ranked], totals[:k], rtol=0, atol=1e-9)
    if totals:
        assert best_assignment(score)[0] == ranked[0][0]

"""Property test: clusters are exactly the components found by a naive union-find."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from hypotrack.association import enumerate_associations, find_clusters, unassociated_measurements


def component_closure(validation):
    """Oracle by repeated set growth: tracks reachable from each track through shared returns."""
    m, n = validation.shape
    seen, groups = set(), []
    for start in range(n):
        if start in seen:
            continue
        tracks, returns = {start}, set()
        while True:
            new_returns = {i for i in range(m) if any(validation[i, j] for j in tracks)}
            new_tracks = {j for j in range(n) if any(validation[i, j] for i in new_returns)} | tracks
            if new_returns == returns and new_tracks == tracks:
                break
            tracks, returns = new_tracks, new_returns
        seen |= tracks
        groups.append((tuple(sorted(tracks)), tuple(sorted(returns))))
    return groups


@st.composite
def validations(draw):
    m = draw(st.integers(0, 8))
    n = draw(st.integers(0, 8))
    return draw(arrays(np.bool_, (m, n)))


@settings(max_examples=200, deadline=None)
@given(validations())
def test_clusters_equal_closure_oracle(validation):
    clusters = find_clusters(validation)
    found = [(tuple(c.tracks.tolist()), tuple(c.measurements.tolist())) for c in clusters]
    assert found == component_closure(validation)
    expected_free = [i for i in range(validation.shape[0]) if not validation[i].any()]
    assert unassociated_measurements(validation).tolist() == expected_free


@settings(max_examples=40, deadline=None)
@given(validations().filter(lambda v: v.size <= 30))
def test_event_count_factorises_over_clusters(validation):
    # Clusters are independent: the number of joint events is the product over clusters.
    m, n = validation.shape
    total = len(enumerate_associations(n, m, allowed=validation, max_events=10**6))
    product = 1
    for c in find_clusters(validation):
        sub = c.submatrix(validation)
        product *= len(enumerate_associations(sub.shape[1], sub.shape[0], allowed=sub))
    assert total == product

"""Clusters of the gating graph: the lecture's example and a union-find oracle."""

import numpy as np
import pytest

from hypotrack.association import Cluster, find_clusters, unassociated_measurements

# Paper 004, "Gating": rows y1..y4, columns T1..T3.
LECTURE_VALIDATION = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)


def union_find_clusters(validation):
    """Naive oracle: union tracks that share a gated return; attach each gated return."""
    m, n = validation.shape
    parent = list(range(n))

    def root(j):
        while parent[j] != j:
            j = parent[j]
        return j

    for i in range(m):
        tracks = np.flatnonzero(validation[i])
        for j in tracks[1:]:
            parent[root(j)] = root(tracks[0])
    groups = {}
    for j in range(n):
        groups.setdefault(root(j), ([], []))[0].append(j)
    for i in range(m):
        tracks = np.flatnonzero(validation[i])
        if tracks.size:
            groups[root(tracks[0])][1].append(i)
    return {(tuple(t), tuple(sorted(r))) for t, r in groups.values()}


def as_set(clusters):
    return {(tuple(c.tracks.tolist()), tuple(c.measurements.tolist())) for c in clusters}


def test_lecture_example():
    clusters = find_clusters(LECTURE_VALIDATION)
    # The lecture: "grouped into two clusters T1&T2, T3"; y2 is gated by nobody.
    assert clusters == [Cluster([0, 1], [2, 3]), Cluster([2], [0])]
    np.testing.assert_array_equal(unassociated_measurements(LECTURE_VALIDATION), [1])


def test_random_matrices_against_union_find():
    rng = np.random.default_rng(7)
    for _ in range(300):
        m, n = rng.integers(0, 9, size=2)
        validation = rng.random((m, n)) < rng.uniform(0.0, 0.5)
        clusters = find_clusters(validation)
        assert as_set(clusters) == union_find_clusters(validation)
        # A partition of the tracks, ordered by smallest track index.
        tracks = np.concatenate([c.tracks for c in clusters]) if clusters else np.zeros(0, int)
        assert sorted(tracks.tolist()) == list(range(n))
        assert [c.tracks[0] for c in clusters] == sorted(c.tracks[0] for c in clusters)
        gated = {i for c in clusters for i in c.measurements.tolist()}
        assert gated.isdisjoint(unassociated_measurements(validation).tolist())
        assert len(gated) + len(unassociated_measurements(validation)) == m


def test_isolated_tracks_and_empty_inputs():
    singletons = [Cluster([0], []), Cluster([1], []), Cluster([2], [])]
    assert find_clusters(np.zeros((0, 3), dtype=bool)) == singletons
    assert find_clusters(np.zeros((4, 0), dtype=bool)) == []
    np.testing.assert_array_equal(unassociated_measurements(np.zeros((4, 0), dtype=bool)), [0, 1, 2, 3])


def test_cluster_value_semantics_and_submatrix():
    c = Cluster([2, 0], [3])
    assert c.tracks.tolist() == [0, 2] and not c.tracks.flags.writeable
    assert c == Cluster(np.array([0, 2]), (3,)) and hash(c) == hash(Cluster([0, 2], [3]))
    matrix = np.arange(12).reshape(4, 3)
    np.testing.assert_array_equal(c.submatrix(matrix), [[9, 11]])


def test_bad_input():
    with pytest.raises(TypeError, match="validation"):
        find_clusters(np.ones((2, 2)))
    with pytest.raises(ValueError, match="validation"):
        find_clusters(np.ones(3, dtype=bool))
    with pytest.raises(TypeError, match="validation"):
        unassociated_measurements([[1, 0]])


def test_clusters_differing_in_tracks_or_returns_are_unequal():
    """Equality needs the same tracks *and* the same returns."""
    c = Cluster([0, 1], [2])
    assert c != Cluster([0, 1], [3])  # same tracks, other return
    assert c != Cluster([0, 2], [2])  # same return, other tracks
    assert c != "Cluster(tracks=[0, 1], measurements=[2])"
    assert len({c, Cluster([0, 1], [3]), Cluster([0, 1], [2])}) == 2

"""The engine's state object and the scan interval rule."""

import numpy as np
import pytest

from hypotrack.hypotheses.state import FilterState, scan_interval
from hypotrack.hypotheses.tracks import TrackStore


def test_initial_state_holds_one_hypothesis_of_weight_one():
    s = FilterState.initial(np.zeros((3, 4)), np.repeat(np.eye(4)[None], 3, axis=0), labels=[4, 9, 2])
    assert len(s) == 1 and s.log_w.tolist() == [0.0] and s.tracks[0].tolist() == [0, 1, 2] and s.keys == [()]
    assert s.next_label == 10 and s.labels.tolist() == [2, 4, 9]
    empty = FilterState.initial(np.zeros((0, 4)), ndim=4)
    assert len(empty.store) == 0 and empty.store.ndim == 4 and empty.next_label == 0 and empty.tracks[0].size == 0
    with pytest.raises(ValueError, match="covs are required"):
        FilterState.initial(np.zeros((1, 4)))


def test_same_as_compares_every_number_but_not_the_lineage():
    store = TrackStore(np.arange(8.0).reshape(2, 4), np.repeat(np.eye(4)[None], 2, axis=0), np.array([0, 1]))
    a = FilterState(store, np.log([0.25, 0.75]), [np.array([0]), np.array([0, 1])], [("a",), ("b",)], 2)
    assert a.same_as(FilterState(store, a.log_w.copy(), [t.copy() for t in a.tracks], [1, 2], 2))
    assert not a.same_as(a.with_next_label(3))
    assert not a.same_as(FilterState(store, np.log([0.75, 0.25]), a.tracks, a.keys, 2))
    assert not a.same_as(FilterState(store, a.log_w, [np.array([1]), np.array([0, 1])], a.keys, 2))
    moved = TrackStore(store.means + 1e-12, store.covs, store.labels)
    assert not a.same_as(a.with_store(moved)) and a.with_store(moved).log_w is a.log_w


@pytest.mark.parametrize("now, time, dt, want", [
    (2.0, 3.5, None, (1.5, 3.5)),
    (2.0, 2.0, None, (0.0, 2.0)),  # a zero interval: an update without prediction
    (2.0, None, 0.25, (0.25, 2.25)),
    (2.0, None, 0.0, (0.0, 2.0)),
    (2.0, None, None, (1.0, 3.0)),  # neither: the default interval
])
def test_scan_interval(now, time, dt, want):
    assert scan_interval(now, time, dt, 1.0) == want


@pytest.mark.parametrize("time, dt, match", [
    (1.0, None, "^time must be >= the filter's time 2.0"),
    (None, -1.0, "^dt must be a finite number >= 0, got -1.0"),
    (3.0, 1.0, "^give the scan's time or its interval dt, not both"),
    (np.inf, None, "^time must be a finite number"),
    (None, "x", "^dt must be a finite number"),
])
def test_scan_interval_refuses(time, dt, match):
    with pytest.raises(ValueError, match=match):
        scan_interval(2.0, time, dt, 1.0)

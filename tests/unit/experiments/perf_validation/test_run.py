"""The validation-cost benchmark records the checks a tracker really makes, and restores the library."""

import collections

import numpy as np
import pytest

import hypotrack.trackers.tracker as tracker_module
from hypotrack import _validation
from hypotrack.experiments.perf_validation.run import (_kernel_calls, kernel_overhead, recorded_checks,
                                                   tracker_validation_share)
from hypotrack.models import ConstantVelocity
from hypotrack.trackers._sht_common import ScanModel
from hypotrack.trackers.tracker import SingleHypothesisTracker

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])


def test_recording_sees_one_scan_check_per_step_and_restores_the_checks():
    tracker = SingleHypothesisTracker(ConstantVelocity(0.1), ScanModel(H, np.eye(2), 0.9, 0.99, 1e-3, 0.0),
                                      association="gnn")
    tracker.initialise(np.zeros((2, 4)), np.stack([np.eye(4)] * 2), time=0.0)
    with recorded_checks() as calls:
        assert tracker_module.check_measurements is not _validation.check_measurements
        for k in range(3):
            tracker.step(np.array([[0.1, 0.2], [5.0, 5.0]]), float(k + 1))
    assert tracker_module.check_measurements is _validation.check_measurements
    scans = [(args[1:], kwargs) for f, args, kwargs in calls if f is _validation.check_measurements]
    assert scans == [(("Z", 2), {})] * 3  # each scan's returns, checked once, as (m, 2)
    assert all(f.__module__ == "hypotrack._validation" for f, _, _ in calls)


def test_checked_and_unchecked_kernels_do_the_same_work():
    """The comparison is fair only if both forms compute the same thing: equal outputs, bit for bit."""
    for name, checked, unchecked in _kernel_calls(5, 3, np.random.default_rng(2)):
        a, b = checked(), unchecked()
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y, err_msg=name)
    table = kernel_overhead((1, 4), n_returns=3, repeats=1, target_seconds=1e-3)
    assert list(table["kernel"]) == ["predict", "innovation", "update", "mahalanobis2_matrix"] * 2
    assert list(table["n_tracks"]) == [1] * 4 + [4] * 4


def test_tracker_share_counts_every_scans_check():
    pytest.importorskip("stonesoup")
    table = tracker_validation_share({"gnn": {}}, n_targets=3, n_scans=4, clutter_rate=2.0, repeats=1, seed=1)
    (row,) = table.itertuples()
    assert row.check_calls_per_scan >= 1.0  # every scan's returns are checked
    assert 0.0 < row.validation_ms_per_scan < row.step_ms_per_scan
    assert collections.Counter(table["algorithm"]) == {"gnn": 1}

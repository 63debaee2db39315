"""The Stone Soup adapter checks its input at its boundary, with its own parameter names."""

import datetime
import pickle

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.measurement.nonlinear import CartesianToBearingRange  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402

from hypotrack.interop.stonesoup import HypotrackTracker  # noqa: E402

T0 = datetime.datetime(2025, 1, 1)
SECOND = datetime.timedelta(seconds=1)
REGION = [[-60.0, 60.0], [-60.0, 60.0]]
OPTIONS = {"gnn": {}, "jpda": {}, "hfisst": {"max_hypotheses": 5}, "glmb": {"max_hypotheses": 5, "n_sweeps": 20}}


def _tracker(algorithm="gnn", **kw):
    args = dict(transition_model=CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05)] * 2),
                measurement_model=LinearGaussian(4, (0, 2), np.eye(2)), algorithm=algorithm,
                detection_probability=0.9, clutter_rate=2.0, clutter_region=REGION,
                initial_states=[GaussianState([[0.0], [1.0], [0.0], [0.0]], np.eye(4), timestamp=T0)],
                options=OPTIONS.get(algorithm, {}))
    args.update(kw)
    return HypotrackTracker(**args)


def _state(tracker):
    """What a refused scan must leave unchanged: the adapter's tracks and time, the tracker's state."""
    inner = tracker.tracker
    core = {k: v for k, v in vars(inner).items() if isinstance(v, (np.ndarray, int, float, type(None), list, tuple))}
    rng = getattr(inner, "rng", None)
    return pickle.dumps((tracker._time, tracker._n_scans, sorted(map(str, tracker.all_tracks)), core,
                         None if rng is None else rng.bit_generator.state))


@pytest.mark.parametrize("algorithm", ["gnn", "hfisst"])
def test_a_bearing_range_measurement_model_is_refused(algorithm):
    """It was read as positions: (bearing, range) as (x, y)."""
    model = CartesianToBearingRange(4, (0, 2), np.diag([1e-4, 1.0]))
    with pytest.raises(ValueError, match=r"measurement_model CartesianToBearingRange is not a linear-Gaussian.*"
                                         r"supported: a linear-Gaussian position measurement"):
        _tracker(algorithm, measurement_model=model)


def test_a_linear_model_of_velocities_is_refused():
    with pytest.raises(ValueError, match=r"measurement_model LinearGaussian with mapping \(1, 3\) does not measure "
                                         r"distinct position components.*\(0, 2\)"):
        _tracker(measurement_model=LinearGaussian(4, (1, 3), np.eye(2)))


@pytest.mark.parametrize("algorithm", ["gnn", "hfisst", "glmb"])
def test_a_detection_stamped_at_another_time_is_refused_and_changes_nothing(algorithm):
    tracker = _tracker(algorithm)
    tracker.update_tracker(T0 + SECOND, {Detection([[1.0], [0.0]], timestamp=T0 + SECOND)})
    before = _state(tracker)
    late = Detection([[2.5], [0.5]], timestamp=T0 + 3 * SECOND)
    with pytest.raises(ValueError, match=r"detection at \[\[?2\.5\]?, \[?0\.5\]?\] \(Detection\) has timestamp "
                                         r"2025-01-01 00:00:03, but its scan's time is 2025-01-01 00:00:02"):
        tracker.update_tracker(T0 + 2 * SECOND, {Detection([[2.0], [0.0]], timestamp=T0 + 2 * SECOND), late})
    assert _state(tracker) == before
    tracker.update_tracker(T0 + 2 * SECOND, {Detection([[2.0], [0.0]], timestamp=None)})  # no stamp: the scan's


@pytest.mark.parametrize("algorithm", ["gnn", "hfisst"])
def test_arrays_and_float_times_are_refused_with_the_adapter_names(algorithm):
    tracker = _tracker(algorithm)
    before = _state(tracker)
    with pytest.raises(TypeError, match=r"detections must be Stone Soup Detections.*got a ndarray"):
        tracker.update_tracker(T0 + SECOND, [np.array([1.0, 0.0])])
    with pytest.raises(TypeError, match=r"detections must be a set \(or list\) of Stone Soup Detections, got ndarray"):
        tracker.update_tracker(T0 + SECOND, np.zeros((2, 2)))
    with pytest.raises(TypeError, match=r"time must be a datetime\.datetime.*got float 1\.0"):
        tracker.update_tracker(1.0, set())
    assert _state(tracker) == before


@pytest.mark.parametrize("algorithm, kw, err, message", [
    ("hfisst", {"detection_probability": 1.0}, ValueError, r"detection_probability must lie in \(0, 1\) for the hypothesis"),
    ("gnn", {"detection_probability": 0.0}, ValueError, r"detection_probability must lie in \(0, 1\] for gnn"),
    ("gnn", {"detection_probability": "0.9"}, TypeError, r"detection_probability must be a real number"),
    ("hfisst", {"clutter_rate": -1.0}, ValueError, r"clutter_rate \(expected clutter returns per scan\) must be"),
    ("hfisst", {"clutter_rate": float("inf")}, ValueError, r"clutter_rate .* must be a finite number >= 0"),
    ("jpda", {"clutter_rate": 0.0}, ValueError, r"clutter_rate must be a finite number > 0 for jpda"),
    ("gnn", {"initial_states": [GaussianState([[0.0], [1.0], [0.0], [0.0]], -np.eye(4))]}, ValueError,
     r"initial_states\[0\]\.covar must be positive definite"),
    ("hfisst", {"initial_states": [GaussianState([[0.0], [1.0]], np.eye(2))]}, ValueError,
     r"initial_states\[0\]\.state_vector must hold 4 finite components"),
    ("gnn", {"initial_states": [np.zeros(4)]}, TypeError, r"initial_states\[0\] must be a GaussianState"),
    ("pmbm_murty", {"clutter_rate": 0.0}, ValueError, r"clutter_rate must be a finite number > 0 for pmbm_murty"),
    ("pmb_lbp", {}, ValueError, r"algorithm 'pmb_lbp': a PMB filter's Bernoullis mix several returns"),
])
def test_range_errors_name_the_adapter_parameters(algorithm, kw, err, message):
    """They named p_D, rate and covs, the hypotrack tracker's parameters behind the adapter."""
    with pytest.raises(err, match=message):
        _tracker(algorithm, **kw)


@pytest.mark.parametrize("algorithm, p_D", [("gnn", 1.0), ("jpda", 1.0), ("hfisst", 0.99)])
def test_valid_values_at_the_edges_still_build(algorithm, p_D):
    _tracker(algorithm, detection_probability=p_D, clutter_rate=0.5)

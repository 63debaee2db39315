"""The single-hypothesis tracker on the common tracker surface (hypotrack.protocol): labels given at
initialise and kept, new tracks labelled above every label held, step(Z, time) with a zero interval an
update without prediction, and deletion that counts misses in view only."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.protocol import HypothesisTracker, TrackEstimates, Tracker
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
MOTION = ConstantVelocity(0.1)
P1 = np.diag([1.0, 1.0, 0.5, 0.5])


def _model():
    return ScanModel(H, np.eye(2), 0.9, 0.99, 1e-3)


def test_labels_are_kept_and_new_tracks_are_labelled_above_every_label_held():
    mdl = _model()
    tr = SingleHypothesisTracker(MOTION, mdl, initiator=MOfNInitiator(MOTION, mdl, m=1, n=1))
    assert isinstance(tr, Tracker) and not isinstance(tr, HypothesisTracker)
    np.testing.assert_array_equal(tr.initialise([[0.0, 0, 0, 0], [50.0, 0, 0, 0]], [P1, P1], [40, 7], time=0.0),
                                  [40, 7])
    # returns at both tracks and one far away: the far one starts (1-of-1) a track labelled 41
    est = tr.step(np.array([[0.2, 0.0], [50.1, 0.0], [200.0, 200.0]]), 1.0)
    assert isinstance(est, TrackEstimates) and est.labels.tolist() == [40, 7, 41] and est.ids is est.labels
    with pytest.raises(ValueError, match=r"labels \[7\] are already held"):
        tr.initialise([[9.0, 9, 0, 0]], [P1], [7], time=1.0)


def test_zero_interval_is_an_update_without_prediction():
    tr = SingleHypothesisTracker(MOTION, _model())
    tr.initialise([[0.0, 0.0, 1.0, 0.0]], [P1], time=3.0)
    est = tr.step(np.array([[1.0, 0.0]]), 3.0)  # same time: the prior is not moved by its velocity
    # Kalman update of x = 0 (variance 1) with z = 1 (variance 1): the mean halfway, the variance halved
    np.testing.assert_allclose(est.x[0, :2], [0.5, 0.0], atol=1e-12)
    np.testing.assert_allclose(est.P[0, :2, :2], 0.5 * np.eye(2), atol=1e-12)
    np.testing.assert_allclose(est.x[0, 2:], [1.0, 0.0], atol=1e-12)  # velocity uncorrelated: unchanged


def test_misses_count_in_view_only():
    """Two tracks, no returns for 3 scans, max_misses 2: the track at x = 0 (in view, x < 10) is deleted
    after its second miss, the one at x = 100 (out of view) is kept whatever the number of scans."""
    def run(in_view):
        tr = SingleHypothesisTracker(MOTION, _model(), max_misses=2, in_view=in_view)
        tr.initialise([[0.0, 0, 0, 0], [100.0, 0, 0, 0]], [P1, P1], [1, 2], time=0.0)
        return [tr.step(np.zeros((0, 2)), float(k)).labels.tolist() for k in (1, 2, 3)]

    assert run(None) == [[1, 2], [], []]
    assert run(lambda x: x[:, 0] < 10.0) == [[1, 2], [2], [2]]
    with pytest.raises(TypeError, match="in_view must be a callable"):
        SingleHypothesisTracker(MOTION, _model(), in_view=3)

"""The tracker's validity test, its argument checks and its empty state, by hand: a confirmed track whose mean
fails ``validity`` is deleted (and one missed too often is deleted whatever its validity), a tentative track the
initiator confirms is not started where validity fails; a validity mask of 0/1 integers is read as booleans."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker

MOTION = ConstantVelocity(0.0)
H = np.hstack([np.eye(2), np.zeros((2, 2))])
MODEL = ScanModel(H, 0.01 * np.eye(2), 0.9, 0.999, 1e-4)
P0 = np.diag([0.01, 0.01, 0.01, 0.01])


@pytest.mark.parametrize("as_int", [False, True])
def test_validity_deletes_and_refuses_tracks(as_int):
    """A moves at 10/s from x = 0 and leaves ``x ≤ 50`` at t = 6; B stays at x = 20 and is seen; C (x = 30) is never
    seen and goes after max_misses = 2; of the two objects the initiator confirms at t = 2, the one at x = 100 is
    refused and the one at x = 40 started (id 3)."""
    def valid(x):
        ok = np.asarray(x)[:, 0] <= 50.0
        return ok.astype(np.int64) if as_int else ok

    tr = SingleHypothesisTracker(MOTION, MODEL, max_misses=2, validity=valid,
                                 initiator=MOfNInitiator(MOTION, MODEL, m=2, n=3, initial_velocity_std=0.1))
    tr.initialise(np.array([[0.0, 0.0, 10.0, 0.0], [20.0, 0.0, 0.0, 0.0], [30.0, 5.0, 0.0, 0.0]]),
                  np.stack([P0] * 3), [0, 1, 2], time=0.0)
    est = tr.step(np.array([[10.0, 0.0], [20.0, 0.0], [100.0, 100.0], [40.0, 40.0]]), 1.0)
    assert est.ids.tolist() == [0, 1, 2] and tr.misses.tolist() == [0, 0, 1]
    est = tr.step(np.array([[20.0, 0.0], [20.0, 0.0], [100.0, 100.0], [40.0, 40.0]]), 2.0)
    assert est.ids.tolist() == [0, 1, 3]  # C missed twice; (100, 100) confirmed but refused; (40, 40) started
    np.testing.assert_allclose(est.x[2, :2], [40.0, 40.0], atol=1e-9)
    for t in (3.0, 4.0, 5.0):
        est = tr.step(np.array([[10.0 * t, 0.0], [20.0, 0.0], [40.0, 40.0]]), t)
    assert est.ids.tolist() == [0, 1, 3]
    est = tr.step(np.array([[60.0, 0.0], [20.0, 0.0], [40.0, 40.0]]), 6.0)
    assert est.ids.tolist() == [1, 3]  # A at x = 60: unphysical, deleted


def test_argument_checks_name_the_argument():
    view = lambda x: np.ones(len(x), dtype=bool)  # noqa: E731
    cases = [
        (dict(in_view=3), TypeError, r"^in_view must be a callable of the track states or None, got int$"),
        (dict(validity=3), TypeError, r"^validity must be a callable of the track means or None, got int$"),
        (dict(p_detect=3), TypeError, r"^p_detect must be a callable of the track states or None, got int$"),
        (dict(gate_out_of_view="no"), TypeError, r"^gate_out_of_view must be True, False or None, got 'no'$"),
        (dict(gate_out_of_view=False), ValueError,
         r"^lazy=True and gate_out_of_view=False need in_view \(where the sensor sees\)$"),
        (dict(lazy=True, gate_out_of_view=True, in_view=view), ValueError,
         r"^lazy=True needs gate_out_of_view=False \(a deferred track takes no return\)$"),
    ]
    for kw, err, msg in cases:
        with pytest.raises(err, match=msg):
            SingleHypothesisTracker(MOTION, MODEL, **kw)
    tr = SingleHypothesisTracker(MOTION, MODEL)
    with pytest.raises(TypeError, match=r"^step\(Z, time\) takes the returns and the scan's time; got a \(time, Z\) "
                                        r"pair \(use run\(\) for a sequence of \(time, Z\) pairs\)$"):
        tr.step((1.0, np.zeros((0, 2))))
    with pytest.raises(TypeError, match=r"^time is required: step\(Z, time\) with the scan's time \(the "
                                        r"single-hypothesis trackers have no default scan interval\)$"):
        tr.step(np.zeros((0, 2)))
    assert tr.step(([1.0, 2.0], [3.0, 4.0]), 1.0).ids.tolist() == []  # a tuple of two returns is a scan


def test_a_new_tracker_has_no_state():
    tr = SingleHypothesisTracker(MOTION, MODEL)
    assert tr.last_predicted == 0 and tr.time is None
    assert tr.state_times().shape == (0,)
    est = tr.estimates()
    assert est.x.shape == (0, 4) and est.P.shape == (0, 4, 4) and est.time == -np.inf


def test_a_lazy_tracker_advances_a_lone_unseen_track_and_never_asks_about_no_tracks():
    """One track out of view moving at (2, −1)/s: its mean is advanced each scan (x₀ + v t) though it is not
    predicted; with no tracks at all, the view is never asked about an empty state array."""
    def view(x):
        assert len(x), "in_view called with no states"
        return np.asarray(x)[:, 0] < -100.0

    tr = SingleHypothesisTracker(MOTION, MODEL, in_view=view, lazy=True)
    tr.step(np.zeros((0, 2)), 0.0)  # no tracks yet
    tr.initialise(np.array([[0.0, 0.0, 2.0, -1.0]]), P0[None], [7], time=0.0)
    for t in (1.0, 2.5):
        est = tr.step(np.zeros((0, 2)), t)
        assert tr.last_predicted == 0 and est.time == t
        np.testing.assert_allclose(est.x, [[2.0 * t, -t, 2.0, -1.0]], atol=1e-12)
        assert tr.misses.tolist() == [0] and tr.misses.dtype == np.int64  # unseen out of view: not missed


def test_gating_in_view_only_and_lbp_marginals():
    """gate_out_of_view=False: the track in view takes its return by the Kalman update (by hand), the one out of view
    keeps its prediction though a return lies on it. jpda_marginals="lbp": the tracker's β are loopy BP's of its own
    gating, not the exact marginals (two tracks gating two returns: a cycle)."""
    from hypotrack.trackers.jpda import jpda_probabilities

    def view(x):
        return np.asarray(x)[:, 0] < 50.0

    tr = SingleHypothesisTracker(MOTION, MODEL, in_view=view, gate_out_of_view=False)
    tr.initialise(np.array([[0.0, 0.0, 0.0, 0.0], [100.0, 0.0, 0.0, 0.0]]), np.stack([P0, P0]), [0, 1], time=0.0)
    est = tr.step(np.array([[0.1, 0.0], [100.0, 0.1]]), 0.0)
    k = 0.01 / (0.01 + 0.01)  # position gain P/(P + R)
    np.testing.assert_allclose(est.x, [[k * 0.1, 0.0, 0.0, 0.0], [100.0, 0.0, 0.0, 0.0]], atol=1e-12)
    assert tr.misses.tolist() == [0, 0]  # the unseen track out of view is not missed

    model = ScanModel(H, 0.5 * np.eye(2), 0.9, 0.999, 1e-3)
    tr = SingleHypothesisTracker(MOTION, model, association="jpda", jpda_marginals="lbp")
    tr.initialise(np.array([[0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]), np.stack([np.eye(4)] * 2), [0, 1], time=0.0)
    tr.step(np.array([[0.3, 0.1], [0.8, -0.2]]), 0.0)
    lbp = jpda_probabilities(tr.last_gated, model, marginals="lbp")
    exact = jpda_probabilities(tr.last_gated, model, marginals="exact")
    np.testing.assert_allclose(tr.last_association, lbp, atol=1e-12)
    assert np.abs(lbp - exact).max() > 1e-6

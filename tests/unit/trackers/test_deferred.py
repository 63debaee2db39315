"""Deferred prediction of out-of-view tracks: :func:`replay` is the eager tracker's scan-by-scan predictions,
checked row by row against a brute-force loop (rows deferred since different scans, given out of order, a
repeated scan time, a prediction that depends on how an interval is split); :func:`predict_gap` is one
prediction per row over its whole gap (``Φ(gap)``, ``Q(gap)`` of the motion model); :class:`ScanTimes` keeps
absolute scan indices across trimming."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.trackers.deferred import ScanTimes, predict_gap, replay


def _times(values):
    times = ScanTimes()
    for t in values:
        times.append(t)
    return times


def _step(x, P, dt):
    """A per-scan prediction whose result depends on how a gap is cut (dt² is not additive) and on the order."""
    return 0.5 * x + dt**2, P * (1.0 + dt) + dt


def _brute(x, P, since, t):
    """Each row alone, predicted at every scan from its own to the last, zero intervals skipped."""
    out_x, out_P = x.copy(), P.copy()
    for i, s in enumerate(since):
        for j in range(s, len(t) - 1):
            dt = t[j + 1] - t[j]
            if dt != 0:
                a, b = _step(out_x[i:i + 1], out_P[i:i + 1], dt)
                out_x[i], out_P[i] = a[0], b[0]
    return out_x, out_P


def test_replay_is_the_scan_by_scan_prediction_of_each_row():
    t = [0.0, 1.0, 3.0, 3.0, 4.5, 7.0, 8.0]  # scan 3 repeats scan 2's time: nothing to predict there
    times = _times(t)
    rng = np.random.default_rng(5)
    since = np.array([4, 0, 6, 2, 0, 5])  # out of order, two rows since scan 0, one already at now
    x = rng.normal(0, 1, (6, 2))
    P = rng.uniform(1, 2, (6, 2, 2))
    got_x, got_P = replay(_step, x, P, since, times)
    want_x, want_P = _brute(x, P, since, np.array(t))
    np.testing.assert_allclose(got_x, want_x, rtol=1e-13)
    np.testing.assert_allclose(got_P, want_P, rtol=1e-13)
    assert np.array_equal(got_x[2], x[2])  # deferred since now: unchanged
    # hand-computed row 0 (since scan 4): dt 2.5 then 1
    assert got_x[0, 0] == pytest.approx(0.5 * (0.5 * x[0, 0] + 2.5**2) + 1.0, rel=1e-14)
    # rows all deferred since scan 0: every scan predicts all of them in one batch
    all_x, all_P = replay(_step, x, P, np.zeros(6, dtype=int), times)
    ref_x, ref_P = _brute(x, P, np.zeros(6, dtype=int), np.array(t))
    np.testing.assert_allclose(all_x, ref_x, rtol=1e-13)
    np.testing.assert_allclose(all_P, ref_P, rtol=1e-13)


def test_replay_with_nothing_deferred_returns_copies():
    times = _times([0.0, 1.0, 2.0])
    x, P = np.ones((2, 2)), np.ones((2, 2, 2))
    for since in ([2, 2], []):
        rows = len(since)
        gx, gP = replay(_step, x[:rows], P[:rows], since, times)
        assert np.array_equal(gx, x[:rows]) and np.array_equal(gP, P[:rows])
        assert gx is not x and gP is not P
    gx[...] = 7.0
    assert np.all(x == 1.0)


def test_predict_gap_is_one_prediction_over_each_rows_gap():
    motion = ConstantVelocity(q=0.3)
    t = [0.0, 2.0, 2.5, 6.0, 6.0, 9.0]
    times = _times(t)
    rng = np.random.default_rng(2)
    since = np.array([3, 0, 5, 1])
    x = rng.normal(0, 3, (4, 4))
    A = rng.normal(0, 1, (4, 4, 4))
    P = A @ np.swapaxes(A, 1, 2) + np.eye(4)
    gx, gP = predict_gap(motion, x, P, since, times)
    for i, s in enumerate(since):
        gap = t[-1] - t[s]
        if gap == 0:
            assert np.array_equal(gx[i], x[i]) and np.array_equal(gP[i], P[i])
            continue
        F = motion.F(gap)
        np.testing.assert_allclose(gx[i], F @ x[i], rtol=1e-12)
        np.testing.assert_allclose(gP[i], F @ P[i] @ F.T + motion.Q(gap), rtol=1e-12)
    # rows all deferred since later scans (the times read from the oldest one's on)
    late = np.array([4, 2, 3, 5])
    lx, lP = predict_gap(motion, x, P, late, times)
    for i, s in enumerate(late):
        gap = t[-1] - t[s]
        F = motion.F(gap) if gap else np.eye(4)
        np.testing.assert_allclose(lx[i], F @ x[i], rtol=1e-12)
        np.testing.assert_allclose(lP[i], F @ P[i] @ F.T + (motion.Q(gap) if gap else 0), rtol=1e-12)
    ex, eP = predict_gap(motion, x[:0], P[:0], [], times)
    assert ex.shape == (0, 4) and eP.shape == (0, 4, 4)


def test_scan_times_keep_absolute_indices_across_trimming():
    t = np.arange(200) * 1.5
    times = _times(t)
    assert len(times) == 200 and times.now == 199
    times.trim(30)  # a short head: kept, indices unchanged
    np.testing.assert_array_equal(times.since(10), t[10:])
    times.trim(100)
    assert len(times) == 200 and times.now == 199
    np.testing.assert_array_equal(times.since(120), t[120:])
    np.testing.assert_array_equal(times.since(100), t[100:])
    times.pop()
    assert times.now == 198
    np.testing.assert_array_equal(times.since(150), t[150:199])
    times.append(400.0)
    times.trim(180)
    np.testing.assert_array_equal(times.since(180), np.r_[t[180:199], 400.0])
    # replay after trimming reads the same times by absolute index
    x, P = np.zeros((1, 1)), np.ones((1, 1, 1))
    gx, _ = replay(_step, x, P, [197], times)
    want, _ = _brute(x, P, [0], np.r_[t[197:199], 400.0])
    np.testing.assert_allclose(gx, want, rtol=1e-14)

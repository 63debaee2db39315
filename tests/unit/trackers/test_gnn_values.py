"""GNN association on hand-built gain matrices: a many-track problem (more tracks than one joint
assignment takes) with lone, contested and returnless tracks, the Mahalanobis gains' missed
distance, the event vector's type and the messages of refused gains."""

import numpy as np
import pytest

from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.gnn import _JOINT_LIMIT, gnn_associate, mahalanobis_gains


def test_many_tracks_lone_contested_and_returnless():
    """More tracks than one joint assignment takes, 4 returns: return 0 alone in track 5's gate;
    returns 1 and 2 contest tracks 7 and 8 (1→7 + 2→8 = 4.5 beats 1→8 alone, 2.5, or 2→8 alone);
    return 3 in no gate; the other tracks have no return and stay unassigned."""
    n = _JOINT_LIMIT + 6
    assert n > _JOINT_LIMIT
    gain = np.full((4, n), -np.inf)
    gain[0, 5] = 3.0
    gain[1, 7], gain[1, 8], gain[2, 8] = 2.0, 1.0, 2.5
    a = gnn_associate(gain)
    np.testing.assert_array_equal(a, [5, 7, 8, -1])
    assert a.dtype == np.int64
    # the same answer from the small problem of the four useful tracks alone
    np.testing.assert_array_equal(gnn_associate(gain[:, [5, 7, 8]]), [0, 1, 2, -1])
    gain[2, 8] = 0.5  # now 1→8 (1.0) + nothing < 1→7 (2.0) + 2→8 (0.5)
    np.testing.assert_array_equal(gnn_associate(gain), [5, 7, 8, -1])
    gain[1, 7], gain[1, 8], gain[2, 8] = 0.4, 0.3, 0.2  # small gains: 1→7 + 2→8 (0.6) beats 1→8 alone (0.3)
    np.testing.assert_array_equal(gnn_associate(gain), [5, 7, 8, -1])
    gain[1, 7], gain[1, 8], gain[2, 8] = -np.inf, 1.0, 0.5  # 1→8 (1.0) beats 2→8 (0.5)
    np.testing.assert_array_equal(gnn_associate(gain), [5, 8, -1, -1])


def test_gnn_associate_messages_and_empty_problems():
    with pytest.raises(ValueError, match=r"^gain must have shape \(m, n\), got \(3,\)$"):
        gnn_associate(np.zeros(3))
    with pytest.raises(ValueError, match=r"^gain must not contain NaN or \+inf$"):
        gnn_associate([[np.nan]])
    assert gnn_associate(np.zeros((3, 0))).tolist() == [-1, -1, -1]
    assert gnn_associate(np.zeros((3, 0))).dtype == np.int64


def test_mahalanobis_gains_take_any_positive_missed_distance():
    H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    model = ScanModel(H, np.eye(2), 0.9, 0.99, 1e-3)
    x, P = np.zeros((1, 4)), np.eye(4)[None]
    gated = gate_tracks(x, P, np.array([[0.5, 0.0], [2.0, 0.0]]), model)  # S = 2 I: d = 0.354, 1.414
    d = np.sqrt([0.125, 2.0])
    np.testing.assert_allclose(mahalanobis_gains(gated, 0.5)[:, 0], [0.5 - d[0], -np.inf])
    np.testing.assert_allclose(mahalanobis_gains(gated, 3.0)[:, 0], 3.0 - d)
    for g in (0.0, -1.0, np.inf):
        with pytest.raises(ValueError, match="^missed_distance must be a finite number > 0"):
            mahalanobis_gains(gated, g)

"""The EKF replay with tracks side by side in vector lanes (:func:`hypotrack.models.orbit3d_replay.replay_lanes`) against
the replay one track at a time (:func:`hypotrack.models.orbit3d_replay._replay`): the same operations lane by lane,
so the means and covariances bit for bit on any machine — groups of equal and unequal gaps, of one and two RK4
substeps per step, a partly filled last group, groups left track by track, rows left as they are, and a state
through the Earth's centre inside a group named as the row-by-row replay names it."""

import numpy as np
import pytest

from hypotrack.models.orbit import _H_STEP
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.models.orbit3d_replay import LANE_GROUP_COST, LANES, _replay, replay_j2, replay_lanes



def leo(n, seed):
    """``n`` LEO states on circular orbits of random planes (radii 6,900–7,500 km) and SPD covariances."""
    rng = np.random.default_rng(seed)
    r = 6900 + rng.uniform(0, 600, n)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    w = np.cross(u, rng.normal(size=(n, 3)))
    w /= np.linalg.norm(w, axis=1)[:, None]
    X = np.hstack([u * r[:, None], w * np.sqrt(398600.8 / r)[:, None]])
    L = rng.normal(size=(n, 6, 6)) * np.r_[[0.5] * 3, [5e-4] * 3][None, :, None]
    P = L @ np.swapaxes(L, 1, 2) + np.diag([1e-2] * 3 + [1e-8] * 3)
    return X, 0.5 * (P + np.swapaxes(P, 1, 2))


def constants(model):
    return (float(model.max_step), float(model.q), float(model.mu), float(1.5 * model.j2 * model.mu * model.radius**2),
            _H_STEP)


def order_of(model, h, k):
    steps = np.flatnonzero(k > 0)
    return steps[np.lexsort((-k[steps], np.ceil(np.abs(h[steps]) / model.max_step)))]


def gaps(seed):
    """27 rows: 11 back after about an orbit (570 ± 12 steps of 10 s: one substep), 9 of 45 s (two substeps) over
    3–40 steps, 4 of one step, 3 left as they are (k = 0)."""
    rng = np.random.default_rng(seed)
    h = np.r_[np.full(11, 10.0), np.full(9, 45.0), np.full(4, 10.0), np.full(3, 10.0)]
    k = np.r_[rng.integers(558, 583, 11), rng.integers(3, 41, 9), np.ones(4), np.zeros(3)].astype(np.int64)
    p = rng.permutation(len(h))
    return h[p], k[p]


@pytest.mark.parametrize("q", [1e-8, 0.0])
def test_the_lanes_are_the_row_by_row_replay_bit_for_bit(q):
    model = J2Orbit3D(q=q)
    X, P = leo(27, 7)
    h, k = gaps(8)
    order = order_of(model, h, k)
    lanes = replay_lanes(X, P, h, k, order, *constants(model))
    rows = _replay(X, P, h, k, *constants(model))
    assert lanes[2] == rows[2] == -1
    np.testing.assert_array_equal(lanes[0], rows[0])
    np.testing.assert_array_equal(lanes[1], rows[1])
    np.testing.assert_array_equal(lanes[0][k == 0], X[k == 0])
    np.testing.assert_array_equal(lanes[1][k == 0], P[k == 0])
    # the public entry takes the lanes
    out = replay_j2(model, X, P, h, k)
    np.testing.assert_array_equal(out[0], rows[0])
    np.testing.assert_array_equal(out[1], rows[1])


def test_groups_in_lanes_and_track_by_track_alike():
    # one full group of equal gaps (in lanes: Σk = 8 kmax), one of a long gap and seven single steps (track by
    # track: Σk < LANE_GROUP_COST kmax) — whichever way a group goes, the row-by-row numbers
    model = J2Orbit3D(q=2e-8)
    X, P = leo(2 * LANES, 9)
    h = np.full(2 * LANES, 10.0)
    k = np.r_[np.full(LANES, 100), [300], np.ones(LANES - 1)].astype(np.int64)
    assert LANES * 100 >= LANE_GROUP_COST * 100 and 300 + LANES - 1 < LANE_GROUP_COST * 300
    lanes = replay_lanes(X, P, h, k, order_of(model, h, k), *constants(model))
    rows = _replay(X, P, h, k, *constants(model))
    np.testing.assert_array_equal(lanes[0], rows[0])
    np.testing.assert_array_equal(lanes[1], rows[1])


def test_a_state_through_the_centre_in_a_group_is_named_as_row_by_row():
    model = J2Orbit3D()
    X, P = leo(12, 10)
    X[[5, 9]] = 0.0  # both in the group of the eight longest gaps; row 5 the first
    h = np.full(12, 10.0)
    k = np.r_[np.full(10, 20), [1, 1]].astype(np.int64)
    lanes = replay_lanes(X, P, h, k, order_of(model, h, k), *constants(model))
    rows = _replay(X, P, h, k, *constants(model))
    assert lanes[2] == rows[2] == 5
    ok = np.r_[np.arange(5), [6, 7, 8, 10, 11]]  # the other rows still replayed in full
    np.testing.assert_array_equal(lanes[0][ok], _replay(X[ok], P[ok], h[ok], k[ok], *constants(model))[0])
    with pytest.raises(ValueError, match="x: state 5 .* non-finite"):
        replay_j2(model, X, P, h, k)

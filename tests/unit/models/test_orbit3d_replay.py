"""The compiled EKF replay of the J2 orbit (:mod:`hypotrack.models.orbit3d_replay`) against the array passes it
replaces (:func:`hypotrack.hypotheses.factored.lane.predict_each` scan by scan through ``transition``): the means
bit for bit, the covariances bit for bit where numpy and its BLAS round as the kernel does (``rounds_as_numpy``: this
machine) and to 1e-12 of their scale elsewhere, over gaps of 0, 1, a few and ~570 steps (an orbit's gap between
passes); one step against ``Φ P Φᵀ + Q`` written out; a state through the Earth's centre refused."""

from dataclasses import dataclass, fields

import numpy as np
import pytest

from hypotrack.hypotheses.factored.lane import predict_each
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.models.orbit3d_replay import replay_j2, rounds_as_numpy

BITWISE = rounds_as_numpy()


@dataclass(frozen=True)
class ArrayPasses(J2Orbit3D):
    """The same model without the compiled replay: ``predict_each`` takes its array passes, one batch a step."""

    replay_each = None


def array_passes(model: J2Orbit3D) -> ArrayPasses:
    return ArrayPasses(**{f.name: getattr(model, f.name) for f in fields(model)})


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


def close_to_scale(A, B, rel=1e-12):
    """Every matrix of ``A`` within ``rel`` of its largest entry of ``B``'s."""
    scale = np.abs(B).reshape(len(B), -1).max(axis=1)
    assert np.all(np.abs(A - B).reshape(len(B), -1).max(axis=1) <= rel * scale)


@pytest.mark.parametrize("q", [1e-8, 0.0])
def test_replay_matches_the_array_passes_over_short_and_orbit_long_gaps(q):
    model = J2Orbit3D(q=q)
    X, P = leo(14, 1)
    # 0 (left as is), 1 step, a step longer than max_step (two RK4 substeps each), non-integer, ~an orbit
    dt = np.array([0.0, 10.0, 20.0, 33.3, 120.0, 600.0, 5700.0, 5710.0, 45.0, 10.0, 0.0, 3880.0, 7.5, 1234.5])
    for s in (10.0, 45.0):
        old = predict_each(array_passes(model), X, P, dt, step=s)
        new = predict_each(model, X, P, dt, step=s)
        np.testing.assert_array_equal(new[0], old[0])  # the means: the same operations, bit for bit
        close_to_scale(new[1], old[1])
        if BITWISE:  # and the covariances, with numpy's and OpenBLAS's fused multiply-adds
            np.testing.assert_array_equal(new[1], old[1])
        np.testing.assert_array_equal(new[1], np.swapaxes(new[1], 1, 2))
        assert np.all(np.linalg.eigvalsh(new[1]) > 0)
        np.testing.assert_array_equal(new[0][dt == 0], X[dt == 0])
        np.testing.assert_array_equal(new[1][dt == 0], P[dt == 0])


def test_one_step_is_phi_p_phi_t_plus_q_written_out():
    model = J2Orbit3D(q=3e-8)
    X, P = leo(3, 2)
    h = np.array([10.0, 45.0, 7.0])
    x, F = model.transition_each(X, h)
    xo, Po = replay_j2(model, X, P, h, np.ones(3, dtype=np.int64))
    np.testing.assert_array_equal(xo, x)
    for i, t in enumerate(h):
        Q = 3e-8 * np.block([[t**3 / 3 * np.eye(3), t**2 / 2 * np.eye(3)], [t**2 / 2 * np.eye(3), t * np.eye(3)]])
        A = F[i] @ P[i] @ F[i].T + Q
        close_to_scale(Po[i][None], (0.5 * (A + A.T))[None])
    # k steps of h: the same as k single steps chained
    xk, Pk = replay_j2(model, X, P, h, np.full(3, 4, dtype=np.int64))
    x1, P1 = X, P
    for _ in range(4):
        x1, P1 = replay_j2(model, x1, P1, h, np.ones(3, dtype=np.int64))
    np.testing.assert_array_equal(xk, x1)
    np.testing.assert_array_equal(Pk, P1)


def test_a_state_through_the_centre_is_refused_and_no_rows_work():
    model = J2Orbit3D()
    X, P = leo(2, 3)
    X[1] = 0.0
    with pytest.raises(ValueError, match="x: state 1 .* non-finite"):
        replay_j2(model, X, P, np.array([10.0, 10.0]), np.array([2, 2]))
    x, P0 = replay_j2(model, np.zeros((0, 6)), np.zeros((0, 6, 6)), np.zeros(0), np.zeros(0, dtype=np.int64))
    assert x.shape == (0, 6) and P0.shape == (0, 6, 6)


def test_the_first_row_predicted_to_a_non_finite_state_is_named_and_a_row_left_as_is_is_not_tested():
    # row 0 at the centre but given no step (left as it is, as the array passes leave it); rows 2 and 3 at the
    # centre with steps: the first of them named, whatever the rows after it
    model = J2Orbit3D()
    X, P = leo(4, 4)
    X[0] = X[2] = X[3] = 0.0
    with pytest.raises(ValueError, match="x: state 2 .* non-finite"):
        replay_j2(model, X, P, np.full(4, 10.0), np.array([0, 3, 1, 2]))
    x, Po = replay_j2(model, X[:2], P[:2], np.full(2, 10.0), np.array([0, 3]))
    np.testing.assert_array_equal(x[0], X[0])
    np.testing.assert_array_equal(Po[0], P[0])
    ref = predict_each(array_passes(model), X[1:2], P[1:2], np.array([30.0]), step=10.0)
    np.testing.assert_array_equal(x[1:], ref[0])
    if BITWISE:
        np.testing.assert_array_equal(Po[1:], ref[1])

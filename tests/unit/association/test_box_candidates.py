"""The band-and-box candidate pairs are exactly the pairs a brute-force check over all (return, track) pairs finds
inside every half-width, with an angle wrapped by the residual, and hold every gated pair."""

import numpy as np

from hypotrack.association.gating import box_candidates


def _wrapped(Z_rows, z_pred):
    r = Z_rows - z_pred
    r[:, 1] = (r[:, 1] + np.pi) % (2 * np.pi) - np.pi
    return r


def test_box_candidates_are_the_brute_force_pairs_with_a_wrapped_angle():
    rng = np.random.default_rng(4)
    Z = np.column_stack([rng.uniform(0, 20, 60), rng.uniform(-np.pi, np.pi, 60)])
    z_pred = np.column_stack([rng.uniform(0, 20, 25), rng.uniform(-np.pi, np.pi, 25)])
    z_pred[0, 1] = np.pi - 0.01  # a track at the wrap: returns just past -pi are inside its box
    Z[0] = [z_pred[0, 0], -np.pi + 0.01]
    half = rng.uniform(0.5, 2.0, (25, 2)) * [1.0, 0.3]
    rows, cols = box_candidates(Z, z_pred, half, _wrapped)
    nu = _wrapped(np.repeat(Z, 25, axis=0), np.tile(z_pred, (60, 1))).reshape(60, 25, 2)
    want = np.all(np.abs(nu) <= half[None], axis=-1)
    got = np.zeros_like(want)
    got[rows, cols] = True
    assert np.array_equal(got, want) and len(rows) == want.sum() and got[0, 0]
    assert 0 < want.sum() < want.size / 4  # far fewer than all pairs, and some
    # every pair of a gate of radius sqrt(gamma) in a diagonal S is inside the box built from that S
    S = half**2 / 9.0
    d2 = np.sum(nu**2 / S[None], axis=-1)
    assert np.all(got[d2 <= 9.0])

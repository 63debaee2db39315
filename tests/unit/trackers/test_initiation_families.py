"""M-of-N mixture initiation, by hand on a 2-D constant-velocity case with q = 0 and ``S = I``: the family labels
(one per return sent to the initiator, counted over the run), the scores ``log w_c + Σ gains`` (the gains decide
against the prior weights), a confirmed sibling dropping its family and no other, a tentative sibling leaving the
admissible set dropped before it confirms; the per-track arrays stay aligned and integer in every case."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.trackers import MOfNInitiator, ScanModel

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
R = 0.5 * np.eye(2)
P_D, P_G, BETA = 0.5, 0.999, 1e-3
MODEL = ScanModel(H, R, P_D, P_G, BETA)
MOTION = ConstantVelocity(0.0)  # no process noise: the predictions below are F x, F P Fᵀ exactly
COV = np.diag([0.25, 0.25, 0.25, 0.25])  # after one second: position variance 0.25 + 0.25, so S = 0.5 + R = I


class TwoWay:
    """Two components at the return, velocity (+1, 0) with weight ``w[0]`` and (−1, 0) with ``w[1]``."""

    def __init__(self, w=(0.5, 0.5), admissible=None):
        self.w = np.asarray(w, dtype=float)
        if admissible is not None:
            self.admissible = admissible

    def components(self, z):
        means = np.array([[z[0], z[1], 1.0, 0.0], [z[0], z[1], -1.0, 0.0]])
        return self.w.copy(), means, np.stack([COV, COV])


def gain(d2, S_var=1.0):
    """The lecture's gain ``ln P_D + ln N(ν; 0, S) − ln(1 − P_D P_G) − ln β_EX`` for ``S = S_var I₂``, ``|ν|²_S = d2``."""
    return np.log(P_D) - np.log(2 * np.pi * S_var) - d2 / 2 - np.log(1 - P_D * P_G) - np.log(BETA)


def check_aligned(init):
    k = len(init.x)
    assert init.P.shape == (k, 4, 4)
    for name in ("hits", "age", "family"):
        a = getattr(init, name)
        assert a.shape == (k,) and a.dtype == np.int64, name
    assert init.score.shape == (k,) and init.score.dtype == np.float64


@pytest.mark.parametrize("mixture", [None, TwoWay()])
def test_the_per_track_arrays_stay_aligned_and_integer(mixture):
    """Built, after births, after a scan that confirms one track and leaves others tentative, after an empty scan."""
    init = MOfNInitiator(MOTION, MODEL, m=2, n=3, initial_velocity_std=0.5, mixture=mixture)
    check_aligned(init)
    assert len(init) == 0
    for t, Z in ((0.0, [[0.0, 0.0], [50.0, 0.0]]), (1.0, [[1.0, 0.0]]), (2.0, np.zeros((0, 2)))):
        init.step(t, Z)
        check_aligned(init)


def test_gains_add_to_the_scores_and_outweigh_the_prior_weights():
    """m = n = 3. Scan 1: sibling A (w = 0.6) takes a return 1.5 off its prediction (|ν|² = 2.25), B (w = 0.4) one
    on its prediction: scores ln 0.6 + g(2.25), ln 0.4 + g(0). Scan 2: both take returns on their predictions
    (equal gains, S = 1.1875 I), both confirm, and B — the lighter prior, the better returns — is the one output."""
    init = MOfNInitiator(MOTION, MODEL, m=3, n=3, mixture=TwoWay((0.6, 0.4)))
    init.step(0.0, [[0.0, 0.0]])
    x, _ = init.step(1.0, [[1.0, 1.5], [-1.0, 0.0]])  # A predicted at (1, 0), B at (−1, 0)
    assert len(x) == 0 and init.hits.tolist() == [2, 2] and init.family.tolist() == [0, 0]
    np.testing.assert_allclose(init.score, [np.log(0.6) + gain(2.25), np.log(0.4) + gain(0.0)], rtol=1e-12)
    # A after its update: gain K = [0.5, 0.25] per axis, so y = 0 + 0.5·1.5, vy = 0 + 0.25·1.5; predicted (2, 1.125)
    np.testing.assert_allclose(init.x[0], [1.0, 0.75, 1.0, 0.375], atol=1e-12)
    x, P = init.step(2.0, [[2.0, 1.125], [-2.0, 0.0]])
    assert len(x) == 1 and len(init) == 0
    # B updated at zero innovation: per axis P_pred = [[0.6875, 0.3125], [0.3125, 0.1875]], S = 1.1875
    np.testing.assert_allclose(x[0], [-2.0, 0.0, -1.0, 0.0], atol=1e-12)
    Pp = np.array([[0.6875, 0.3125], [0.3125, 0.1875]])
    K = Pp[:, 0] / 1.1875
    Pu = Pp - np.outer(K, K) * 1.1875
    np.testing.assert_allclose(P[0][np.ix_([0, 2], [0, 2])], Pu, atol=1e-12)
    np.testing.assert_allclose(P[0][np.ix_([1, 3], [1, 3])], Pu, atol=1e-12)


def test_a_confirmed_sibling_drops_its_family_and_only_its_family():
    """m = 2, n = 3. Families: 0 from (100, 0) at t = 0; 1 from (0, 0) and 2 from (−100, 0) at t = 1. At t = 2 the
    return (1, 0) confirms family 1's +1 sibling; its −1 sibling (alive, 1 hit in 2 scans) goes with it; family 0
    (1 hit in 3 scans) has died; family 2 (1 hit in 2 scans) stays whole."""
    init = MOfNInitiator(MOTION, MODEL, m=2, n=3, mixture=TwoWay())
    init.step(0.0, [[100.0, 0.0]])
    init.step(1.0, [[0.0, 0.0], [-100.0, 0.0]])
    assert init.family.tolist() == [0, 0, 1, 1, 2, 2]
    x, _ = init.step(2.0, [[1.0, 0.0]])
    np.testing.assert_allclose(x, [[1.0, 0.0, 1.0, 0.0]], atol=1e-12)
    assert init.family.tolist() == [2, 2]
    np.testing.assert_allclose(init.x[:, :3], [[-99.0, 0.0, 1.0], [-101.0, 0.0, -1.0]], atol=1e-12)
    assert init.hits.tolist() == [1, 1] and init.age.tolist() == [2, 2]
    init.step(3.0, [[7.0, 7.0], [8.0, -8.0], [9.0, 9.0]])  # family labels go on counting the returns: 3, 4, 5
    assert init.family.tolist() == [3, 3, 4, 4, 5, 5]


@pytest.mark.parametrize("as_int", [False, True])
def test_a_tentative_sibling_leaving_the_admissible_set_is_dropped_before_it_confirms(as_int):
    """m = 3: after scan 1 both siblings are tentative (2 hits); the −1 sibling's mean is outside ``vx > 0`` and is
    dropped, the +1 one kept. The admissible mask may come as 0/1 integers: it is read as booleans."""
    def admissible(X):
        ok = X[:, 2] > 0
        return ok.astype(np.int64) if as_int else ok

    init = MOfNInitiator(MOTION, MODEL, m=3, n=3, mixture=TwoWay((0.3, 0.7), admissible=admissible))
    init.step(0.0, [[0.0, 0.0]])
    x, _ = init.step(1.0, [[1.0, 0.0], [-1.0, 0.0]])
    assert len(x) == 0 and len(init) == 1
    np.testing.assert_allclose(init.x[0], [1.0, 0.0, 1.0, 0.0], atol=1e-12)
    assert init.hits.tolist() == [2] and init.family.tolist() == [0]
    x, _ = init.step(2.0, [[2.0, 0.0]])
    np.testing.assert_allclose(x, [[2.0, 0.0, 1.0, 0.0]], atol=1e-12)
    assert len(init) == 0


def test_set_model_checks_its_arguments():
    init = MOfNInitiator(MOTION, MODEL, mixture=TwoWay())
    with pytest.raises(TypeError, match=r"^mixture must have components\(z\) -> \(weights, means, covs\), got int$"):
        init.set_model(MODEL, 3)
    with pytest.raises(TypeError, match=r"^model must be a ScanModel, got str$"):
        init.set_model("model")
    with pytest.raises(ValueError, match=r"^model must have state dimension 4, got 6$"):
        init.set_model(ScanModel(np.eye(2, 6), R, P_D, P_G, BETA))


def test_a_sensor_without_a_mixture_starts_one_point_tracks_each_its_own_family():
    """Two fused sensors, one with the mixture and one without: ``set_model(model, None)`` starts one-point tracks
    (not the other sensor's mixture), and two of them confirming at the mixture sensor's next scan both confirm (a
    shared family label would have let only the better-scored one through and dropped the other)."""
    init = MOfNInitiator(MOTION, MODEL, m=2, n=3, initial_velocity_std=0.5, mixture=TwoWay())
    init.set_model(MODEL, None)
    init.step(0.0, [[0.0, 0.0], [30.0, 0.0]])
    assert init.mixture is None and len(init) == 2  # one-point starts: one track per return, not two per return
    assert len(set(init.family.tolist())) == 2
    np.testing.assert_array_equal(init.x[:, 2:], 0.0)
    init.set_model(MODEL, TwoWay())
    x, _ = init.step(1.0, [[0.0, 0.0], [30.0, 0.0]])
    assert len(x) == 2
    np.testing.assert_allclose(np.sort(x[:, 0]), [0.0, 30.0])
    assert len(init) == 0  # both returns went to the confirmed tracks: nothing left to start

"""The PDAF's "all_at_once" form (one PDA update per scan with all 2N returns as candidates, variance R each) and
its "jpda" form (two tracks coupled, sensor after sensor: lecture 004 Eq. (1), then each track's PDA update
with its marginals, Eqs. 5.14–5.17) by hand on a two-sensor scan of two runs, one where the straight assignment is
the likelier and one where the crossed one is; and a run whose crossed assignment is certain (the weights' ratio
beyond e^700) gives each track the other return exactly."""

import math

import numpy as np
import pytest

from hypotrack.models import OrnsteinUhlenbeck
from hypotrack.trackers.ecmht import ECMHTFilter, PDAFilter

SIGMA2, GAMMA, R = 0.02, 0.01, 0.5
MODEL = OrnsteinUhlenbeck(SIGMA2, GAMMA)
A = math.exp(-GAMMA)
Q = SIGMA2 / (2 * GAMMA) * (1 - A * A)  # Eq. 5.3 with dt = 1


def _pair_update(x, P, returns):
    """Both tracks' update with one sensor's two returns, written out with the Gaussian densities."""
    S = [P[0] + R, P[1] + R]

    def g(z, j):
        return math.exp(-((z - x[j]) ** 2) / (2 * S[j])) / math.sqrt(2 * math.pi * S[j])

    straight = g(returns[0], 0) * g(returns[1], 1)
    crossed = g(returns[1], 0) * g(returns[0], 1)
    b = straight / (straight + crossed)
    out = []
    for j, beta in ((0, (b, 1 - b)), (1, (1 - b, b))):
        L = P[j] / (P[j] + R)
        nus = [z - x[j] for z in returns]
        nu_c = sum(w * v for w, v in zip(beta, nus))
        spread = sum(w * v * v for w, v in zip(beta, nus)) - nu_c**2
        out.append((x[j] + L * nu_c, (1 - L) * P[j] + L * L * spread))
    return [o[0] for o in out], [o[1] for o in out], b


def test_two_sensors_by_hand():
    f = PDAFilter(MODEL, R, 2, variant="jpda")
    # run 0: tracks at (−0.5, 1.5); run 1: at (0, 3); P = R/2 (Eqs. 6.1–6.3)
    f.step(np.array([[[0.0, 2.0], [-1.0, 1.0]], [[0.5, 2.5], [-0.5, 3.5]]]))
    scan = np.array([[[-0.2, 0.9], [1.4, -0.6]], [[2.4, 0.2], [0.1, 2.9]]])  # (runs, sensors, returns)
    got = f.step(scan)
    for run, start in enumerate(((-0.5, 1.5), (0.0, 3.0))):
        x, P = [A * v for v in start], [A * A * R / 2 + Q] * 2
        bs = []
        for n in range(2):
            x, P, b = _pair_update(x, P, scan[run, n])
            bs.append(b)
        np.testing.assert_allclose(got[run], x, rtol=1e-12)
        np.testing.assert_allclose(f.P[run], P, rtol=1e-12)
        if run == 0:  # sensor 1 lists the returns in the crossed order: both forms are exercised
            assert bs[0] > 0.5 > bs[1]


def test_a_certain_crossed_assignment_takes_the_other_return():
    """Tracks at (0, 100), returns listed (100, 0): the straight assignment's log weight is about 2·100²/(2S) below
    the crossed one (far beyond e^700), so each track takes the return at its own place as with probability one
    (track 0 to within 1e-300: the ratio is clipped at e^700, not overflowed)."""
    f = PDAFilter(MODEL, R, 1, variant="jpda")
    f.step(np.array([[[0.0, 100.0]]]))
    with np.errstate(over="raise"):  # the weights' ratio is clipped, not overflowed
        got = f.step(np.array([[[100.0, 0.0]]]))
    P = A * A * R + Q
    L = P / (P + R)
    assert abs(got[0, 0]) < 1e-300
    assert got[0, 1] == pytest.approx(A * 100.0 + L * (100.0 - A * 100.0), rel=1e-12)
    np.testing.assert_allclose(f.P[0], [(1 - L) * P] * 2, rtol=1e-12)


def test_rejects_a_scan_of_another_shape():
    f = PDAFilter(MODEL, R, 2, variant="jpda")
    with pytest.raises(ValueError):
        f.step(np.zeros((1, 3, 2)))


def test_all_at_once_two_sensors_by_hand():
    """Each track weighs the scan's four returns ``w_i ∝ exp(−(z_i − x)²/(2(P + R)))`` and takes the PDA update."""
    f = PDAFilter(MODEL, R, 2, variant="all_at_once")  # three runs, two sensors: the runs' returns kept apart
    f.step(np.array([[[0.0, 2.0], [-1.0, 1.0]], [[0.5, 2.5], [-0.5, 3.5]], [[1.0, 1.0], [1.0, 1.0]]]))
    scan = np.array([[[-0.2, 0.9], [0.1, 1.6]], [[2.4, 0.2], [0.1, 2.9]], [[0.7, 1.5], [1.1, 0.8]]])
    got = f.step(scan)
    Pp = A * A * R / 2 + Q
    L = Pp / (Pp + R)
    for run, start in enumerate(((-0.5, 1.5), (0.0, 3.0), (1.0, 1.0))):
        returns = scan[run].ravel()
        for j in range(2):
            m = A * start[j]
            w = [math.exp(-((z - m) ** 2) / (2 * (Pp + R))) for z in returns]
            beta = [v / sum(w) for v in w]
            nu_c = sum(b * (z - m) for b, z in zip(beta, returns))
            spread = sum(b * (z - m) ** 2 for b, z in zip(beta, returns)) - nu_c**2
            assert got[run, j] == pytest.approx(m + L * nu_c, rel=1e-12)
            assert f.P[run, j] == pytest.approx((1 - L) * Pp + L * L * spread, rel=1e-12)


def test_ecmht_names_its_seed_in_errors():
    with pytest.raises(ValueError, match=r"^rng must be an integer >= 0, got -1$"):
        ECMHTFilter(MODEL, R, 2, rng=-1)

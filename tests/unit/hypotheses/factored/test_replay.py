"""``replay``: a lazy factored filter that predicts a woken track over its gap scan by scan holds the eager
filter's posterior on an orbit, where the lazy one-step prediction does not.

Three objects on one equatorial circular orbit 12 km apart in-track, known at t = 0 just past a slab-shaped
field of view (x > 4,000 km), out of view for 68 min (410 scans of 10 s), then one scan with a return near
each: three tracks and three returns in one gate. The eager filter predicts every scan; the lazy one only
advances the means and predicts the tracks once they may be seen, in one step or (``replay``) scan by scan.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import FactoredFilter, ReidWeights
from hypotrack.hypotheses import ExhaustiveGenerator
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

MOTION = J2Orbit3D(q=1e-9)
VIEW = Box([4000.0, -7500.0, -3000.0], [7500.0, 7500.0, 3000.0])
R = 0.25 * np.eye(3)
SENSOR = Sensor(LinearPositionSensor(R, 6, (0, 1, 2)), DetectionModel(0.9, VIEW), PoissonClutter(1.0, VIEW))
DT, N_DARK = 10.0, 410
_r = 7000.0
_u = np.radians(58.0) + np.array([0.0, 12.0, 24.0]) / _r  # just past the view (x = r cos u < 4,000 km)
X0 = np.column_stack([_r * np.cos(_u), _r * np.sin(_u), np.zeros(3), -np.sqrt(398600.4418 / _r) * np.sin(_u),
                      np.sqrt(398600.4418 / _r) * np.cos(_u), np.zeros(3)])
P0 = np.broadcast_to(np.diag([0.25] * 3 + [2.5e-7] * 3), (3, 6, 6)).copy()


def _run(**options):
    f = FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), means=X0, covs=P0,
                       labels=[0, 1, 2], gate_probability=0.999, **options)
    X = X0.copy()
    for k in range(1, N_DARK + 1):
        X = MOTION.propagate(X, DT)
        f.step(np.zeros((0, 3)), k * DT)
    X = MOTION.propagate(X, DT)
    assert SENSOR.detection.in_view(X[:, :3]).all()
    Z = X[:, :3] + np.array([[0.3, -0.2, 0.1], [-0.1, 0.4, -0.3], [0.2, 0.1, 0.2]])
    f.step(Z, (N_DARK + 1) * DT)
    (g,) = f.groups  # the three objects shared the returns: one group
    return f, g, Z


@pytest.fixture(scope="module")
def runs():
    return {name: _run(**opts) for name, opts in (("eager", {}), ("lazy", dict(lazy=True, gate_out_of_view=False)),
                                                  ("replay", dict(lazy=True, gate_out_of_view=False, replay=True)))}


def test_all_dark_then_one_gate_of_three(runs):
    f, g, Z = runs["eager"]
    assert not SENSOR.detection.in_view(X0[:, :3]).any()
    assert f.last_stats["largest_group"] == 3 and len(g.log_w) > 6  # every return open to every track


def test_replay_holds_the_eager_posterior(runs):
    _, ge, _ = runs["eager"]
    fr, gr, _ = runs["replay"]
    assert fr.stats_history[0]["n_predicted"] == 0  # the replaying filter did not predict while dark
    np.testing.assert_allclose(np.sort(gr.log_w), np.sort(ge.log_w), atol=1e-8)
    np.testing.assert_allclose(gr.store.means, ge.store.means, atol=1e-6)
    np.testing.assert_allclose(gr.store.covs, ge.store.covs, rtol=1e-7, atol=1e-12)


def test_one_step_lazy_prediction_is_another_posterior(runs):
    _, ge, _ = runs["eager"]
    _, gl, _ = runs["lazy"]
    # the one-step Q(4,110 s) is isotropic where the scan-by-scan noise is sheared along the track
    assert np.max(np.abs(np.sort(gl.log_w) - np.sort(ge.log_w))) > 0.1


def test_the_map_track_is_the_hand_computed_ekf(runs):
    # by hand: object 0's prior predicted scan by scan over 411 scans of 10 s, one Kalman update with its return
    _, g, Z = runs["replay"]
    x, P = X0[[0]], P0[0]
    for _ in range(N_DARK + 1):
        x, F = MOTION.transition(x, DT)
        P = F[0] @ P @ F[0].T + MOTION.Q(DT)
    H = np.hstack([np.eye(3), np.zeros((3, 3))])
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    xu, Pu = x[0] + K @ (Z[0] - H @ x[0]), (np.eye(6) - K @ H) @ P
    best = g.tracks[int(np.argmax(g.log_w))]
    (j,) = [i for i in best if g.store.labels[i] == 0]
    np.testing.assert_allclose(g.store.means[j], xu, atol=1e-6)
    np.testing.assert_allclose(g.store.covs[j], Pu, rtol=1e-6, atol=1e-10)

"""The Stone Soup side of the side-by-side timings (:class:`hypotrack.interop.stonesoup.peer.StoneSoupPeer`)
solves the same problem as hypotrack's stepper: on a formation of closely spaced targets in
clutter (the perf_sht scenario, 8 targets, neighbours sharing returns) Stone Soup's GNN gives the
same return-to-track assignment at every scan and its JPDA the same association probabilities,
with the same states to rounding — and the states come back in hypotrack's order (the
[x, y, vx, vy] ↔ [x, vx, y, vy] permutation is undone; a wrong inverse would move velocities
into positions and fail the state comparison)."""

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity as CV  # noqa: E402
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402

from hypotrack.experiments.perf_sht.run import HypotrackStepper, formation, prior_covariance, scan_model  # noqa: E402
from hypotrack.experiments.stepping import max_abs_difference, run_side_by_side  # noqa: E402
from hypotrack.interop.stonesoup.peer import StoneSoupPeer  # noqa: E402

CFG = dict(spacing=8.0, speed=10.0, n_scans=6, dt=1.0, q_truth=0.5, sigma=5.0, p_D=0.9, margin=100.0, q=0.5,
           p_gate=0.95, prior_position_std=5.0, prior_velocity_std=2.0)


def _peer(sc, kind, perm=(0, 2, 1, 3)):
    n = len(sc.initial_states)
    predictor = KalmanPredictor(CombinedLinearGaussianTransitionModel([CV(CFG["q"]), CV(CFG["q"])]))
    return StoneSoupPeer(kind, predictor, scan_model(sc, CFG), (0, 2), sc.initial_states,
                         np.broadcast_to(prior_covariance(CFG), (n, 4, 4)), sc.scan_list(), perm=list(perm))


@pytest.mark.parametrize("algorithm,kind", [("gnn", "GNNWith2DAssignment"), ("jpda", "JPDAwithEHM2")])
def test_peer_solves_the_same_problem(algorithm, kind):
    sc = formation(8, 5.0, CFG, 3)
    runs = run_side_by_side({"hypotrack": HypotrackStepper(sc, algorithm, CFG), kind: _peer(sc, kind)},
                            len(sc.times), warmup=False)
    ours, peer = runs["hypotrack"], runs[kind]
    assert len(ours.outputs) == len(peer.outputs) == len(sc.times) - 1
    d_out, d_state = max_abs_difference(ours, peer)
    assert d_out <= 1e-9 and d_state <= 1e-6
    if algorithm == "gnn":  # the scene has power: some return is left unassigned and several are assigned
        assert any((o < 0).any() and (o >= 0).sum() >= 3 for o in ours.outputs)
    else:
        assert any(((o > 0.05) & (o < 0.95)).sum() >= 2 for o in ours.outputs)  # genuinely shared returns


def test_peer_bad_kind():
    sc = formation(2, 1.0, CFG, 3)
    with pytest.raises(ValueError, match="kind"):
        _peer(sc, "MHT")


@pytest.mark.parametrize("dt", [10.0, 600.0])
def test_orbit_transition_model_is_hypotracks_motion_model(dt):
    """The Stone Soup wrapper of an orbit model (the catalogue peers' EKF dynamics) gives hypotrack's
    propagation as ``function``, its state-transition matrix as ``jacobian`` and ``Q(dt)`` as ``covar``,
    over one scan (10 s: one RK4 step) and over a gap of many steps (600 s: J2 moves the state by
    metres); Stone Soup's EKF predictor on it is hypotrack's EKF prediction."""
    import datetime

    from stonesoup.predictor.kalman import ExtendedKalmanPredictor
    from stonesoup.types.state import GaussianState, State

    from hypotrack.interop.stonesoup.transition import orbit_transition_model
    from hypotrack.models.orbit3d import J2Orbit3D, TwoBodyOrbit3D

    motion = J2Orbit3D(q=1e-9)
    x = np.array([6800.0, 1200.0, 900.0, -1.1, 5.2, 5.3])  # LEO, inclined: J2 acts on every component
    step = datetime.timedelta(seconds=dt)
    model = orbit_transition_model(motion)
    assert model.ndim_state == 6
    xp, F = motion.transition(x[None], dt)
    np.testing.assert_allclose(np.ravel(model.function(State(x.reshape(-1, 1)), time_interval=step)),
                               motion.propagate(x, dt), rtol=1e-12, atol=0)
    np.testing.assert_allclose(model.jacobian(State(x.reshape(-1, 1)), time_interval=step), F[0], rtol=1e-12, atol=0)
    np.testing.assert_array_equal(model.covar(time_interval=step), motion.Q(dt))
    # not two-body: the J2 term is wrapped, not dropped
    assert np.linalg.norm(motion.propagate(x, dt)[:3] - TwoBodyOrbit3D(q=1e-9).propagate(x, dt)[:3]) > 1e-4

    t0 = datetime.datetime(2026, 1, 1)
    P = np.diag([1.0, 1.0, 1.0, 1e-3, 1e-3, 1e-3])
    pred = ExtendedKalmanPredictor(model).predict(GaussianState(x.reshape(-1, 1), P, timestamp=t0), timestamp=t0 + step)
    np.testing.assert_allclose(np.ravel(pred.state_vector), xp[0], rtol=1e-12, atol=0)
    np.testing.assert_allclose(pred.covar, F[0] @ P @ F[0].T + motion.Q(dt), rtol=1e-10, atol=1e-15)

"""The complete single-hypothesis tracker and its M-of-N initiator on worked scans: which return
updates which track under each association, deletion after the default number of misses, the
fresh state and the integer attributes, and the messages of refused input."""

import numpy as np
import pytest

from hypotrack.gaussian import update
from hypotrack.models import ConstantVelocity
from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.gnn import gnn_associate, gnn_gains
from hypotrack.trackers.initiation import MOfNInitiator
from hypotrack.trackers.jpda import jpda_log_weights, jpda_probabilities, pda_update, pdaf_probabilities
from hypotrack.trackers.tracker import SingleHypothesisTracker

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
MOTION = ConstantVelocity(0.1)
P1 = np.diag([1.0, 1.0, 0.5, 0.5])


def model(beta_fa=1e-3, p_D=0.9):
    return ScanModel(H, np.eye(2), p_D, 0.99, beta_fa)


def one_track(mdl, **kw):
    tr = SingleHypothesisTracker(MOTION, mdl, **kw)
    tr.initialise([[0.0, 0.0, 0.0, 0.0]], [P1], time=0.0)
    return tr


def test_lecture_score_leaves_a_costly_return_to_clutter_where_mahalanobis_assigns_it():
    """d = 2 inside the gate (g = √9.21 = 3.03) but dense clutter: the lecture's gain
    log(P_D N / ((1 − P_D P_G) β_EX)) < 0, so GNN leaves the return to EX; Stone Soup's criterion
    (g − d > 0) assigns it."""
    mdl = model(beta_fa=0.2)
    z = np.array([[2.0 * np.sqrt(2.0), 0.0]])  # S = 2 I at dt = 0, so d² = 8 / 2 = 4
    lecture, maha = one_track(mdl), one_track(mdl, gnn_score="mahalanobis")
    assert lecture.gnn_score == "lecture"
    gain = np.log(0.9) - 0.5 * (4 + np.log(4.0) + 2 * np.log(2 * np.pi)) - np.log1p(-0.9 * 0.99) - np.log(0.2)
    assert gain < 0  # ≈ −0.81
    est = lecture.step(z, 0.0)
    np.testing.assert_array_equal(lecture.last_association, [-1])
    np.testing.assert_array_equal(est.x, [[0.0, 0.0, 0.0, 0.0]])
    np.testing.assert_array_equal(lecture.misses, [1])
    est = maha.step(z, 0.0)
    np.testing.assert_array_equal(maha.last_association, [0])
    x_kf, P_kf = update(np.zeros(4), P1, z[0], H, np.eye(2))
    np.testing.assert_allclose(est.x[0], x_kf, atol=1e-12)
    np.testing.assert_allclose(est.P[0], P_kf, atol=1e-12)
    np.testing.assert_array_equal(maha.misses, [0])
    # a tighter missed distance (g = 1.5 < d) rejects the pair again
    tight = one_track(mdl, gnn_score="mahalanobis", missed_distance=1.5)
    tight.step(z, 0.0)
    np.testing.assert_array_equal(tight.last_association, [-1])


def two_tracks_three_returns(association):
    """Tracks at (0, 0) and (5, 0); one return in both gates, one near each and one far away."""
    mdl = model()
    tr = SingleHypothesisTracker(MOTION, mdl, association=association)
    P = np.stack([P1, P1])
    tr.initialise([[0.0, 0, 0, 0], [5.0, 0, 0, 0]], P, time=0.0)
    Z = np.array([[2.4, 0.2], [-0.5, -0.3], [5.3, 0.4], [40.0, 40.0]])
    return tr, mdl, Z


@pytest.mark.parametrize("association", ["gnn", "jpda", "pdaf"])
def test_each_association_updates_with_its_own_rule(association):
    tr, mdl, Z = two_tracks_three_returns(association)
    x0, P0 = tr.x.copy(), tr.P.copy()
    est = tr.step(Z, 1.0)
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    x_pred = x0 @ F.T
    P_pred = F @ P0 @ F.T + Q
    gated = gate_tracks(x_pred, P_pred, Z, mdl)
    np.testing.assert_array_equal(gated.valid, [[True, True], [True, False], [False, True], [False, False]])
    if association == "gnn":
        a = gnn_associate(gnn_gains(gated, mdl))
        np.testing.assert_array_equal(a, [-1, 0, 1, -1])  # the middle return is left to EX
        np.testing.assert_array_equal(tr.last_association, a)
        for t, i in ((0, 1), (1, 2)):
            x_kf, P_kf = update(x_pred[t], P_pred[t], Z[i], H, mdl.R)
            np.testing.assert_allclose(est.x[t], x_kf, atol=1e-10)
            np.testing.assert_allclose(est.P[t], P_kf, atol=1e-10)
    else:
        lw = jpda_log_weights(gated, mdl)
        beta_j, beta_p = jpda_probabilities(gated, mdl), pdaf_probabilities(lw)
        assert np.abs(beta_j - beta_p).max() > 0.02  # the shared returns make JPDA and PDAF differ
        beta = beta_j if association == "jpda" else beta_p
        np.testing.assert_allclose(tr.last_association, beta, atol=1e-12)
        x_u, P_u = pda_update(gated, beta, mdl)
        np.testing.assert_allclose(est.x, x_u, atol=1e-10)
        np.testing.assert_allclose(est.P, P_u, atol=1e-10)
    np.testing.assert_array_equal(tr.misses, [0, 0])
    assert est.time == 1.0 and tr.last_gated.n_meas == 4


@pytest.mark.parametrize("association", ["gnn", "jpda"])
def test_default_deletion_after_three_missed_scans(association):
    tr = one_track(model(), association=association)
    empty = np.zeros((0, 2))
    assert [len(tr.step(empty, float(k))) for k in (1, 2, 3)] == [1, 1, 0]
    assert tr.max_misses == 3


def test_run_is_step_over_the_scans():
    scans = [(1.0, np.array([[0.1, 0.0]])), (2.0, np.zeros((0, 2))), (3.0, np.array([[0.3, 0.1], [9.0, 9.0]]))]
    a, b = one_track(model()), one_track(model())
    ran = a.run(scans)
    stepped = [b.step(Z, t) for t, Z in scans]
    assert len(ran) == 3
    for r, s in zip(ran, stepped):
        assert r.time == s.time
        np.testing.assert_array_equal(r.ids, s.ids)
        np.testing.assert_array_equal(r.x, s.x)


def test_fresh_tracker_state_and_integer_ids():
    tr = SingleHypothesisTracker(MOTION, model())
    assert tr.last_gated is None and tr.last_association is None
    est = tr.estimates()
    assert est.time == -np.inf and len(est) == 0
    assert tr.ids.dtype == np.int64 and tr.misses.dtype == np.int64
    ids = tr.initialise(np.zeros((2, 4)), np.stack([P1, P1]), time=5.0)
    np.testing.assert_array_equal(ids, [0, 1])
    assert ids.dtype == np.int64 and tr.ids.dtype == np.int64 and tr.misses.dtype == np.int64
    assert tr.initialise(np.zeros((0, 4)), np.zeros((0, 4, 4)), time=5.0).shape == (0,)
    np.testing.assert_array_equal(tr.initialise([[1.0, 1.0, 0.0, 0.0]], P1, time=5.0), [2])  # same time: allowed
    with pytest.raises(ValueError, match=r"^time: initialise\(\) must be called before the first scan or at the "
                                         r"current time 5.0, got 6.0$"):
        tr.initialise([[1.0, 1.0, 0.0, 0.0]], P1, time=6.0)
    with pytest.raises(ValueError, match="^covs must hold one covariance per track: 2 means, 1 covariances$"):
        tr.initialise(np.zeros((2, 4)), P1, time=5.0)


def test_tracker_messages_name_the_argument():
    mdl = model()
    with pytest.raises(TypeError, match="^model must be a ScanModel, got dict$"):
        SingleHypothesisTracker(MOTION, {})
    with pytest.raises(ValueError, match="^gnn_score must be 'lecture' or 'mahalanobis', got 'x'$"):
        SingleHypothesisTracker(MOTION, mdl, gnn_score="x")
    with pytest.raises(TypeError, match="^initiator must be an MOfNInitiator or None, got str$"):
        SingleHypothesisTracker(MOTION, mdl, initiator="x")
    other = ScanModel(np.eye(4)[:3], np.eye(3), 0.9, 0.99, 1e-3)
    with pytest.raises(ValueError, match=r"^initiator's scan model has H of shape \(3, 4\), the tracker's \(2, 4\)"):
        SingleHypothesisTracker(MOTION, mdl, initiator=MOfNInitiator(MOTION, other))
    with pytest.raises(TypeError, match=r"^time is required: step\(Z, time\)"):
        SingleHypothesisTracker(MOTION, mdl).step(np.zeros((0, 2)))
    with pytest.raises(TypeError, match=r"got a \(time, Z\) pair"):
        SingleHypothesisTracker(MOTION, mdl).step((1.0, np.zeros((0, 2))))


def test_fresh_initiator_is_empty_with_integer_counters_and_default_p0():
    mdl = model()
    init = MOfNInitiator(MOTION, mdl)
    assert len(init) == 0 and init.x.shape == (0, 4) and init.P.shape == (0, 4, 4)
    assert init.hits.shape == (0,) and init.age.shape == (0,)
    assert init.hits.dtype == np.int64 and init.age.dtype == np.int64
    init.step(0.0, [[1.0, 2.0]])
    assert len(init) == 1
    np.testing.assert_array_equal(init.x, [[1.0, 2.0, 0.0, 0.0]])
    np.testing.assert_allclose(init.P[0], np.diag([1.0, 1.0, 100.0, 100.0]), atol=1e-12)  # default σ_v = 10
    assert init.hits.dtype == np.int64 and init.age.dtype == np.int64
    np.testing.assert_array_equal(init.hits, [1])


def feed(init, pattern, vel=5.0):
    confirmed = []
    for k, hit in enumerate(pattern):
        Z = np.array([[vel * k, 0.0]]) if hit else np.zeros((0, 2))
        x, _ = init.step(float(k), Z)
        confirmed += [k] * len(x)
    return confirmed


@pytest.mark.parametrize("pattern,expected", [([1, 1], [1]), ([1, 0, 1], [2]), ([1, 0, 0, 1, 1], [4])])
def test_default_rule_is_two_of_three(pattern, expected):
    assert feed(MOfNInitiator(MOTION, model()), pattern) == expected


def test_an_assigned_return_does_not_start_a_second_tentative_track():
    init = MOfNInitiator(MOTION, model(), m=3, n=3)
    feed(init, [1, 1])
    assert len(init) == 1
    np.testing.assert_array_equal(init.hits, [2])
    np.testing.assert_array_equal(init.age, [2])


def test_one_of_one_confirms_every_return_with_the_initial_covariance():
    init = MOfNInitiator(MOTION, model(), m=1, n=1, initial_velocity_std=3.0)
    x, P = init.step(0.0, [[1.0, 2.0], [50.0, 50.0]])
    np.testing.assert_array_equal(x, [[1.0, 2.0, 0.0, 0.0], [50.0, 50.0, 0.0, 0.0]])
    np.testing.assert_allclose(P, np.broadcast_to(np.diag([1.0, 1.0, 9.0, 9.0]), (2, 4, 4)), atol=1e-12)
    assert len(init) == 0


def test_initiator_messages_name_the_argument():
    mdl = model()
    with pytest.raises(TypeError, match="^model must be a ScanModel, got str$"):
        MOfNInitiator(MOTION, "model")
    with pytest.raises(ValueError, match=r"^the motion model's states are 2-dimensional but the scan model \(H of shape \(2, 4\)\) expects 4-dimensional states"):
        MOfNInitiator(ConstantVelocity(0.1, n_spatial=1), mdl)
    with pytest.raises(ValueError, match=r"^n must be an integer in \[1, inf\], got 0"):
        MOfNInitiator(MOTION, mdl, m=1, n=0)
    with pytest.raises(ValueError, match=r"^Z must be finite"):
        MOfNInitiator(MOTION, mdl).step(0.0, [[np.nan, 0.0]])


class DragMotion:
    """A motion model the tracker does not know (velocity decays by e^{−c dt}): predicted through its
    own ``transition`` (mean and Jacobian) and ``Q``."""

    ndim = 4

    def __init__(self, c=0.5, q=0.2):
        self.c, self.q = c, q

    def jacobian(self, dt):  # no ``F``: the tracker must go through ``transition``
        e = np.exp(-self.c * dt)
        F = np.eye(4)
        F[0, 2] = F[1, 3] = (1 - e) / self.c
        F[2, 2] = F[3, 3] = e
        return F

    def transition(self, x, dt):
        x = np.atleast_2d(x)
        F = self.jacobian(dt)
        return x @ F.T, np.broadcast_to(F, (len(x), 4, 4))

    def Q(self, dt):
        return self.q * dt * np.eye(4)


def test_a_motion_model_of_its_own_predicts_through_its_transition():
    mdl, motion = model(), DragMotion()
    tr = SingleHypothesisTracker(motion, mdl)
    assert tr.motion is motion
    x0 = np.array([[0.0, 0.0, 2.0, -1.0]])
    tr.initialise(x0, [P1], time=0.0)
    z = np.array([[3.1, -1.2], [30.0, 30.0], [-20.0, 5.0]])
    est = tr.step(z, 2.0)
    F = motion.jacobian(2.0)
    x_pred, P_pred = F @ x0[0], F @ P1 @ F.T + 0.4 * np.eye(4)
    x_kf, P_kf = update(x_pred, P_pred, z[0], H, mdl.R)
    np.testing.assert_allclose(est.x[0], x_kf, atol=1e-10)
    np.testing.assert_allclose(est.P[0], P_kf, atol=1e-10)
    np.testing.assert_array_equal(tr.last_association, [0, -1, -1])


def test_scan_model_from_a_sensor():
    from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

    meas, det = LinearPositionSensor(2.0 * np.eye(2), 4), DetectionModel(0.8)
    box = Box([0.0, 0.0], [100.0, 50.0])
    mdl = ScanModel.from_sensor(Sensor(meas, det, PoissonClutter(10.0, box)))
    np.testing.assert_array_equal(mdl.H, H)
    np.testing.assert_array_equal(mdl.R, 2.0 * np.eye(2))
    assert (mdl.p_D, mdl.p_gate, mdl.new_target_density) == (0.8, 0.99, 0.0)
    assert mdl.clutter_density == pytest.approx(10.0 / 5000.0)
    explicit = ScanModel.from_sensor(Sensor(meas, det), p_gate=0.9, new_target_density=1e-4, clutter_density=3e-3)
    assert (explicit.p_gate, explicit.new_target_density, explicit.clutter_density) == (0.9, 1e-4, 3e-3)
    no_clutter = "^sensor has no clutter \\(β_FA = 0\\): pass clutter_density > 0 for the JPDA/GNN scores$"
    for sensor in (Sensor(meas, det), Sensor(meas, det, PoissonClutter(0.0, box))):
        with pytest.raises(ValueError, match=no_clutter):
            ScanModel.from_sensor(sensor)


def test_scan_model_stores_validated_arrays_and_names_bad_input():
    mdl = ScanModel([[1, 0, 0, 0], [0, 1, 0, 0]], [[1, 0], [0, 1]], 1, 0.5, 2, 0)
    assert isinstance(mdl.H, np.ndarray) and isinstance(mdl.R, np.ndarray) and mdl.H.dtype == float
    assert [type(v) for v in (mdl.p_D, mdl.p_gate, mdl.clutter_density, mdl.new_target_density)] == [float] * 4
    assert set(vars(mdl)) == {"H", "R", "p_D", "p_gate", "clutter_density", "new_target_density", "gate", "measurement"}
    assert mdl.measurement is None  # a linear model
    good = dict(H=H, R=np.eye(2), p_D=0.9, p_gate=0.99, clutter_density=1e-3)
    for bad, msg in [(dict(H=np.full((2, 4), np.nan)), "^H must be finite"),
                     (dict(H=np.zeros((1, 2, 4))), "^H must be a 2-D array"),
                     (dict(p_D=0.0), r"^p_D must lie in \(0, 1\]"),
                     (dict(new_target_density=-1.0), "^new_target_density must be a finite number >= 0")]:
        with pytest.raises(ValueError, match=msg):
            ScanModel(**{**good, **bad})


def test_gating_without_tracks_and_with_an_explicit_gate():
    mdl = model()
    Z = np.array([[0.5, 0.0], [2.0, 0.0], [3.0, 1.0]])
    empty = gate_tracks(np.zeros((0, 4)), np.zeros((0, 4, 4)), Z, mdl)
    assert empty.S.shape == (0, 2, 2) and empty.K.shape == (0, 4, 2) and empty.z_pred.shape == (0, 2)
    assert empty.valid.shape == (3, 0) and empty.log_likelihood().shape == (3, 0)
    x, P = np.zeros((1, 4)), P1[None]
    default, tight = gate_tracks(x, P, Z, mdl), gate_tracks(x, P, Z, mdl, gate=1.0)  # S = 2 I: d² = 0.125, 2, 5
    np.testing.assert_array_equal(default.valid[:, 0], [True, True, True])
    np.testing.assert_array_equal(tight.valid[:, 0], [True, False, False])
    with pytest.raises(ValueError, match=r"^Z must be finite; rows \[1\]"):
        gate_tracks(x, P, [[0.0, 0.0], [np.nan, 1.0]], mdl)


def test_jpda_with_lbp_marginals():
    """``jpda_marginals="lbp"``: on this scene the gating graph (t0–r0–t1, t0–r1, t1–r2) is a tree, so
    the tracker's β and update equal the exact JPDA's; a bad name is refused."""
    exact, mdl, Z = two_tracks_three_returns("jpda")
    approx = SingleHypothesisTracker(MOTION, mdl, association="jpda", jpda_marginals="lbp")
    approx.initialise(exact.x, exact.P, time=0.0)
    e, a = exact.step(Z, 1.0), approx.step(Z, 1.0)
    np.testing.assert_allclose(approx.last_association, exact.last_association, atol=1e-12)
    np.testing.assert_allclose(a.x, e.x, atol=1e-10)
    with pytest.raises(ValueError, match="jpda_marginals must be 'exact' or 'lbp'"):
        SingleHypothesisTracker(MOTION, mdl, association="jpda", jpda_marginals="bp")

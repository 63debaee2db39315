"""Two sensors fused in the factored filter (:mod:`hypotrack.hypotheses.factored.multisensor`).

The oracle is the sequential single-sensor update done by hand: an unfactored δ-GLMB filter per sensor (exhaustive
association, no cap) handed the previous scan's posterior, its birth terms built here from the previous scan's
unexplained returns (listed by hand) — one-point states at their scan, predicted by the real interval (none at a zero
interval), observed through the *next* scan's sensor. Scene: sensor A sees x <= 1, sensor B x >= -1, with other noise,
p_D and clutter; object a is seen by A only, c by B only, b by both; N1 is born from A's return and confirmed by B's
return at the same instant, N2 born from B's return; clutter seeds a birth term too.
"""

import itertools

import numpy as np
import pytest

from hypotrack.hypotheses import ExhaustiveGenerator, GaussianBirthTerm, GLMBWeights, HypothesisFilter
from hypotrack.hypotheses import LabeledMultiBernoulliPopulation
from hypotrack.hypotheses.factored import AdaptiveBirth
from hypotrack.hypotheses.factored.multisensor import MultiSensorFactored, SensorScan, merge_scans
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import position_sensor

MOTION = ConstantVelocity(q=0.02)
R_A, R_B = np.eye(2) * 0.3, np.diag([0.1, 0.6])
SENSOR_A = position_sensor(R_A, 0.85, Box([-10.0, -10.0], [1.0, 10.0]), 1.0)
SENSOR_B = position_sensor(R_B, 0.7, Box([-1.0, -10.0], [10.0, 10.0]), 0.5)
GATE, R_BIRTH, V_STD = 0.999, 0.3, 1.0
X0 = np.array([[-6.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.0, 0.5], [6.0, 0.0, -0.5, 0.0]])  # a, b, c
P0 = np.repeat(np.diag([0.3, 0.3, 0.02, 0.02])[None], 3, axis=0)
# (time, sensor, returns, the returns no track or birth term can explain — by hand)
SCANS = [(1.0, 0, np.array([[-5.5, 0.05], [0.05, 0.5], [0.2, 6.0]]), [2]),  # a, b, N1
         (1.0, 1, np.array([[0.02, 0.45], [5.5, 0.05], [0.15, 6.1], [5.0, -6.0]]), [3]),  # b, c, N1, N2
         (2.0, 0, np.array([[-5.0, 0.05], [0.0, 1.0], [0.2, 6.05], [-8.0, 8.0]]), [3]),  # a, b, N1, clutter
         (2.5, 1, np.array([[0.02, 1.25], [4.75, 0.0], [5.0, -6.05], [0.2, 5.95]]), [])]  # b, c, N2, N1


def _population():
    return LabeledMultiBernoulliPopulation([], r_birth=R_BIRTH, p_survive=1.0)


def _engine(sensor):
    return HypothesisFilter(MOTION, sensor, GLMBWeights(), ExhaustiveGenerator(), population=_population(),
                            max_hypotheses=10**6, gate_probability=GATE, means=X0, covs=P0, seed=0)


def _fused():
    birth = AdaptiveBirth(position_std=0.0, velocity_std=V_STD, r_birth=R_BIRTH, gate_probability=GATE)
    return MultiSensorFactored.from_filters([_engine(SENSOR_A), _engine(SENSOR_B)], [birth, birth], split="exact")


def _one_point(Z, R):
    """One-point states by hand: position the return (covariance R), velocity N(0, V_STD² I)."""
    x = np.hstack([Z, np.zeros_like(Z)])
    P = np.zeros((len(Z), 4, 4))
    P[:, :2, :2], P[:, 2:, 2:] = R, np.eye(2) * V_STD**2
    return x, P


def _by_hand():
    """The oracle's posterior (a HypothesisFilter) after each scan of SCANS."""
    sensors, Rs = [SENSOR_A, SENSOR_B], [R_A, R_B]
    state, t_prev, held, out = None, 0.0, None, []
    for t, s, Z, unexplained in SCANS:
        f = _engine(sensors[s])
        if state is not None:
            f.state = state
        f.time = t_prev
        terms = []
        if held is not None:
            x, P, t_held = held
            if t > t_held:  # the real interval from the returns' scan; none at a zero interval
                F = MOTION.F(t - t_held)
                x, P = x @ F.T, F @ P @ F.T + MOTION.Q(t - t_held)
            H = sensors[s].measurement.H
            terms = [GaussianBirthTerm(x[i], P[i], H, Rs[s], gate_probability=GATE) for i in range(len(x))]
        f.set_population(_population().with_birth_terms(terms, r_birth=R_BIRTH))
        f.step(Z, t)
        state, t_prev = f.state, t
        held = (*_one_point(Z[unexplained], Rs[s]), t)
        out.append(f)
    return out


def _key(store, j):
    return tuple(np.round(np.concatenate([store.means[j], store.covs[j].ravel()]), 6))


def _table(items):
    out = {}
    for w, tracks in items:
        k = tuple(sorted(x[0] for x in tracks))
        assert k not in out
        out[k] = (w, sorted(tracks, key=lambda x: x[0]))
    return out


def _unfactored(f):
    return _table((np.exp(lw), [(_key(f.store, j), f.store.means[j], f.store.covs[j]) for j in t])
                  for lw, t in zip(f.log_weights, f.track_lists))


def _factored(ff):
    groups = [[(lw, [(_key(g.store, j), g.store.means[j], g.store.covs[j]) for j in t]) for lw, t in zip(g.log_w, g.tracks)]
              for g in ff.groups]
    return _table((np.exp(sum(h[0] for h in c)), [x for h in c for x in h[1]]) for c in itertools.product(*groups))


@pytest.fixture(scope="module")
def runs():
    ff, tables = _fused(), []
    for t, s, Z, _ in SCANS:
        ff.step(Z, t, sensor=s)
        tables.append(_factored(ff))
    return ff, tables, [_unfactored(f) for f in _by_hand()]


def test_fused_posterior_is_the_sequential_single_sensor_updates(runs):
    """After every scan the fused filter's joint hypotheses are the oracle's, weight for weight and track for track
    (1e-9): tracks updated through the scan's own sensor, births from both sensors, one at a zero interval."""
    ff, got, want = runs
    for g, w in zip(got, want, strict=True):
        assert g.keys() == w.keys()
        keys = list(w)
        for t in (g, w):  # every weight, mean and covariance entry, in one array each
            t["_stack"] = [np.array([t[k][0] for k in keys])] + [
                np.concatenate([np.ravel(x[i]) for k in keys for x in t[k][1]] or [np.zeros(0)]) for i in (1, 2)]
        for a, b in zip(g["_stack"], w["_stack"]):
            np.testing.assert_allclose(a, b, atol=1e-9, rtol=0)
    # the engine's unexplained returns are the ones listed by hand; something happened at every scan
    assert [s["n_adaptive_terms"] for s in ff.stats_history] == [len(u) for *_, u in SCANS]
    assert [len(w) for w in want][-1] > 20 and ff.sensor == 1


def test_births_from_each_sensor_and_an_object_one_sensor_never_sees(runs):
    """N1 (A's return, B's at the same instant) and N2 (B's return) are born; a is never in B's view and c never in
    A's, and each keeps its track: the MAP holds five objects near the truth."""
    ff, _, _ = runs
    est = ff.posterior().map_estimate
    assert len(est.labels) == 5
    want = np.array([[-4.75, 0.0], [0.0, 1.25], [4.75, 0.0], [0.2, 6.0], [5.0, -6.0]])
    d = np.linalg.norm(est.means[:, None, :2] - want[None], axis=-1)
    assert np.all(d.min(axis=0) < 0.5)


def test_birth_at_a_zero_interval_is_the_first_returns_state_updated_by_the_other_sensors_return():
    """A's return starts a held state (one-point, R_A on the position); B's return at the same instant is its first
    detection: the born track is that state, not predicted (zero interval), Kalman-updated with B's H and R_B by hand
    — and not with A's R_A."""
    ff = _fused()
    for t, s, Z, _ in SCANS[:2]:
        ff.step(Z, t, sensor=s)
    x0, P0 = _one_point(SCANS[0][2][[2]], R_A)
    z = SCANS[1][2][2]
    H = SENSOR_B.measurement.H

    def updated(R):
        K = P0[0] @ H.T @ np.linalg.inv(H @ P0[0] @ H.T + R)
        IKH = np.eye(4) - K @ H
        return x0[0] + K @ (z - H @ x0[0]), IKH @ P0[0] @ IKH.T + K @ R @ K.T

    tracks = [(g.store.means[j], g.store.covs[j]) for g in ff.groups for j in range(len(g.store))]

    def held(x, P):
        return any(np.allclose(m, x, atol=1e-10, rtol=0) and np.allclose(c, P, atol=1e-10, rtol=0) for m, c in tracks)

    assert held(*updated(R_B)) and not held(*updated(R_A))
    assert held(x0[0], P0[0])  # and the born-undetected alternative keeps the term's state


def test_held_state_out_of_the_next_sensors_view_waits_for_a_later_scan():
    """A's return at (-6, 6) (outside B's view) is unexplained at t = 1; B's scan at t = 1 offers it no birth term (B
    could not have seen it: no hypothesis holds a track there); A's scan at t = 2 does, the state predicted over the
    1-s interval and updated with A's return by hand."""
    ff = _fused()
    z1, z2 = np.array([-6.0, 6.0]), np.array([-6.1, 6.2])
    ff.step(np.array([[-5.5, 0.05], [0.05, 0.5], z1]), 1.0, sensor=0)
    ff.step(np.array([[0.02, 0.45], [5.5, 0.05]]), 1.0, sensor=1)
    assert ff.stats_history[-1]["n_adaptive_terms"] == 1  # still held

    def near(ff, p):
        return [(g.store.means[j], g.store.covs[j]) for g in ff.groups for j in range(len(g.store))
                if np.linalg.norm(g.store.means[j][:2] - p) < 2]

    assert near(ff, z1) == []
    ff.step(np.array([[-5.0, 0.05], [0.0, 1.0], z2]), 2.0, sensor=0)
    x0, P0 = _one_point(z1[None], R_A)
    F = MOTION.F(1.0)
    x, P = F @ x0[0], F @ P0[0] @ F.T + MOTION.Q(1.0)
    H = SENSOR_A.measurement.H
    K = P @ H.T @ np.linalg.inv(H @ P @ H.T + R_A)
    IKH = np.eye(4) - K @ H
    want = (x + K @ (z2 - H @ x), IKH @ P @ IKH.T + K @ R_A @ K.T)
    assert any(np.allclose(m, want[0], atol=1e-10, rtol=0) and np.allclose(c, want[1], atol=1e-10, rtol=0)
               for m, c in near(ff, z2))


def test_merge_scans_orders_by_time_then_sensor_and_checks_times():
    a = [(0.0, np.zeros((0, 2))), (10.0, np.ones((1, 2)))]
    b = [(0.0, np.ones((2, 2))), (5.0, np.zeros((0, 2))), (10.0, np.zeros((0, 2)))]
    m = merge_scans([a, b])
    assert [(x.time, x.sensor, len(x.Z)) for x in m] == [(0.0, 0, 0), (0.0, 1, 2), (5.0, 1, 0), (10.0, 0, 1),
                                                         (10.0, 1, 0)]
    assert isinstance(m[0], SensorScan)
    with pytest.raises(ValueError, match=r"sequences\[1\]: scan times must not decrease"):
        merge_scans([a, [(2.0, np.zeros((0, 2))), (1.0, np.zeros((0, 2)))]])


def test_bad_sensor_index_and_failed_step_leave_the_filter_as_it_was():
    ff = _fused()
    with pytest.raises(ValueError, match="sensor"):
        ff.step(SCANS[0][2], 1.0, sensor=2)
    ff.step(SCANS[0][2], 1.0, sensor=0)
    before = ff.state()
    with pytest.raises(ValueError):
        ff.step(np.zeros((1, 3)), 1.0, sensor=1)  # returns of the wrong dimension
    assert ff.sensor == 0 and ff.state().same_as(before)
    ff.step(SCANS[1][2], 1.0, sensor=1)  # and the scan can be retried
    assert ff.sensor == 1
    with pytest.raises(ValueError, match="births must hold one"):
        MultiSensorFactored.from_filters([_engine(SENSOR_A), _engine(SENSOR_B)], [None])

"""GNN and JPDA with ``lazy=True`` (hypotrack.trackers.deferred): tracks out of view are not predicted each
scan, yet the posterior is the eager tracker's (``gate_out_of_view=False``) — checked on an orbital scene
(the J2 EKF of the catalogue experiment) whose objects leave the field of view and come back, with
clutter, missed detections, track births (M-of-N) and deletions after misses in view."""

import numpy as np
import pytest

from hypotrack.models import ConstantVelocity
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker

H3 = np.hstack([np.eye(3), np.zeros((3, 3))])
SIGMA = 0.5  # km
DT = 30.0


def in_view(x):
    """A slab of space the objects cross once an orbit (x > 4,000 km, |z| < 3,000 km)."""
    return (x[:, 0] > 4000.0) & (np.abs(x[:, 2]) < 3000.0)


def orbit_scene(n_objects=12, n_scans=260, seed=5):
    """Circular LEO orbits (radius 6,900–7,300 km, inclinations 20–80°, seeded phases): truth by the J2
    model itself, returns with p_D = 0.9 in view, σ = 0.5 km, Poisson clutter (mean 2) in the slab."""
    rng = np.random.default_rng(seed)
    motion = J2Orbit3D(q=1e-9)
    r = rng.uniform(6900, 7300, n_objects)
    inc = np.radians(rng.uniform(20, 80, n_objects))
    raan, u = rng.uniform(0, 2 * np.pi, (2, n_objects))
    v = np.sqrt(398600.8 / r)
    pos = np.stack([np.cos(raan) * np.cos(u) - np.sin(raan) * np.sin(u) * np.cos(inc),
                    np.sin(raan) * np.cos(u) + np.cos(raan) * np.sin(u) * np.cos(inc), np.sin(u) * np.sin(inc)], 1)
    vel = np.stack([-np.cos(raan) * np.sin(u) - np.sin(raan) * np.cos(u) * np.cos(inc),
                    -np.sin(raan) * np.sin(u) + np.cos(raan) * np.cos(u) * np.cos(inc), np.cos(u) * np.sin(inc)], 1)
    X = np.hstack([pos * r[:, None], vel * v[:, None]])
    scans, truth = [], []
    for k in range(n_scans):
        if k:
            X = motion.propagate(X, DT)
        seen = in_view(X) & (rng.random(n_objects) < 0.9)
        Z = X[seen, :3] + SIGMA * rng.standard_normal((int(seen.sum()), 3))
        clutter = np.column_stack([rng.uniform(4000, 7500, 10), rng.uniform(-7500, 7500, 10),
                                   rng.uniform(-3000, 3000, 10)])[: rng.poisson(2.0)]
        scans.append((k * DT, rng.permutation(np.vstack([Z, clutter]))))
        truth.append(X.copy())
    return motion, scans, np.array(truth)


def make(motion, association, **kw):
    model = ScanModel(H3, SIGMA**2 * np.eye(3), 0.9, 0.999, 2.0 / (3500 * 15000 * 6000), 1e-12)
    init = MOfNInitiator(motion, model, m=2, n=3, initial_velocity_std=8.0)
    return SingleHypothesisTracker(motion, model, association=association, initiator=init, max_misses=3,
                                   in_view=in_view, **kw)


@pytest.fixture(scope="module")
def scene():
    return orbit_scene()


@pytest.mark.parametrize("association", ["gnn", "jpda"])
def test_lazy_gives_the_eager_posterior_through_passes_out_of_view(scene, association):
    motion, scans, truth = scene
    eager = make(motion, association, gate_out_of_view=False)
    lazy = make(motion, association, lazy=True)
    # 10 of the 12 objects known (the other two must be born from the data), 1 km / 1 m/s off
    rng = np.random.default_rng(1)
    known = np.arange(10)
    X0 = truth[0, known] + np.r_[np.ones(3), 1e-3 * np.ones(3)] * rng.standard_normal((10, 6))
    P0 = np.broadcast_to(np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6]), (10, 6, 6))
    for tr in (eager, lazy):
        tr.initialise(X0, P0, known + 100, time=0.0)
    deferred, reentered, compared = 0, 0, 0
    asleep_since = {}
    for k, (t, Z) in enumerate(scans):
        e = eager.step(Z, t)
        lazy.step(Z, t)
        deferred += len(e) - lazy.last_predicted
        m = lazy.estimates(covariances=False)
        np.testing.assert_array_equal(m.labels, e.labels)  # same tracks born and deleted
        assert m.P is None
        np.testing.assert_allclose(m.x, e.x, rtol=1e-12, atol=0)  # means advanced alone
        view = in_view(e.x)
        for lab, v in zip(e.labels.tolist(), view.tolist()):
            if not v:
                asleep_since.setdefault(lab, k)
            elif lab in asleep_since:
                reentered += k - asleep_since.pop(lab) >= 20  # back in view after ≥ 20 scans asleep
        if k in (60, 150, len(scans) - 1):  # the deferred tracks predicted scan by scan to now
            full = lazy.estimates()
            np.testing.assert_array_equal(full.labels, e.labels)
            np.testing.assert_allclose(full.x, e.x, rtol=1e-12, atol=0)
            np.testing.assert_allclose(full.P, e.P, rtol=1e-10, atol=1e-10 * np.abs(e.P).max())
            compared += 1
    assert compared == 3
    assert deferred > 5 * len(scans)  # most tracks out of view most of the time: not predicted
    assert reentered >= 5  # and tracks came back into view after long gaps
    born = set(e.labels.tolist()) - set((known + 100).tolist())
    assert born  # tracks born from the data (the two unknown objects, clutter)


def test_eager_gating_out_of_view_differs_and_lazy_follows_the_in_view_rule():
    """A track just outside the view (x = 10.2, view x < 10) and a return at x = 9.8 in its gate: the
    lecture's eager tracker (every track gated) updates it; with p_D = 0 out of view (gate_out_of_view=False
    and lazy) it takes no return, the return starts a track instead, and both agree exactly."""
    motion = ConstantVelocity(0.01)
    H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    model = ScanModel(H, 0.04 * np.eye(2), 0.9, 0.99, 1e-3)

    def run(**kw):
        tr = SingleHypothesisTracker(motion, model, initiator=MOfNInitiator(motion, model, m=1, n=1),
                                     in_view=lambda x: x[:, 0] < 10.0, **kw)
        tr.initialise([[10.2, 0.0, 0.0, 0.0]], [np.diag([0.25, 0.25, 0.01, 0.01])], [5], time=0.0)
        tr.step(np.array([[9.8, 0.0]]), 1.0)
        return tr.estimates()

    every, in_view_only, lazy = run(), run(gate_out_of_view=False), run(lazy=True)
    assert every.labels.tolist() == [5] and every.x[0, 0] < 10.2 - 0.1  # pulled toward the return
    assert in_view_only.labels.tolist() == [5, 6] and in_view_only.x[0, 0] == 10.2  # not updated, a new track
    np.testing.assert_array_equal(lazy.labels, in_view_only.labels)
    np.testing.assert_array_equal(lazy.x, in_view_only.x)
    np.testing.assert_array_equal(lazy.P, in_view_only.P)


def test_lazy_options_are_checked():
    motion = ConstantVelocity(0.01)
    model = ScanModel(np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]]), np.eye(2), 0.9, 0.99, 1e-3)
    with pytest.raises(ValueError, match="need in_view"):
        SingleHypothesisTracker(motion, model, lazy=True)
    with pytest.raises(ValueError, match="lazy=True needs gate_out_of_view=False"):
        SingleHypothesisTracker(motion, model, lazy=True, gate_out_of_view=True, in_view=lambda x: x[:, 0] < 1)
    with pytest.raises(TypeError, match="lazy must be True or False"):
        SingleHypothesisTracker(motion, model, lazy="yes", in_view=lambda x: x[:, 0] < 1)


def test_lazy_with_no_tracks_and_empty_scans():
    """No tracks, then a return starting one (1-of-1), then an empty scan: the lazy tracker's means and its
    predicted covariance equal the eager (in-view gating) tracker's."""
    motion = ConstantVelocity(0.01)
    model = ScanModel(np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]]), np.eye(2), 0.9, 0.99, 1e-3)

    def run(**kw):
        tr = SingleHypothesisTracker(motion, model, initiator=MOfNInitiator(motion, model, m=1, n=1),
                                     in_view=lambda x: x[:, 0] < 10.0, **kw)
        out = [tr.step(np.zeros((0, 2)), 0.0), tr.step(np.array([[1.0, 1.0]]), 1.0), tr.step(np.zeros((0, 2)), 2.0)]
        return out, tr.estimates()

    (a0, a1, a2), a = run(lazy=True)
    (_, _, e2), e = run(gate_out_of_view=False)
    assert len(a0) == 0 and a1.labels.tolist() == [0] and a2.P is None
    np.testing.assert_array_equal(a2.x, e2.x)
    np.testing.assert_array_equal(a.P, e.P)


def stripes(x):
    """In view on stripes 40 wide every 100 in x: a straight-line target leaves and comes back."""
    return np.mod(x[:, 0], 100.0) < 40.0


def stripe_scene(n_objects=8, n_scans=120, seed=3):
    """Constant-velocity targets crossing the stripes (speeds 1–3 per scan), p_D = 0.9 in view, σ = 0.3,
    Poisson clutter (mean 1) in view; truth propagated by the model's own mean."""
    rng = np.random.default_rng(seed)
    X = np.column_stack([rng.uniform(0, 300, n_objects), rng.uniform(0, 50, n_objects),
                         rng.uniform(1, 3, n_objects), rng.uniform(-0.2, 0.2, n_objects)])
    motion = ConstantVelocity(0.001)
    scans = []
    for k in range(n_scans):
        if k:
            X = motion.propagate(X, 1.0)
        seen = stripes(X) & (rng.random(n_objects) < 0.9)
        Z = X[seen, :2] + 0.3 * rng.standard_normal((int(seen.sum()), 2))
        c = np.column_stack([100 * rng.integers(0, 6, 5) + rng.uniform(0, 40, 5), rng.uniform(0, 50, 5)])
        scans.append((float(k), rng.permutation(np.vstack([Z, c[: rng.poisson(1.0)]]))))
    return motion, scans, X


@pytest.mark.parametrize("association", ["gnn", "jpda"])
def test_gap_prediction_is_the_eager_posterior_for_white_noise_acceleration(association):
    """``lazy_prediction="gap"`` predicts a deferred track once over its gap. The constant-velocity model's
    continuous white-noise-acceleration Q composes exactly (Q(kΔ) = Σ_j Φ(Δ)^j Q(Δ) Φ(Δ)^jᵀ), so on targets
    that leave the view and come back (with births, deletions and clutter) the gap tracker is the eager
    one up to rounding — tracks deferred over 30 scans included."""
    motion, scans, _ = stripe_scene()
    model = ScanModel(np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]]), 0.09 * np.eye(2), 0.9, 0.999, 1.0 / (240 * 50))

    def make_cv(**kw):
        return SingleHypothesisTracker(motion, model, association=association, max_misses=3, in_view=stripes,
                                       initiator=MOfNInitiator(motion, model, m=2, n=3, initial_velocity_std=3.0),
                                       **kw)

    eager, gap = make_cv(gate_out_of_view=False), make_cv(lazy=True, lazy_prediction="gap")
    longest, compared = 0, 0
    for k, (t, Z) in enumerate(scans):
        e = eager.step(Z, t)
        gap.step(Z, t)
        np.testing.assert_array_equal(gap.estimates(covariances=False).labels, e.labels)
        if k in (40, 80, len(scans) - 1):  # the deferred tracks brought to now, each in one step
            longest = max(longest, round((t - gap.state_times().min()) / 1.0))  # scans are 1 s apart
            assert (eager.state_times() == t).all()  # an eager tracker keeps every track at now
            g = gap.estimates()
            np.testing.assert_allclose(g.x, e.x, rtol=0, atol=1e-9)
            np.testing.assert_allclose(g.P, e.P, rtol=0, atol=1e-9)
            compared += 1
    assert compared == 3 and len(e) >= 6 and longest >= 30


def test_gap_prediction_on_an_orbit_is_one_long_step_not_the_replay(scene):
    """On the J2 EKF the gap tracker's deferred track is one EKF prediction over the gap (the factored
    engine's lane), which differs from the scan-by-scan replay by the linearisation along the way."""
    motion, scans, truth = scene
    known = np.arange(12)
    P0 = np.broadcast_to(np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6]), (12, 6, 6))
    runs = {}
    for how in ("replay", "gap"):
        tr = make(motion, "gnn", lazy=True, lazy_prediction=how)
        tr.initialise(truth[0], P0, known, time=0.0)
        for t, Z in scans[:80]:
            tr.step(Z, t)
        runs[how] = tr
    tr = runs["gap"]
    t_now = scans[79][0]
    late = np.flatnonzero(tr.state_times() < t_now)
    assert len(late) >= 3
    j = late[0]
    t_s = tr.state_times()[j]
    assert t_s in [t for t, _ in scans[:79]]  # the last scan it was predicted to
    x1, F = motion.transition(tr.x[[j]], t_now - t_s)
    P1 = F @ tr.P[[j]] @ np.swapaxes(F, -1, -2) + motion.Q(t_now - t_s)
    row = np.flatnonzero(tr.ids == tr.ids[j])[0]
    g, r = tr.estimates(), runs["replay"].estimates()
    np.testing.assert_allclose(g.x[row], x1[0], rtol=1e-12)
    np.testing.assert_allclose(g.P[row], P1[0], rtol=1e-9, atol=1e-12)
    assert np.abs(g.P[row] - r.P[np.flatnonzero(r.labels == g.labels[row])[0]]).max() > 1e-9


def test_lazy_prediction_is_checked():
    motion = ConstantVelocity(0.01)
    model = ScanModel(np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]]), np.eye(2), 0.9, 0.99, 1e-3)
    with pytest.raises(ValueError, match="lazy_prediction must be one of"):
        SingleHypothesisTracker(motion, model, lazy=True, lazy_prediction="once", in_view=lambda x: x[:, 0] < 1)


@pytest.mark.parametrize("association", ["gnn", "jpda"])
def test_reading_the_estimates_does_not_change_the_run(scene, association):
    """``estimates()`` predicts the deferred tracks to now; a run read every scan must end with the tracks of a run
    never read, bit for bit. (The catalogue's scored and timed passes of GNN once differed by six label switches at
    N = 10,855 because reading rounded a near tie the other way; this small scene does not reach such a tie, so it
    guards the property, not that case.)"""
    motion, scans, truth = scene
    read, unread = make(motion, association, lazy=True), make(motion, association, lazy=True)
    known = np.arange(10)
    P0 = np.broadcast_to(np.diag([1.0, 1.0, 1.0, 1e-6, 1e-6, 1e-6]), (10, 6, 6))
    for tr in (read, unread):
        tr.initialise(truth[0, known], P0, known + 100, time=0.0)
    n_deferred = 0
    for t, Z in scans:
        read.step(Z, t)
        unread.step(Z, t)
        n_deferred += read.last_predicted < len(read.estimates(covariances=False))
        read.estimates()
    assert n_deferred > 50  # the reads did predict deferred tracks
    a, b = read.estimates(), unread.estimates()
    np.testing.assert_array_equal(a.labels, b.labels)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.P, b.P)

"""GNN: the lecture's assignment matrix, its best hypothesis, the Kalman update, bad input."""

import numpy as np
import pytest

from hypotrack.association import enumerate_associations
from hypotrack.gaussian import update
from hypotrack.models import ConstantVelocity
from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.gnn import assignment_matrix, gnn_associate, gnn_gains, gnn_update, mahalanobis_gains
from hypotrack.trackers.tracker import SingleHypothesisTracker

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
SIGMA = 2.0


def scan_model(p_D=0.9, p_gate=0.99, beta_fa=1e-3, beta_nt=2e-4):
    return ScanModel(H, SIGMA**2 * np.eye(2), p_D, p_gate, beta_fa, beta_nt)


def tracks_at(positions, pos_var=1.0):
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    x = np.concatenate([positions, np.zeros_like(positions)], axis=1)
    P = np.broadcast_to(np.diag([pos_var, pos_var, 1.0, 1.0]), (len(x), 4, 4)).copy()
    return x, P


def lecture_example():
    """Tracks T1–T3 and returns y1–y4 laid out to give the lecture's validation matrix.

    S = (1 + 4) I, gate 9.21 → gate radius ≈ 6.8: y3 (between T1 and T2) is in both gates,
    y4 only in T2's, y1 only in T3's and y2 in none.
    """
    x, P = tracks_at([[0, 0], [10, 0], [100, 0]])
    Z = np.array([[101.0, 1.0], [50.0, 50.0], [5.0, 0.5], [14.0, -1.0]])
    return x, P, Z


LECTURE_VALIDATION = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)


def test_lecture_assignment_matrix_pattern_and_entries():
    model = scan_model()
    x, P, Z = lecture_example()
    gated = gate_tracks(x, P, Z, model)
    np.testing.assert_array_equal(gated.valid, LECTURE_VALIDATION)
    A = assignment_matrix(gated, model)
    assert A.shape == (4, 3 + 4)
    # The × (−∞) pattern of the lecture's matrix: target columns follow the validation
    # matrix, EX columns a diagonal of log β_EX with β_EX = β_FA + β_NT.
    np.testing.assert_array_equal(np.isfinite(A[:, :3]), LECTURE_VALIDATION)
    np.testing.assert_allclose(np.diag(A[:, 3:]), np.log(1e-3 + 2e-4))
    assert np.isneginf(A[:, 3:][~np.eye(4, dtype=bool)]).all()
    # ℓ_ij = log(P_D p_j(y_i) / (1 − P_D P_G)) with p_j = N(ẑ_j, S_j), S_j = P_pos + R = 5 I.
    S = 5.0 * np.eye(2)
    r = Z[2] - np.array([0.0, 0.0])
    p = np.exp(-0.5 * r @ np.linalg.solve(S, r)) / (2 * np.pi * np.sqrt(np.linalg.det(S)))
    assert A[2, 0] == pytest.approx(np.log(0.9 * p / (1 - 0.9 * 0.99)), rel=1e-12)


def fundamental_theorem_log_posterior(a, gated, model):
    """log P(θ | Y) up to a constant: lecture 004 "Fundamental Theorem of TT" with EX = FA ∪ NT."""
    loglik = gated.log_likelihood()
    detected = a[a >= 0]
    logp = (a < 0).sum() * np.log(model.external_density)
    logp += sum(np.log(model.p_D) + loglik[i, a[i]] for i in np.flatnonzero(a >= 0))
    undetected = np.setdiff1d(np.arange(gated.n_tracks), detected)
    return logp + len(undetected) * np.log1p(-model.p_D * model.p_gate)


def random_scene(rng, n, m, spread=12.0):
    x, P = tracks_at(rng.uniform(0, spread, size=(n, 2)), pos_var=rng.uniform(0.5, 3.0))
    Z = rng.uniform(-3, spread + 3, size=(m, 2))
    return x, P, Z


def test_gnn_is_the_best_hypothesis_of_the_fundamental_theorem():
    """Brute force over every gated association event: GNN's event maximises log P(θ | Y)."""
    rng = np.random.default_rng(404)
    model = scan_model(beta_fa=5e-3, beta_nt=1e-3)
    n_nontrivial = 0
    for _ in range(150):
        n, m = int(rng.integers(1, 6)), int(rng.integers(0, 7))
        gated = gate_tracks(*random_scene(rng, n, m), model)
        a = gnn_associate(gnn_gains(gated, model))
        events = enumerate_associations(n, m, allowed=gated.valid).astype(np.int64)
        scores = np.array([fundamental_theorem_log_posterior(e, gated, model) for e in events])
        # The assignment-matrix sum differs from log P(θ | Y) by one constant for all θ.
        A = assignment_matrix(gated, model)
        sums = np.array([A[np.arange(m), np.where(e >= 0, e, n + np.arange(m))].sum() for e in events])
        np.testing.assert_allclose(sums - scores, (sums - scores)[0], atol=1e-9)
        best = events[np.argmax(scores)]
        np.testing.assert_array_equal(a, best)
        n_nontrivial += int((gated.valid.sum(axis=1) > 1).any())
    assert n_nontrivial > 30


def test_mahalanobis_mode_minimises_summed_distances():
    """Stone Soup's criterion: min Σ d_ij + g · (#targets with a candidate left unassigned)."""
    rng = np.random.default_rng(5)
    model = scan_model()
    g = 3.0
    for _ in range(100):
        n, m = int(rng.integers(1, 5)), int(rng.integers(0, 6))
        gated = gate_tracks(*random_scene(rng, n, m, spread=8.0), model)
        d = np.sqrt(gated.d2)
        allowed = d < g
        a = gnn_associate(mahalanobis_gains(gated, g))
        events = enumerate_associations(n, m, allowed=allowed).astype(np.int64)
        has_candidate = allowed.any(axis=0)

        def cost(e):
            assigned = set(e[e >= 0].tolist())
            return sum(d[i, e[i]] for i in np.flatnonzero(e >= 0)) + g * sum(
                1 for j in range(n) if has_candidate[j] and j not in assigned
            )

        costs = np.array([cost(e) for e in events])
        np.testing.assert_array_equal(a, events[np.argmin(costs)])


def test_gnn_update_is_kalman_update_of_assigned_tracks():
    model = scan_model()
    x, P, Z = lecture_example()
    gated = gate_tracks(x, P, Z, model)
    a = gnn_associate(gnn_gains(gated, model))
    # y1 -> T3 (alone); y3, y4 -> T1, T2 (y4 is T2's only return); y2 -> EX.
    np.testing.assert_array_equal(a, [2, -1, 0, 1])
    x_u, P_u, detected = gnn_update(gated, a, model)
    assert detected.all()
    for i, j in enumerate(a):
        if j >= 0:
            xj, Pj = update(x[j], P[j], Z[i], model.H, model.R)
            np.testing.assert_allclose(x_u[j], xj, atol=1e-12)
            np.testing.assert_allclose(P_u[j], Pj, atol=1e-12)


def test_unassigned_tracks_keep_prediction_and_bad_pairs_are_left_to_ex():
    """A return in the gate but less likely than clutter (ℓ < log β_EX) is not assigned."""
    model = scan_model(beta_fa=0.05, beta_nt=0.0)
    x, P = tracks_at([[0, 0]])
    Z = np.array([[6.0, 0.0]])  # d² = 36/5 = 7.2 < 9.21: gated, but density ≈ 8e-4 < β_EX
    gated = gate_tracks(x, P, Z, model)
    assert gated.valid.all()
    a = gnn_associate(gnn_gains(gated, model))
    np.testing.assert_array_equal(a, [-1])
    x_u, P_u, detected = gnn_update(gated, a, model)
    assert not detected.any()
    np.testing.assert_array_equal(x_u, x)
    np.testing.assert_array_equal(P_u, P)


def test_empty_scan_no_tracks_and_all_outside_gates():
    model = scan_model()
    x, P = tracks_at([[0, 0], [10, 0]])
    assert gnn_associate(gnn_gains(gate_tracks(x, P, np.zeros((0, 2)), model), model)).shape == (0,)
    gated = gate_tracks(np.zeros((0, 4)), np.zeros((0, 4, 4)), np.ones((3, 2)), model)
    np.testing.assert_array_equal(gnn_associate(gnn_gains(gated, model)), [-1, -1, -1])
    far = np.array([[500.0, 500.0], [-400.0, 0.0]])
    np.testing.assert_array_equal(gnn_associate(gnn_gains(gate_tracks(x, P, far, model), model)), [-1, -1])


def test_duplicated_returns_one_is_assigned():
    model = scan_model()
    x, P = tracks_at([[0, 0]])
    Z = np.array([[1.0, 0.5], [1.0, 0.5]])
    a = gnn_associate(gnn_gains(gate_tracks(x, P, Z, model), model))
    assert sorted(a.tolist()) == [-1, 0]


def test_bad_input():
    model = scan_model()
    x, P = tracks_at([[0, 0]])
    with pytest.raises(ValueError, match="Z"):
        gate_tracks(x, P, np.array([[np.nan, 0.0]]), model)
    with pytest.raises(ValueError, match="gain"):
        gnn_associate(np.array([[np.nan]]))
    with pytest.raises(ValueError, match="missed_distance"):
        mahalanobis_gains(gate_tracks(x, P, np.zeros((1, 2)), model), -1.0)
    with pytest.raises(ValueError, match="p_D"):
        scan_model(p_D=0.0)
    with pytest.raises(ValueError, match="p_gate"):
        scan_model(p_gate=1.0)
    with pytest.raises(ValueError, match="clutter_density"):
        scan_model(beta_fa=0.0)
    with pytest.raises(ValueError, match="R"):
        ScanModel(H, -np.eye(2), 0.9, 0.99, 1e-3)


def test_tracker_handles_empty_scans_and_rejects_nan_returns():
    model = scan_model()
    tr = SingleHypothesisTracker(ConstantVelocity(0.1), model, association="gnn", max_misses=2)
    x, P = tracks_at([[0, 0]])
    tr.initialise(x, P, time=0.0)
    est = tr.step(np.zeros((0, 2)), 1.0)
    assert est.ids.tolist() == [0]
    est = tr.step([], 2.0)
    assert len(est) == 0  # deleted after two consecutive misses
    with pytest.raises(ValueError, match="rows \\[1\\]"):
        tr.step(np.array([[0.0, 0.0], [np.nan, 1.0]]), 3.0)
    with pytest.raises(ValueError, match="decrease"):
        tr.step(np.zeros((0, 2)), 1.0)
    with pytest.raises(TypeError, match="scan"):
        tr.step(5.0)
    with pytest.raises(ValueError, match="association"):
        SingleHypothesisTracker(ConstantVelocity(0.1), model, association="mht")


def test_many_clusters_packed_equal_one_global_assignment():
    """Above the joint-solve limit clusters are packed into groups; the optimum must not change."""
    from hypotrack.association import association_score_matrix, best_assignment, columns_to_event
    from hypotrack.association import find_clusters

    rng = np.random.default_rng(21)
    model = scan_model(beta_fa=1e-3)
    centres = rng.uniform(0, 3000, size=(40, 2))
    x, P = tracks_at(np.repeat(centres, 5, axis=0) + rng.normal(0, 3.0, size=(200, 2)))
    Z = np.concatenate([x[:, :2] + rng.normal(0, 2.0, size=(200, 2)), rng.uniform(0, 3000, size=(50, 2))])
    gated = gate_tracks(x, P, Z, model)
    gain = gnn_gains(gated, model)
    assert len(find_clusters(gain > 0)) > 20 and (gated.valid.sum(axis=1) > 1).sum() > 64
    a = gnn_associate(gain)
    total, cols = best_assignment(association_score_matrix(np.where(gain > 0, gain, -np.inf), np.zeros(len(Z))))
    expected = columns_to_event(cols, gated.n_tracks)
    np.testing.assert_array_equal(a, expected)
    assert total == pytest.approx(gain[a >= 0, a[a >= 0]].sum(), rel=1e-12)


def test_lecture_worked_example_hypotheses_and_clusters():
    """Lecture 004: θ maps y1–y4 to {FA, T1, T2, T3, NT}; brute force over all 5⁴ maps is the oracle."""
    import itertools

    from hypotrack.experiments.sht.run import lecture_hypotheses, lecture_summary

    labels = ["FA", "T1", "T2", "T3", "NT"]
    valid = [
        theta for theta in itertools.product(labels, repeat=4)
        if all(lab in ("FA", "NT") or LECTURE_VALIDATION[i, int(lab[1]) - 1] for i, lab in enumerate(theta))
        and len([lab for lab in theta if lab.startswith("T")]) == len({lab for lab in theta if lab.startswith("T")})
    ]
    table = lecture_hypotheses(LECTURE_VALIDATION)
    listed = set(map(tuple, table[["y1", "y2", "y3", "y4"]].to_numpy().tolist()))
    assert len(table) == len(valid) == 66 and listed == set(valid)
    assert table["event"].nunique() == 10  # FA and NT merged: GNN assignment rows / JPDA joint events
    summary, clusters = lecture_summary(LECTURE_VALIDATION)
    value = dict(zip(summary["quantity"], summary["value"]))
    assert value["hypotheses_FA_NT"] == 66 and value["hypotheses_EX"] == 10 and value["product_over_clusters"] == 10
    assert clusters["tracks"].tolist() == ["T1 T2", "T3", ""]
    assert clusters["returns"].tolist() == ["y3 y4", "y1", "y2"]
    assert clusters["events"].tolist() == [5, 2, 1]


@pytest.mark.parametrize("n_clusters", [60, 200])
def test_cluster_groups_pack_whole_clusters_and_keep_the_optimum(n_clusters):
    """Many small clusters (more contested tracks than one joint solve takes): groups of whole
    clusters, none above the limit unless a single cluster is, and the same optimum as one global
    assignment (scipy on the full square matrix, the oracle)."""
    from hypotrack.association import association_score_matrix, best_assignment, columns_to_event
    from hypotrack.association import find_clusters
    from hypotrack.trackers.gnn import _JOINT_LIMIT, _cluster_groups

    rng = np.random.default_rng(n_clusters)
    model = scan_model(beta_fa=1e-3)
    centres = rng.uniform(0, 100 * n_clusters, size=(n_clusters, 2))
    x, P = tracks_at(np.repeat(centres, 5, axis=0) + rng.normal(0, 3.0, size=(5 * n_clusters, 2)))
    Z = np.concatenate([x[:, :2] + rng.normal(0, 2.0, size=(len(x), 2)), rng.uniform(0, 3000, size=(50, 2))])
    gain = gnn_gains(gate_tracks(x, P, Z, model), model)
    useful = gain > 0
    tracks = np.flatnonzero(useful.any(axis=0))
    groups = _cluster_groups(useful, tracks)
    assert len(tracks) > _JOINT_LIMIT and len(groups) > 1
    np.testing.assert_array_equal(np.sort(np.concatenate(groups)), tracks)
    cluster_of = {int(t): k for k, c in enumerate(find_clusters(useful)) for t in c.tracks}
    for g in groups:
        clusters = {cluster_of[int(t)] for t in g}
        assert sum(cluster_of[int(t)] in clusters for t in tracks) == len(g)  # whole clusters only
        assert len(g) <= _JOINT_LIMIT or len(clusters) == 1
    a = gnn_associate(gain)
    _, cols = best_assignment(association_score_matrix(np.where(useful, gain, -np.inf), np.zeros(len(Z))))
    np.testing.assert_array_equal(a, columns_to_event(cols, len(x)))


@pytest.mark.parametrize("p", [1, 2, 3])
def test_trackers_lean_gating_equals_checked_gating(p):
    """The trackers' own gating (one inverse of S per scan) gives the checked path's predicted
    measurements, gains, distances, log-determinants and validation matrix, up to rounding; empty
    scans and no tracks included."""
    from hypotrack.trackers._sht_common import _gate_scan

    rng = np.random.default_rng(p)
    d = 2 * p
    H = np.eye(p, d)
    A = rng.normal(size=(p, p))
    model = ScanModel(H, A @ A.T + np.eye(p), 0.9, 0.99, 1e-3)
    B = rng.normal(size=(7, d, d))
    x, P = rng.normal(0, 3, size=(7, d)), B @ np.swapaxes(B, 1, 2) + 0.1 * np.eye(d)
    for Z in (rng.normal(0, 3, size=(11, p)), np.zeros((0, p))):
        for n in (7, 0):
            ref, got = gate_tracks(x[:n], P[:n], Z, model), _gate_scan(x[:n], P[:n], Z, model)
            for name in ("z_pred", "S", "K", "d2", "logdet"):
                np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=1e-12, atol=1e-12, err_msg=name)
            np.testing.assert_array_equal(got.valid, ref.valid)
            assert got.d2.shape == (len(Z), n) and (got.d2 >= 0).all()


def test_trackers_prediction_reuses_the_model_and_equals_predict_tracks():
    """Linear models: F(dt), Q(dt) built once per scan period, the same numbers as predict_tracks
    (bit for bit); a nonlinear model goes through predict_tracks itself."""
    from hypotrack.models import OrnsteinUhlenbeck
    from hypotrack.models.orbit import TwoBodyOrbit
    from hypotrack.trackers._sht_common import _ScanPredictor, predict_tracks

    rng = np.random.default_rng(3)
    for motion, d in ((ConstantVelocity(0.3), 4), (OrnsteinUhlenbeck(2.0, 0.1), 1)):
        B = rng.normal(size=(5, d, d))
        x, P = rng.normal(size=(5, d)), B @ np.swapaxes(B, 1, 2)
        predict = _ScanPredictor(motion)
        for dt in (1.0, 1.0, 0.25, 0.0):
            got, ref = predict(x, P, dt), predict_tracks(motion, x, P, dt)
            np.testing.assert_array_equal(got[0], ref[0])
            np.testing.assert_array_equal(got[1], ref[1])
    assert not _ScanPredictor(TwoBodyOrbit()).linear


def test_mahalanobis_tracker_skips_logdet_but_likelihood_is_still_right():
    """The Mahalanobis criterion needs no log det S, so the tracker's gating leaves it out; the
    predicted-measurement log density is then computed from S on demand, equal to the full gating's."""
    model = scan_model()
    x, P, Z = lecture_example()
    tracker = SingleHypothesisTracker(ConstantVelocity(0.1), model, gnn_score="mahalanobis", max_misses=5)
    tracker.initialise(x, P, time=0.0)
    tracker.step(Z, 0.0)
    assert tracker.last_gated.logdet is None
    ref = gate_tracks(x, P, Z, model)
    np.testing.assert_allclose(tracker.last_gated.log_likelihood(), ref.log_likelihood(), rtol=1e-12)
    np.testing.assert_array_equal(tracker.last_gated.valid, LECTURE_VALIDATION)

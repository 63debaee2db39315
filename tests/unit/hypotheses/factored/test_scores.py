"""A scan's scores at scale (:mod:`hypotrack.hypotheses.factored.scores`): the gated pairs found through the
k-d tree carry the engine's dense matrices' numbers bit for bit, no gated pair is missed (tracks of very
different spreads, returns at the gate's edge), the blocks the steps read are the dense ones on the gate, and
a factored filter scoring that way holds the dense-scoring posterior bit for bit."""

import numpy as np
import pytest

import hypotrack.hypotheses.factored.scores as scores_module
from hypotrack.hypotheses import LabeledMultiBernoulliPopulation, glmb
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredFilter
from hypotrack.hypotheses.factored.scores import score_tracks
from hypotrack.hypotheses.tracks import TrackStore
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box
from scenes import observed_scans, position_sensor

VIEW = Box([-500.0, -500.0], [500.0, 500.0])
SENSOR = position_sensor(R=0.5, p_D=0.85, view=VIEW, clutter_rate=5.0)
MOTION = ConstantVelocity(q=0.01)


def _engine(gate=0.999):
    return glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0),
                n_sweeps=10, max_hypotheses=5, gate_probability=gate)


def _scene(seed=0):
    """400 tracks (a quarter out of view, spreads from 0.1 to 400 per axis, some elongated) and 600 returns:
    near tracks, at their gate's edge, and uniform."""
    rng = np.random.default_rng(seed)
    n = 400
    means = np.column_stack([rng.uniform(-650, 650, (n, 2)), rng.normal(size=(n, 2))])
    A = rng.normal(size=(n, 4, 4)) * rng.choice([0.3, 3.0, 20.0], size=(n, 1, 1))
    covs = A @ np.swapaxes(A, 1, 2) + np.eye(4) * 0.1
    covs[::7, 0, 0] += 400.0**2  # very elongated along x
    pred = TrackStore(means, covs, np.arange(n))
    near = means[rng.integers(0, n, 300), :2] + rng.normal(size=(300, 2)) * 3
    S = covs[:50, :2, :2] + 0.5 * np.eye(2)
    u = rng.normal(size=(50, 2))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    edge = means[:50, :2] + np.einsum("nij,nj->ni", np.linalg.cholesky(S), u) * np.sqrt(13.8155) * 0.9999999
    Z = np.vstack([near, edge, rng.uniform(-500, 500, (250, 2))])
    return pred, Z


@pytest.mark.parametrize("in_view", [True, False])
def test_the_gated_pairs_are_the_dense_matrices_bit_for_bit(in_view):
    engine = _engine()
    pred, Z = _scene()
    loglik, allowed, p_detect = engine.track_scores(pred, Z)
    if not in_view:
        allowed = allowed & (p_detect > 0)[None, :]
    sparse = score_tracks(engine, pred, Z, gate_out_of_view=in_view, dense_pairs=0)
    dense = score_tracks(engine, pred, Z, gate_out_of_view=in_view, dense_pairs=10**9)
    assert sparse.loglik is None and dense.loglik is not None  # the two forms
    r, c = np.nonzero(allowed)
    assert len(r) > 600 and (p_detect == 0).sum() > 50  # many pairs gated, many tracks out of view
    for s in (sparse, dense):
        gr, gc = s.gated()
        np.testing.assert_array_equal(gr, r)
        np.testing.assert_array_equal(gc, c)
        np.testing.assert_array_equal(s.at(r, c), loglik[r, c])
        np.testing.assert_array_equal(s.p_detect, p_detect)
    rows, cols = np.array([3, 40, 305, 320, 599]), np.arange(0, 400, 3)
    ll_s, al_s, pd_s, _ = sparse.block(rows, cols)
    ll_d, al_d, pd_d, _ = dense.block(rows, cols)
    np.testing.assert_array_equal(al_s, al_d)
    np.testing.assert_array_equal(ll_s[al_s], ll_d[al_d])
    assert np.all(ll_s[~al_s] == -np.inf) and np.all(np.isfinite(ll_d))  # off the gate: -inf, never read
    with pytest.raises(KeyError, match="not in the gate"):
        sparse.at([0], [int(np.flatnonzero(~allowed[0])[0])])


def test_without_a_gate_the_scores_stay_dense():
    engine = _engine(gate=None)
    pred, Z = _scene(1)
    s = score_tracks(engine, pred, Z, dense_pairs=0)
    assert s.loglik is not None and s.allowed.all()


def test_a_factored_filter_scoring_gated_pairs_holds_the_dense_posterior(monkeypatch):
    """121 objects, births from the data, 8 scans: the k-d tree's scores (every scan) and the dense ones
    give the same posterior bit for bit, fast path on."""
    grid = np.arange(-400.0, 401.0, 80.0)
    truth = np.array([[x, y, 0.5, -0.3] for x in grid for y in grid])
    scans, _ = observed_scans(truth, MOTION, SENSOR, 8, seed=5)
    rng = np.random.default_rng(1)
    known = np.arange(len(truth)) % 7 != 3
    means = truth[known] + rng.normal(size=(known.sum(), 4)) * [1.0, 1.0, 0.3, 0.3]
    covs = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], known.sum(), axis=0)

    def make():
        f = glmb(MOTION, SENSOR, population=LabeledMultiBernoulliPopulation([], r_birth=0.5, p_survive=1.0),
                 n_sweeps=50, max_hypotheses=20, gate_probability=0.999, seed=3, means=means, covs=covs)
        birth = AdaptiveBirth(position_std=0.0, velocity_std=2.0, r_birth=0.01, gate_probability=0.999)
        return FactoredFilter.from_filter(f, adaptive_birth=birth, min_weight=0.001, fast_path=True)

    dense, sparse = make(), make()
    for k, Z in enumerate(scans):
        dense.step(Z, float(k + 1))
        monkeypatch.setattr(scores_module, "DENSE_PAIRS", 0)
        sparse.step(Z, float(k + 1))
        monkeypatch.setattr(scores_module, "DENSE_PAIRS", 200_000)
        assert dense.same_posterior(sparse)
    assert dense.next_label > known.sum()  # objects were born

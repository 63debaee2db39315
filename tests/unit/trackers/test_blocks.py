"""A large scan solved block by block (:mod:`hypotrack.trackers.blocks`) is the whole matrix's solution.

The candidate pairs contain every gated pair (checked against the dense gate, linear and wrapped-angle
measurements); blocks are unions of whole components, so no gated pair crosses two; and GNN/JPDA/PDAF trackers
stepped over scans with contested returns (three objects sharing returns), missed and deleted tracks, clutter and
M-of-N births give the same tracks, moments and miss counts with the blocks as with the whole matrices.
"""

import numpy as np
import pytest

import hypotrack.trackers.blocks as blocks
from hypotrack.models import ConstantVelocity
from scenes import RangeBearing
from hypotrack.trackers._sht_common import ScanModel, gate_tracks
from hypotrack.trackers.blocks import candidate_pairs, gate_blocks
from hypotrack.trackers.initiation import MOfNInitiator
from hypotrack.trackers.tracker import SingleHypothesisTracker

H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
MOTION = ConstantVelocity(0.05)


def _objects(rng):
    """Ten triplets 1.5 apart (their gates share returns) on a ring of radius 60, and ten lone objects."""
    centres = 60.0 * np.column_stack([np.cos(np.linspace(0, 2 * np.pi, 20, endpoint=False)),
                                      np.sin(np.linspace(0, 2 * np.pi, 20, endpoint=False))])
    pos = [c + d for c in centres[:10] for d in ([0, 0], [1.5, 0], [0, 1.5])] + list(centres[10:])
    X = np.zeros((len(pos), 4))
    X[:, :2] = pos
    X[:, 2:] = rng.normal(0, 0.2, (len(pos), 2))
    return X


def _scans(X, model, n_scans, seed, p_D=0.85, clutter=6):
    """Returns of ``X`` moved by the motion's mean: detected with ``p_D``, noise of the model's ``R``, and
    ``clutter`` uniform returns a scan; a third of the objects leaves after the middle scan (deaths)."""
    rng = np.random.default_rng(seed)
    F, scans = MOTION.F(1.0), []
    L = np.linalg.cholesky(model.R)
    for k in range(n_scans):
        X = X @ F.T
        alive = X if k < n_scans // 2 else X[: 2 * len(X) // 3]
        det = alive[rng.random(len(alive)) < p_D]
        z = (det @ H.T if model.measurement is None else model.measurement.h(det)) + rng.normal(size=(len(det), 2)) @ L.T
        if model.measurement is None:
            c = rng.uniform(-80, 80, (clutter, 2))
        else:
            c = np.column_stack([rng.uniform(20, 80, clutter), rng.uniform(-np.pi, np.pi, clutter)])
        scans.append(np.vstack([z, c])[rng.permutation(len(z) + clutter)])
    return scans


def _model(kind):
    if kind == "linear":
        return ScanModel(H, 0.3 * np.eye(2), 0.85, 0.999, 1e-3)
    m = RangeBearing()
    return ScanModel(None, m.R, 0.85, 0.999, 1e-3, measurement=m)


@pytest.mark.parametrize("kind", ["linear", "wrapped"])
def test_candidate_pairs_contain_every_gated_pair(kind):
    rng = np.random.default_rng(5)
    model = _model(kind)
    X = _objects(rng)
    G = rng.normal(0, 0.4, (len(X), 4, 4))
    P = G @ np.swapaxes(G, 1, 2) + 0.2 * np.eye(4)
    Z = _scans(X, model, 1, 7)[0]
    valid = gate_tracks(X, P, Z, model).valid
    rows, cols = candidate_pairs(X, P, Z, model)
    cand = np.zeros_like(valid)
    cand[rows, cols] = True
    assert valid.sum() >= 30 and not np.any(valid & ~cand)  # every gated pair is a candidate
    assert cand.sum() < valid.size / 4  # and the candidates are far fewer than all pairs


@pytest.mark.parametrize("kind", ["linear", "wrapped"])
def test_blocks_are_whole_components(kind):
    rng = np.random.default_rng(6)
    model = _model(kind)
    X = _objects(rng)
    P = np.repeat(np.diag([0.6, 0.6, 0.1, 0.1])[None], len(X), axis=0)
    Z = _scans(X, model, 1, 8)[0]
    valid = gate_tracks(X, P, Z, model).valid
    out = gate_blocks(X, P, Z, model, block_tracks=4)
    t_of, r_of = np.full(len(X), -1), np.full(len(Z), -1)
    for b, (t, r) in enumerate(out):
        assert np.all(t_of[t] == -1) and np.all(r_of[r] == -1)  # disjoint
        t_of[t], r_of[r] = b, b
    assert len(out) > 3 and all(len(t) >= 4 for t, _ in out[:-1])
    i, j = np.nonzero(valid)
    assert np.array_equal(r_of[i], t_of[j]) and np.all(t_of[j] >= 0)  # no gated pair crosses blocks or is left out
    # a triplet's gates share returns: some gated return has two or more tracks
    assert valid.sum(axis=1).max() >= 2


def _run(association, kind, monkeypatch, blocked):
    model = _model(kind)
    monkeypatch.setattr(blocks, "BLOCK_TRACKS", 3)
    rng = np.random.default_rng(11)
    X = _objects(rng)
    init = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=1.0)
    tr = SingleHypothesisTracker(MOTION, model, association=association, initiator=init, max_misses=2,
                                 block_pairs=0 if blocked else None)
    P0 = np.repeat(np.diag([0.5, 0.5, 0.1, 0.1])[None], 20, axis=0)
    tr.initialise(X[:20], P0, time=0.0)  # half the objects known, the others to be born from the data
    out = []
    for k, Z in enumerate(_scans(X, model, 12, 21)):
        tr.step(Z, float(k + 1))
        a = np.array(tr.last_association, copy=True) if association == "gnn" else None  # return -> track
        out.append((tr.ids.copy(), tr.x.copy(), tr.P.copy(), tr.misses.copy(), a))
    return out


@pytest.mark.parametrize("association", ["gnn", "jpda", "pdaf"])
@pytest.mark.parametrize("kind", ["linear", "wrapped"])
def test_tracker_with_blocks_equals_the_whole_matrices(association, kind, monkeypatch):
    whole = _run(association, kind, monkeypatch, blocked=False)
    parts = _run(association, kind, monkeypatch, blocked=True)
    born = max(int(ids.max(initial=-1)) for ids, *_ in whole) >= 20
    deleted = any(len(a[0]) < len(b[0]) for a, b in zip(whole[1:], whole[:-1]))
    assert born and deleted  # the scans hold births and deletions
    for (i0, x0, P0, m0, a0), (i1, x1, P1, m1, a1) in zip(whole, parts):
        np.testing.assert_array_equal(i0, i1)
        if association == "gnn":
            np.testing.assert_array_equal(a0, a1)
        np.testing.assert_array_equal(m0, m1)
        np.testing.assert_allclose(x1, x0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(P1, P0, rtol=0, atol=1e-12)


def test_block_pairs_default_and_refusal():
    model = _model("linear")
    X = _objects(np.random.default_rng(2))
    P0 = np.repeat(np.diag([0.5, 0.5, 0.1, 0.1])[None], len(X), axis=0)
    Z = _scans(X, model, 1, 3)[0]
    for pairs, whole in ((None, True), (len(X) * len(Z), True), (len(X) * len(Z) - 1, False)):
        kw = {} if pairs is None else dict(block_pairs=pairs)
        tr = SingleHypothesisTracker(MOTION, model, **kw)
        tr.initialise(X, P0, time=0.0)
        tr.step(Z, 1.0)
        assert (tr.last_gated is not None) == whole  # the default (SPARSE_PAIRS) keeps this small scan whole
    with pytest.raises(ValueError, match="block_pairs"):
        SingleHypothesisTracker(MOTION, model, block_pairs=-1)

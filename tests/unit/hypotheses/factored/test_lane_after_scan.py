"""The lane's end-of-scan rebuild (:meth:`Lane.after_scan`: kept singletons gathered by runs of consecutive rows, the
pruned Bernoulli singletons never copied) against the plain construction it replaces: every row built — the kept
singletons gathered one by one, the quiet candidates replaced by their prediction, the new ones appended — and then
the pruned rows dropped (:meth:`Lane.where`). Bit for bit, on lanes of a few to a few hundred singletons, with
candidates stepped and quiet, new singletons, existences that the pruning drops or rounds up to 1, and the
validity verdicts of asleep singletons."""

import numpy as np
import pytest

from hypotrack.hypotheses.factored.lane import Lane, bernoulli_prune, take
from hypotrack.hypotheses.tracks import TrackStore


def _reference(lane, cand, quiet, pred, now, view, new, exist):
    keep = np.ones(len(lane), dtype=bool)
    keep[cand] = False
    keep[cand[quiet]] = True
    idx = np.flatnonzero(keep)
    n_keep = len(idx)
    pos = np.cumsum(keep) - 1
    moved = cand[quiet]
    means = np.concatenate([lane.store.means[idx], new.means])
    covs = np.concatenate([lane.store.covs[idx], new.covs])
    means[pos[moved]], covs[pos[moved]] = pred.means[quiet], pred.covs[quiet]
    times = np.concatenate([lane.times[idx], np.full(len(new), now)])
    times[pos[moved]] = now
    lane_view = np.concatenate([(lane.store.means if view is None else view)[idx], new.means])
    lane_view[pos[moved]] = pred.means[quiet]
    labels = np.concatenate([lane.store.labels[idx], new.labels])
    if exist is None:
        return Lane(TrackStore(means, covs, labels), times, lane_view), n_keep
    r_quiet, p_quiet, r_new, p_new, min_weight, ok = exist
    r = lane.r[idx] * lane.p_s[idx] * (1.0 if ok is None else ok[idx])
    r = np.concatenate([r, r_new])
    p_s = np.concatenate([lane.p_s[idx], p_new])
    r[pos[moved]], p_s[pos[moved]] = r_quiet, p_quiet
    alive, r = bernoulli_prune(r, min_weight)
    out = Lane(TrackStore(means, covs, labels), times, lane_view, r, p_s)
    return (out if alive.all() else out.where(alive)), n_keep


def _store(rng, n, first_label):
    A = rng.normal(size=(n, 6, 6))
    return TrackStore(rng.normal(size=(n, 6)), A @ np.swapaxes(A, 1, 2) + np.eye(6), np.arange(first_label, first_label + n))


@pytest.mark.parametrize("n", [0, 3, 7, 300])
@pytest.mark.parametrize("bernoulli", [False, True])
@pytest.mark.parametrize("lazy", [False, True])
def test_after_scan_is_the_plain_construction_bit_for_bit(n, bernoulli, lazy):
    rng = np.random.default_rng(n + 10 * bernoulli + 100 * lazy)
    for trial in range(6):
        store = _store(rng, n, 0)
        r = np.where(rng.random(n) < 0.5, 1.0, rng.uniform(1e-6, 1.0, n)) if bernoulli else None
        p_s = np.where(rng.random(n) < 0.5, 1.0, rng.uniform(0.9, 1.0, n)) if bernoulli else None
        lane = Lane(store, rng.uniform(0, 50, n), store.means + 1.0, r, p_s)
        cand = np.sort(rng.choice(n, size=rng.integers(0, n + 1), replace=False)).astype(np.int64) if n else np.zeros(0, np.int64)
        quiet = rng.random(len(cand)) < 0.6
        pred = _store(rng, len(cand), 10_000)
        pred = TrackStore(pred.means, pred.covs, store.labels[cand])
        new = _store(rng, int(rng.integers(0, 4)), 20_000)
        view = rng.normal(size=(n, 6)) if lazy else None
        exist = None
        if bernoulli:
            ok = None if trial % 2 else (rng.random(n) < 0.9).astype(float)
            # existences near the pruning's thresholds (min_weight 1e-3: dropped below it, 1 above 1 - 1e-3)
            r_quiet = rng.choice([1e-4, 0.3, 1 - 1e-4, 1.0], size=int(quiet.sum()))
            r_new = rng.choice([1e-4, 0.5, 1.0], size=len(new))
            exist = (r_quiet, rng.uniform(0.9, 1, len(r_quiet)), r_new, np.ones(len(new)), 1e-3, ok)
        got, n_got = lane.after_scan(cand, quiet, pred, 60.0, view, new, exist)
        want, n_want = _reference(lane, cand, quiet, pred, 60.0, view, new, exist)
        assert n_got == n_want
        assert got.same_as(want)
        if bernoulli and n:
            assert len(got) <= n_want + len(new)


def test_after_scan_drops_a_pruned_singleton_and_keeps_order():
    """Three singletons: the first stepped (leaves), the second quiet (its prediction), the third asleep with
    ``r p_S`` below ``min_weight`` (dropped); one new singleton appended."""
    store = TrackStore(np.arange(18.0).reshape(3, 6), np.broadcast_to(np.eye(6), (3, 6, 6)).copy(), np.array([4, 5, 6]))
    lane = Lane(store, np.array([0.0, 0.0, 0.0]), store.means.copy(), np.array([1.0, 1.0, 0.002]), np.array([1.0, 1.0, 0.4]))
    pred = TrackStore(np.full((2, 6), 7.0), np.broadcast_to(2 * np.eye(6), (2, 6, 6)).copy(), np.array([4, 5]))
    new = TrackStore(np.full((1, 6), 9.0), np.broadcast_to(3 * np.eye(6), (1, 6, 6)).copy(), np.array([8]))
    exist = (np.array([1.0]), np.array([1.0]), np.array([1.0]), np.array([1.0]), 1e-3, None)
    got, n_keep = lane.after_scan(np.array([0, 1]), np.array([False, True]), pred, 10.0, None, new, exist)
    assert n_keep == 2
    assert got.store.labels.tolist() == [5, 8]
    assert np.array_equal(got.store.means, np.vstack([np.full(6, 7.0), np.full(6, 9.0)]))
    assert got.times.tolist() == [10.0, 10.0] and got.r.tolist() == [1.0, 1.0]
    assert np.array_equal(got.store.covs[0], 2 * np.eye(6))
    assert len(take(got.store, np.array([0]))) == 1


@pytest.mark.parametrize("bernoulli", [False, True])
def test_candidates_in_any_order_are_the_plain_construction(bernoulli):
    """The compiled pass walks the candidates in lane order: given in another order (their predictions and the quiet
    ones' existences in that order), the rows are those of the plain construction, bit for bit."""
    rng = np.random.default_rng(7 + bernoulli)
    n = 40
    for _ in range(5):
        store = _store(rng, n, 0)
        r = np.where(rng.random(n) < 0.5, 1.0, rng.uniform(1e-6, 1.0, n)) if bernoulli else None
        p_s = np.where(rng.random(n) < 0.5, 1.0, rng.uniform(0.9, 1.0, n)) if bernoulli else None
        lane = Lane(store, rng.uniform(0, 50, n), store.means + 1.0, r, p_s)
        cand = rng.permutation(n)[:17].astype(np.int64)  # not ascending
        assert np.any(np.diff(cand) < 0)
        quiet = rng.random(len(cand)) < 0.5
        pred = _store(rng, len(cand), 10_000)
        pred = TrackStore(pred.means, pred.covs, store.labels[cand])
        new = _store(rng, 2, 20_000)
        exist = None
        if bernoulli:
            r_quiet = rng.choice([1e-4, 0.3, 1 - 1e-4, 1.0], size=int(quiet.sum()))
            exist = (r_quiet, rng.uniform(0.9, 1, len(r_quiet)), np.array([0.5, 1e-4]), np.ones(2), 1e-3, None)
        view = rng.normal(size=(n, 6))
        got, n_got = lane.after_scan(cand, quiet, pred, 60.0, view, new, exist)
        want, n_want = _reference(lane, cand, quiet, pred, 60.0, view, new, exist)
        assert n_got == n_want
        assert got.same_as(want)


def _scan(rng, lane, n_label, bernoulli):
    """One random scan's arguments for ``lane``: candidates (ascending), which are quiet, their predictions, the
    means at the scan, new singletons (labels from ``n_label``) and with ``bernoulli`` the existences."""
    n = len(lane)
    cand = np.sort(rng.choice(n, size=int(rng.integers(0, n // 3 + 2)), replace=False)).astype(np.int64) if n else \
        np.zeros(0, np.int64)
    quiet = rng.random(len(cand)) < 0.6
    pred = _store(rng, len(cand), 0)
    pred = TrackStore(pred.means, pred.covs, lane.labels[cand])
    new = _store(rng, int(rng.integers(0, 6)), n_label)
    exist = None
    if bernoulli:
        r_quiet = rng.choice([1e-4, 0.3, 1 - 1e-4, 1.0], size=int(quiet.sum()))
        ok = None if rng.random() < 0.5 else (rng.random(n) < 0.95).astype(float)
        exist = (r_quiet, rng.uniform(0.9, 1, len(r_quiet)), rng.choice([1e-4, 0.5, 1.0], size=len(new)),
                 rng.uniform(0.95, 1, len(new)), 1e-3, ok)
    return cand, quiet, pred, rng.normal(size=(n, 6)), new, exist


@pytest.mark.parametrize("bernoulli", [False, True])
def test_a_lane_stepped_scan_after_scan_appends_and_compacts_as_the_plain_construction(bernoulli, monkeypatch):
    """Forty scans of a lane of 60-120 singletons: each scan's lane (its moments appended to those of the scans
    before, compacted when the garbage passes the bound: here every few scans) is the plain construction from the
    previous one, bit for bit, and so is every earlier lane, still held, after the later scans appended."""
    import hypotrack.hypotheses.factored.lane as lane_module

    monkeypatch.setattr(lane_module, "COMPACT_ROWS", 40)
    rng = np.random.default_rng(11 + bernoulli)
    store = _store(rng, 80, 0)
    lane = Lane(store, np.zeros(80), store.means.copy(), np.ones(80) if bernoulli else None,
                np.full(80, 0.999) if bernoulli else None)
    plain = Lane(TrackStore(store.means.copy(), store.covs.copy(), store.labels.copy()), lane.times, lane.view, lane.r,
                 lane.p_s)
    held, n_label, compactions = [], 1_000, 0
    for k in range(40):
        args = _scan(rng, lane, n_label, bernoulli)
        n_label += 10
        got, n_got = lane.after_scan(args[0], args[1], args[2], float(k + 1), *args[3:])
        want, n_want = _reference(plain, args[0], args[1], args[2], float(k + 1), *args[3:])  # (plain all along)
        assert n_got == n_want and got.same_as(want)
        compactions += got._buf is not lane._buf
        held.append((got, want))
        lane, plain = got, want
    assert 3 <= compactions < 40  # both ways taken: appended and compacted
    for got, want in held:  # the later scans' appends left every earlier lane's rows as they were (gathered afresh)
        again = Lane(None, got.times, got.view, got.r, got.p_s, moments=got._buf, rows=got._rows, labels=got.labels)
        assert again.same_as(want)


def test_two_lanes_from_one_and_a_discarded_one_do_not_write_each_others_rows():
    """Two scans from the same lane (a lane restored after a failed step takes the next one): the second finds the
    moments appended to since and compacts instead; both results, and the first lane, are the plain ones."""
    rng = np.random.default_rng(5)
    store = _store(rng, 50, 0)
    lane = Lane(store, np.zeros(50), store.means.copy())
    args = _scan(rng, lane, 100, False)
    lane, _ = lane.after_scan(args[0], args[1], args[2], 1.0, *args[3:])
    snapshot = (lane.store.means.copy(), lane.store.covs.copy(), lane.labels.copy(), lane.times.copy())
    lane = Lane(None, lane.times, lane.view, moments=lane._buf, rows=lane._rows, labels=lane.labels)  # store not read
    a_args, b_args = _scan(rng, lane, 200, False), _scan(rng, lane, 300, False)
    a, _ = lane.after_scan(a_args[0], a_args[1], a_args[2], 2.0, *a_args[3:])
    b, _ = lane.after_scan(b_args[0], b_args[1], b_args[2], 2.0, *b_args[3:])
    assert a._buf is lane._buf and b._buf is not lane._buf  # the first appended, the second compacted
    plain = Lane(TrackStore(*snapshot[:3]), snapshot[3], lane.view)
    for got, args in ((a, a_args), (b, b_args)):
        assert got.same_as(_reference(plain, args[0], args[1], args[2], 2.0, *args[3:])[0])
    assert np.array_equal(lane.store.means, snapshot[0]) and np.array_equal(lane.store.covs, snapshot[1])

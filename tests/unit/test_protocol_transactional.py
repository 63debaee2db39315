"""Every tracker's step is all-or-nothing: a step that raises leaves the tracker exactly as it
was (time, tracks, hypotheses, random-generator state), and retrying gives the result of a run
that never failed."""

import copy
import functools

import numpy as np
import pytest

import hypotrack.trackers.ecmht as ecmht_module
import hypotrack.trackers.initiation as initiation_module
import hypotrack.trackers.jpda as jpda_module
from hypotrack.association import EnumerationBudgetError
from hypotrack.association.marginals import MarginalsBudgetError, jpda_marginals
from hypotrack.hypotheses import ExhaustiveGenerator, hfisst, rfisst
from hypotrack.models import ConstantVelocity, OrnsteinUhlenbeck
from hypotrack.trackers import (
    CardinalityTracker,
    ClassicalCountMHT,
    ECMHTFilter,
    GNNFilter,
    IdealFilter,
    MOfNInitiator,
    PDAFilter,
    ScanModel,
    SingleHypothesisTracker,
)

from scenes import H_POSITION, REGION, THREE_COVS, THREE_MEANS, observed_scans, position_sensor, single_event_population

MOTION = ConstantVelocity(0.05)
H = H_POSITION


def _state(obj):
    """Deep copy of everything a tracker holds, random generators as their bit states."""
    out = {}
    for k, v in vars(obj).items():
        if isinstance(v, np.random.Generator):
            out[k] = v.bit_generator.state
        elif k == "initiator" and v is not None:
            out[k] = _state(v)
        elif v is None or isinstance(v, (np.ndarray, np.generic, int, float, str, list, tuple, dict)):
            out[k] = copy.deepcopy(v)
        else:  # configuration (models, sensors): the same object
            out[k] = ("object", id(v))
    return out


def _assert_same(a, b):
    assert a.keys() == b.keys()
    for k in a:
        va, vb = a[k], b[k]
        if isinstance(va, dict):
            _assert_same(va, vb) if k == "initiator" else np.testing.assert_equal(va, vb)
        else:
            np.testing.assert_equal(va, vb, err_msg=k)


# ------------------------------------------------------------------ single-hypothesis tracker
def _crowd(n=24, seed=0):
    """``n`` targets in a 10 m box: every return in every gate, one JPDA cluster."""
    rng = np.random.default_rng(seed)
    x = np.zeros((n, 4))
    x[:, :2] = rng.uniform(0.0, 10.0, size=(n, 2))
    P = np.repeat(np.diag([4.0, 4.0, 1.0, 1.0])[None], n, axis=0)
    return x, P, x[:, :2] + rng.normal(scale=0.5, size=(n, 2))


def _sht(association="jpda", initiator=False):
    model = ScanModel(H, np.eye(2), 0.9, 0.99, 1e-3)
    init = MOfNInitiator(MOTION, model, m=2, n=3) if initiator else None
    return SingleHypothesisTracker(MOTION, model, association=association, initiator=init)


def test_jpda_marginals_budget_error_leaves_tracker_unchanged_and_retry_matches(monkeypatch):
    """24 targets in a 10 m box exceed the exact JPDA recursion's budget (a smaller budget than
    the default only makes it fail in milliseconds instead of seconds)."""
    x, P, Z = _crowd()
    tr = _sht("jpda")
    tr.initialise(x, P, time=0.0)
    before = _state(tr)
    with monkeypatch.context() as mp:
        mp.setattr(jpda_module, "jpda_marginals", functools.partial(jpda_marginals, max_nodes=20_000))
        with pytest.raises(MarginalsBudgetError, match="max_nodes"):
            tr.step(Z, 1.0)
    _assert_same(_state(tr), before)  # time not advanced, priors not replaced
    # the same time again with a scan the tracker can take (two far returns): as if never failed
    ok = (1.0, np.array([[3.0, 3.0], [500.0, 500.0]]))
    ref = _sht("jpda")
    ref.initialise(x, P, time=0.0)
    got, want = tr.step(ok), ref.step(ok)
    assert got.time == want.time == 1.0
    np.testing.assert_array_equal(got.x, want.x)
    np.testing.assert_array_equal(got.P, want.P)
    np.testing.assert_array_equal(got.ids, want.ids)


@pytest.mark.parametrize("association", ["gnn", "jpda", "pdaf"])
def test_bad_scans_leave_tracker_unchanged(association):
    tr = _sht(association, initiator=True)
    rng = np.random.default_rng(1)
    scans = [(np.array([[t, 0.0], [0.0, -t]]) + rng.normal(scale=0.3, size=(2, 2)), float(t)) for t in range(4)]  # (Z, time)
    for s in scans[:3]:
        tr.step(*s)
    before = _state(tr)
    for bad in [(np.array([[np.nan, 0.0]]), 3.0), (np.zeros((2, 3)), 3.0), (np.zeros((0, 2)), 1.0), ([], np.inf)]:
        with pytest.raises(ValueError):
            tr.step(*bad)
        _assert_same(_state(tr), before)
    ref = _sht(association, initiator=True)
    for s in scans[:3]:
        ref.step(*s)
    got, want = tr.step(*scans[3]), ref.step(*scans[3])
    np.testing.assert_array_equal(got.x, want.x)
    np.testing.assert_array_equal(got.ids, want.ids)


def test_failure_inside_the_initiator_rolls_back_tracker_and_initiator(monkeypatch):
    tr = _sht("gnn", initiator=True)
    tr.initialise(np.array([[0.0, 0.0, 1.0, 0.0]]), np.diag([1.0, 1.0, 0.5, 0.5])[None], time=0.0)
    scans = [(np.array([[1.0, 0.1], [20.0, 20.0]]), 1.0), (np.array([[2.1, 0.0], [20.5, 20.2]]), 2.0)]  # (Z, time)
    tr.step(*scans[0])
    before = _state(tr)

    def boom(*args, **kwargs):
        raise RuntimeError("simulated failure inside the initiator")

    with monkeypatch.context() as mp:
        mp.setattr(initiation_module, "gnn_update", boom)
        with pytest.raises(RuntimeError, match="simulated"):
            tr.step(*scans[1])
    _assert_same(_state(tr), before)
    ref = _sht("gnn", initiator=True)
    ref.initialise(np.array([[0.0, 0.0, 1.0, 0.0]]), np.diag([1.0, 1.0, 0.5, 0.5])[None], time=0.0)
    ref.step(*scans[0])
    got, want = tr.step(*scans[1]), ref.step(*scans[1])
    assert len(got) == 2  # the second target confirmed (2 of 3)
    np.testing.assert_array_equal(got.x, want.x)
    np.testing.assert_array_equal(got.P, want.P)


# ------------------------------------------------------------------ hypothesis filter
X0, P0 = THREE_MEANS, THREE_COVS


def _sensor():
    return position_sensor(0.5, 0.9, REGION, 1.0)


def _population():
    return single_event_population(0.01, 0.01, 1, (REGION,))


def _scans(n, seed=3):
    return observed_scans(X0.copy(), MOTION, _sensor(), n, seed)[0]


def _filter_state(f):
    return (f.log_weights, f.track_lists, f.store.means, f.store.covs, f.store.labels, f.lineage_keys,
            f.scan_index, f.rng.bit_generator.state, f.next_label, f.time)


def test_rfisst_failure_in_a_later_parent_restores_rng_and_retry_matches(monkeypatch):
    """The MCMC generator draws from the filter's generator for the first parent, then the
    second parent fails: the draws are given back and the retry equals an uninterrupted run."""
    make = lambda: rfisst(MOTION, _sensor(), population=_population(), n_steps=300, max_hypotheses=6,
                          cap="sample", means=X0, covs=P0, seed=11)
    scans = _scans(3)
    f, ref = make(), make()
    for Z in scans[:2]:
        f.step(Z)
        ref.step(Z)
    assert len(f.log_weights) > 1
    before = _filter_state(f)
    cls = type(f.generator)
    real = cls.generate
    calls = []

    def flaky(self, problem, rng=None, keep=None):
        calls.append(1)
        if len(calls) == 2:
            raise EnumerationBudgetError(10**9, 10)
        return real(self, problem, rng, keep=keep)

    with monkeypatch.context() as mp:
        mp.setattr(cls, "generate", flaky)
        with pytest.raises(EnumerationBudgetError):
            f.step(scans[2])
    assert len(calls) == 2
    np.testing.assert_equal(_filter_state(f), before)
    f.step(scans[2])
    ref.step(scans[2])
    np.testing.assert_equal(_filter_state(f), _filter_state(ref))


def test_hfisst_budget_error_then_retry_with_larger_budget():
    Z = np.vstack([_scans(1)[0], REGION.sample_uniform(6, np.random.default_rng(0))])
    f = hfisst(MOTION, _sensor(), population=_population(), max_events=50, max_hypotheses=10,
               means=X0, covs=P0, seed=2, cap="sample")
    before = _filter_state(f)
    with pytest.raises(EnumerationBudgetError, match="max_events"):
        f.step(Z)
    np.testing.assert_equal(_filter_state(f), before)
    f.generator = ExhaustiveGenerator(max_events=10**7)
    ref = hfisst(MOTION, _sensor(), population=_population(), max_hypotheses=10, means=X0, covs=P0, seed=2,
                 cap="sample")
    f.step(Z)
    ref.step(Z)
    np.testing.assert_equal(_filter_state(f), _filter_state(ref))


def test_hypothesis_filter_bad_scan_leaves_state():
    f = hfisst(MOTION, _sensor(), population=_population(), max_hypotheses=10, means=X0, covs=P0)
    f.step(_scans(1)[0])
    before = _filter_state(f)
    for bad in [np.array([[np.nan, 1.0]]), np.zeros((2, 3)), np.zeros(3)]:
        with pytest.raises(ValueError, match="Z"):
            f.step(bad)
        np.testing.assert_equal(_filter_state(f), before)
    with pytest.raises(ValueError, match="dt"):
        f.step(np.zeros((0, 2)), dt=-1.0)
    np.testing.assert_equal(_filter_state(f), before)


# ------------------------------------------------------------------ closely spaced (ECMHT & co.)
OU = OrnsteinUhlenbeck(0.01, 0.005)


def _ou_scans(n, n_runs=5, N=4, seed=0):
    rng = np.random.default_rng(seed)
    return [rng.normal(scale=0.1, size=(n_runs, N, 2)) for _ in range(n)]


@pytest.mark.parametrize("make", [
    lambda: ECMHTFilter(OU, 1.0, 4, rng=5),
    lambda: GNNFilter(OU, 1.0, 4),
    lambda: IdealFilter(OU, 1.0, 4),
    lambda: PDAFilter(OU, 1.0, 4),
])
def test_closely_spaced_filters_roll_back_a_failed_update(make, monkeypatch):
    """A failure after the ECMHT drew its random sensor orders (in the swap merge) — or in any
    filter's update — restores the estimates, predictions and the generator's state."""
    scans = _ou_scans(4)
    f, ref = make(), make()
    for Z in scans[:3]:
        f.step(Z)
        ref.step(Z)
    before = _state(f)

    def boom(*args, **kwargs):
        raise FloatingPointError("simulated failure mid-update")

    with monkeypatch.context() as mp:
        mp.setattr(ecmht_module, "swap_merge", boom)
        mp.setattr(ecmht_module, "_to_track_order", boom)
        mp.setattr(ecmht_module, "_pda_update", boom)
        with pytest.raises(FloatingPointError):
            f.step(scans[3])
    _assert_same(_state(f), before)
    with pytest.raises(ValueError, match="runs"):
        f.step(scans[3][:2])
    _assert_same(_state(f), before)
    np.testing.assert_array_equal(f.step(scans[3]), ref.step(scans[3]))
    np.testing.assert_array_equal(f.predictions(), ref.predictions())


# ------------------------------------------------------------------ cardinality trackers
@pytest.mark.parametrize("cls", [CardinalityTracker, ClassicalCountMHT])
def test_count_trackers_reject_bad_counts_without_change(cls):
    f, ref = cls(0.9, 0.01, 1.0, 10.0), cls(0.9, 0.01, 1.0, 10.0)
    counts = [12, 9, 11, 14, 10]
    for r in counts[:3]:
        f.step(r)
        ref.step(r)
    first = f.estimates().copy()
    for bad in [-1, 2.5, np.nan, "3"]:
        with pytest.raises((ValueError, TypeError)):
            f.step(bad)
        np.testing.assert_array_equal(f.counts, counts[:3])
        np.testing.assert_array_equal(f.estimates(), first)
    for r in counts[3:]:
        f.step(r)
        ref.step(r)
    np.testing.assert_array_equal(f.estimates(), ref.estimates())

"""The radar's compiled EKF moments (:mod:`hypotrack.scenarios.catalogue.radar_kernels`) against the array passes of
:class:`~hypotrack.models.measurement.ExtendedMeasurement` they replace (``RadarMeasurement(compiled=False)``): the
Jacobian and the first-order return bit for bit, the second-order moments, gain and Joseph update to 1e-12 of their
scale on tracks from tight to kilometres wide; the in-view prefilter bit for bit; and the δ-GLMB over the real
catalogue (default configuration: admissible-region births, decaying Bernoulli singletons, the fast path), stepped
once with the array passes and once with the compiled kernels (these and the birth mixtures',
:mod:`~hypotrack.scenarios.catalogue.admissible_kernels`), holding the same groups, labels and hypotheses at every scan with weights, means and covariances
to 1e-12, through births, deaths and objects out of view."""

import numpy as np
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.run import (build_scenario, initial_tracks, make_motion, make_problem,
                                                    make_tracker, tracker_sensor)
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth
from hypotrack.scenarios.catalogue.radar_kernels import teme_near
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, _r3, site_teme


def _scaled_close(a, b, rtol=1e-12):
    """``a`` equals ``b`` to ``rtol`` (a number, or one per track) of the largest entry of each track's block (one
    row of the batch)."""
    a, b = np.asarray(a), np.asarray(b)
    shape = (len(b),) + (1,) * (b.ndim - 1)
    scale = np.abs(b).reshape(len(b), -1).max(axis=1).reshape(shape)
    tol = np.broadcast_to(np.asarray(rtol, dtype=float), (len(b),)).reshape(shape)
    assert np.all(np.abs(a - b) <= tol * scale), float(np.max(np.abs(a - b) / scale))


def _gain_rtol(S):
    """Per track, the tolerance of a Kalman gain ``P Hᵀ S⁻¹`` computed in two orders: solving with ``S`` moves a
    result by up to ~``cond(S) ε`` of itself (Higham, *Accuracy and Stability of Numerical Algorithms*, §7.1), so
    two backward-stable orders differ by a few times that — seen: 1.02e-12 for a track with cond(S) = 1.0e4, where
    the BLAS of another machine rounded the array passes differently; 1e-12 where that bound is smaller."""
    return np.maximum(1e-12, 8.0 * np.linalg.cond(S) * np.finfo(float).eps)


def _tracks(meas, n=60, seed=4):
    """States above the site (400-3000 km of range, LEO speeds) with covariances 1e-3 to 1e3 wide, and returns."""
    rng = np.random.default_rng(seed)
    s, _ = site_teme(meas.sensor.radar.site, meas.sensor.theta)
    up = s / np.linalg.norm(s)
    dirs = rng.normal(size=(n, 3)) + 2 * up
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    X = np.hstack([s + dirs * rng.uniform(400, 3000, (n, 1)), rng.normal(scale=5, size=(n, 3))])
    A = rng.normal(size=(n, 6, 6))
    P = A @ np.swapaxes(A, 1, 2) * rng.choice([1e-3, 1e-1, 10.0, 1e3], size=n)[:, None, None] + 1e-6 * np.eye(6)
    Z = meas.h(X) + rng.normal(size=(n, 4)) * np.sqrt(np.diag(meas.R))
    return X, P, Z


@pytest.mark.parametrize("theta", [0.3, 2.9])
def test_the_compiled_moments_are_the_array_passes(theta):
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(theta).measurement
    X, P, Z = _tracks(meas)
    meas.compiled = False
    ref = meas._moments(X, P), meas.innovation(X, P), meas.update(X, P, Z)
    meas.second_order = False
    ref1 = meas._moments(X, P)
    meas.compiled = True
    got1 = meas._moments(X, P)
    meas.second_order = True
    got = meas._moments(X, P), meas.innovation(X, P), meas.update(X, P, Z)
    J = meas.sensor.jacobian(X)  # rae_rate_jacobian's array passes
    assert np.array_equal(got1[1], ref1[1]) and np.array_equal(got1[1], J)  # the Jacobian, bit for bit
    assert np.array_equal(meas.jacobian(X), J) and meas.jacobian(X[:0]).shape == (0, 4, 6)
    assert np.array_equal(got1[2], meas.R)
    np.testing.assert_allclose(got1[0], ref1[0], rtol=1e-15, atol=0)  # h: atan2 may round differently (an ulp)
    gain_rtol = _gain_rtol(ref[1][1])  # the array passes' S of each track
    for g, r in zip(got, ref):
        assert len(g) == len(r)
        for a, b in zip(g, r):
            assert a.shape == b.shape
            _scaled_close(a, b, gain_rtol if a.shape[1:] == (6, 4) else 1e-12)  # the gain solves with S
    # the second-order terms are there (the bias and S₂ of the wide tracks), and the update is a covariance
    assert np.max(np.abs(got[0][0] - got1[0])) > 1e-3 and np.max(np.abs(got[0][2] - meas.R)) > 1e-3
    x, Pu = got[2]
    assert np.array_equal(Pu, np.swapaxes(Pu, 1, 2)) and np.all(np.linalg.eigvalsh(Pu) > 0)
    # a row does not depend on its batch
    one = meas.update(X[7:8], P[7:8], Z[7:8])
    assert np.array_equal(one[0][0], x[7]) and np.array_equal(one[1][0], Pu[7])


def test_the_compiled_moments_handle_empty_batches_and_singular_innovations():
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(1.0).measurement
    z, S, K, H = meas.innovation(np.zeros((0, 6)), np.zeros((0, 6, 6)))
    assert z.shape == (0, 4) and S.shape == (0, 4, 4) and K.shape == (0, 6, 4) and H.shape == (0, 4, 6)
    x, P = meas.update(np.zeros((0, 6)), np.zeros((0, 6, 6)), np.zeros((0, 4)))
    assert x.shape == (0, 6) and P.shape == (0, 6, 6)
    X, P, _ = _tracks(meas, n=2)
    R0 = meas.R
    meas.R = np.zeros((4, 4))
    meas.second_order = False
    try:
        with pytest.raises(np.linalg.LinAlgError):  # P of rank 0 and no noise: S = 0, as numpy's solve refuses it
            meas.innovation(X, np.zeros((2, 6, 6)))
    finally:
        meas.R, meas.second_order = R0, True


def test_the_in_view_prefilter_is_the_array_passes_bit_for_bit():
    rng = np.random.default_rng(2)
    X = rng.normal(size=(5000, 6)) * 7000.0
    X[::97] = np.nan
    radar, f = DEFAULT_RADAR, DEFAULT_RADAR.fov
    for theta in (0.1, 2.2, 5.0):
        loc = (X[:, :3] @ _r3(theta).T - radar.site.ef) @ radar.site.enu.T
        near = np.sum(loc * loc, axis=-1) <= (f.r_max_km * (1 + 1e-9)) ** 2
        near &= loc[:, 2] > 0 if f.el_min_deg > 0 else True
        got_loc, got_near = teme_near(X, _r3(theta), radar.site.ef, radar.site.enu, f.r_max_km, f.el_min_deg > 0)
        assert np.array_equal(got_loc, loc, equal_nan=True) and np.array_equal(got_near, near)
        assert near.sum() > 10
        sensor = RadarTrackerSensor(radar).at(theta)
        assert np.array_equal(sensor.detection.in_view(X), radar.in_view(X[:, :3] @ _r3(theta).T))


N_SCANS = 30


def test_the_glmb_over_the_catalogue_is_the_same_with_the_array_passes():
    with open("workflows/config/default.yaml") as fh:
        cfg = dict(yaml.safe_load(fh)["ssa_catalogue"], n_scans=N_SCANS)
    objects, unknown, sc, init_seed = build_scenario(cfg, 300, 1)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    problem = make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels)
    meas = tsensor.measurement
    ref, new = (make_tracker("glmb", cfg, problem, 1, fast_path=True) for _ in range(2))
    mixtures = [tr.options.adaptive_birth.mixture for tr in (ref, new)]
    assert all(isinstance(x, AdmissibleRegionBirth) for x in mixtures)
    label0 = ref.next_label
    seen = dict(fast=0, general=0, out_of_view=0, dropped=0)
    for k, (t, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        Z = tsensor.returns(Z)
        before = ref.n_objects_held
        for on in (False, True):  # the array passes, then the compiled kernels (the birth mixtures' too)
            meas.compiled = on
            for x in mixtures:
                object.__setattr__(x, "compiled", on)
            (new if on else ref).step(Z, float(t))
        ga, gb = ref.groups, new.groups
        assert len(ga) == len(gb) and ref.next_label == new.next_label
        for s, u in zip(ga, gb):
            np.testing.assert_array_equal(s.store.labels, u.store.labels)
            assert all(np.array_equal(x, y) for x, y in zip(s.tracks, u.tracks))
            np.testing.assert_allclose(u.log_w, s.log_w, rtol=0, atol=1e-12)
            np.testing.assert_allclose(u.store.means, s.store.means, rtol=1e-12, atol=1e-12)
            _scaled_close(u.store.covs, s.store.covs)
        st = new.last_stats
        seen["fast"] += st["n_fast_path"]
        seen["general"] += st["n_touched"] - st["n_fast_path"]
        seen["out_of_view"] += ref.n_objects_held - st["n_predicted"] > 0
        seen["dropped"] += ref.n_objects_held < before + (ref.next_label - label0)
    # the run holds what the check is for: lone tracks updated by the fast path and steps of the general one,
    # births, objects out of view, objects dropped
    assert seen["fast"] > 0 and seen["general"] > 0 and seen["out_of_view"] == N_SCANS
    assert new.next_label > label0 and seen["dropped"] > 0

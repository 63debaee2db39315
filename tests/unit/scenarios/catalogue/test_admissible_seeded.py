"""The seeded admissible birth against its region: the components are the region's with those whose mean is
no bound orbit above the floor dropped (a return whose three blocks give one centroid off the region, another
whose single block's centroid falls in the region's hole) and the weights renormalised; the cache follows the
sensor's GMST; the region's floor is the test's; bad parameters are refused by name."""

import dataclasses
import numpy as np
import pytest

from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth, SeededAdmissibleBirth
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor

C = DEFAULT_RADAR.fov.az_center
Z_DROP = np.array([400.0, C + 0.2, np.deg2rad(60.0), -3.0])  # 3 blocks' centroids, one not a bound orbit
Z = np.array([1200.0, C + 0.2, np.deg2rad(40.0), 1.5])


def _region(theta=0.4, **kw):
    return AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(theta), **kw)


def test_components_drop_implausible_means_and_renormalise():
    region = _region(n_blocks=3, cells=6)
    w0, m0, c0 = region.components(Z_DROP)
    ok = plausible_orbits(m0)
    assert len(w0) == 3 and ok.sum() == 2  # the case: one of three dropped
    w, m, c = SeededAdmissibleBirth(region).components(Z_DROP)
    np.testing.assert_allclose(w, w0[ok] / w0[ok].sum(), rtol=1e-14)
    assert w.sum() == pytest.approx(1.0, rel=1e-14) and w.sum() > w0[ok].sum()
    np.testing.assert_array_equal(m, m0[ok])
    np.testing.assert_array_equal(c, c0[ok])
    # a (1, 4) return is the same return
    for u, v in zip(SeededAdmissibleBirth(region).components(Z_DROP[None]), (w, m, c)):
        np.testing.assert_array_equal(u, v)


def test_a_region_whose_centroids_all_fail_and_a_return_with_no_region():
    one_block = _region(n_blocks=1, cells=24)
    z = np.array([300.0, C + 0.2, np.deg2rad(45.0), -3.0])  # 300 km away: the region is a thin ring
    w0, m0, _ = one_block.components(z)
    assert len(w0) == 1 and not plausible_orbits(m0).any()  # its centroid lies in its hole
    w, m, c = SeededAdmissibleBirth(one_block).components(z)
    assert w.shape == (0,) and m.shape == (0, 6) and c.shape == (0, 6, 6)
    w, m, c = SeededAdmissibleBirth(_region()).components(np.r_[Z[:3], 15.0])  # above escape speed
    assert w.shape == (0,) and m.shape == (0, 6) and c.shape == (0, 6, 6)


def test_the_cache_follows_the_gmst_and_hands_out_copies():
    seeded = SeededAdmissibleBirth(_region(0.4, n_blocks=2, cells=8))
    first = seeded.components(Z)
    first[1][...] = 0.0  # a caller's change does not reach the cache
    np.testing.assert_array_equal(seeded.components(Z)[1], SeededAdmissibleBirth(_region(0.4, n_blocks=2, cells=8))
                                  .components(Z)[1])
    seeded.region.sensor.at(1.1)
    fresh = SeededAdmissibleBirth(_region(1.1, n_blocks=2, cells=8)).components(Z)
    for u, v in zip(seeded.components(Z), fresh):
        np.testing.assert_array_equal(u, v)
    assert not np.allclose(fresh[1], SeededAdmissibleBirth(_region(0.4, n_blocks=2, cells=8)).components(Z)[1])
    small = SeededAdmissibleBirth(_region(1.1, n_blocks=2, cells=8), cache_size=1)
    small.components(Z_DROP)  # a second return with a cache of one
    for u, v in zip(small.components(Z), fresh):
        np.testing.assert_array_equal(u, v)


def test_the_test_is_the_regions_floor():
    seeded = SeededAdmissibleBirth(_region(min_perigee_km=600.0))
    r_a, r_p = 6378.135 + 900.0, 6378.135 + 300.0  # perigee 300 km up: above 100, below 600
    a = (r_a + r_p) / 2
    state = np.array([[r_a, 0, 0, 0, np.sqrt(398600.4418 * (2 / r_a - 1 / a)), 0.0]])
    assert plausible_orbits(state)[0] and not seeded.admissible(state)[0]


def test_bad_parameters_are_refused_by_name():
    with pytest.raises(TypeError, match="^region must be an AdmissibleRegionBirth, got str"):
        SeededAdmissibleBirth("region")
    with pytest.raises(ValueError, match=r"^cache_size must be an integer in \[1, inf\]"):
        SeededAdmissibleBirth(_region(), cache_size=0)
    assert SeededAdmissibleBirth(_region(), cache_size=1).cache_size == 1


def test_prime_puts_the_batch_in_the_cache_equal_to_each_return_s_own_mixture():
    """A scan of five returns — one with a dropped centroid, one above escape speed (no component), one twice —
    primed in one batch: each return's cached mixture is its own (:meth:`components` of a fresh instance, one
    region each) to 1e-12 with the same number of components; nothing is recomputed for a cached return; a new
    GMST starts a new cache."""
    region = _region(0.4, n_blocks=3, cells=6)
    scan = np.array([Z_DROP, Z, np.r_[Z[:3], 15.0], [900.0, C - 0.1, np.deg2rad(25.0), -0.5], Z])
    seeded = SeededAdmissibleBirth(region)
    assert seeded.prime(scan) == 4  # the repeated return once
    batch = [seeded.components(z) for z in scan]
    assert seeded.prime(scan[:2]) == 0  # all cached at this GMST
    for z, (w, m, c) in zip(scan, batch):
        w0, m0, c0 = SeededAdmissibleBirth(region).components(z)  # one return, the region's own mixture
        assert len(w) == len(w0)
        np.testing.assert_allclose(w, w0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(m, m0, rtol=1e-12, atol=0)
        np.testing.assert_allclose(c, c0, rtol=1e-12, atol=1e-12 * np.abs(c0).max(initial=0))
    assert [len(b[0]) for b in batch] == [2, len(batch[1][0]), 0, len(batch[3][0]), len(batch[1][0])]
    assert len(batch[1][0]) > 1 and len(batch[3][0]) > 1
    region.sensor.at(1.1)
    assert seeded.prime(scan[1:2]) == 1  # a new GMST: a new cache
    np.testing.assert_allclose(seeded.components(Z)[1], SeededAdmissibleBirth(_region(1.1, n_blocks=3, cells=6))
                               .components(Z)[1], rtol=1e-12)
    assert seeded.prime(np.zeros((0, 4))) == 0
    with pytest.raises(ValueError, match="Z"):
        seeded.prime(np.array([[1.0, 2.0, np.nan, 0.0]]))


def test_a_primed_return_maps_its_covariances_only_when_its_track_is_asked_for():
    """After :meth:`prime`, :meth:`component_weights` hands out the weights and means with no covariance mapped
    (the fast path's decision and the births' scores need no more); the first :meth:`components` maps them, equal
    to the batch's own :meth:`AdmissibleRegionBirth.components_batch` (kept components) to 1e-12, and keeps them."""
    region = _region(0.4, n_blocks=3, cells=6)
    scan = np.array([Z_DROP, Z, np.r_[Z[:3], 15.0], [900.0, C - 0.1, np.deg2rad(25.0), -0.5]])
    seeded = SeededAdmissibleBirth(region)
    seeded.prime(scan)
    # prime runs the array passes (batch_parts), bit for bit those of components_batch without the kernel
    w_all, m_all, c_all, owner = dataclasses.replace(region, compiled=False).components_batch(scan)
    ok = plausible_orbits(m_all)
    for i, z in enumerate(scan):
        w, m = seeded.component_weights(z)
        entry = seeded._cache[z.tobytes()]
        assert entry[2] is None  # no covariance mapped yet
        sel = (owner == i) & ok
        np.testing.assert_array_equal(m, m_all[sel])
        np.testing.assert_allclose(w, w_all[sel] / w_all[sel].sum() if sel.any() else w_all[sel], rtol=1e-15)
        w2, m2, c2 = seeded.components(z)
        np.testing.assert_array_equal(w2, w)
        np.testing.assert_array_equal(m2, m)
        np.testing.assert_allclose(c2, c_all[sel], rtol=1e-12, atol=1e-12 * np.abs(c_all).max())
        assert seeded._cache[z.tobytes()][2] is not None and c2.shape == (sel.sum(), 6, 6)
    # a return never primed: its whole mixture at once, the same numbers by either call
    fresh = SeededAdmissibleBirth(region)
    w, m = fresh.component_weights(Z)
    for u, v in zip((w, m), seeded.components(Z)):
        np.testing.assert_allclose(u, v, rtol=1e-12)


def test_a_primed_scan_larger_than_the_cache_is_kept_whole(monkeypatch):
    """A cache of two returns primed with a scan of four: all four stay (no return is rebuilt one by one when the
    engine asks for it, however often), equal to a fresh instance's mixtures to 1e-12; a new GMST starts again
    with the stated room, and a miss with the cache full starts it afresh (the asked return is computed)."""
    region = _region(0.4, n_blocks=3, cells=6)
    scan = np.array([Z_DROP, Z, np.r_[Z[:3], 15.0], [900.0, C - 0.1, np.deg2rad(25.0), -0.5]])
    seeded = SeededAdmissibleBirth(region, cache_size=2)
    assert seeded.prime(scan) == 4
    fresh = [SeededAdmissibleBirth(_region(0.4, n_blocks=3, cells=6)).components(z) for z in scan]
    calls = []
    original = AdmissibleRegionBirth.components
    monkeypatch.setattr(AdmissibleRegionBirth, "components", lambda self, z: calls.append(1) or original(self, z))
    for _ in range(3):
        for z, (w0, m0, _) in zip(scan, fresh):
            w, m = seeded.component_weights(z)
            np.testing.assert_allclose(w, w0, rtol=0, atol=1e-12)
            np.testing.assert_allclose(m, m0, rtol=1e-12)
            seeded.components(z)
    assert calls == [] and len(seeded._cache) == 4
    seeded.components(np.array([2000.0, C, np.deg2rad(30.0), 0.5]))  # a return of no scan: computed, the scan kept
    assert len(calls) == 1 and len(seeded._cache) == 5
    calls.clear()
    region.sensor.at(0.5)
    for z in scan[:3]:  # not primed at this GMST: one by one, in a cache of two
        seeded.components(z)
    assert len(calls) == 3 and len(seeded._cache) == 1

"""The compiled field-of-view test (fov_kernels): every point it decides is decided as the array passes
(local_to_rae, then RadarFieldOfView.contains) decide it, the points it leaves undecided lie within its margin of a
bound (or are not finite), and GroundRadar.in_view_local (which tests the undecided by the array passes) equals the
array passes on every point — random points, points on each bound and a few ulps either side, the wrap of the
azimuth behind the sector, NaN/inf rows, zero range, sectors centred south, north and west and a full circle."""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue import GroundRadar, GroundSite, RadarFieldOfView
from hypotrack.scenarios.catalogue.fov_kernels import MARGIN, fov_decide
from hypotrack.scenarios.catalogue.frames import local_to_rae, rae_to_enu

FOVS = [RadarFieldOfView(180.0, 120.0, 5.0, 85.0, 200.0, 3000.0),  # the catalogue's radar: centre south
        RadarFieldOfView(0.0, 90.0, 0.0, 90.0, 0.0, 2000.0),  # centre north: atan2's ±π behind the sector
        RadarFieldOfView(-90.0, 359.0, 20.0, 23.0, 100.0, 40000.0),  # a fence nearly all round
        RadarFieldOfView(270.0, 360.0, 10.0, 60.0, 300.0, 1000.0)]  # every azimuth


def _array_passes(fov, loc, near):
    out = np.zeros(len(loc), dtype=bool)
    out[near] = fov.contains(local_to_rae(loc[near], fov.az_center))
    return out


def _edge_points(fov, rng, n):
    """Local ENU points whose range, azimuth and elevation each sit on a bound, 0-3 ulps off it, a margin off it or
    well inside, in every combination drawn at random."""
    def around(v):
        k = rng.integers(-3, 4, n)
        ulps = np.array([np.nextafter(v, np.inf if s > 0 else -np.inf) if s else v for s in np.sign(k)])
        for _ in range(2):  # up to 3 ulps
            ulps = np.where(np.abs(k) > 1, np.nextafter(ulps, np.where(k > 0, np.inf, -np.inf)), ulps)
            k = np.where(np.abs(k) > 1, k - np.sign(k), k)
        return ulps
    half = np.deg2rad(fov.az_width_deg) / 2
    r_opts = np.array([fov.r_min_km, fov.r_max_km, 0.5 * (fov.r_min_km + fov.r_max_km)])
    az_opts = fov.az_center + np.array([-half, half, 0.0, np.pi, -np.pi, half + 10 * MARGIN, half - 10 * MARGIN])
    el_opts = np.deg2rad(np.array([fov.el_min_deg, fov.el_max_deg, 0.5 * (fov.el_min_deg + fov.el_max_deg)]))
    r = np.array([around(v)[0] for v in rng.choice(r_opts, n)])
    az = np.array([around(v)[0] for v in rng.choice(az_opts, n)])
    el = np.array([around(v)[0] for v in rng.choice(el_opts, n)])
    return rae_to_enu(np.column_stack([r, az, el]))


@pytest.mark.parametrize("k", range(len(FOVS)))
def test_decided_points_agree_with_the_array_passes_and_undecided_ones_sit_at_a_bound(k):
    fov = FOVS[k]
    rng = np.random.default_rng(11 + k)
    rand = rng.uniform(-1.2, 1.2, (20000, 3)) * fov.r_max_km
    edge = _edge_points(fov, rng, 3000)
    special = np.array([[np.nan, 1.0, 1.0], [1.0, np.inf, 1.0], [0.0, 0.0, 0.0], [0.0, -500.0, 100.0],
                        [0.0, -500.0, -100.0], [-0.0, -500.0, 100.0]])
    loc = np.concatenate([rand, edge, special])
    near = np.ones(len(loc), dtype=bool)
    near[::7] = False
    code = fov_decide(loc, near, fov.r_min_km, fov.r_max_km, np.deg2rad(fov.el_min_deg), np.deg2rad(fov.el_max_deg),
                      fov.az_center, np.deg2rad(fov.az_width_deg) / 2, fov.az_width_deg >= 360)
    want = _array_passes(fov, loc, near)
    decided = code != 2
    np.testing.assert_array_equal(code[decided] == 1, want[decided])
    assert not code[~near].any()  # a point not near is out
    # the undecided: not finite, zero range, or within the margin of a bound in the array passes' own numbers
    rae = local_to_rae(loc, fov.az_center)
    off = np.abs((rae[:, 1] - fov.az_center + np.pi) % (2 * np.pi) - np.pi)
    half = np.deg2rad(fov.az_width_deg) / 2
    close = (np.abs(rae[:, 0] - fov.r_min_km) <= 2 * MARGIN) | (np.abs(rae[:, 0] - fov.r_max_km) <= 2 * MARGIN) \
        | (np.abs(rae[:, 2] - np.deg2rad(fov.el_min_deg)) <= 2 * MARGIN) \
        | (np.abs(rae[:, 2] - np.deg2rad(fov.el_max_deg)) <= 2 * MARGIN) \
        | ((np.abs(off - half) <= 2 * MARGIN) & (fov.az_width_deg < 360)) | ~np.isfinite(loc).all(axis=1) | (rae[:, 0] == 0)
    assert close[code == 2].all()
    # nearly all random points decided here, and edge points both in and out among the decided ones
    assert (code[:20000][near[:20000]] != 2).all()
    assert 0 < (code == 1).sum() < len(loc) and (code == 2).sum() > 100


@pytest.mark.parametrize("k", range(len(FOVS)))
def test_in_view_local_equals_the_array_passes_on_every_point(k):
    fov = FOVS[k]
    radar = GroundRadar(GroundSite(45.0, 0.0, 0.1, "site"), fov, revisit_s=10.0, p_D=0.9, clutter_rate=2.0,
                        measurement="enu", sigma_enu_km=0.5)
    rng = np.random.default_rng(23 + k)
    loc = np.concatenate([rng.uniform(-1.2, 1.2, (5000, 3)) * fov.r_max_km, _edge_points(fov, rng, 2000),
                          [[np.nan, 0.0, 0.0], [0.0, 0.0, 0.0]]])
    near = rng.random(len(loc)) < 0.9
    got = radar.in_view_local(loc, near)
    np.testing.assert_array_equal(got, _array_passes(fov, loc, near))
    assert got.dtype == bool and 0 < got.sum() < len(loc)
    assert radar.in_view_local(np.zeros((0, 3)), np.zeros(0, bool)).shape == (0,)


def test_bad_shapes_are_refused_by_the_kernel_wrapper():
    with pytest.raises(ValueError):
        fov_decide(np.zeros((4, 2)), np.ones(4, bool), 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, False)

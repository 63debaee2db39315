"""The fence sensor: in view on known geometry, a second sensor in one scenario, a few returns per crossing."""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue import DEFAULT_RADAR, load_catalogue, select_groups, simulate_catalogue
from hypotrack.scenarios.catalogue.fence import FENCE_SITE, space_fence
from hypotrack.scenarios.catalogue.snr import S_BAND_SNR


def _point(az_deg, el_deg, r_km, site=FENCE_SITE):
    """Earth-fixed position at (azimuth, elevation, range) from the site: ENU (r cos el sin az, r cos el cos az,
    r sin el) rotated by the site's ENU rows."""
    a, e = np.deg2rad(az_deg), np.deg2rad(el_deg)
    return site.ef + r_km * np.array([np.cos(e) * np.sin(a), np.cos(e) * np.cos(a), np.sin(e)]) @ site.enu


def test_fence_in_view_on_known_geometry():
    fence = space_fence()
    pts = np.stack([_point(0, 21.5, 1500), _point(200, 20.1, 3900), _point(90, 19.9, 1500),
                    _point(90, 23.1, 1500), _point(45, 22.0, 4100), _point(300, 22.0, 150)])
    assert fence.in_view(pts).tolist() == [True, True, False, False, False, False]
    rae = fence.rae(pts[:2])
    assert rae[:, 0] == pytest.approx([1500, 3900], rel=1e-9)
    assert np.rad2deg(rae[:, 2]) == pytest.approx([21.5, 20.1], abs=1e-9)
    # the site: Kwajalein, 8.72 N 167.73 E; geodetic latitude ~ geocentric here: |z| / |r| = sin(8.66 deg)
    assert np.rad2deg(np.arcsin(FENCE_SITE.ef[2] / np.linalg.norm(FENCE_SITE.ef))) == pytest.approx(8.66, abs=0.01)
    assert np.rad2deg(np.arctan2(FENCE_SITE.ef[1], FENCE_SITE.ef[0])) == pytest.approx(167.73, abs=1e-9)
    assert space_fence(snr=True).snr is S_BAND_SNR and space_fence().snr is None


def test_two_sensors_in_one_scenario():
    cat = load_catalogue()
    objs = select_groups(cat, "active").iloc[::10].reset_index(drop=True)  # 679 payloads
    fence = space_fence(p_D=1.0, clutter_rate=0.0)
    one = simulate_catalogue(objs, DEFAULT_RADAR, n_scans=360, seed=4)
    both = simulate_catalogue(objs, [DEFAULT_RADAR, fence], n_scans=360, seed=4)
    # the first sensor's returns do not change when a second one is added (one stream per sensor)
    a = one.scans.reset_index(drop=True)
    b = both.scans[both.scans["sensor"] == 0].reset_index(drop=True)
    assert a[["scan", "z_0", "z_1", "z_2", "origin"]].equals(b[["scan", "z_0", "z_1", "z_2", "origin"]])
    f = both.scans[both.scans["sensor"] == 1]
    assert len(f) == both.n_in_view[:, 1].sum() > 0  # p_D = 1, no clutter: one return per object in view
    # every fence return's elevation lies in the 20-23 degree band up to the noise (0.05 deg)
    assert np.all(np.abs(np.rad2deg(f["z_2"].to_numpy()) - 21.5) < 1.5 + 5 * 0.05)
    # a crossing of the band lasts a few scans, not a pass of minutes
    runs = []
    for _, g in f.groupby("origin"):
        s = np.sort(g["scan"].to_numpy())
        runs += list(np.diff(np.r_[0, np.flatnonzero(np.diff(s) > 1) + 1, len(s)]))
    assert 1.5 < np.mean(runs) < 5

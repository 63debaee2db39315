"""GroundRadar.in_view computes the angles of the points within range only: the same decisions as the
field of view's test on every point's (range, azimuth, elevation) — checked on points around the
range limits, the horizon and the azimuth edges, and NaN rows."""

import numpy as np

from hypotrack.scenarios.catalogue import GroundRadar, GroundSite, RadarFieldOfView
from hypotrack.scenarios.catalogue.frames import rae_to_enu


def test_in_view_equals_the_field_of_view_test_on_every_point():
    site = GroundSite(45.0, 0.0, 0.1, "site")
    fov = RadarFieldOfView(180.0, 120.0, 5.0, 85.0, 200.0, 3000.0)
    radar = GroundRadar(site, fov, revisit_s=10.0, p_D=0.9, clutter_rate=2.0, measurement="enu", sigma_enu_km=0.5)
    rng = np.random.default_rng(3)
    # points in local (range, az, el) straddling every edge of the field of view, then to Earth-fixed
    r = rng.choice([199.9999, 200.0, 1500.0, 2999.9999, 3000.0, 3000.0001, 5000.0], 4000)
    az = np.radians(rng.choice([119.999, 120.0, 180.0, 240.0, 240.001, 0.0], 4000))
    el = np.radians(rng.choice([-10.0, 4.999, 5.0, 45.0, 85.0, 85.001], 4000))
    enu = rae_to_enu(np.column_stack([r, az, el]))
    r_ef = site.ef + enu @ site.enu
    r_ef[:7] = np.nan
    got = radar.in_view(r_ef)
    want = fov.contains(radar.rae(r_ef))
    np.testing.assert_array_equal(got, want)
    assert 100 < got.sum() < 3000 and not got[:7].any()
    assert radar.in_view(np.zeros((0, 3))).shape == (0,)

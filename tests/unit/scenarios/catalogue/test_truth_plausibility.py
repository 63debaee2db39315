"""The truth side leaves out states SGP4 returns without an error code but no real object can be in.

Cosmos 2251 fragment NORAD 34970 (perigee 459 km at its 2021 element epoch) propagated to the bundled
scenario's default start (2022-11-02 19:40 UTC, about 13 months on): SGP4 returns error code 0 and a
state whose osculating orbit has its perigee about 58 km and its apogee about 110 km up — it re-enters
within the revolution. The truth and the returns must not hold it, even for a radar right below it.
"""

import numpy as np
import pytest

from hypotrack.models.plausibility import perigee_apogee_radius, plausible_orbits
from hypotrack.scenarios.catalogue import (
    GroundRadar,
    GroundSite,
    RadarFieldOfView,
    load_catalogue,
    propagate,
    reference_epoch,
    simulate_catalogue,
)
from hypotrack.scenarios.catalogue.frames import gmst, teme_to_ef
from hypotrack.scenarios.catalogue.propagation import IMPLAUSIBLE, time_grid_jd
from hypotrack.scenarios.catalogue.tle import satrec_array

R_E = 6378.135
NORAD = 34970


@pytest.fixture(scope="module")
def case():
    cat = load_catalogue()
    start = reference_epoch(cat)
    one = cat[cat["norad"] == NORAD].reset_index(drop=True)
    return one, start


def _raw_sgp4(one, start):
    jd, fr = time_grid_jd(start, np.array([0.0]))
    e, r, v = satrec_array(one).sgp4(jd, fr)
    return int(e[0, 0]), r[0, 0], v[0, 0], jd, fr


def test_sgp4_returns_a_state_below_the_perigee_floor_without_error(case):
    one, start = case
    assert str(start) == "2022-11-02 19:40:00"
    err, r, v, _, _ = _raw_sgp4(one, start)
    assert err == 0 and np.all(np.isfinite(r))
    rp, ra = perigee_apogee_radius(np.r_[r, v])
    assert 50 < rp - R_E < 65 and ra - R_E > 100  # perigee ~58 km, apogee ~110 km
    # independent of the library: a = -mu / (2 eps), e from h, perigee a (1 - e)
    mu = 398600.4418
    eps = v @ v / 2 - mu / np.linalg.norm(r)
    a = -mu / (2 * eps)
    e = np.sqrt(1 + 2 * eps * np.sum(np.cross(r, v) ** 2) / mu**2)
    assert a * (1 - e) == pytest.approx(rp, abs=1e-6)
    assert not plausible_orbits(np.r_[r, v])


def test_the_state_is_left_out_of_the_truth_and_the_returns(case):
    one, start = case
    p = propagate(one, np.array([0.0]), start)
    assert p.error[0, 0] == IMPLAUSIBLE and np.isnan(p.r).all()
    # a radar right below the object, seeing the whole sky down to 10 km range, p_D = 1, no clutter
    err, r, v, jd, fr = _raw_sgp4(one, start)
    r_ef, _ = teme_to_ef(r[None, None], v[None, None], gmst(jd, fr))
    r_ef = r_ef[0, 0]
    lat = np.degrees(np.arcsin(r_ef[2] / np.linalg.norm(r_ef)))
    lon = np.degrees(np.arctan2(r_ef[1], r_ef[0])) % 360.0
    radar = GroundRadar(GroundSite(lat, lon, 0.0), RadarFieldOfView(180.0, 360.0, 5.0, 90.0, 10.0, 3000.0),
                        p_D=1.0, clutter_rate=0.0)
    assert radar.in_view(r_ef[None])[0]  # the raw SGP4 state would be seen (the control)
    sc = simulate_catalogue(one, radar, n_scans=1, seed=0, start=start, truth_rows="all")
    assert len(sc.truth) == 0
    assert len(sc.scans) == 0 or not (sc.scans["origin"] == NORAD).any()
    assert sc.decayed.tolist() == [NORAD]


def test_every_bundled_object_below_the_floor_at_the_default_start_is_absent(case):
    """All bundled objects SGP4 propagates to the default start without an error code but with an
    osculating perigee below 100 km are absent (four: Fengyun-1C 31298, Cosmos 2251 34970, 35283, 35610)."""
    cat = load_catalogue()
    start = reference_epoch(cat)
    jd, fr = time_grid_jd(start, np.array([0.0]))
    e, r, v = satrec_array(cat).sgp4(jd, fr)
    rp, _ = perigee_apogee_radius(np.concatenate([r, v], axis=-1))
    low = (e[:, 0] == 0) & (rp[:, 0] - R_E < 100)
    assert sorted(cat["norad"][low]) == [31298, 34970, 35283, 35610]
    p = propagate(cat[low], np.array([0.0]), start)
    assert (p.error == IMPLAUSIBLE).all()

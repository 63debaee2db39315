"""The catalogue scenario: bundled TLEs, SGP4 propagation, frames, ground radars, scans in the schema.

Real values throughout: the sgp4 package's own documented ISS example and Vallado's verification
case (tcppver.out, satellite 00005), Vallado's GMST example, the WGS-84 position of a geodetic point,
the bundled files' object counts, hand-computed elevations, and Monte Carlo statistics of the
sensor model within stated standard errors.
"""

import gzip
import math
import re
from importlib import resources

import numpy as np
import pandas as pd
import pytest
from sgp4.propagation import gstime

from hypotrack.scenarios.catalogue import (
    BUNDLED,
    GROUPS,
    GroundRadar,
    GroundSite,
    RadarFieldOfView,
    load_catalogue,
    parse_tle,
    propagate,
    read_tle,
    reference_epoch,
    sample_objects,
    select_altitude,
    select_groups,
    simulate_catalogue,
)
from hypotrack.scenarios.catalogue.benchmark import benchmark_propagation, two_body_mismatch
from hypotrack.scenarios.catalogue.frames import (
    ef_to_rae,
    enu_matrix,
    geodetic_to_ef,
    gmst,
    julian_date,
    rae_to_enu,
    teme_to_ef,
)
from hypotrack.scenarios.catalogue.propagation import IMPLAUSIBLE, time_grid_jd
from hypotrack.scenarios.catalogue.tle import tle_checksum
from hypotrack.scenarios.tables import CLUTTER, validate_scans, validate_truth

# The sgp4 package's README example (PyPI page, "Usage"): the ISS at 2019-12-09 20:42:00 UTC.
ISS_2019 = (
    "ISS (ZARYA)\n"
    "1 25544U 98067A   19343.69339541  .00001764  00000-0  38792-4 0  9991\n"
    "2 25544  51.6439 211.2001 0007417  17.6667  85.6398 15.50103472202482\n"
)
# Vallado's verification set (sgp4/SGP4-VER.TLE, expected states in sgp4/tcppver.out): 00005 (Vanguard 1).
VANGUARD = (
    "00005\n"
    "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753\n"
    "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667\n"
)
R_E = 6378.137


@pytest.fixture(scope="module")
def cat():
    return load_catalogue()


@pytest.fixture(scope="module")
def objects(cat):
    """The headline mix: 1,000 sampled active satellites + the Fengyun-1C debris cloud."""
    return pd.concat(
        [sample_objects(select_groups(cat, "active"), 1000, seed=1), select_groups(cat, "fengyun-1c-debris")],
        ignore_index=True,
    )


# --- data ----------------------------------------------------------------------------------------


def test_bundled_object_counts(cat):
    counts = cat.groupby("group").size().to_dict()
    assert counts == {
        "active": 6789,
        "fengyun-1c-debris": 2686,
        "cosmos-2251-debris": 1048,
        "iridium-33-debris": 332,
    }
    assert len(cat) == 10855 and cat["norad"].is_unique
    assert list(dict.fromkeys(cat["group"])) == list(GROUPS)
    for g, (_, _, n) in BUNDLED.items():
        assert len(load_catalogue(g)) == n


def test_bundled_files_deterministic_gzip_and_readme_hashes():
    folder = resources.files("hypotrack").joinpath("data", "tle")
    readme = folder.joinpath("README.md").read_text()
    for name, (fname, sha, _) in BUNDLED.items():
        raw = folder.joinpath(fname).read_bytes()
        assert raw[:3] == b"\x1f\x8b\x08"
        assert raw[3] == 0, f"{fname}: gzip header flags must be 0 (no file name)"
        assert raw[4:8] == b"\0\0\0\0", f"{fname}: gzip header mtime must be 0"
        assert re.search(rf"^{sha}  {re.escape(fname[:-3])}$", readme, re.M), (
            f"README must list {name}'s hash"
        )


def test_checksum_mismatch_is_refused(tmp_path):
    path = tmp_path / "iridium-33-debris_2021-10-02.tle.gz"
    text = gzip.decompress(resources.files("hypotrack").joinpath("data", "tle", path.name).read_bytes())
    path.write_bytes(gzip.compress(text.replace(b"IRIDIUM 33 DEB", b"IRIDIUM 33 XYZ", 1), mtime=0))
    with pytest.raises(ValueError, match="SHA-256"):
        read_tle(path, sha256=BUNDLED["iridium-33-debris"][1])
    assert len(read_tle(path)) == 332  # still a valid TLE file without the expected hash
    assert read_tle(path)["group"].iloc[0] == "iridium-33-debris"


def test_iss_in_the_active_catalogue(cat):
    iss = cat[cat["norad"] == 25544].iloc[0]
    assert iss["name"] == "ISS (ZARYA)" and iss["intl_designator"] == "98067A"
    assert iss["epoch"] == pd.Timestamp("2022-11-03 04:45:30.587616")  # 22307.19827069
    assert iss["inclination_deg"] == pytest.approx(51.6449)
    assert iss["mean_motion_rev_day"] == pytest.approx(15.49699110)
    assert 410 < iss["perigee_alt_km"] < iss["apogee_alt_km"] < 425  # the ISS flew at ~415-420 km then
    r = np.linalg.norm(propagate(cat[cat["norad"] == 25544], np.array([0.0]), iss["epoch"]).r[0, 0])
    assert 6378.137 + 405 < r < 6378.137 + 430


# --- SGP4 against its own references -------------------------------------------------------------


def test_sgp4_readme_iss_example():
    c = parse_tle(ISS_2019)
    p = propagate(c, np.array([0.0]), "2019-12-09T20:42:00")
    # README: r = (-6088.92..., -936.13..., -2866.44...) km, v = (-1.525..., -5.538..., 5.068...) km/s.
    np.testing.assert_allclose(p.r[0, 0], [-6088.925, -936.135, -2866.445], atol=0.005)
    np.testing.assert_allclose(p.v[0, 0], [-1.5255, -5.5385, 5.0685], atol=0.0005)


def test_sgp4_vallado_verification_case():
    c = parse_tle(VANGUARD)
    epoch = c["epoch"].iloc[0]
    assert epoch == pd.Timestamp("2000-06-27 18:50:19.733568")
    p = propagate(c, np.array([0.0, 360.0 * 60]), epoch)
    # tcppver.out, satellite 5, tsince 0 and 360 min (the epoch is held to the microsecond: 3.5 mm).
    np.testing.assert_allclose(p.r[0, 0], [7022.46529266, -1400.08296755, 0.03995155], atol=1e-5)
    np.testing.assert_allclose(p.v[0, 0], [1.893841015, 6.405893759, 4.534807250], atol=1e-8)
    np.testing.assert_allclose(p.r[0, 1], [-7154.03120202, -3783.17682504, -3536.19412294], atol=1e-5)
    np.testing.assert_allclose(p.v[0, 1], [4.741887409, -4.151817765, -2.093935425], atol=1e-8)


def test_debris_propagated_past_its_decay_is_absent(cat):
    """Fengyun-1C fragment 33709 (perigee 311 km, B* 0.0078 in 2021): fine at its epoch; 13 months
    later SGP4 returns a state 2.8e12 km out with error code 0, which the check rejects."""
    frag = cat[cat["norad"] == 33709]
    own = propagate(frag, np.array([0.0, 600.0]))
    assert (own.error == 0).all() and np.all(np.abs(np.linalg.norm(own.r, axis=-1) - 6698) < 40)
    late = propagate(frag, np.array([0.0]), reference_epoch(cat))
    assert late.error[0, 0] == IMPLAUSIBLE and np.isnan(late.r).all()
    active = propagate(select_groups(cat, "active"), np.arange(0, 86400, 3600.0))
    assert active.valid.all()  # no real object trips it near its epoch


# --- time and frames -----------------------------------------------------------------------------


def test_julian_date_and_gmst():
    assert julian_date("2019-12-09T20:42:00") == (2458826.5, 0.8625)  # the sgp4 README's (jd, fr)
    assert julian_date(pd.Timestamp("2000-01-01T12:00", tz="Europe/Paris")) == (2451544.5, 11 / 24)
    # Vallado, Fundamentals of Astrodynamics, Example 3-5: 1992-08-20 12:14 UT1 -> 152.578788 deg.
    assert math.degrees(gmst(2448854.5, 734 / 1440)) == pytest.approx(152.578788, abs=2e-6)
    jd = 2459886.5 + np.linspace(0, 3, 7)
    np.testing.assert_allclose(gmst(jd), [gstime(x) for x in jd], atol=1e-10)  # SGP4's own gstime


def test_geodetic_site_position_and_zenith():
    # WGS-84 point at 45 deg N, 0 deg E on the ellipsoid: N = a / sqrt(1 - e^2/2) = 6388.838 km.
    np.testing.assert_allclose(geodetic_to_ef(45.0, 0.0, 0.0), [4517.590879, 0.0, 4487.348409], atol=1e-6)
    site = GroundSite(45.0, 30.0, 0.2)
    up = enu_matrix(45.0, 30.0)[2]
    np.testing.assert_allclose(enu_matrix(45.0, 30.0) @ enu_matrix(45.0, 30.0).T, np.eye(3), atol=1e-15)
    rae = ef_to_rae(site.ef + 700.0 * up, site.ef, site.enu)
    assert rae[0] == pytest.approx(700.0) and math.degrees(rae[2]) == pytest.approx(90.0, abs=1e-6)


def test_hand_computed_elevation_and_visibility():
    """Site on the equator at 0 deg E: east = +y, north = +z, up = +x (Earth-fixed)."""
    site = GroundSite(0.0, 0.0, 0.0)
    pts = np.array(
        [
            [R_E + 1000.0, 0.0, 1000.0],  # 1000 km north, 1000 km up: az 0, el 45, range 1414.2
            [R_E + 300.0, 1000.0, 0.0],  # 1000 km east, 300 km up: az 90, el atan(0.3) = 16.699
            [R_E + 500.0, 0.0, 0.0],  # zenith
            [R_E - 10.0, 0.0, 900.0],  # 10 km below the horizontal plane, north
        ]
    )
    rae = ef_to_rae(pts, site.ef, site.enu)
    np.testing.assert_allclose(rae[0], [1000 * math.sqrt(2), 0.0, math.pi / 4], atol=1e-9)
    np.testing.assert_allclose(rae[1], [math.hypot(1000, 300), math.pi / 2, math.atan(0.3)], atol=1e-9)
    assert math.degrees(rae[1, 2]) == pytest.approx(16.69924423)
    assert rae[2, 2] == pytest.approx(math.pi / 2)
    assert math.degrees(rae[3, 2]) == pytest.approx(-math.degrees(math.atan(10 / 900)))
    wide = dict(az_center_deg=45.0, az_width_deg=120.0, el_max_deg=89.0, r_max_km=2000.0)
    assert GroundRadar(site, RadarFieldOfView(el_min_deg=10.0, **wide)).in_view(pts).tolist() == [
        True,
        True,
        False,  # above el_max
        False,  # below the horizon
    ]
    assert GroundRadar(site, RadarFieldOfView(el_min_deg=20.0, **wide)).in_view(pts).tolist() == [
        True,
        False,  # 16.7 deg < 20 deg
        False,
        False,
    ]
    narrow = RadarFieldOfView(az_center_deg=90.0, az_width_deg=60.0, el_min_deg=10.0, r_max_km=2000.0)
    assert GroundRadar(site, narrow).in_view(pts).tolist() == [False, True, False, False]  # az 0 is outside
    short = RadarFieldOfView(az_center_deg=45.0, az_width_deg=120.0, el_min_deg=10.0, r_max_km=1200.0)
    assert GroundRadar(site, short).in_view(pts).tolist() == [False, True, False, False]  # 1414 km > 1200


def test_teme_to_earth_fixed_holds_a_geostationary_satellite_still(cat):
    geo = cat[cat["norad"] == 28358]  # INTELSAT 10-02, inclination 0.002 deg
    p = propagate(geo, np.arange(0, 86400 + 1, 3600.0))
    theta = gmst(*time_grid_jd(p.start, p.times))
    r_ef, v_ef = teme_to_ef(p.r[0], p.v[0], theta)
    lon = np.degrees(np.arctan2(r_ef[:, 1], r_ef[:, 0]))
    ra = np.degrees(np.unwrap(np.arctan2(p.r[0, :, 1], p.r[0, :, 0])))
    assert ra[-1] - ra[0] == pytest.approx(361.0, abs=0.5)  # inertially: one sidereal turn a day
    assert np.ptp(lon) < 0.1  # Earth-fixed: station-kept within 0.1 deg
    assert abs(lon.mean() - (-1.0)) < 0.5  # Intelsat 10-02 is stationed at 1.0 deg W
    assert np.linalg.norm(v_ef, axis=1).max() < 0.01  # km/s, against 3.07 km/s inertial


# --- selection ----------------------------------------------------------------------------------


def test_selections_are_deterministic(cat):
    a = sample_objects(cat, 50, seed=7)
    assert a["norad"].tolist() == sample_objects(cat, 50, seed=7)["norad"].tolist()
    assert a["norad"].tolist() != sample_objects(cat, 50, seed=8)["norad"].tolist()
    assert a.index.tolist() == list(range(50)) and a["norad"].isin(cat["norad"]).all()
    pos = cat.reset_index().set_index("norad").loc[a["norad"], "index"].to_numpy()
    assert np.all(np.diff(pos) > 0)  # catalogue order
    assert len(sample_objects(cat, 0, seed=1)) == 0
    leo = select_altitude(select_groups(cat, "active"), 200.0, 2000.0)
    assert len(leo) == 6035
    assert (leo["perigee_alt_km"] >= 200).all() and (leo["apogee_alt_km"] <= 2000).all()
    geo = select_altitude(cat, 35286.0, 36286.0)
    assert len(geo) > 400 and set(geo["group"]) == {"active"}
    debris = select_groups(cat, ["iridium-33-debris", "cosmos-2251-debris"])
    assert len(debris) == 1380 and list(dict.fromkeys(debris["group"])) == [
        "cosmos-2251-debris",
        "iridium-33-debris",
    ]


def test_reference_epoch(cat):
    assert reference_epoch(select_groups(cat, "active")) == pd.Timestamp("2022-11-02 19:40")
    assert reference_epoch(select_groups(cat, "fengyun-1c-debris")) == pd.Timestamp("2021-10-02 01:12")
    assert reference_epoch(cat) == pd.Timestamp("2022-11-02 19:40")  # the latest group's median


# --- the scenario -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def headline(objects):
    return simulate_catalogue(objects, n_scans=60, seed=11)


def test_scenario_tables_and_labels(headline, objects):
    sc = headline
    validate_scans(sc.scans)
    validate_truth(sc.truth)
    assert sc.start == reference_epoch(objects) and sc.times[1] == 10.0
    assert abs(sc.start - pd.Timestamp("2022-11-02 19:40")) < pd.Timedelta("30min")
    assert list(sc.scans.columns[4:7]) == ["z_0", "z_1", "z_2"]
    assert sc.truth["in_view"].all()
    assert 25 < sc.n_in_view.mean() < 75  # 48 in this first 10 min; 36 over 6 h (scenario docstring)
    assert np.array_equal(sc.truth.groupby("scan").size().to_numpy(), sc.n_in_view[:, 0])
    det = sc.scans[sc.scans["origin"] != CLUTTER]
    assert det["origin"].isin(objects["norad"]).all()
    keys = set(zip(sc.truth["scan"], sc.truth["target"]))
    assert all((k, o) in keys for k, o in zip(det["scan"], det["origin"]))  # every label is a truth row
    # Every detection lies within 6 sigma of the radar's noise-free measurement of the truth.
    radar = sc.sensors[0]
    tr = sc.truth.set_index(["scan", "target"])
    X = tr.loc[list(zip(det["scan"], det["origin"])), [f"state_{i}" for i in range(6)]].to_numpy()
    h = np.vstack([radar.h(x, sc.theta[k]) for x, k in zip(X, det["scan"])])
    resid = (det[["z_0", "z_1", "z_2"]].to_numpy() - h) / np.sqrt(np.diag(radar.R))
    assert np.abs(resid).max() < 6
    np.testing.assert_allclose(resid.std(axis=0), 1.0, atol=4 / math.sqrt(2 * len(resid)))
    np.testing.assert_allclose(resid.mean(axis=0), 0.0, atol=4 / math.sqrt(len(resid)))
    lo, hi = radar.fov.low, radar.fov.high
    assert (det["z_1"] >= lo[1] - 0.01).all() and (det["z_1"] <= hi[1] + 0.01).all()  # no azimuth wrap


def test_scenario_is_deterministic(objects):
    sub = objects.iloc[::4].reset_index(drop=True)
    a = simulate_catalogue(sub, n_scans=20, seed=5)
    b = simulate_catalogue(sub, n_scans=20, seed=5)
    pd.testing.assert_frame_equal(a.scans, b.scans)
    pd.testing.assert_frame_equal(a.truth, b.truth)
    c = simulate_catalogue(sub, n_scans=20, seed=6)
    pd.testing.assert_frame_equal(a.truth, c.truth)  # the truth has no randomness
    assert not a.scans[["z_0", "z_1", "z_2"]].equals(c.scans[["z_0", "z_1", "z_2"]])
    # A second sensor has its own stream: sensor 0's returns do not change.
    north = GroundRadar(GroundSite(60.0, 20.0, 0.0), RadarFieldOfView(az_center_deg=0.0))
    d = simulate_catalogue(sub, [GroundRadar(), north], n_scans=20, seed=5)
    s0 = d.scans[d.scans["sensor"] == 0].reset_index(drop=True)
    pd.testing.assert_frame_equal(s0, a.scans)
    assert (d.scans["sensor"] == 1).any()
    full = simulate_catalogue(sub, n_scans=3, seed=5, truth_rows="all")
    valid = propagate(sub, full.times, full.start).valid
    assert len(full.truth) == valid.sum() > 0.99 * 3 * len(sub)  # all but the decayed fragments
    assert full.truth["in_view"].sum() == full.n_in_view.sum()


def test_nothing_in_view_gives_clutter_only_and_empty_scans(cat):
    geo = select_altitude(cat, 35286.0, 36286.0).iloc[:20]  # beyond the default radar's 3,000 km
    sc = simulate_catalogue(geo, GroundRadar(clutter_rate=0.5), n_scans=30, seed=1)
    assert (sc.n_in_view == 0).all() and len(sc.truth) == 0
    assert (sc.scans["origin"] == CLUTTER).all() and 0 < len(sc.scans) < 60
    scans = sc.scan_list()
    assert len(scans) == 30 and any(len(Z) == 0 for _, Z in scans)
    Z, origin = GroundRadar(clutter_rate=0.0).observe(np.full((3, 3), np.nan), np.random.default_rng(0))
    assert Z.shape == (0, 3) and origin.shape == (0,)


def test_observe_labels_rows_of_earth_fixed_input():
    site = GroundSite(0.0, 0.0, 0.0)
    radar = GroundRadar(site, RadarFieldOfView(az_center_deg=0.0), p_D=1.0, clutter_rate=3.0)
    pts = np.array([[R_E + 1000.0, 0.0, 1000.0], [np.nan] * 3, [R_E + 300.0, 0.0, 800.0], [-R_E, 0.0, 0.0]])
    Z, origin = radar.observe(pts, np.random.default_rng(2))
    assert sorted(origin[origin >= 0].tolist()) == [0, 2]
    np.testing.assert_allclose(Z[origin == 0, 0], 1000 * math.sqrt(2), atol=0.2)


def test_detection_and_clutter_statistics(objects):
    """p_D = 0.7, 3 clutter returns per scan: frequencies within 4 standard errors."""
    radar = GroundRadar(p_D=0.7, clutter_rate=3.0)
    sc = simulate_catalogue(objects, radar, n_scans=150, seed=3)
    n_view = sc.n_in_view.sum()
    n_det = (sc.scans["origin"] != CLUTTER).sum()
    assert n_view > 5000
    assert abs(n_det / n_view - 0.7) < 4 * math.sqrt(0.7 * 0.3 / n_view)
    clutter = sc.scans[sc.scans["origin"] == CLUTTER]
    per_scan = clutter.groupby("scan").size().reindex(range(150), fill_value=0).to_numpy()
    assert abs(per_scan.mean() - 3.0) < 4 * math.sqrt(3.0 / 150)
    assert abs(per_scan.var(ddof=1) / 3.0 - 1) < 4 * math.sqrt(2 / 149 + 1 / (3 * 150))  # Poisson: var = mean
    Z = clutter[["z_0", "z_1", "z_2"]].to_numpy()
    lo, hi = radar.fov.low, radar.fov.high
    assert (Z >= lo).all() and (Z <= hi).all()
    u = (Z - lo) / (hi - lo)  # uniform over the measurement box: each coordinate U(0, 1)
    np.testing.assert_allclose(u.mean(axis=0), 0.5, atol=4 * math.sqrt(1 / 12 / len(u)))
    assert radar.clutter_density == pytest.approx(1 / (2800 * math.radians(120) * math.radians(80)))


def test_enu_measurement_and_physical_clutter(objects):
    radar = GroundRadar(measurement="enu", sigma_enu_km=0.5, clutter_rate=0.0)
    sc = simulate_catalogue(objects.iloc[::3].reset_index(drop=True), radar, n_scans=20, seed=4)
    tr = sc.truth.set_index(["scan", "target"])
    X = tr.loc[list(zip(sc.scans["scan"], sc.scans["origin"])), [f"state_{i}" for i in range(6)]].to_numpy()
    h = np.vstack([radar.h(x, sc.theta[k]) for x, k in zip(X, sc.scans["scan"])])
    resid = sc.scans[["z_0", "z_1", "z_2"]].to_numpy() - h
    assert len(resid) > 100 and np.abs(resid).max() < 6 * 0.5
    # Uniform over the physical volume: r^3 and sin(el) uniform.
    fov = radar.fov
    pts = fov.sample_enu(20000, np.random.default_rng(0))
    r = np.linalg.norm(pts, axis=1)
    assert fov.contains(
        np.column_stack([r, np.arctan2(pts[:, 0], pts[:, 1]), np.arcsin(pts[:, 2] / r)])
    ).all()
    u = (r**3 - fov.r_min_km**3) / (fov.r_max_km**3 - fov.r_min_km**3)
    assert abs(u.mean() - 0.5) < 4 * math.sqrt(1 / 12 / len(u))
    v = (pts[:, 2] / r - math.sin(fov.low[2])) / (math.sin(fov.high[2]) - math.sin(fov.low[2]))
    assert abs(v.mean() - 0.5) < 4 * math.sqrt(1 / 12 / len(v))
    assert radar.clutter_density == pytest.approx(1 / fov.physical_volume)


def test_azimuth_is_reported_in_the_window_around_the_sector_centre():
    """A full-circle sector centred north: true azimuth 179.99 deg with 1-deg noise wraps into [-180, 180)."""
    radar = GroundRadar(
        fov=RadarFieldOfView(az_center_deg=0.0, az_width_deg=360.0), sigma_az_deg=1.0, p_D=1.0
    )
    rae = np.tile([1000.0, math.radians(179.99), 0.5], (2000, 1))
    Z, origin = radar.observe_rae(rae, np.random.default_rng(1))
    z = Z[origin >= 0, 1]
    assert len(z) == 2000 and (z >= -math.pi).all() and (z < math.pi).all()
    assert 0.3 < (z < 0).mean() < 0.7  # about half the noisy azimuths cross 180 deg
    south = GroundRadar(sigma_az_deg=1.0, p_D=1.0)  # centred at 180 deg: no wrap there
    Z, origin = south.observe_rae(rae, np.random.default_rng(1))
    assert abs(Z[origin >= 0, 1].mean() - math.radians(179.99)) < 4 * math.radians(1.0) / math.sqrt(2000)


def test_measurement_jacobian_matches_finite_differences():
    radar = GroundRadar()
    x = np.array([5000.0, -1500.0, 3900.0, 1.0, 6.0, -3.0])
    theta = 1.2
    H = radar.h_jacobian(x, theta)[0]
    eps = 1e-3
    for j in range(6):
        dx = np.zeros(6)
        dx[j] = eps
        fd = (radar.h(x + dx, theta)[0] - radar.h(x - dx, theta)[0]) / (2 * eps)
        np.testing.assert_allclose(H[:, j], fd, rtol=1e-6, atol=1e-12)
    enu = GroundRadar(measurement="enu")
    np.testing.assert_allclose(rae_to_enu(radar.h(x, theta)), enu.h(x, theta), atol=1e-9)


# --- model mismatch and benchmark ---------------------------------------------------------------


def test_two_body_one_scan_mismatch_against_sgp4(cat):
    """The numbers in hypotrack.models.orbit3d's docstring (active LEO objects, their own epoch):
    10 s: median 0.62 m, max 5.8 m; the J2-dominated error grows as dt^2."""
    leo = select_altitude(select_groups(cat, "active"), 200.0, 2000.0)
    m10 = two_body_mismatch(leo, 10.0)
    m20 = two_body_mismatch(leo, 20.0)
    e = m10["position_error_km"] * 1e3
    assert len(m10) == 6035
    assert 0.4 < e.median() < 0.9 and e.max() < 8.0
    assert 0.07 < m10["velocity_error_km_s"].median() * 1e3 < 0.16  # m/s: J2 ~ 0.012 m/s^2 x 10 s
    ratio = (m20["position_error_km"] / m10["position_error_km"]).median()
    assert 3.6 < ratio < 4.4


def test_benchmark_propagation_reports(objects):
    b = benchmark_propagation(objects.iloc[:50], n_epochs=3, repeats=1)
    assert b["n_objects"] == 50 and b["n_epochs"] == 3
    assert b["us_per_object_epoch"] > 0 and b["us_per_object_epoch_checked"] > 0


# --- bad input ----------------------------------------------------------------------------------


def _radar(**kw):
    return lambda: GroundRadar(**kw)


@pytest.mark.parametrize(
    "make, fragment",
    [
        (lambda: GroundSite(91.0, 0.0), r"lat_deg must lie in \[-90, 90\]"),
        (lambda: GroundSite(0.0, 400.0), "lon_deg"),
        (lambda: GroundSite(0.0, 0.0, 50.0), "alt_km"),
        (lambda: GroundSite(float("nan"), 0.0), "lat_deg"),
        (lambda: RadarFieldOfView(az_width_deg=0.0), r"az_width_deg must lie in \(0, 360\]"),
        (lambda: RadarFieldOfView(el_min_deg=-1.0), r"el_min_deg must lie in \[0, 90\)"),
        (lambda: RadarFieldOfView(el_min_deg=30.0, el_max_deg=20.0), "el_max_deg"),
        (lambda: RadarFieldOfView(r_min_km=500.0, r_max_km=400.0), "r_max_km must be > r_min_km"),
        (_radar(p_D=1.5), r"p_D must lie in \(0, 1\]"),
        (_radar(p_D=0.0), "p_D"),
        (_radar(clutter_rate=-1.0), "clutter_rate"),
        (_radar(sigma_range_km=0.0), "sigma_range_km"),
        (_radar(sigma_az_deg=-0.1), "sigma_az_deg"),
        (_radar(revisit_s=0.0), "revisit_s"),
        (_radar(measurement="xyz"), "measurement must be one of"),
        (_radar(site=(45.0, 0.0)), "site must be a GroundSite"),
    ],
)
def test_bad_sensor_input(make, fragment):
    with pytest.raises((ValueError, TypeError), match=fragment):
        make()


L1, L2 = ISS_2019.splitlines()[1:]
L2_OTHER = L2.replace("25544", "25545")[:68] + str(tle_checksum(L2.replace("25544", "25545")))


@pytest.mark.parametrize(
    "text, fragment",
    [
        (f"ISS\n{L1[:68]}0\n{L2}\n", "checksum"),
        (f"ISS\n{L2}\n{L1}\n", "expected TLE line 1"),
        (f"ISS\n{L1}\n", "whole number of three-line"),
        (f"{L1}\n{L2}\nISS\n", "expected a name line"),
        (f"ISS\n{L1}\n{L2_OTHER}\n", "NORAD numbers differ"),
        (f"ISS\n{L1}\n{L2}\nISS\n{L1}\n{L2}\n", "NORAD numbers repeat"),
    ],
)
def test_bad_tle_text(text, fragment):
    with pytest.raises(ValueError, match=fragment):
        parse_tle(text, source="bad.tle")


def test_bad_scenario_and_selection_input(cat, objects):
    small = objects.iloc[:5]
    with pytest.raises(ValueError, match=r"n must be an integer in \[0, 10855\]"):
        sample_objects(cat, 10856, seed=1)
    with pytest.raises(ValueError, match="n must be"):
        sample_objects(cat, -1, seed=1)
    with pytest.raises(ValueError, match="high_km must be > low_km"):
        select_altitude(cat, 2000.0, 200.0)
    with pytest.raises(ValueError, match="low_km"):
        select_altitude(cat, -5.0, 200.0)
    with pytest.raises(ValueError, match="groups must be 'all' or names among"):
        load_catalogue("starlink")
    with pytest.raises(ValueError, match="groups must be names among"):
        select_groups(cat, "starlink")
    with pytest.raises(ValueError, match=r"n_scans must be an integer in \[1, inf\]"):
        simulate_catalogue(small, n_scans=0, seed=1)
    with pytest.raises(ValueError, match="truth_rows must be one of"):
        simulate_catalogue(small, n_scans=1, seed=1, truth_rows="some")
    with pytest.raises(ValueError, match="sensors\\[1\\].revisit_s must equal"):
        simulate_catalogue(small, [GroundRadar(), GroundRadar(revisit_s=5.0)], n_scans=1, seed=1)
    with pytest.raises(ValueError, match="sensors\\[1\\].measurement must equal"):
        simulate_catalogue(small, [GroundRadar(), GroundRadar(measurement="enu")], n_scans=1, seed=1)
    with pytest.raises(ValueError, match="sensors must hold at least one"):
        simulate_catalogue(small, [], n_scans=1, seed=1)
    with pytest.raises(ValueError, match="start must be a UTC date-time"):
        simulate_catalogue(small, n_scans=1, seed=1, start="yesterday-ish")
    with pytest.raises(ValueError, match="catalogue must hold at least one object"):
        simulate_catalogue(small.iloc[:0], n_scans=1, seed=1)
    with pytest.raises(ValueError, match="catalogue is missing columns"):
        simulate_catalogue(small[["norad", "name"]], n_scans=1, seed=1)
    with pytest.raises(ValueError, match="times must be a 1-D array"):
        propagate(small, np.zeros((2, 2)))
    with pytest.raises(ValueError, match="times must be finite"):
        propagate(small, np.array([0.0, np.nan]))

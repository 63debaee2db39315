"""The NASA standard breakup model's laws (hand-computed values) and the breakup scenario built on them."""

import numpy as np
import pytest

from hypotrack.models.plausibility import perigee_apogee_radius, plausible_orbits
from hypotrack.scenarios.catalogue import GroundRadar, GroundSite, RadarFieldOfView
from hypotrack.scenarios.catalogue.breakup import (FRAGMENT_ID_BASE, BreakupEvent, gate_radius_km,
                                                    nearest_neighbour_km, simulate_breakup)
from hypotrack.scenarios.catalogue.sbm import (am_parameters, delta_v_mean_log10, isotropic_directions,
                                                sample_area_to_mass, sample_breakup, sample_delta_v, sample_sizes,
                                                sbm_count)


def test_counts_by_hand():
    # 6 * 0.08^-1.6 = 6 * 56.905 = 341.4; 0.1 * 1000^0.75 * 0.1^-1.71 = 0.1 * 177.83 * 51.286 = 912.0
    assert sbm_count("explosion", 0.08) == 341
    assert sbm_count("explosion", 0.05) == 724  # 6 * 120.70
    assert sbm_count("explosion", 0.08, scaling=2.0) == 682
    assert sbm_count("collision", 0.1, mass_kg=1000.0) == 912
    with pytest.raises(ValueError, match="mass_kg"):
        sbm_count("collision", 0.1)
    with pytest.raises(ValueError, match="kind must be one of"):
        sbm_count("impact", 0.1)
    with pytest.raises(ValueError, match="lc_min_m"):
        sbm_count("explosion", 0.0)


def test_size_law_quantiles():
    # P(L > l | L > Lmin) = (l/Lmin)^-1.6: median Lmin * 2^(1/1.6) = 1.5422 Lmin, 90 % 10^(1/1.6) = 4.2170 Lmin
    L = sample_sizes(200_000, 0.05, "explosion", np.random.default_rng(1))
    assert L.min() >= 0.05
    assert np.quantile(L, 0.5) == pytest.approx(0.05 * 1.5422, rel=0.01)
    assert np.quantile(L, 0.9) == pytest.approx(0.05 * 4.2170, rel=0.02)
    # collision exponent 1.71: median 2^(1/1.71) = 1.4994
    Lc = sample_sizes(200_000, 0.1, "collision", np.random.default_rng(2))
    assert np.quantile(Lc, 0.5) == pytest.approx(0.1 * 1.4994, rel=0.01)


def test_area_to_mass_parameters_by_hand():
    # small fragments, lambda = -2: mu = -0.3, sigma = 0.2 + 0.1333 * 1.5 = 0.39995
    mu_s, sd_s, *_ = am_parameters(0.01)
    assert (float(mu_s), float(sd_s)) == pytest.approx((-0.3, 0.39995))
    # lambda = -1.5: mu = -0.3 - 1.4 * 0.25 = -0.65
    assert float(am_parameters(10**-1.5)[0]) == pytest.approx(-0.65)
    # spacecraft at 1 m: alpha = 0.3 + 0.4 * 1.2 = 0.78, mu1 = -0.95, s1 = 0.3, mu2 = -2.0, s2 = 0.3
    _, _, a, m1, s1, m2, s2 = am_parameters(1.0)
    assert [float(v) for v in (a, m1, s1, m2, s2)] == pytest.approx([0.78, -0.95, 0.3, -2.0, 0.3])
    # upper stage at 1 m: alpha = 0.5, mu1 = -0.9, s1 = 0.55, mu2 = -0.9, s2 = 0.28 - 0.1636 = 0.1164 (the
    # paper's slope 0.1636 is 0.18 / 1.1 rounded: the ramp between its end points gives 0.11636)
    _, _, a, m1, s1, m2, s2 = am_parameters(1.0, "rocket_body")
    assert [float(v) for v in (a, m1, s1, m2, s2)] == pytest.approx([0.5, -0.9, 0.55, -0.9, 0.1164], rel=4e-4)
    # spacecraft, lambda = -0.5: mu1 = -0.6 - 0.318 * 0.6 = -0.7908, s2 = 0.5 (the paper's rounded slope again)
    _, _, _, m1, _, _, s2 = am_parameters(10**-0.5)
    assert (float(m1), float(s2)) == pytest.approx((-0.7908, 0.5), rel=4e-4)
    with pytest.raises(ValueError, match="parent must be one of"):
        am_parameters(1.0, "station")


def test_area_to_mass_samples():
    rng = np.random.default_rng(3)
    chi = sample_area_to_mass(np.full(100_000, 0.01), rng)  # N(-0.3, 0.4)
    assert chi.mean() == pytest.approx(-0.3, abs=0.005)
    assert chi.std() == pytest.approx(0.39995, rel=0.01)
    big = sample_area_to_mass(np.full(100_000, 1.0), rng)  # mixture mean 0.78 * -0.95 + 0.22 * -2.0 = -1.181
    assert big.mean() == pytest.approx(-1.181, abs=0.005)


def test_delta_v_law_quantiles():
    # explosion: log10 dv ~ N(0.2 chi + 1.85, 0.4); chi = -1: median 10^1.65 = 44.67 m/s,
    # quartiles 10^(1.65 -+ 0.6745 * 0.4) = 23.99, 83.15 m/s
    assert float(delta_v_mean_log10(-1.0, "explosion")) == pytest.approx(1.65)
    assert float(delta_v_mean_log10(-1.0, "collision")) == pytest.approx(2.0)  # 0.9 chi + 2.9
    dv = sample_delta_v(np.full(200_000, -1.0), "explosion", np.random.default_rng(4))
    assert np.quantile(dv, [0.25, 0.5, 0.75]) == pytest.approx([23.99, 44.67, 83.15], rel=0.01)


def test_isotropic_and_momentum():
    u = isotropic_directions(100_000, np.random.default_rng(5))
    assert np.linalg.norm(u, axis=1) == pytest.approx(np.ones(100_000))
    assert np.abs(u.mean(axis=0)).max() < 4 / np.sqrt(3 * 100_000)
    f = sample_breakup("explosion", 0.02, np.random.default_rng(6))
    n = len(f)
    assert n == 3136  # 6 * 0.02^-1.6 = 6 * 522.70
    # the model conserves momentum in expectation only: mean dv within 4 sampling s.e. of zero per axis
    se = np.sqrt(np.mean(f.dv_km_s**2, axis=0) / n)
    assert np.all(np.abs(f.dv_km_s.mean(axis=0)) < 4 * se)
    assert np.linalg.norm(f.dv_km_s, axis=1) == pytest.approx(1e-3 * f.dv_m_s)


def _radar():
    site = GroundSite(78.15, 16.05, 0.4, "high-latitude site")
    fov = RadarFieldOfView(0.0, 360.0, 10.0, 90.0, 200.0, 3000.0)
    return GroundRadar(site, fov, revisit_s=10.0, p_D=0.9, clutter_rate=1.0, measurement="enu", sigma_enu_km=0.5)


@pytest.fixture(scope="module")
def small():
    # 6 * 0.2^-1.6 = 78.8: 78 fragments; 120 to 150 min after the event (the cloud's first pass over the site)
    return simulate_breakup(BreakupEvent(lc_min_m=0.2), _radar(), obs_start_s=7200.0, obs_end_s=9000.0, seed=3)


def test_breakup_scenario(small):
    sc = small
    assert len(sc.x0) + sc.n_removed == 78
    assert sc.parent["norad"] == 28654 and sc.parent["name"] == "NOAA 18"
    assert plausible_orbits(sc.x0).all()
    rp, _ = perigee_apogee_radius(sc.x0)
    assert (rp - 6378.135 >= 100.0).all()
    assert len(sc.times) == 181 and sc.times[0] == 0.0 and sc.times[-1] == 1800.0
    assert sc.truth["target"].min() >= FRAGMENT_ID_BASE
    assert sc.n_in_view.sum() == len(sc.truth) > 0  # the cloud passes over the site in this window
    # truth rows are the states() of the truth model at the scan times
    k = int(sc.truth["scan"].iloc[0])
    X, valid = sc.states(np.array([sc.times[k], 0.0]))
    g = sc.truth[sc.truth["scan"] == k]
    rows = g["target"].to_numpy() - FRAGMENT_ID_BASE
    assert valid.all()
    assert X[rows, 0] == pytest.approx(g[[f"state_{i}" for i in range(6)]].to_numpy(), abs=1e-9)
    # every detected fragment's return labelled with its id; clutter -1
    o = sc.scans["origin"].to_numpy()
    assert set(o[o >= 0]) <= set(sc.truth["target"])


def test_breakup_deterministic(small):
    again = simulate_breakup(BreakupEvent(lc_min_m=0.2), _radar(), obs_start_s=7200.0, obs_end_s=9000.0, seed=3)
    assert again.scans.equals(small.scans) and again.truth.equals(small.truth)
    other = simulate_breakup(BreakupEvent(lc_min_m=0.2), _radar(), obs_start_s=7200.0, obs_end_s=9000.0, seed=4)
    assert not np.array_equal(other.x0, small.x0)


def test_perigee_below_100_km_removed():
    # a collision's fragments (mean log10 dv = 0.9 chi + 2.9: ~300 m/s, tail to km/s) include some that
    # re-enter within the revolution: removed and counted, the rest kept
    sc = simulate_breakup(BreakupEvent(kind="collision", mass_kg=1000.0, lc_min_m=0.3), _radar(),
                          obs_start_s=3600.0, obs_end_s=3610.0, seed=1)
    n = sbm_count("collision", 0.3, mass_kg=1000.0)
    assert sc.n_removed > 0 and len(sc.x0) + sc.n_removed == n
    assert plausible_orbits(sc.x0).all()


def test_nearest_neighbour_and_gate():
    import pandas as pd
    from hypotrack.scenarios.tables import truth_table
    X = np.zeros((4, 6))
    X[:, 0] = [0.0, 3.0, 10.0, 50.0]
    t = truth_table([0, 0, 0, 1], [0.0, 0, 0, 10], [1, 2, 3, 1], X, [True, True, True, True])
    assert isinstance(t, pd.DataFrame)
    nn = nearest_neighbour_km(t)
    assert nn[:3] == pytest.approx([3.0, 3.0, 7.0]) and np.isnan(nn[3])
    assert gate_radius_km(0.5, 0.999) == pytest.approx(0.5 * np.sqrt(16.2662), rel=1e-4)
    with pytest.raises(ValueError, match="sigma_km"):
        gate_radius_km(0.0, 0.999)


def test_bad_input():
    with pytest.raises(ValueError, match="parent_norad"):
        simulate_breakup(BreakupEvent(parent_norad=1), _radar(), obs_start_s=10.0, obs_end_s=20.0, seed=1)
    with pytest.raises(ValueError, match="obs_end_s"):
        simulate_breakup(BreakupEvent(), _radar(), obs_start_s=10.0, obs_end_s=5.0, seed=1)
    with pytest.raises(TypeError, match="radar"):
        simulate_breakup(BreakupEvent(), None, obs_start_s=10.0, obs_end_s=20.0, seed=1)

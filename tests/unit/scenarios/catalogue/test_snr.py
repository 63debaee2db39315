"""SNR detection: RCS of a known size, Swerling I p_D at known SNR, the truth side's draws, the tracker's marginal."""

import numpy as np
import pytest
from scipy.integrate import quad

from hypotrack.scenarios.catalogue import DEFAULT_RADAR, GroundRadar, load_catalogue, select_groups, simulate_catalogue
from hypotrack.scenarios.catalogue.snr import (
    S_BAND_SNR,
    UHF_SNR,
    SizeModel,
    SnrModel,
    SnrTrackerDetection,
    rcs_sphere,
    swerling1_p_detect,
)
from hypotrack.scenarios.catalogue.tracking import TrackerSensor


def test_rcs_optical_and_rayleigh_by_hand():
    # 1-m sphere at S-band (x = 10): optical, pi d^2 / 4
    assert rcs_sphere(1.0, 0.1) == pytest.approx(0.7853981634, rel=1e-10)
    # 5-cm sphere at UHF (x = 0.0725): Rayleigh 9 pi^5 d^6 / (4 lambda^4) = 688.5443 * 1.5625e-8 / 0.22667121
    assert rcs_sphere(0.05, 0.69) == pytest.approx(688.5443 * 1.5625e-8 / 0.69**4, rel=1e-6)
    assert rcs_sphere(0.05, 0.69) == pytest.approx(4.74630e-5, rel=1e-5)
    # the two asymptotes meet at x = 1 / (sqrt(3) pi): continuous there
    x = 1 / (np.sqrt(3) * np.pi)
    lo, hi = rcs_sphere([x * (1 - 1e-9), x * (1 + 1e-9)], 1.0)
    assert lo == pytest.approx(hi, rel=1e-7) and hi == pytest.approx(np.pi * x**2 / 4, rel=1e-7)
    with pytest.raises(ValueError, match="d_m"):
        rcs_sphere(0.0, 0.1)


def test_swerling1_at_known_snr():
    # P_FA^(1/(1+SNR)): SNR 0 -> P_FA; ln(1e-6)/ln(0.9) - 1 = 130.126 -> 0.9; 18.9316 -> 0.5
    assert swerling1_p_detect(0.0, 1e-6) == pytest.approx(1e-6, rel=1e-12)
    assert swerling1_p_detect(130.126071960697, 1e-6) == pytest.approx(0.9, rel=1e-12)
    assert swerling1_p_detect(18.931568569324174, 1e-6) == pytest.approx(0.5, rel=1e-12)
    assert swerling1_p_detect(99.0, 1e-2) == pytest.approx(0.01 ** 0.01, rel=1e-12)  # 0.954992586
    with pytest.raises(ValueError, match="p_fa"):
        swerling1_p_detect(1.0, 1.0)


def test_snr_model_design_point_and_range_law():
    m = UHF_SNR
    assert m.snr_ref == pytest.approx(18.931568569324174, rel=1e-12)
    assert m.p_detect(0.1, 3000.0) == pytest.approx(0.5, rel=1e-12)
    # half the range: SNR x 16 = 302.905 -> exp(ln 1e-6 / 303.905) = 0.955558
    assert m.p_detect(0.1, 1500.0) == pytest.approx(0.9555578717768954, rel=1e-10)
    # a 5-cm object at 3,000 km: Rayleigh, sigma ratio (1/2)^6 = 1/64 -> SNR 0.2958 -> 1e-6^(1/1.2958)
    assert m.p_detect(0.05, 3000.0) == pytest.approx(np.exp(np.log(1e-6) / (1 + 18.931568569324174 / 64)), rel=1e-10)
    # the same 5-cm object is optical... no: x = 0.5 at S-band, optical (pi d^2/4): ratio 1/4 to 10 cm
    assert S_BAND_SNR.snr(0.05, 3000.0) == pytest.approx(18.931568569324174 / 4, rel=1e-10)
    with pytest.raises(ValueError, match="ref_p_D"):
        SnrModel(ref_p_D=1e-7)


def test_catalogue_sizes_stated_and_stable():
    cat = load_catalogue()
    sm = SizeModel()
    some = cat.iloc[[0, 1, 7000, 7001, 9000]]
    d = sm.sizes(some, seed=3)
    act = (some["group"] == "active").to_numpy()
    assert np.all(d[act] == 2.0)
    assert np.all(d[~act] >= 0.1)
    # the same object gets the same size in any selection
    assert sm.sizes(cat.iloc[[9000]], seed=3)[0] == d[-1]
    # the debris law: L = 0.1 U^(-1/1.71), so P(L > 0.2) = 2^-1.71 = 0.3057 over a whole cloud
    deb = select_groups(cat, "fengyun-1c-debris")
    share = np.mean(sm.sizes(deb, seed=0) > 0.2)
    assert abs(share - 2**-1.71) < 3 * np.sqrt(0.3057 * 0.6943 / len(deb))


def test_tracker_marginal_is_the_size_average():
    sensor = TrackerSensor(GroundRadar(measurement="enu"))
    sm = SizeModel(debris_share=0.7)
    det = SnrTrackerDetection(sensor, UHF_SNR, sm, n_nodes=2000)
    r = 2500.0

    def debris(u):  # the debris law's quantile function, integrated over U(0, 1)
        return UHF_SNR.p_detect(0.1 * u ** (-1 / 1.71), r)

    oracle = 0.3 * UHF_SNR.p_detect(2.0, r) + 0.7 * quad(debris, 0, 1, limit=200)[0]
    # a state at 2,500 km range from the site (theta = 0: TEME = Earth-fixed), due south at 45 deg elevation
    site = sensor.radar.site
    x = np.r_[site.ef + r * np.array([0, -np.sqrt(0.5), np.sqrt(0.5)]) @ site.enu, 0, 0, 0]
    assert det.p_D_of(x[None])[0] == pytest.approx(oracle, abs=2e-4)
    assert 0 < det.p_D < 1 and det.in_view(x[None, :3])[0]


def test_truth_side_uses_the_object_sizes():
    """Same draws, per-object p_D: a 1-cm object at UHF is nearly never seen; payloads always are."""
    cat = load_catalogue()
    objs = cat.iloc[:300].reset_index(drop=True)
    radar = GroundRadar(snr=UHF_SNR, clutter_rate=0.0)
    big = simulate_catalogue(objs, radar, n_scans=60, seed=1, sizes=np.full(300, 2.0))
    tiny = simulate_catalogue(objs, radar, n_scans=60, seed=1, sizes=np.full(300, 0.01))
    const = simulate_catalogue(objs, GroundRadar(clutter_rate=0.0), n_scans=60, seed=1)
    n_view = int(big.n_in_view.sum())
    assert n_view > 100
    assert len(big.scans) == n_view  # p_D = 1 - 1e-6^(1/(1+SNR)) with SNR > 1e6: every pass detected
    # 1 cm at UHF: sigma / sigma_ref = 1e-6 at best -> SNR <= 19 * 1e-6 * (3000/200)^4 = 0.96 -> p_D <= 1e-3
    assert len(tiny.scans) <= 0.01 * n_view
    # without sizes the sensor's p_D = 0.9 (the draws are the constant model's)
    assert 0.85 * n_view < len(const.scans) < 0.95 * n_view
    with pytest.raises(ValueError, match="sizes"):
        simulate_catalogue(objs, radar, n_scans=2, seed=1, sizes=np.ones(3))
    assert DEFAULT_RADAR.snr is None

"""SNR detection's tracker side against independent numbers: the field-of-view p_D as the r²-weighted average of
the size-marginal p_D (``scipy`` quadrature of the directly computed marginal), the tabulated p̄_D(range) against
that marginal at ranges between the grid nodes, at a GMST other than 0; the debris quantile nodes by hand; the
sizes of rocket bodies, payloads and debris; and the errors of bad input, each naming its parameter."""

import numpy as np
import pytest
from scipy.integrate import quad

from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, attributable_to_state
from hypotrack.scenarios.catalogue.snr import (
    UHF_SNR,
    SizeModel,
    SnrModel,
    SnrTrackerDetection,
    attach_snr_detection,
    check_sizes,
    rcs_sphere,
    swerling1_p_detect,
)

SIZES = SizeModel(debris_share=0.6)


def _marginal(r, n=64):
    d, w = SIZES.nodes(n)
    return float(UHF_SNR.p_detect(d, r) @ w)


def test_field_of_view_p_D_is_the_volume_weighted_marginal():
    fov = DEFAULT_RADAR.fov
    det = SnrTrackerDetection(RadarTrackerSensor(DEFAULT_RADAR), UHF_SNR, SIZES)
    num = quad(lambda r: _marginal(r) * r * r, fov.r_min_km, fov.r_max_km, limit=200)[0]
    den = (fov.r_max_km**3 - fov.r_min_km**3) / 3
    assert det.p_D == pytest.approx(num / den, abs=2e-6)
    assert 0.5 < det.p_D < 1.0


def test_tabulated_marginal_at_ranges_between_nodes_and_another_gmst():
    theta = 0.7
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(theta)
    det = attach_snr_detection(sensor, UHF_SNR, SIZES).detection
    assert sensor.detection is det and det.model is UHF_SNR and det.sizes is SIZES
    r = np.array([437.3, 1234.5, 2011.1, 2987.6])
    x = attributable_to_state(np.column_stack([r, np.full(4, DEFAULT_RADAR.fov.az_center), np.full(4, 0.6),
                                               np.zeros((4, 3))]), DEFAULT_RADAR.site, theta)
    np.testing.assert_allclose(det.p_D_of(x), [_marginal(v) for v in r], rtol=0, atol=2e-6)
    np.testing.assert_allclose(det.p_D_of(x[:, :3]), det.p_D_of(x), rtol=0, atol=0)  # positions alone
    none = det.p_D_of(np.zeros((0, 6)))
    assert none.shape == (0,)
    assert det.in_view(x[:, :3]).tolist() == RadarTrackerSensor(DEFAULT_RADAR).at(theta).detection.in_view(x).tolist()
    coarse = SnrTrackerDetection(RadarTrackerSensor(DEFAULT_RADAR).at(theta), UHF_SNR, SIZES, n_grid=20, n_nodes=8)
    assert len(coarse.ranges) == 20 and coarse.ranges[-1] == DEFAULT_RADAR.fov.r_max_km
    attached = attach_snr_detection(RadarTrackerSensor(DEFAULT_RADAR), UHF_SNR, SIZES, n_grid=20, n_nodes=8).detection
    np.testing.assert_array_equal(attached.table, coarse.table)  # the keywords reach the detection
    assert coarse.p_D_of(x)[1] == pytest.approx(np.interp(1234.5, coarse.ranges, coarse.table), abs=1e-15)


def test_default_table_is_the_marginal_over_the_size_models_nodes():
    """At the grid's ranges the default detection's p̄_D is the marginal over ``sizes.nodes()`` (class docstring)."""
    det = SnrTrackerDetection(RadarTrackerSensor(DEFAULT_RADAR), UHF_SNR, SIZES)
    k = np.array([0, 77, 300, len(det.ranges) - 1])
    x = attributable_to_state(np.column_stack([det.ranges[k], np.full(4, DEFAULT_RADAR.fov.az_center),
                                               np.full(4, 0.6), np.zeros((4, 3))]), DEFAULT_RADAR.site, 0.0)
    d, w = SIZES.nodes()
    want = [min(float(UHF_SNR.p_detect(d, r) @ w), 1 - 1e-9) for r in det.ranges[k]]
    np.testing.assert_allclose(det.p_D_of(x), want, rtol=1e-9)


def test_debris_quantile_nodes_by_hand():
    d, w = SizeModel(payload_diameter_m=1.5, debris_min_m=0.2, debris_exponent=2.0, debris_share=0.4).nodes(4)
    u = np.array([1, 3, 5, 7]) / 8
    np.testing.assert_allclose(d, np.r_[1.5, 0.2 / np.sqrt(u)], rtol=1e-14)
    np.testing.assert_allclose(w, [0.6, 0.1, 0.1, 0.1, 0.1], rtol=1e-14)
    d64, w64 = SizeModel().nodes()
    assert len(d64) == len(w64) and w64.sum() == pytest.approx(1.0)


def test_sizes_of_payloads_rocket_bodies_and_debris():
    cat = {"norad": [11, 22, 33, 44, 55], "group": ["active", "active", "iridium-33-debris", "cosmos-2251-debris", "x"],
           "name": ["SAT A", "SL-4 R/B", "IRIDIUM 33 DEB", "SL-8 R/B", "COSMOS DEB"]}
    sm = SizeModel(payload_diameter_m=2.5, rocket_body_diameter_m=4.0, debris_min_m=0.1)
    d = sm.sizes(cat, seed=5)
    assert d[[0, 1, 3]].tolist() == [2.5, 4.0, 4.0]
    assert np.all(d[[2, 4]] > 0.1) and d[2] != d[4]
    np.testing.assert_array_equal(sm.sizes(cat), sm.sizes(cat, seed=0))
    assert not np.array_equal(sm.sizes(cat, seed=0), d)
    empty = sm.sizes({"norad": [], "group": [], "name": []})
    assert empty.shape == (0,)


def test_bad_input_names_the_parameter():
    with pytest.raises(ValueError, match="^d_m must be finite and > 0"):
        rcs_sphere([0.1, np.nan], 0.69)
    with pytest.raises(ValueError, match="^wavelength_m must be"):
        rcs_sphere(0.1, 0.0)
    with pytest.raises(ValueError, match=r"^snr must be >= 0 \(linear"):
        swerling1_p_detect(-0.5, 1e-6)
    with pytest.raises(ValueError, match="^snr must be"):
        swerling1_p_detect(np.nan, 1e-6)
    with pytest.raises(ValueError, match=r"^p_fa must lie in \(0, 1\)"):
        swerling1_p_detect(1.0, 0.0)
    with pytest.raises(ValueError, match=r"^range_km must be > 0"):
        UHF_SNR.snr(0.1, 0.0)
    assert UHF_SNR.snr(0.1, 0.5) == pytest.approx(UHF_SNR.snr_ref * 6000.0**4, rel=1e-12)  # half a km is a range
    for kw, name in [({"wavelength_m": 0.0}, "wavelength_m"), ({"ref_range_km": -1.0}, "ref_range_km"),
                     ({"p_fa": 0.0}, "p_fa"), ({"p_fa": 1.0}, "p_fa"), ({"ref_p_D": 1.0}, "ref_p_D")]:
        with pytest.raises(ValueError, match=f"^{name} must"):
            SnrModel(**kw)
    with pytest.raises(ValueError, match=r"^ref_p_D must lie in \(0, 1\)"):
        SnrModel(ref_p_D=0.0)
    with pytest.raises(ValueError, match=r"^ref_p_D must lie in \(p_fa, 1\)"):
        SnrModel(ref_p_D=1e-6, p_fa=1e-6)
    for kw, name in [({"payload_diameter_m": 0.0}, "payload_diameter_m"), ({"debris_share": 1.5}, "debris_share")]:
        with pytest.raises(ValueError, match=f"^{name} must"):
            SizeModel(**kw)
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    with pytest.raises(TypeError, match="^model must be an SnrModel, got str"):
        SnrTrackerDetection(sensor, "uhf")
    with pytest.raises(TypeError, match="^sizes must be a SizeModel, got dict"):
        SnrTrackerDetection(sensor, UHF_SNR, {})
    np.testing.assert_array_equal(check_sizes([0.5, 2], 2), [0.5, 2.0])
    with pytest.raises(ValueError, match="^sizes must hold one size > 0"):
        check_sizes([1.0, 0.0], 2)
    with pytest.raises(ValueError, match="^sizes must hold one size > 0"):
        check_sizes([1.0, 2.0], 3)
    with pytest.raises(ValueError, match="^sizes must be a 1-D array"):
        check_sizes(np.ones((2, 1)), 2)

"""The admissible region's construction against independent checks, on a return made from a chosen attributable:
the rate box's edges are exactly the speed bound (|v − ω × r| = v_esc + |ω × r| there), each cell's verdict is
the plausibility of its centre and four corners tested one point at a time, each component maps back to the
return's noise ``R`` and its own rate covariance (through the attributable's Jacobian), the weights are the
blocks' shares of admissible cells, and bad parameters are refused by name."""

import json

import numpy as np
import pytest

from hypotrack.models.orbit import MU_EARTH
from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import (
    AdmissibleRegionBirth,
    StateMixture,
    attributable_jacobian,
    attributable_to_state,
)
from hypotrack.scenarios.catalogue.frames import EARTH_ROTATION
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor

SITE = DEFAULT_RADAR.site
THETA = 0.4
Z = np.array([1200.0, DEFAULT_RADAR.fov.az_center + 0.2, np.deg2rad(40.0), 1.5])


def _sensor():
    return RadarTrackerSensor(DEFAULT_RADAR).at(THETA)


def test_the_rate_box_edges_are_the_speed_bound():
    b = AdmissibleRegionBirth(_sensor())
    a_max, e_max = b.rate_box(Z, THETA)
    edges = np.array([[a_max, 0.0], [-a_max, 0.0], [0.0, e_max], [0.0, -e_max]])
    x = attributable_to_state(np.column_stack([np.broadcast_to(Z, (4, 4)), edges]), SITE, THETA)
    r, v = x[:, :3], x[:, 3:]
    w_x_r = EARTH_ROTATION * np.column_stack([-r[:, 1], r[:, 0], np.zeros(4)])
    bound = np.sqrt(2 * MU_EARTH / np.linalg.norm(r, axis=1)) + np.linalg.norm(w_x_r, axis=1)
    np.testing.assert_allclose(np.linalg.norm(v - w_x_r, axis=1), bound, rtol=1e-12)
    assert not plausible_orbits(x).any()  # at the speed bound's edge no orbit is bound
    # a range-rate 10 m/s short of the bound leaves a box of about 0.4 km/s across the line of sight
    z = np.r_[Z[:3], bound[0] - 0.01]
    a_max, e_max = b.rate_box(z, THETA)
    assert e_max * Z[0] == pytest.approx(np.sqrt(bound[0] ** 2 - z[3] ** 2), rel=1e-9)  # ρ ε̇ ≤ V
    assert a_max * Z[0] * np.cos(Z[2]) == pytest.approx(e_max * Z[0], rel=1e-12)  # ρ α̇ cos el ≤ V
    assert b.rate_box(np.r_[Z[:3], bound[0] + 0.5], THETA) == (0.0, 0.0)  # beyond it: an empty box


def test_each_cell_is_its_centre_and_four_corners_tested_one_by_one():
    b = AdmissibleRegionBirth(_sensor(), n_blocks=2, cells=8, min_perigee_km=150.0)
    ac, ec, ok = b.region(Z)  # the sensor's GMST
    a_max, e_max = b.rate_box(Z, THETA)
    assert len(ac) == len(ec) == 16 and ok.shape == (16, 16)
    da, de = 2 * a_max / 16, 2 * e_max / 16
    np.testing.assert_allclose(ac, -a_max + da * (np.arange(16) + 0.5), rtol=1e-12)
    np.testing.assert_allclose(ec, -e_max + de * (np.arange(16) + 0.5), rtol=1e-12)

    def plausible(a, e):
        return bool(plausible_orbits(attributable_to_state(np.r_[Z, a, e], SITE, THETA), min_perigee_km=150.0)[0])

    want = np.array([[all(plausible(a + sa * da / 2, e + se * de / 2) for sa, se in [(0, 0), (-1, -1), (1, -1), (-1, 1),
                                                                                      (1, 1)])
                      for e in ec] for a in ac])
    np.testing.assert_array_equal(ok, want)
    assert 0 < ok.sum() < 256  # a part of the box is admissible
    # a higher floor admits fewer cells
    assert AdmissibleRegionBirth(_sensor(), n_blocks=2, cells=8, min_perigee_km=600.0).region(Z)[2].sum() < ok.sum()


def test_components_map_back_to_the_returns_noise_and_their_rate_covariance():
    s = _sensor()
    b = AdmissibleRegionBirth(s, n_blocks=3, cells=6, spread=0.5)
    mix = b.mixture(Z)
    ac, ec, ok = b.region(Z, THETA)
    a_max, e_max = b.rate_box(Z, THETA)
    da, de = 2 * a_max / 18, 2 * e_max / 18
    assert len(mix) == len(mix.weights) == len(mix.means) >= 2
    assert mix.area == pytest.approx(ok.sum() * da * de, rel=1e-12)
    # blocks by brute force: weights are admissible-cell shares, means the centroids, covariances the scatter
    # plus a uniform cell's, times spread²
    A, E = np.meshgrid(ac, ec, indexing="ij")
    blocks = []
    for i in range(3):
        for j in range(3):
            sel = ok[6 * i:6 * i + 6, 6 * j:6 * j + 6]
            if sel.any():
                pts = np.column_stack([A[6 * i:6 * i + 6, 6 * j:6 * j + 6][sel], E[6 * i:6 * i + 6, 6 * j:6 * j + 6][sel]])
                blocks.append((len(pts), pts.mean(axis=0), np.cov(pts.T, bias=True) + np.diag([da**2, de**2]) / 12))
    n = np.array([c for c, _, _ in blocks], dtype=float)
    np.testing.assert_allclose(mix.weights, n / n.sum(), rtol=1e-14)
    np.testing.assert_allclose(mix.rate_means, [m for _, m, _ in blocks], rtol=1e-12)
    np.testing.assert_allclose(mix.rate_covs, [0.25 * c for _, _, c in blocks], rtol=1e-10, atol=1e-30)
    for k in range(len(mix)):
        y = np.r_[Z, mix.rate_means[k]]
        np.testing.assert_allclose(mix.means[k], attributable_to_state(y, SITE, THETA)[0], rtol=1e-14)
        H = s.jacobian(mix.means[k:k + 1])[0]
        np.testing.assert_allclose(H @ mix.covs[k] @ H.T, s.R, rtol=1e-5, atol=1e-14)
        J = attributable_jacobian(y, SITE, THETA)
        Cy = np.linalg.solve(J, np.linalg.solve(J, mix.covs[k]).T)
        np.testing.assert_allclose(Cy[4:, 4:], mix.rate_covs[k], rtol=1e-6, atol=1e-15)
        assert np.array_equal(mix.covs[k], mix.covs[k].T)
    w, m, c = b.components(Z)
    np.testing.assert_array_equal(w, mix.weights)
    np.testing.assert_array_equal(m, mix.means)
    np.testing.assert_array_equal(c, mix.covs)
    w0, m0, c0 = b.components(np.r_[Z[:3], 15.0])  # above the escape speed: no component
    assert w0.shape == (0,) and m0.shape == (0, 6) and c0.shape == (0, 6, 6)


def test_single_cell_blocks_and_a_gmst_other_than_the_sensors():
    theta2 = THETA + 0.3
    b = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(THETA), n_blocks=12, cells=1, spread=0.8)
    at2 = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(theta2), n_blocks=12, cells=1, spread=0.8)
    for u, v in zip(b.region(Z, theta2), at2.region(Z)):
        np.testing.assert_array_equal(u, v)
    # the cells do not depend on the GMST (another θ turns every state about the polar axis: same energy, perigee)
    np.testing.assert_array_equal(b.region(Z)[2], b.region(Z, theta2)[2])
    mix, mix2 = b.mixture(Z, theta2), at2.mixture(Z)
    assert not np.allclose(mix.means, b.mixture(Z).means)  # the states themselves turn with it
    np.testing.assert_array_equal(mix.means, mix2.means)
    np.testing.assert_array_equal(mix.covs, mix2.covs)
    # one cell per block: each admissible cell is a component, its rate covariance the uniform cell's × spread²
    a_max, e_max = b.rate_box(Z, theta2)
    ac, ec, ok = b.region(Z, theta2)
    assert len(mix) == ok.sum() >= 1
    np.testing.assert_allclose(mix.weights, 1.0 / ok.sum(), rtol=1e-14)
    cell = np.diag([(2 * a_max / 12) ** 2, (2 * e_max / 12) ** 2]) / 12 * 0.64
    np.testing.assert_allclose(mix.rate_covs, np.broadcast_to(cell, mix.rate_covs.shape), rtol=1e-12)
    ii, jj = np.nonzero(ok)
    np.testing.assert_allclose(mix.rate_means, np.column_stack([ac[ii], ec[jj]]), rtol=1e-12)


def test_parameters_are_stored_as_plain_numbers():
    b = AdmissibleRegionBirth(_sensor(), n_blocks=np.int64(2), cells=np.int32(3), spread=np.float32(0.5))
    assert json.loads(json.dumps([b.n_blocks, b.cells, b.spread])) == [2, 3, 0.5]


def test_mixture_draws():
    mix = AdmissibleRegionBirth(_sensor(), n_blocks=2, cells=8).mixture(Z, THETA)
    X = mix.sample(40000, np.random.default_rng(4))
    assert X.shape == (40000, 6)
    np.testing.assert_allclose(X.mean(axis=0), mix.weights @ mix.means, atol=0.05)
    one = StateMixture(np.array([1.0]), mix.means[:1], mix.covs[:1], mix.rate_means[:1], mix.rate_covs[:1], 1.0)
    Y = one.sample(40000, np.random.default_rng(5))
    white = np.linalg.solve(np.linalg.cholesky(mix.covs[0]), (Y - mix.means[0]).T)  # N(0, I) if drawn right
    np.testing.assert_allclose(np.cov(white), np.eye(6), atol=0.03)
    np.testing.assert_allclose(white.mean(axis=1), 0.0, atol=0.03)


def test_bad_parameters_are_refused_by_name():
    s = _sensor()
    with pytest.raises(TypeError, match="^sensor must be a RadarTrackerSensor, got GroundRadar"):
        AdmissibleRegionBirth(DEFAULT_RADAR)
    for kw, name in [({"n_blocks": 0}, "n_blocks"), ({"cells": 0}, "cells"), ({"spread": 0.0}, "spread")]:
        with pytest.raises(ValueError, match=f"^{name} must"):
            AdmissibleRegionBirth(s, **kw)
    b = AdmissibleRegionBirth(s, n_blocks=1, cells=2)
    assert b.n_blocks == 1 and b.cells == 2
    with pytest.raises(ValueError, match=r"^z must have shape \(4\)"):
        b.mixture(Z[:3])
    with pytest.raises(ValueError, match=r"^z must have shape \(4\)"):
        b.region(Z[:3])
    with pytest.raises(ValueError, match=r"no admissible angle rates for return z = \[1200\.0, .*>= 100\.0 km"):
        b.mixture(np.r_[Z[:3], 15.0])

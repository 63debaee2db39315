"""The admissible-region mixtures of all of a scan's returns built in one vectorised pass
(:meth:`AdmissibleRegionBirth.components_batch`) against the per-return construction (:meth:`~.mixture`): every
component's weight, mean and covariance, in the same order, on returns whose regions differ in shape (near and far,
rising and falling, a thin ring) and on returns with no admissible cell (none where ``mixture`` raises); the adaptive
birth's terms are the same whichever path builds them."""

import numpy as np
import pytest

from hypotrack.hypotheses.population_adaptive import AdaptiveBirth
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor

THETA = 0.4
C = DEFAULT_RADAR.fov.az_center
RETURNS = np.array([
    [1200.0, C + 0.2, np.deg2rad(40.0), 1.5],
    [15.0e3 / 10, C - 0.3, np.deg2rad(25.0), -4.0],
    [1200.0, C, np.deg2rad(60.0), 15.0],          # above escape speed: no admissible cell
    [300.0, C + 0.2, np.deg2rad(45.0), -3.0],     # 300 km away: the region is a thin ring
    [2500.0, C + 0.1, np.deg2rad(30.0), 0.2],
])


def _per_return(b, Z):
    out = []
    for z in Z:
        try:
            out.append(b.mixture(z, THETA))
        except ValueError:
            out.append(None)
    return out


def _compare(b, Z):
    w, means, covs, owner = b.components_batch(Z, THETA)
    ref = _per_return(b, Z)
    assert owner.tolist() == [i for i, r in enumerate(ref) if r is not None for _ in range(len(r))]
    for i, r in enumerate(ref):
        k = owner == i
        if r is None:
            assert not k.any()
            continue
        np.testing.assert_allclose(w[k], r.weights, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(means[k], r.means, rtol=1e-12, atol=1e-12 * np.abs(r.means).max())
        np.testing.assert_allclose(covs[k], r.covs, rtol=1e-12, atol=1e-12 * np.abs(r.covs).max())
        np.testing.assert_array_equal(covs[k], np.swapaxes(covs[k], 1, 2))
    return w, owner


@pytest.mark.parametrize("n_blocks, cells, sizes", [(3, 8, [4, 4, 0, 4, 5]), (8, 8, [13, 14, 0, 8, 17]),
                                                    (1, 24, [1, 1, 0, 1, 1]), (4, 1, [0, 0, 0, 0, 0])])
def test_the_batch_is_the_per_return_mixture_component_by_component(n_blocks, cells, sizes):
    """``sizes``: each return's number of components (blocks with an admissible cell), as the per-return
    construction gives them; (4, 1) is a grid so coarse that no cell has its centre and four corners bound."""
    b = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(THETA), n_blocks=n_blocks, cells=cells)
    w, owner = _compare(b, RETURNS)
    assert np.bincount(owner, minlength=5).tolist() == sizes
    has = np.array(sizes) > 0
    np.testing.assert_allclose(np.bincount(owner, weights=w, minlength=5), has.astype(float), rtol=1e-14)


def test_order_and_the_sensors_gmst():
    b = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(THETA), n_blocks=3)
    _compare(b, RETURNS[::-1])  # owner follows the order of the returns
    w, m, c, o = b.components_batch(RETURNS)  # default GMST: the sensor's (THETA)
    w2, m2, c2, o2 = b.components_batch(RETURNS, THETA)
    np.testing.assert_array_equal(m, m2)
    np.testing.assert_array_equal(o, o2)
    w3, m3, _, _ = b.components_batch(RETURNS, THETA + 0.1)  # another GMST moves the site: other means
    assert np.abs(m3[:, :3] - m[:, :3]).max() > 100.0


def test_no_returns_and_bad_input():
    b = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(THETA))
    w, m, c, o = b.components_batch(np.zeros((0, 4)))
    assert w.shape == (0,) and m.shape == (0, 6) and c.shape == (0, 6, 6) and o.shape == (0,)
    w, m, c, o = b.components_batch(RETURNS[2:3], THETA)  # one return, no region
    assert len(w) == 0 and m.shape == (0, 6)
    with pytest.raises(ValueError, match="Z must have shape"):
        b.components_batch(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="Z"):
        b.components_batch(np.array([[np.nan, 0.0, 0.5, 1.0]]))


def test_adaptive_birth_components_are_the_per_return_ones():
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(THETA)
    region = AdmissibleRegionBirth(sensor, n_blocks=3)
    meas = sensor.measurement
    x0, P0, w = AdaptiveBirth(r_birth=0.1, mixture=region).components(RETURNS, None, meas.R, meas)
    assert len(w) == 4 + 4 + 0 + 4 + 5  # the blocks with an admissible cell, return by return
    per_return = type("PerReturn", (), {"components": staticmethod(region.components)})()  # no components_batch
    x1, P1, w1 = AdaptiveBirth(r_birth=0.1, mixture=per_return).components(RETURNS, None, meas.R, meas)
    np.testing.assert_allclose(w, w1, rtol=1e-12)
    np.testing.assert_allclose(x0, x1, rtol=1e-12)
    parts = [region.components(z) for z in RETURNS]
    np.testing.assert_allclose(w, np.concatenate([p[0] for p in parts]), rtol=1e-12)
    np.testing.assert_allclose(x0, np.concatenate([p[1] for p in parts]), rtol=1e-12)
    np.testing.assert_allclose(P0, np.concatenate([p[2] for p in parts]), rtol=1e-12, atol=1e-9)

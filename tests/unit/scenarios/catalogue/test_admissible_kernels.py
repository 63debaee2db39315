"""The admissible-region mixtures of a scan's returns in one compiled pass
(:mod:`hypotrack.scenarios.catalogue.admissible_kernels`) against the array passes of
:meth:`~hypotrack.scenarios.catalogue.admissible.AdmissibleRegionBirth.components_batch` (``compiled=False``): the same
components, one for one and of the same returns, weights, means and covariances to 1e-12 of their scale, over returns
across the field of view (one above the escape speed: no component), grids of several shapes and two sidereal angles;
and the closed-form Jacobian of the kernel against the complex-step one of the array passes."""

import dataclasses

import numpy as np
import pytest

from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth
from hypotrack.scenarios.catalogue.admissible_kernels import _jacobian
from hypotrack.scenarios.catalogue.frames import EARTH_ROTATION
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor, _r3, attributable_jacobian


def _returns(m=30, seed=5):
    rng = np.random.default_rng(seed)
    f = DEFAULT_RADAR.fov
    Z = np.column_stack([rng.uniform(f.r_min_km, f.r_max_km, m), rng.uniform(f.az_center - 0.5, f.az_center + 0.5, m),
                         rng.uniform(np.deg2rad(max(f.el_min_deg, 1.0)), np.deg2rad(min(f.el_max_deg, 80.0)), m),
                         rng.uniform(-7.0, 7.0, m)])
    Z[3, 3] = 12.0  # above the escape speed: no admissible cell, no component
    return Z


@pytest.mark.parametrize("theta", [0.9, 4.1])
@pytest.mark.parametrize("grid", [dict(), dict(n_blocks=3, cells=8), dict(n_blocks=2, cells=5), dict(n_blocks=1, cells=13)])
def test_the_compiled_mixtures_are_the_array_passes(theta, grid):
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(theta)
    fast = AdmissibleRegionBirth(sensor, **grid)
    slow = dataclasses.replace(fast, compiled=False)
    Z = _returns()
    w, x, P, owner = fast.components_batch(Z)
    w0, x0, P0, owner0 = slow.components_batch(Z)
    assert len(w) == len(w0) > 0 and np.array_equal(owner, owner0) and 3 not in owner
    assert np.bincount(owner).max() == 1 if fast.n_blocks == 1 else np.bincount(owner).max() > 1  # one per block
    np.testing.assert_allclose(w, w0, rtol=1e-12, atol=0)
    for a, b in ((x, x0), (P, P0)):
        scale = np.abs(b).reshape(len(b), -1).max(axis=1).reshape((-1,) + (1,) * (b.ndim - 1))
        assert np.all(np.abs(a - b) <= 1e-12 * scale)
    np.testing.assert_allclose(np.bincount(owner, weights=w, minlength=len(Z)), np.where(np.isin(np.arange(len(Z)), owner), 1.0, 0.0),
                               rtol=1e-12)
    assert np.array_equal(P, np.swapaxes(P, 1, 2)) and np.all(np.linalg.eigvalsh(P) > 0)
    empty = fast.components_batch(np.zeros((0, 4)))
    assert [a.shape for a in empty] == [(0,), (0, 6), (0, 6, 6), (0,)]


def test_the_closed_form_jacobian_is_the_complex_step_one():
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(1.3)
    site = sensor.radar.site
    M = site.enu @ _r3(1.3)
    rng = np.random.default_rng(1)
    for _ in range(20):
        y = np.array([rng.uniform(300, 3000), rng.uniform(-3, 3), rng.uniform(0.1, 1.4), rng.uniform(-7, 7),
                      rng.normal(scale=1e-3), rng.normal(scale=1e-3)])
        J = np.empty((6, 6))
        _jacobian(*y, M, EARTH_ROTATION, J)
        want = attributable_jacobian(y, site, 1.3)
        assert np.all(np.abs(J - want) <= 1e-12 * np.abs(want).max(axis=1, keepdims=True))

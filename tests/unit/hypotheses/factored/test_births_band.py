"""The birth likelihoods' band test compiled (births_kernels) against the array passes (band_pairs_loop), bit for
bit: the same terms hit, the same returns in the same order, the same residuals (sign of zero included) — returns
across the azimuth's wrap (offsets of exactly ±π, ±3π, one ulp around ±π), on a bound exactly, NaN returns, terms
with empty bands and with zero widths — and a measurement model with its own residual taking the array passes."""

import numpy as np
import pytest

from hypotrack.hypotheses.factored.births import band_pairs, band_pairs_loop
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor


def _case(seed, m=400, B=60):
    rng = np.random.default_rng(seed)
    z_pred = np.column_stack([rng.uniform(500, 2500, B), rng.uniform(-np.pi, np.pi, B), rng.uniform(0, 1.4, B),
                              rng.uniform(-7, 7, B)])
    pick = rng.integers(0, B, m)
    off = rng.choice([0.0, np.pi, -np.pi, 3 * np.pi, -3 * np.pi, np.nextafter(np.pi, 4), np.nextafter(-np.pi, -4),
                      0.3, -0.3, 2 * np.pi], m)
    Z = z_pred[pick] + rng.normal(0, 1, (m, 4)) * np.array([200.0, 0.05, 0.05, 1.0])
    Z[:, 1] = z_pred[pick, 1] + off + rng.choice([0.0, 1e-3], m)
    half = np.abs(rng.normal(0, 1, (B, 4))) * np.array([300.0, 0.1, 0.1, 2.0])
    half[::9] = 0.0  # zero widths: only an exact return passes
    Z[5] = z_pred[0]  # exactly on a term: a zero residual passes a zero width
    Z[7] = np.nan
    Z[9, 1] = z_pred[pick[9], 1] + half[pick[9], 1]  # on the bound
    order = np.argsort(Z[:, 0], kind="stable")
    z0 = Z[order, 0]
    lo = np.searchsorted(z0, z_pred[:, 0] - half[:, 0], side="left")
    hi = np.searchsorted(z0, z_pred[:, 0] + half[:, 0], side="right")
    return Z, order, lo, hi, z_pred, half


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_compiled_band_equals_the_array_passes_bit_for_bit(seed):
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(0.7).measurement
    args = _case(seed)
    got, want = band_pairs(meas, *args), band_pairs_loop(meas, *args)
    assert got[0] == want[0] and len(want[0]) > 10
    for a, b in zip(got[1], want[1]):
        np.testing.assert_array_equal(a, b)
    for a, b in zip(got[2], want[2]):
        assert a.shape == b.shape and np.array_equal(a, b) and np.array_equal(np.signbit(a), np.signbit(b))
    # returns across the wrap are among those kept (the case tests what it is for)
    Z = args[0]
    kept = np.concatenate(want[1])
    assert np.any(np.abs(Z[kept, 1] - args[4][:, 1].mean()) > np.pi)


def test_no_returns_in_any_band_and_a_model_with_its_own_residual():
    meas = RadarTrackerSensor(DEFAULT_RADAR).at(0.7).measurement
    Z, order, lo, hi, z_pred, half = _case(4)
    assert band_pairs(meas, Z, order, lo, lo, z_pred, half) == ([], [], [])

    class Shifted(type(meas)):  # a residual of its own: the array passes call it
        def residual(self, Z, z_pred):
            return super().residual(Z, z_pred) + 0.0

    other = Shifted.__new__(Shifted)
    other.__dict__.update(meas.__dict__)
    got, want = band_pairs(other, Z, order, lo, hi, z_pred, half), band_pairs_loop(meas, Z, order, lo, hi, z_pred, half)
    assert got[0] == want[0]
    for a, b in zip(got[2], want[2]):
        np.testing.assert_array_equal(a, b)

"""The two-target OU scenario (document 003 Eqs. 5.1–5.4) and the swap-experiment scans."""

import numpy as np
import pytest

from hypotrack.models import OrnsteinUhlenbeck
from hypotrack.scenarios.closely_spaced import simulate_closely_spaced, static_pair_scans
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.experiments.closely_spaced.run import closely_spaced_realisation

MODEL = OrnsteinUhlenbeck(0.01, 0.005)


def test_truth_variance_follows_the_ou_moments():
    """Var x_k = A^{2k} v₀ + σ²/(2γ)(1 − A^{2k}), Cov(x_k, x_{k+1}) = A Var x_k, targets independent."""
    real = simulate_closely_spaced(MODEL, n_runs=20000, n_scans=60, n_sensors=2, R=1.0, initial_variance=0.01, rng=3)
    A = np.exp(-0.005)
    k = np.arange(60)
    want = A ** (2 * k) * 0.01 + 1.0 * (1 - A ** (2 * k))
    got = real.truth[:, :, 0].var(axis=0)
    # sample variance of 20000 Gaussians has relative standard error sqrt(2/20000) = 1 %
    np.testing.assert_allclose(got, want, rtol=0.05)
    lag = np.mean(real.truth[:, 30, 1] * real.truth[:, 31, 1])
    assert lag == pytest.approx(A * want[30], rel=0.05)
    assert abs(np.corrcoef(real.truth[:, -1, 0], real.truth[:, -1, 1])[0, 1]) < 0.03


def test_measurements_are_truth_plus_noise_of_variance_R():
    real = simulate_closely_spaced(MODEL, n_runs=500, n_scans=20, n_sensors=10, R=2.5, rng=4)
    noise = real.scans - real.truth[:, :, None, :]
    assert noise.var() == pytest.approx(2.5, rel=0.02)
    assert real.scans.shape == (500, 20, 10, 2) and real.times[-1] == 19.0
    assert np.all(np.diff(real.sorted_scans, axis=-1) >= 0)


def test_same_seed_same_data_and_zero_initial_spread():
    a = simulate_closely_spaced(MODEL, n_runs=3, n_scans=5, n_sensors=2, R=1.0, initial_variance=0.0, rng=9)
    b = simulate_closely_spaced(MODEL, n_runs=3, n_scans=5, n_sensors=2, R=1.0, initial_variance=0.0, rng=9)
    np.testing.assert_array_equal(a.scans, b.scans)
    assert np.all(a.truth[:, 0] == 0.0)


def test_static_pair_scans():
    truth, lo, hi = static_pair_scans(10.0, n_runs=4000, n_sensors=30, sigma=10.0, rng=0)
    assert truth.tolist() == [0.0, 10.0] and np.all(lo <= hi)
    # E[max] − E[min] of N(0,σ²) and N(d,σ²): the sorted pair spreads the returns beyond d
    assert (hi - lo).mean() > 10.0


def test_realisation_driver_returns_every_method_track():
    out = closely_spaced_realisation(sigma2=0.01, gamma=0.005, n_scans=30, n_sensors=10, R=1.0,
                                     seed=experiment_seeds(1, "cs", 1)[0])
    assert out["truth"].shape == (30, 2)
    for m in ("ideal", "PDAF", "MHT", "ECMHT"):
        assert out[m].shape == (30, 2) and np.all(np.isfinite(out[m]))


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(n_runs=0), "n_runs"),
        (dict(R=-1.0), "R"),
        (dict(initial_variance=-0.1), "initial_variance"),
        (dict(n_sensors=0), "n_sensors"),
    ],
)
def test_bad_inputs_are_rejected(kwargs, match):
    args = dict(n_runs=2, n_scans=3, n_sensors=2, R=1.0, rng=0) | kwargs
    with pytest.raises(ValueError, match=match):
        simulate_closely_spaced(MODEL, **args)


@pytest.mark.parametrize("factors,match", [([1.0], "differ from 1"), ([0.0], "noise_factors"), ([4.0, 4.0], "distinct")])
def test_misstated_noise_factors_are_checked(factors, match):
    from hypotrack.experiments.closely_spaced.run import closely_spaced_monte_carlo

    with pytest.raises(ValueError, match=match):
        closely_spaced_monte_carlo(sigma2=0.01, gamma=0.005, n_runs=2, n_scans=3, n_sensors=2, R=1.0, controls=True,
                                   noise_factors=factors, seed=0)


def test_controls_leave_the_methods_streams_unchanged():
    """Adding the broken MHTs draws their coins from a child stream: the four methods' numbers are unchanged."""
    from hypotrack.experiments.closely_spaced.run import closely_spaced_monte_carlo

    kw = dict(sigma2=0.01, gamma=0.005, n_runs=20, n_scans=6, n_sensors=3, R=1.0, seed=11)
    plain = closely_spaced_monte_carlo(**kw)
    full = closely_spaced_monte_carlo(**kw, controls=True, noise_factors=[4.0])
    for m in ("ideal", "PDAF", "MHT", "ECMHT"):
        np.testing.assert_array_equal(plain["per_run"][m], full["per_run"][m])
    np.testing.assert_array_equal(full["per_run"]["MHT[R × 4]"] == full["per_run"]["MHT"], False)

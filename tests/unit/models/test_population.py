"""Population models: document 000 Eq. 30, document 001 Eq. 32-33 and 59, document 003 Eq. 2.1-2.2."""

import math

import numpy as np
import pytest
from scipy import integrate, stats
from scipy.special import logsumexp

from hypotrack.models.population import (
    BinomialBirth,
    BinomialSurvival,
    SingleEventBirthDeath,
    UniformBirthDensity,
    continuous_birth_death,
)
from hypotrack.models.sensors import Box, FieldOfView

# --- document 000 single-event model ----------------------------------------------------------


def test_single_event_probabilities_eq30():
    m = SingleEventBirthDeath(alpha=1e-3, beta=1e-4, n_birth_regions=10)
    assert m.p_no_event(7) == pytest.approx(1 - 10e-3 - 7e-4, rel=1e-15)
    assert m.log_birth_prob == pytest.approx(math.log(1e-3)) and m.log_death_prob == pytest.approx(
        math.log(1e-4)
    )
    lp = m.event_log_probs(7)
    assert lp.shape == (1 + 10 + 7,)
    assert logsumexp(lp) == pytest.approx(0.0, abs=1e-14)
    assert m.p_no_event(0) == pytest.approx(0.99)


def test_single_event_zero_rates_degenerate_to_no_event():
    m = SingleEventBirthDeath(0.0, 0.0, 3)
    assert m.p_no_event(50) == 1.0 and m.log_birth_prob == -np.inf
    assert logsumexp(m.event_log_probs(50)) == 0.0


def test_single_event_no_event_probability_must_stay_positive():
    m = SingleEventBirthDeath(alpha=0.01, beta=0.05, n_birth_regions=10)
    assert m.p_no_event(17) == pytest.approx(0.05)
    with pytest.raises(ValueError, match="alpha.*beta.*n_birth_regions.*n_in_view"):
        m.p_no_event(18)
    with pytest.raises(ValueError, match="n_birth_regions \\* alpha must be < 1"):
        SingleEventBirthDeath(alpha=0.1, beta=0.0, n_birth_regions=10)


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        ({"alpha": -1e-3}, ValueError, "alpha must lie in"),
        ({"alpha": 1.5}, ValueError, "alpha must lie in"),
        ({"beta": np.nan}, ValueError, "beta must lie in"),
        ({"n_birth_regions": 0}, ValueError, "n_birth_regions"),
        ({"n_birth_regions": -3}, ValueError, "n_birth_regions"),
        ({"n_birth_regions": 2.5}, TypeError, "n_birth_regions"),
        ({"velocity_cov": -np.eye(2)}, ValueError, "velocity_cov"),
        ({"fov": Box([0, 0], [1, 1])}, TypeError, "fov"),
    ],
)
def test_single_event_bad_input(kwargs, exc, match):
    args = {"alpha": 1e-3, "beta": 1e-4, "n_birth_regions": 10} | kwargs
    with pytest.raises(exc, match=match):
        SingleEventBirthDeath(**args)


def test_single_event_bad_n_in_view():
    with pytest.raises(ValueError, match="n_in_view"):
        SingleEventBirthDeath(1e-3, 1e-4, 10).p_no_event(-1)


def test_birth_regions_split_the_fov_and_densities_normalise():
    fov = FieldOfView()
    m = SingleEventBirthDeath(1e-3, 1e-4, 10, fov=fov, velocity_cov=np.diag([0.25, 0.25]))
    regions = m.birth_regions
    assert len(regions) == 10 and math.isclose(sum(r.area for r in regions), fov.area)
    dens = m.birth_density(3)
    assert dens.region == regions[3]
    with pytest.raises(ValueError, match="region"):
        m.birth_density(10)
    with pytest.raises(ValueError, match="fov"):
        SingleEventBirthDeath(1e-3, 1e-4, 10).birth_regions


def test_uniform_birth_density_logpdf_and_samples():
    region = FieldOfView(15, 3, 6578, 30000)
    Sv = np.array([[0.3, 0.05], [0.05, 0.2]])

    def vbar(p):  # a position-dependent mean velocity
        return np.column_stack([-p[:, 1], p[:, 0]]) * 1e-4

    d = UniformBirthDensity(region, Sv, vbar)
    rng = np.random.default_rng(0)
    X = d.sample(50_000, rng)
    assert X.shape == (50_000, 4) and region.contains(X[:, :2]).all()
    resid = X[:, 2:] - vbar(X[:, :2])
    assert np.all(np.abs(np.cov(resid.T) - Sv) < 0.01)
    # Closed-form oracle: -log(area) - log(2 pi) - 0.5 log det Sv - 0.5 r' Sv^-1 r.
    r = resid[:5]
    want = -math.log(region.area) - math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(Sv))
    want = want - 0.5 * np.einsum("ni,ij,nj->n", r, np.linalg.inv(Sv), r)
    np.testing.assert_allclose(d.logpdf(X[:5]), want, rtol=1e-12)
    outside = X[:1].copy()
    outside[0, :2] = [-20000, 0]
    assert d.logpdf(outside)[0] == -np.inf


def test_uniform_birth_density_initial_state():
    d = UniformBirthDensity(Box([0, 0], [10, 10]), np.eye(2) * 4.0)
    mean, cov = d.initial_state([3.0, 4.0], np.eye(2) * 0.5)
    np.testing.assert_array_equal(mean, [3, 4, 0, 0])
    np.testing.assert_array_equal(cov, np.diag([0.5, 0.5, 4.0, 4.0]))
    with pytest.raises(ValueError, match="R must be positive definite"):
        d.initial_state([3.0, 4.0], -np.eye(2))


# --- document 001 binomial birth / survival -----------------------------------------------------


def test_binomial_birth_pmf_exact():
    b = BinomialBirth(12, 0.2)
    for k in range(13):
        assert b.pmf(k) == pytest.approx(math.comb(12, k) * 0.2**k * 0.8 ** (12 - k), rel=1e-12)
    # Sum over all specific birth hypotheses (C(M, p) of each size) is 1 (Eq. 32 left side).
    total = logsumexp([math.log(math.comb(12, p)) + b.log_specific_prob(p) for p in range(13)])
    assert total == pytest.approx(0.0, abs=1e-13)
    assert b.log_specific_prob(3) == pytest.approx(3 * math.log(0.2) + 9 * math.log(0.8))


def test_binomial_birth_poisson_limit_eq32_le_cam_bound():
    lam_V = 2.0
    k = np.arange(60)
    tvs = []
    for M in (10, 100, 1000, 10000):
        b = BinomialBirth(M, lam_V / M)
        lim = b.poisson_limit()
        assert lim.mean() == pytest.approx(lam_V)
        tv = 0.5 * np.sum(np.abs(b.pmf(k) - lim.pmf(k)))
        # Le Cam's inequality: d_TV(Bin(M, a), Poisson(M a)) <= M a^2.
        assert tv <= M * (lam_V / M) ** 2
        tvs.append(tv)
    assert all(a > b for a, b in zip(tvs, tvs[1:]))
    assert tvs[-1] < 1e-4


def test_binomial_birth_eq33_specific_hypothesis_limit():
    lam, V, p = 3e-4, 1e4, 2  # lambda_B V = 3
    errs = []
    for M in (100, 1000, 100000):
        Vbar = V / M
        b = BinomialBirth(M, lam * Vbar)
        rhs = -lam * V + p * math.log(lam) + p * math.log(Vbar)
        errs.append(abs(b.log_specific_prob(p) - rhs))
    assert errs[0] > errs[1] > errs[2] and errs[2] < 1e-4


def test_binomial_survival_eq59():
    s = BinomialSurvival(0.9)
    r = 6
    total = logsumexp([math.log(math.comb(r, p)) + s.log_specific_prob(p, r) for p in range(r + 1)])
    assert total == pytest.approx(0.0, abs=1e-13)
    assert s.pmf(4, r) == pytest.approx(15 * 0.9**4 * 0.1**2)
    assert s.log_specific_prob(0, 0) == 0.0
    assert BinomialSurvival(1.0).log_specific_prob(5, 6) == -np.inf


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: BinomialBirth(-1, 0.1), "n_potential"),
        (lambda: BinomialBirth(10, 1.1), "alpha"),
        (lambda: BinomialSurvival(-0.2), "p_survive"),
        (lambda: BinomialSurvival(0.5).log_specific_prob(4, 3), "p must be"),
        (lambda: BinomialBirth(5, 0.1).log_specific_prob(6), "p must be"),
    ],
)
def test_binomial_bad_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()


# --- document 003 continuous-time rates ----------------------------------------------------------


def test_continuous_birth_death_against_quadrature():
    lam, mu, dt = 1.0, 0.01, 3.0
    lambda_b, p_chi = continuous_birth_death(lam, mu, dt)
    survivors, _ = integrate.quad(lambda s: lam * math.exp(-mu * s), 0, dt, epsabs=0, epsrel=1e-12)
    assert lambda_b == pytest.approx(survivors, rel=1e-12)
    assert p_chi == pytest.approx(1 - math.exp(-mu * dt), rel=1e-14)
    assert lambda_b / p_chi == pytest.approx(lam / mu, rel=1e-12)


def test_continuous_birth_death_simulation_oracle():
    lam, mu, dt = 4.0, 0.5, 2.0
    lambda_b, _ = continuous_birth_death(lam, mu, dt)
    rng = np.random.default_rng(11)
    n = 20_000
    counts = rng.poisson(lam * dt, n)
    born = rng.uniform(0, dt, counts.sum())
    alive = born + rng.exponential(1 / mu, born.size) > dt
    survivors = np.bincount(np.repeat(np.arange(n), counts)[alive], minlength=n)
    # Thinned Poisson: mean and variance both lambda_b.
    assert abs(survivors.mean() - lambda_b) < 5 * math.sqrt(lambda_b / n)
    assert stats.poisson(lambda_b).pmf(0) == pytest.approx(np.mean(survivors == 0), abs=0.01)


def test_continuous_birth_death_zero_death_rate_limit():
    assert continuous_birth_death(2.0, 0.0, 5.0) == (10.0, 0.0)
    lb, _ = continuous_birth_death(2.0, 1e-12, 5.0)
    assert lb == pytest.approx(10.0, rel=1e-10)
    assert continuous_birth_death(2.0, 0.3, 0.0) == (0.0, 0.0)


@pytest.mark.parametrize(
    "args, match", [((-1, 0.1, 1), "birth_rate"), ((1, -0.1, 1), "death_rate"), ((1, 0.1, -1), "dt")]
)
def test_continuous_birth_death_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        continuous_birth_death(*args)


def test_uniform_birth_density_bad_input():
    with pytest.raises(ValueError, match="region must be a 2-D"):
        UniformBirthDensity(Box(0.0, 1.0), np.eye(2))
    with pytest.raises(ValueError, match="velocity_cov must be positive definite"):
        UniformBirthDensity(FieldOfView(), np.diag([1.0, -1.0]))

"""Admissible-region birth: a Gaussian mixture over the angle rates giving a bound orbit above 100 km.

Returns of real bundled objects propagated by SGP4 through the documented radar model; the mixture's
draws are checked with the one plausibility test, against the old zero-velocity birth as the control.
"""

import numpy as np
import pytest
from scipy.stats import chi2

from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth, attributable_to_state
from hypotrack.scenarios.catalogue.frames import EARTH_ROTATION, ef_to_rae, teme_to_ef, wrap_angle
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor
from scenes import sgp4_in_view

SITE = DEFAULT_RADAR.site


@pytest.fixture(scope="module")
def returns():
    """Noise-free returns of 8 (object, time) pairs of bundled active satellites in the default radar's view."""
    _, _, p, theta, vis = sgp4_in_view(400, 7200.0, 30.0)
    obj, k = np.nonzero(vis)
    pick = np.linspace(0, len(obj) - 1, 8).astype(int)
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    out = []
    for n in pick:
        x = np.r_[p.r[obj[n], k[n]], p.v[obj[n], k[n]]]
        out.append((x, float(theta[k[n]]), sensor.at(theta[k[n]]).h(x)[0]))
    return out


def test_attributable_to_state_inverts_h_and_carries_the_angle_rates():
    rng = np.random.default_rng(5)
    theta = 0.9
    sensor = RadarTrackerSensor(DEFAULT_RADAR).at(theta)
    y = np.column_stack([rng.uniform(300, 2500, 50), rng.uniform(0, 2 * np.pi, 50), np.deg2rad(rng.uniform(5, 85, 50)),
                         rng.uniform(-6, 6, 50), rng.uniform(-5e-3, 5e-3, 50), rng.uniform(-5e-3, 5e-3, 50)])
    x = attributable_to_state(y, SITE, theta)
    z = sensor.h(x)
    np.testing.assert_allclose(z[:, [0, 2, 3]], y[:, [0, 2, 3]], rtol=0, atol=1e-9)
    np.testing.assert_allclose(wrap_angle(z[:, 1] - y[:, 1]), 0.0, atol=1e-12)
    # angle rates: central difference of az, el along the straight TEME line r + t v, Earth rotating
    h = 1e-3
    rae = []
    for s in (-h, h):
        r_ef, _ = teme_to_ef((x[:, :3] + s * x[:, 3:])[None], x[:, 3:][None], np.array([theta + EARTH_ROTATION * s]))
        rae.append(ef_to_rae(r_ef[0], SITE.ef, SITE.enu))
    rates = np.column_stack([wrap_angle(rae[1][:, 1] - rae[0][:, 1]), rae[1][:, 2] - rae[0][:, 2]]) / (2 * h)
    np.testing.assert_allclose(rates, y[:, 4:], rtol=1e-6, atol=1e-10)


def test_the_mixture_is_bound_above_the_floor_and_the_zero_velocity_birth_is_not(returns):
    rng = np.random.default_rng(11)
    for x_true, theta, z in returns:
        mix = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR)).mixture(z, theta)
        X = mix.sample(20000, rng)
        assert plausible_orbits(X).mean() >= 0.99
        # the control: position at the return, velocity N(0, (8 km/s)^2 I) (the old one-point birth)
        X0 = np.column_stack([np.broadcast_to(x_true[:3], (20000, 3)), 8.0 * rng.standard_normal((20000, 3))])
        assert plausible_orbits(X0).mean() < 0.10
        # the true state lies inside the mixture: within the 99.9 % ellipsoid of some component
        d2 = [float((x_true - m) @ np.linalg.solve(C, x_true - m)) for m, C in zip(mix.means, mix.covs)]
        assert min(d2) < chi2.ppf(0.999, 6)


def test_the_mixture_reproduces_the_return(returns):
    rng = np.random.default_rng(2)
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    sigma = np.sqrt(np.diag(sensor.R))
    for _, theta, z in returns:
        sensor.at(theta)
        mix = AdmissibleRegionBirth(sensor).mixture(z)
        np.testing.assert_allclose(sensor.innovation(sensor.h(mix.means), z) / sigma, 0.0, atol=1e-6)
        assert mix.weights.sum() == pytest.approx(1.0) and len(mix) >= 2 and mix.area > 0
        # the draws scatter about the return with the return's own noise; the range's mean is biased
        # by the linearisation (the cross-beam spread lengthens |d| by ~σ_⊥²/ρ: a few metres, < 0.15 σ_ρ)
        nu = sensor.innovation(sensor.h(mix.sample(20000, rng)), z) / sigma
        assert np.all(np.abs(nu.mean(axis=0)) < [0.15, 0.05, 0.05, 0.05])
        np.testing.assert_allclose(nu.std(axis=0), 1.0, atol=0.1)


def test_weights_are_proportional_to_area_and_bad_returns_are_refused(returns):
    _, theta, z = returns[0]
    b = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR), n_blocks=1, cells=40)
    one = b.mixture(z, theta)
    assert len(one) == 1 and one.weights.tolist() == [1.0]
    split = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR), n_blocks=4, cells=10).mixture(z, theta)
    assert split.area == pytest.approx(one.area)  # the same 40 x 40 grid of cells
    # a component's weight is its share of the admissible area: the weighted rate mean is the region's centroid
    np.testing.assert_allclose(split.weights @ split.rate_means, one.rate_means[0], rtol=1e-9, atol=1e-12)
    ac, ec, ok = b.region(z, theta)
    assert ok.shape == (40, 40) and ok.sum() * (ac[1] - ac[0]) * (ec[1] - ec[0]) == pytest.approx(one.area)
    with pytest.raises(ValueError, match="no admissible angle rates"):
        b.mixture(np.r_[z[:3], 15.0], theta)  # range-rate above the escape speed
    with pytest.raises(TypeError, match="RadarTrackerSensor"):
        AdmissibleRegionBirth(DEFAULT_RADAR)


def test_admissible_births_survive_the_engine_validity_hook_and_zero_velocity_births_do_not(returns):
    """The pieces together: the mixture's components as the δ-GLMB's birth terms (TEME position returns of
    the ENU radar), the engine pruning implausible hypotheses. A return of a real object gives a newborn
    that passes the physics test; the zero-velocity birth term's newborn never does."""
    from hypotrack.hypotheses import (
        ExhaustiveGenerator,
        GaussianBirthTerm,
        GLMBWeights,
        HypothesisFilter,
        LabeledMultiBernoulliPopulation,
    )
    from hypotrack.models.orbit3d import TwoBodyOrbit3D
    from hypotrack.scenarios.catalogue import GroundRadar
    from hypotrack.scenarios.catalogue.tracking import TrackerSensor

    x_true, theta, z = returns[3]
    enu = TrackerSensor(GroundRadar(measurement="enu", sigma_enu_km=0.5)).at(theta)
    H, R = enu.measurement.H, enu.measurement.R
    mix = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR), n_blocks=2).mixture(z, theta)
    ar_terms = [GaussianBirthTerm(m, c, H, R) for m, c in zip(mix.means, mix.covs)]
    zero_v = GaussianBirthTerm(np.r_[x_true[:3], 0.0, 0.0, 0.0], np.diag([0.25] * 3 + [64.0] * 3), H, R)
    Z = x_true[:3][None] + np.array([[0.2, -0.3, 0.1]])  # the return, as a TEME position

    def newborn_existence(terms, r_birth):
        pop = LabeledMultiBernoulliPopulation(terms, r_birth=r_birth, p_survive=1.0)
        f = HypothesisFilter(TwoBodyOrbit3D(), enu, GLMBWeights(), ExhaustiveGenerator(), population=pop,
                             dt=10.0, max_hypotheses=1000, seed=0, validity=plausible_orbits)
        f.step(Z, dt=0.0)
        w = np.exp(f.log_weights)
        assert np.all(plausible_orbits(f.store.means))
        return sum(wi for wi, t in zip(w, f.track_lists) if len(t)), f.last_stats["n_invalid_pruned"]

    r_ar, _ = newborn_existence(ar_terms, 0.1 * mix.weights)
    r_zero, pruned = newborn_existence([zero_v], 0.1)
    assert r_ar > 0.5 and pruned >= 2  # detected newborn kept; the zero-velocity newborns (detected, unseen) pruned
    assert r_zero == 0.0

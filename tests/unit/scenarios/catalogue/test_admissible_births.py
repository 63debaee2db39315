"""The admissible region as the density of tracks started at one return: HOMHT's seeded births (one option per
component) and GNN/JPDA's M-of-N initiation (one tentative track per component), and the plausibility test with
both on.

Returns of real bundled objects propagated by SGP4 through the documented radar model, and of a *fall-in* object
(at rest in TEME: it falls straight down) beside them; every track is checked with the one plausibility test.
"""

import numpy as np
import pytest
from scipy.stats import chi2

from hypotrack.hypotheses import FactoredFilter, ReidWeights, homht_kbest
from hypotrack.models.orbit3d import TwoBodyOrbit3D
from hypotrack.models.plausibility import plausible_orbits
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth, SeededAdmissibleBirth
from hypotrack.scenarios.catalogue.radar_model import RadarOnePointBirth, RadarTrackerSensor
from hypotrack.trackers import MOfNInitiator, ScanModel
from scenes import sgp4_in_view

MOTION = TwoBodyOrbit3D(q=1e-9)
N_DRAWS = 20000


@pytest.fixture(scope="module")
def scene():
    """``(theta (3,), x_true (3, 6), x_fall (3, 6), returns)``: three scans 10 s apart of a bundled active satellite
    in the default radar's view and of a fall-in object at rest 10 s of arc away in the same view; ``returns``
    twelve noise-free returns of (object, time) pairs in view (the sampling check)."""
    cat, _, p, theta, vis = sgp4_in_view(100, 3600.0, 10.0)
    run = vis[:, :-2] & vis[:, 1:-1] & vis[:, 2:]
    i, k = np.argwhere(run)[0]
    x_true = np.concatenate([p.r[i, k:k + 3], p.v[i, k:k + 3]], axis=1)
    j, kf = np.argwhere(vis & (np.arange(len(cat)) != i)[:, None])[0]  # another object's place, at rest
    x0 = np.r_[p.r[j, kf], 0.0, 0.0, 0.0]
    x_fall = np.array([MOTION.propagate(x0[None], 10.0 * s)[0] for s in range(3)])
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    obj, kk = np.nonzero(vis)
    returns = []
    for n in np.linspace(0, len(obj) - 1, 12).astype(int):
        x = np.r_[p.r[obj[n], kk[n]], p.v[obj[n], kk[n]]]
        returns.append((float(theta[kk[n]]), sensor.at(theta[kk[n]]).h(x)[0]))
    return theta[k:k + 3], x_true, x_fall, returns


def _seeded(sensor):
    return SeededAdmissibleBirth(AdmissibleRegionBirth(sensor, n_blocks=3))  # the catalogue's admissible_blocks


def _draws(w, means, covs, rng):
    k = rng.choice(len(w), N_DRAWS, p=w / w.sum())
    return means[k] + np.einsum("nij,nj->ni", np.linalg.cholesky(covs)[k], rng.standard_normal((N_DRAWS, 6)))


def test_seeded_mixture_means_are_admissible_its_mass_bound_above_100_km_and_z_fits_every_component(scene):
    """Every component's mean is a bound orbit above 100 km (exactly); >= 99 % of the mixture's draws are (a
    Gaussian's tails leave the region: measured 99.6-99.9 %); and the return's predictive density is the same
    under every component, ``N(z; h(m_c), H_c P_c H_cᵀ + R) = N(0; 0, 2R)`` — why ``λ_B w_c`` is the weight
    (:mod:`hypotrack.hypotheses.seeded`)."""
    rng = np.random.default_rng(3)
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    seeded = _seeded(sensor)
    for theta, z in scene[3]:
        sensor.at(theta)
        w, means, covs = seeded.components(z)
        assert len(w) >= 2 and w.sum() == pytest.approx(1.0, abs=1e-12)
        assert plausible_orbits(means).all()
        assert plausible_orbits(_draws(w, means, covs, rng)).mean() >= 0.99
        Hc = sensor.jacobian(means)
        np.testing.assert_allclose(sensor.h(means) - z, 0.0, atol=1e-9)
        for c in range(len(w)):
            np.testing.assert_allclose(Hc[c] @ covs[c] @ Hc[c].T, sensor.R, rtol=1e-6, atol=1e-15)
        w2, means2, _ = seeded.components(z)  # the cache returns copies of the same mixture
        np.testing.assert_array_equal(means2, means)


def _initiator(sensor, mixture):
    model = ScanModel(None, sensor.R, 0.9, 0.999, 1e-3, 1e-4, measurement=sensor.measurement)
    return MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=8.0, mixture=mixture)


def test_mixture_initiation_confirms_the_true_object_once_and_never_the_fall_in(scene):
    theta, x_true, x_fall, _ = scene
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    rng = np.random.default_rng(8)
    out = {}
    for name, mixture in (("admissible", _seeded(sensor)), ("one_point", None)):
        init, confirmed = _initiator(sensor, mixture), []
        for k in range(3):
            sensor.at(theta[k])
            Z = sensor.h(np.stack([x_true[k], x_fall[k]]))
            x, P = init.step(10.0 * k, Z)
            confirmed += list(zip([k] * len(x), x, P))
            if mixture is not None:  # every tentative track a bound orbit above 100 km; their mixture too
                assert len(init) and plausible_orbits(init.x).all()
                w = np.exp(init.score - init.score.max())
                assert plausible_orbits(_draws(w, init.x, init.P, rng)).mean() >= 0.99
        out[name] = confirmed
    (k, x, P), = out["admissible"]  # one confirmed track: the true object, at its second scan
    assert k == 1 and plausible_orbits(x[None])[0]
    e = x - x_true[1]
    assert e @ np.linalg.solve(P, e) < chi2.ppf(0.999, 6) and np.linalg.norm(e[:3]) < 5.0
    # the control, one-point initiation, confirms the fall-in object: a track no real object can hold
    falls = [x for _, x, _ in out["one_point"] if np.linalg.norm(x[:3] - x_fall[1, :3]) < 5.0]
    assert falls and not plausible_orbits(np.array(falls)).any()


def test_plausibility_with_admissible_seeded_births_prunes_a_planted_unphysical_hypothesis(scene):
    """HOMHT on the factored engine: a posterior planted with one-point newborns (a fall-in orbit) at the fall-in
    object's return; one scan with the plausibility test and admissible-region seeded births leaves no track that
    fails it (the control without the test keeps some), and the known object with its return."""
    theta, x_true, x_fall, _ = scene
    sensor = RadarTrackerSensor(DEFAULT_RADAR)
    lam_b = 0.5 / sensor.clutter.region.area
    P0 = np.diag([0.5**2] * 3 + [5e-4**2] * 3)
    f0 = homht_kbest(MOTION, sensor, birth_intensity=lam_b, birth_density=RadarOnePointBirth(sensor.measurement),
                     max_hypotheses=20, gate_probability=0.999, means=x_true[:1], covs=P0[None], labels=[0], dt=10.0)
    sensor.at(theta[0])
    f0.step(sensor.h(np.stack([x_true[0], x_fall[0]])), dt=0.0)
    assert not plausible_orbits(f0.store.means).all()  # planted: a one-point newborn at the fall-in return
    weights = ReidWeights(birth_intensity=lam_b, birth_density=_seeded(sensor))
    held = {}
    for name, validity in (("on", plausible_orbits), ("off", None)):
        f1 = f0.with_options(validity=validity, weights=weights)
        f1.state = f0.state
        f = FactoredFilter.from_filter(f1, lazy=True, min_weight=1e-3)
        sensor.at(theta[1])
        f.step(sensor.h(np.stack([x_true[1], x_fall[1]])), 10.0)
        held[name] = np.concatenate([g.store.means[np.unique(np.concatenate(g.tracks)).astype(int)]
                                     if any(len(t) for t in g.tracks) else np.zeros((0, 6)) for g in f.groups])
        if name == "on":
            labels, means = f.map_means()
            assert 0 in labels and np.linalg.norm(means[list(labels).index(0), :3] - x_true[1, :3]) < 0.5
    assert len(held["on"]) and plausible_orbits(held["on"]).all()
    assert not plausible_orbits(held["off"]).all()

"""Weight models: document 000 Eq. 8 (and its Eq. 9 flaw), document 001 Eq. 6–7 and Reid, by hand."""

import math

import numpy as np
import pytest
from scipy import stats

from hypotrack.association import enumerate_associations
from hypotrack.hypotheses import FISSTPoissonWeights, HFISSTWeights, ReidWeights, ScanContext, make_weight_model


def context(loglik, p_detect, *, rate=2.0, volume=50.0, birth_loglik=None, p_birth=0.9):
    m = loglik.shape[0]
    return ScanContext(
        Z=np.zeros((m, 2)), loglik=loglik, allowed=np.ones(loglik.shape, bool), p_detect=np.asarray(p_detect, float),
        birth_loglik=np.zeros((m, 0)) if birth_loglik is None else birth_loglik, p_detect_birth=p_birth,
        clutter_rate=rate, clutter_volume=volume,
    )


@pytest.mark.parametrize("M", range(0, 7))
@pytest.mark.parametrize("m", range(0, 6))
def test_eq9_sums_to_binomial_cdf_not_one(M, m):
    """Σ_j p_ij over all A(M, m) associations = P[Bin(M, p_D) <= m] (= 1 only when M <= m)."""
    p_D = 0.7
    ctx = context(np.zeros((m, M)), np.full(M, p_D), volume=1.0)  # unit likelihoods and g = 1
    problem = HFISSTWeights().problem(ctx, np.arange(M))
    total = np.exp(problem.log_weights(enumerate_associations(M, m))).sum()
    assert total == pytest.approx(stats.binom.cdf(m, M, p_D), rel=1e-12)
    if M <= m:
        assert total == pytest.approx(1.0, rel=1e-12)
    else:
        assert total < 1.0 - 1e-6


def test_hfisst_weight_by_hand():
    """Eq. 8/17/18: p_D^k (1-p_D)^(M-k) / (C(m,k) k!) Π N(z) Π g(z), p_D = 0 out of view."""
    rng = np.random.default_rng(0)
    loglik = rng.normal(size=(3, 3))
    p = [0.9, 0.8, 0.0]
    V = 50.0
    problem = HFISSTWeights().problem(context(loglik, p, volume=V), np.arange(3), constant=-1.5)
    event = np.array([1, -1, 0])  # z0 -> object 1, z1 clutter, z2 -> object 0; object 2 out of view
    k, m = 2, 3
    expected = (-1.5 + math.log(0.9 * 0.8) + math.log(1.0)  # object 2 (p_D = 0) missed with prob. 1
                - math.log(math.comb(m, k) * math.factorial(k)) + loglik[0, 1] + loglik[2, 0] + math.log(1 / V))
    assert problem.log_weights(event[None])[0] == pytest.approx(expected, abs=1e-12)
    assert problem.log_weights(np.array([[2, -1, -1]]))[0] == -np.inf  # an object out of view is never detected


def test_fisst_poisson_literal_eq6_eq7_and_reid_by_hand():
    rng = np.random.default_rng(1)
    loglik = rng.normal(size=(4, 2))
    p = [0.85, 0.6]
    lam_v, V = 2.0, 50.0
    ctx = context(loglik, p, rate=lam_v, volume=V)
    event = np.array([-1, 0, -1, -1])  # k' = 3 clutter returns, one detection
    kc = 3
    eq6 = math.log(0.85 * (1 - 0.6)) - lam_v + kc * math.log(lam_v) - math.log(math.factorial(kc))
    eq7 = math.log(math.factorial(kc)) - kc * math.log(V) + loglik[1, 0]
    fp = FISSTPoissonWeights().problem(ctx, np.arange(2))
    assert fp.log_weights(event[None])[0] == pytest.approx(eq6 + eq7, abs=1e-12)
    reid = math.log(0.85 * (1 - 0.6)) + kc * math.log(lam_v / V) + loglik[1, 0]  # document 001 Eq. 30
    assert ReidWeights().problem(ctx, np.arange(2)).log_weights(event[None])[0] == pytest.approx(reid, abs=1e-12)


def test_reid_seeded_birth_factor():
    """Document 001 Eq. 35: each birth seeded at a return contributes λ_B (the 1/p_D and p_D cancel)."""

    class Density:
        def initial_state(self, z, R):
            return np.zeros(4), np.eye(4)

    ctx = context(np.zeros((2, 1)), [0.9])
    problem = ReidWeights(birth_intensity=0.3, birth_density=Density()).problem(ctx, np.arange(1))
    w = problem.log_weights(np.array([[-2, -1], [-1, -1]]))
    assert w[0] - w[1] == pytest.approx(math.log(0.3) - math.log(2.0 / 50.0), abs=1e-12)


def test_birth_column_holds_birth_likelihood_and_detection():
    birth = np.array([[np.log(1 / 10.0)], [-np.inf]])
    ctx = context(np.zeros((2, 1)), [0.9], birth_loglik=birth, p_birth=0.9)
    problem = HFISSTWeights().problem(ctx, np.arange(1), population_log_prob=np.array([-0.01, np.log(1e-3)]))
    assert problem.target_scores[0, 1] == pytest.approx(np.log(0.1) + np.log(0.9))
    assert problem.target_scores[1, 1] == -np.inf
    # one birth (b = 1) and the detected object: k = 2 detections among N = 2 objects
    w = problem.log_weights(np.array([[1, 0]]))[0]
    expected = np.log(1e-3) + np.log(0.9) + np.log(0.1) + np.log(0.9) + 0.0 - math.log(2)
    assert w == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("model", ["hfisst", "fisst_poisson"])
def test_births_count_among_detections_m4(model):
    """m = 4 returns, 2 objects, 1 birth region; event: z0 -> object 0, z1 -> birth, z2 clutter,
    z3 -> object 1. The birth's return is a detection: k + b = 3 detections, so H-FISST divides
    by C(4, 3) 3! = 24 (not C(4, 2) 2! = 12) and FISST-Poisson sees k' = 1 clutter return (not 2)."""
    rng = np.random.default_rng(7)
    loglik = rng.normal(size=(4, 2))
    birth = np.log(np.full((4, 1), 1 / 20.0))
    lam_v, V, p_b = 2.0, 50.0, 0.7
    ctx = context(loglik, [0.9, 0.6], rate=lam_v, volume=V, birth_loglik=birth, p_birth=p_b)
    pop = np.array([np.log(0.95), np.log(0.02)])
    problem = make_weight_model(model).problem(ctx, np.arange(2), constant=0.25, population_log_prob=pop)
    event = np.array([[0, 2, -1, 1]])  # column 2 is the birth region
    common = (0.25 + math.log(0.02) + math.log(0.9 * 0.6) + loglik[0, 0] + loglik[3, 1]
              + math.log(1 / 20.0) + math.log(p_b))
    if model == "hfisst":
        expected = common - math.log(math.comb(4, 3) * math.factorial(3)) + math.log(1 / V)
    else:  # Eq. 6-7 with k' = 1: e^{-λV} (λV)^1 / 1! × 1! / V
        expected = common - lam_v + math.log(lam_v) - math.log(V)
    assert problem.log_weights(event)[0] == pytest.approx(expected, abs=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="birth_intensity"):
        ReidWeights(birth_intensity=-1.0)
    with pytest.raises(ValueError, match="birth_density"):
        ReidWeights(birth_intensity=1.0)
    with pytest.raises(ValueError, match="weight model"):
        make_weight_model("jpda")
    with pytest.raises(ValueError, match="clutter_rate"):
        FISSTPoissonWeights().problem(context(np.zeros((1, 1)), [0.9], rate=0.0), np.arange(1))
    with pytest.raises(ValueError, match="population_log_prob"):
        HFISSTWeights().problem(context(np.zeros((1, 1)), [0.9]), np.arange(1), population_log_prob=np.zeros(3))


def test_fisst_poisson_no_clutter_and_overridden_rate():
    """Every return detected (k' = 0): the count term is −λV alone; an explicit clutter_rate
    replaces the scan's λV; more detections than returns are impossible (−inf)."""
    ctx = context(np.zeros((2, 2)), [0.9, 0.9], rate=2.0, volume=50.0)
    phi = FISSTPoissonWeights().count_term(ctx, 2, 0)
    assert phi[2, 0] == pytest.approx(-2.0, abs=1e-14)  # k = m = 2, k' = 0
    assert phi[1, 0] == pytest.approx(-2.0 + math.log(2.0) - math.log(50.0), abs=1e-14)  # k' = 1
    phi3 = FISSTPoissonWeights(clutter_rate=3.0).count_term(ctx, 2, 0)
    assert phi3[1, 0] == pytest.approx(-3.0 + math.log(3.0) - math.log(50.0), abs=1e-14)
    ctx1 = context(np.zeros((1, 2)), [0.9, 0.9])
    np.testing.assert_array_equal(FISSTPoissonWeights().count_term(ctx1, 2, 0)[2], [-np.inf])
    np.testing.assert_array_equal(HFISSTWeights().count_term(ctx1, 2, 0)[2], [-np.inf])


def test_reid_options_births_and_intensity():
    """Reid: the clutter option is log λ_C (scan's λV/V, or the override); a population's birth region
    is a birth column ``log(1/V̄) + log p_D`` with the event probability in the count term (Reid's own
    count term is 0); λ_B is kept as a float."""
    birth = np.log(np.full((2, 1), 1 / 20.0))
    ctx = context(np.zeros((2, 1)), [0.9], rate=2.0, volume=50.0, birth_loglik=birth)
    problem = ReidWeights().problem(ctx, np.arange(1), population_log_prob=np.log([0.9, 0.05]))
    assert problem.target_scores.shape == (2, 2)
    np.testing.assert_allclose(problem.target_scores[:, 1], math.log(0.9 / 20.0))
    np.testing.assert_allclose(problem.count_term, np.log([[0.9, 0.05], [0.9, 0.05]]))
    assert ReidWeights().problem(context(np.zeros((2, 1)), [0.9], rate=2.0, volume=50.0),
                                 np.arange(1)).target_scores.shape == (2, 1)
    np.testing.assert_allclose(problem.option_scores, np.full((2, 1), math.log(2.0 / 50.0)))
    np.testing.assert_allclose(ReidWeights(clutter_intensity=0.5).option_scores(ctx), np.full((2, 1), math.log(0.5)))

    class Density:
        def initial_state(self, z, R):
            return np.zeros(4), np.eye(4)

    w = ReidWeights(birth_intensity=2, birth_density=Density())
    assert isinstance(w.birth_intensity, float) and w.birth_intensity == 2.0


@pytest.mark.parametrize("call, message", [
    (lambda: ReidWeights(birth_intensity=-1.0), "birth_intensity must be a finite number >= 0, got -1.0"),
    (lambda: ReidWeights(birth_intensity=1.0),
     "birth_density with initial_state(z, R) (or a mixture's components(z)) is required when birth_intensity > 0"),
    (lambda: ReidWeights(clutter_intensity=0.0), "clutter_intensity must be a finite number > 0, got 0.0"),
    (lambda: ReidWeights().problem(context(np.zeros((1, 1)), [0.9], rate=0.0), np.arange(1)),
     "clutter intensity must be a finite number > 0, got 0.0"),
    (lambda: FISSTPoissonWeights().problem(context(np.zeros((1, 1)), [0.9], rate=0.0), np.arange(1)),
     "clutter_rate must be a finite number > 0, got 0.0"),
])
def test_weight_model_messages(call, message):
    with pytest.raises(ValueError) as info:
        call()
    assert str(info.value) == message


def test_count_terms_with_a_birth_column_by_hand():
    """m = 2 returns, 2 objects, 1 birth region: φ[k, b] over k detected objects and b detected
    births. Births are detections too, so k + b = 3 > m is impossible (−inf) while k − b is not
    the test (k = 2, b = 1). H-FISST: −log(m! / (m − n)!) with n = k + b; FISST-Poisson (λV = 2,
    V = 50): −λV + k' log(λV) − k' log V with k' = m − k − b clutter returns (the k'! cancel)."""
    ctx = context(np.zeros((2, 2)), [0.9, 0.9], rate=2.0, volume=50.0, birth_loglik=np.zeros((2, 1)))
    l2 = math.log(2.0)
    np.testing.assert_allclose(HFISSTWeights().count_term(ctx, 2, 1),
                               [[0.0, -l2], [-l2, -l2], [-l2, -np.inf]], rtol=0, atol=1e-14)
    c = math.log(2.0 / 50.0)
    np.testing.assert_allclose(FISSTPoissonWeights().count_term(ctx, 2, 1),
                               [[-2 + 2 * c, -2 + c], [-2 + c, -2.0], [-2.0, -np.inf]], rtol=0, atol=1e-14)


@pytest.mark.parametrize("model, phi", [("hfisst", 0.0), ("fisst_poisson", -2.0 + 2 * math.log(2.0 / 50.0))])
def test_a_parent_without_objects_gives_a_clutter_only_problem(model, phi):
    """Zero objects is a normal case: tracks given as an empty list, the only child of a scan
    with two returns (and no birth region) is "both clutter", weighed constant + φ[0, 0] + 2 log g
    with g = 1/V for H-FISST, and the FISST-Poisson clutter factor carried by φ alone."""
    ctx = context(np.zeros((2, 0)), [], rate=2.0, volume=50.0)
    problem = make_weight_model(model).problem(ctx, [], constant=-0.5)
    assert problem.n_objects == 0 and problem.target_scores.shape == (2, 0)
    np.testing.assert_allclose(problem.count_term, [[phi]], rtol=0, atol=1e-14)
    clutter = 2 * math.log(1 / 50.0) if model == "hfisst" else 0.0
    assert problem.log_weights(np.array([[-1, -1]]))[0] == pytest.approx(-0.5 + phi + clutter, abs=1e-12)


def test_population_probability_shape_message_counts_the_birth_columns():
    ctx = context(np.zeros((1, 1)), [0.9], birth_loglik=np.zeros((1, 1)))  # one birth region: b = 0 or 1
    with pytest.raises(ValueError) as info:
        HFISSTWeights().problem(ctx, np.arange(1), population_log_prob=np.zeros(3))
    assert str(info.value) == "population_log_prob must have shape (2,), got (3,)"


def test_the_weight_models_say_which_sensor_parameters_they_use():
    """H-FISST/R-FISST use the clutter density 1/V, not the rate; FISST-Poisson, Reid and GLMB use both."""
    from hypotrack.hypotheses import GLMBWeights

    base = ("measurement.H", "measurement.R", "detection.p_D")
    assert HFISSTWeights().sensor_parameters == (*base, "clutter.region")
    assert "clutter.rate" in FISSTPoissonWeights().sensor_parameters
    assert "clutter.rate" not in FISSTPoissonWeights(clutter_rate=3.0).sensor_parameters  # overridden
    assert {"clutter.rate", "clutter.region"} <= set(ReidWeights().sensor_parameters)
    assert ReidWeights(clutter_intensity=0.1).sensor_parameters == base
    assert {"clutter.rate", "clutter.region"} <= set(GLMBWeights().sensor_parameters)


def test_rfisst_and_hfisst_posteriors_do_not_depend_on_the_clutter_rate():
    """What sensor_parameters says: rates 0, 2 and 50 give bit-identical posteriors (only 1/V counts)."""
    from hypotrack.hypotheses import hfisst, rfisst
    from hypotrack.models import ConstantVelocity
    from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

    region = Box([-100.0, -100.0], [100.0, 100.0])
    scans = [np.array([[-19.0, 0.3], [19.2, -0.1], [50.0, 60.0]]), np.array([[-18.1, 0.2], [-70.0, 5.0]])]
    for preset, opts in ((hfisst, {}), (rfisst, {"n_steps": 200, "seed": 1})):
        out = []
        for rate in (0.0, 2.0, 50.0):
            sensor = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4), DetectionModel(p_D=0.9, fov=region),
                            PoissonClutter(rate=rate, region=region))
            t = preset(ConstantVelocity(q=0.1), sensor, max_hypotheses=20, **opts)
            assert "clutter.rate" not in t.sensor_parameters
            t.initialise(means=[[-20.0, 0.0, 1.0, 0.0], [20.0, 0.0, -1.0, 0.0]], covs=np.tile(np.eye(4), (2, 1, 1)))
            for Z in scans:
                t.step(Z)
            out.append((t.log_weights.tobytes(), t.store.means.tobytes()))
        assert out[0] == out[1] == out[2]

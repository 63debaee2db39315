"""The PMBM and PMB filters: a hand-computed scan, the PMB collapse against the PMBM's marginals and LBP against
exact marginals, bad input, empty scans, the registry kinds."""

import numpy as np
import pytest

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    GaussianBirthTerm,
    GibbsGenerator,
    LabeledMultiBernoulliPopulation,
    MurtyGenerator,
    PoissonIntensity,
)
from hypotrack.hypotheses.pmbm import PMBMFilter, poisson_binomial
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.protocol import HypothesisTracker
from hypotrack.registry import MeasurementBirths, SpecError, TrackerSpec, TrackingProblem, build, kinds
from hypotrack.registry.spec import FAMILIES

VIEW = Box([-50.0, -50.0], [50.0, 50.0])


def sensor(p_D=0.8, rate=1.0, R=1.0):
    return Sensor(LinearPositionSensor(R * np.eye(2), 4), DetectionModel(p_D, VIEW), PoissonClutter(rate, VIEW))


def pmbm(collapse=None, p_D=0.8, generator=None, **kw):
    opts = dict(max_hypotheses=1000, hypothesis_threshold=0.0, existence_threshold=0.0, poisson_threshold=0.0,
                allocation="exact")
    opts.update(kw)
    return PMBMFilter(ConstantVelocity(0.1), sensor(p_D), generator or ExhaustiveGenerator(), collapse=collapse,
                      **opts)


# ------------------------------------------------------------------------------------ hand-computed
def test_one_bernoulli_one_return_by_hand():
    """A known object (r = 1, N(0, diag(2, 2, 1, 1))), a Poisson birth 0.2 N((3, 0, 0, 0), diag(4, 4, 1, 1)),
    p_S = 0.9, p_D = 0.8, κ = 1/10⁴, R = I, one return z = (1, 0) at the priors' epoch (no motion)."""
    f = pmbm(p_survive=0.9, birth_means=[[3.0, 0, 0, 0]], birth_covs=[np.diag([4.0, 4, 1, 1])], birth_weights=[0.2])
    f.initialise([[0.0, 0, 0, 0]], [np.diag([2.0, 2, 1, 1])], labels=[5])
    f.step(np.array([[1.0, 0.0]]), 0.0)
    r, pd, kappa = 0.9, 0.8, 1e-4
    n_track = np.exp(-0.5 * 1.0 / 3.0) / (2 * np.pi * 3.0)  # N(z; (0, 0), 3 I)
    n_birth = np.exp(-0.5 * 4.0 / 5.0) / (2 * np.pi * 5.0)  # N(z; (3, 0), 5 I)
    detected = r * pd * n_track  # the track takes z; the new track does not exist
    e = 0.2 * pd * n_birth
    missed = (1 - r * pd) * (kappa + e)  # the track missed; z starts the new track
    w_det = detected / (detected + missed)
    hyps = f.global_hypotheses()
    assert len(hyps) == 2
    a, b = sorted(hyps, key=lambda h: len(h.existence))
    assert abs(a.weight - w_det) < 1e-12 and abs(b.weight - (1 - w_det)) < 1e-12
    # detected: r = 1, mean 0 + 2/3 (1 - 0), covariance 2 − 4/3
    assert a.labels.tolist() == [5] and a.existence.tolist() == [1.0]
    np.testing.assert_allclose(a.means[0], [2 / 3, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(np.diag(a.covs[0]), [2 / 3, 2 / 3, 1, 1], atol=1e-12)
    # missed: r = 0.9 · 0.2 / 0.28, the prior moments; the new track r = e / (κ + e), mean 3 + 4/5 (1 − 3)
    np.testing.assert_allclose(b.existence, [0.9 * 0.2 / 0.28, e / (kappa + e)], atol=1e-12)
    np.testing.assert_allclose(b.means[1], [3 - 1.6, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(np.diag(b.covs[1]), [0.8, 0.8, 1, 1], atol=1e-12)
    assert b.labels.tolist() == [5, 6]
    # undetected: the birth thinned by 1 − p_D
    np.testing.assert_allclose(np.exp(f.undetected.log_w), [0.2 * 0.2], atol=1e-15)
    post = f.posterior()
    card = w_det * np.array([0, 1, 0]) + (1 - w_det) * poisson_binomial(b.existence)
    np.testing.assert_allclose(post.cardinality, card, atol=1e-12)
    # estimator 1: the detected hypothesis is the heavier here, its one Bernoulli reported
    assert w_det > 0.5 and f.estimates().labels.tolist() == [5] and post.map_estimate.labels.tolist() == [5]
    assert post.map_estimate.weight == a.weight


@pytest.mark.parametrize("threshold, reported", [(0.5, [5]), (0.7, [])])
def test_posterior_map_estimate_uses_the_filters_existence_threshold(threshold, reported):
    """A known object missed (no return): r = 0.9 (1 − 0.8) / (1 − 0.9 · 0.8) = 0.643, between the two
    thresholds; the posterior's MAP estimate and ``estimates()`` report it exactly when r exceeds the option."""
    f = pmbm(p_survive=0.9, existence_estimate=threshold, birth_means=[[3.0, 0, 0, 0]],
             birth_covs=[np.diag([4.0, 4, 1, 1])], birth_weights=[0.2])
    f.initialise([[0.0, 0, 0, 0]], [np.diag([2.0, 2, 1, 1])], labels=[5])
    f.step(np.zeros((0, 2)), 0.0)
    post = f.posterior()
    np.testing.assert_allclose(post.top[0].existence, [0.18 / 0.28], atol=1e-12)
    assert post.map_estimate.labels.tolist() == reported == f.estimates().labels.tolist()


# ------------------------------------------------------------------------------------ PMB
Z3 = np.array([[-1.0, 0.3], [2.0, -0.2], [5.0, 0.4]])


def two_tracks_three_returns(collapse, gate=None, step=True, **kw):
    f = pmbm(collapse, gate_probability=gate, birth_means=[[0.0, 5, 0, 0]], birth_covs=[np.diag([30.0, 30, 1, 1])],
             birth_weights=[0.5], **kw)
    f.initialise([[0.0, 0, 0, 0], [4.0, 0, 0, 0]], [np.eye(4), np.eye(4)])
    if step:
        f.step(Z3, 0.0)  # the priors' epoch: no motion, p_S = 1
    return f


def marginals(f):
    """Per label: (Σ_a W_a r(a), mean, covariance of the existence-weighted mixture)."""
    acc = {}
    for h in f.global_hypotheses():
        for lab, r, m, P in zip(h.labels, h.existence, h.means, h.covs):
            acc.setdefault(int(lab), []).append((h.weight * r, m, P))
    out = {}
    for lab, items in acc.items():
        w = sum(x[0] for x in items)
        mean = sum(x[0] * x[1] for x in items) / w
        cov = sum(x[0] * (x[2] + np.outer(x[1] - mean, x[1] - mean)) for x in items) / w
        out[lab] = (w, mean, cov)
    return out


def test_pmb_with_exact_marginals_is_the_pmbm_marginalised():
    """Williams 2015: each Bernoulli of the PMB is its track's existence-weighted mixture over the PMBM's global
    hypotheses, and every return's new track has r = P(unassigned) e / (κ + e)."""
    full, pmb = marginals(two_tracks_three_returns(None)), two_tracks_three_returns("exact")
    (h,) = pmb.global_hypotheses()
    assert sorted(full) == sorted(h.labels.tolist()) == [0, 1, 2, 3, 4]
    for lab, r, m, P in zip(h.labels, h.existence, h.means, h.covs):
        np.testing.assert_allclose([r], [full[int(lab)][0]], atol=1e-12, rtol=0)
        np.testing.assert_allclose(m, full[int(lab)][1], atol=1e-10, rtol=0)
        np.testing.assert_allclose(P, full[int(lab)][2], atol=1e-10, rtol=0)


def test_lbp_is_exact_on_a_tree_and_close_on_a_loopy_graph():
    """Gated (P_G = 0.9), the tracks and returns form a chain (track 0 – return 0, 1; track 1 – return 1, 2): belief
    propagation is exact on it. Ungated every track sees every return: cycles, and LBP is an approximation."""
    for gate, exact in ((0.9, True), (None, False)):
        a, b = two_tracks_three_returns("lbp", gate), two_tracks_three_returns("exact", gate)
        (ha,), (hb,) = a.global_hypotheses(), b.global_hypotheses()
        assert ha.labels.tolist() == hb.labels.tolist()
        diff = np.max(np.abs(ha.existence - hb.existence))
        if exact:
            assert diff < 1e-9
            np.testing.assert_allclose(ha.means, hb.means, atol=1e-8, rtol=0)
        else:
            assert 1e-6 < diff < 0.02  # measured: 2.8e-4


def test_the_gated_problem_is_a_chain_and_the_ungated_one_has_cycles():
    for gate, pattern in ((0.9, [[True, True, False], [False, True, True]]), (None, [[True] * 3] * 2)):
        f = two_tracks_three_returns(None, gate, step=False)
        _, _, log_det, _ = f.single_target_hypotheses(Z3)
        assert np.isfinite(log_det).tolist() == pattern


def test_the_trimmed_problem_gives_every_child_of_the_full_one():
    """Gated rows (always missed) and returns only their new track can take are left out of the generator's
    problem and put back: the children and their weights are those of the full problem."""
    f = two_tracks_three_returns(None, gate=0.9, step=False)
    f.initialise([[0.0, 0, 0, 0], [4.0, 0, 0, 0], [40.0, 40, 0, 0]], [np.eye(4)] * 3)  # the third sees nothing
    log_miss, _, log_det, (_, _, log_rho, _, _) = f.single_target_hypotheses(np.vstack([Z3, [[-40.0, -40]]]))
    _, problem = f.association_problem(0, log_miss, log_det, log_rho)
    ev_full, lw_full = ExhaustiveGenerator().generate(problem)
    ev, lw = f._generate(problem)
    key = lambda e, w: sorted(zip(map(tuple, np.asarray(e).tolist()), np.round(w, 12)))
    # track 0: miss, z0 or z1; track 1: miss, z1 or z2; not both on z1: 3 × 3 − 1
    assert key(ev, lw) == key(ev_full, lw_full) and len(lw) == 8


def test_proportional_allocation_asks_each_hypothesis_for_its_share():
    """``ceil(H W_a)`` children of global hypothesis ``a`` (the 2018 paper's implementation) instead of ``H``."""
    runs = {}
    for allocation in ("exact", "proportional"):
        f = two_tracks_three_returns(None, max_hypotheses=10, allocation=allocation, generator=MurtyGenerator(k=10))
        weights = np.exp(f.log_w)
        f.step(Z3 + 0.5, 1.0)
        runs[allocation] = (f.last_stats["n_children"], int(np.sum(np.ceil(10 * weights))), len(weights))
    (n_exact, _, n_parents), (n_prop, bound, _) = runs["exact"], runs["proportional"]
    assert n_exact == 10 * n_parents and n_prop <= bound < n_exact
    # Gibbs: ceil(n_sweeps W_a) sweeps; one sweep finds at most one child besides the all-missed start
    f = two_tracks_three_returns(None, gate=0.9, step=False, generator=GibbsGenerator(n_sweeps=100), seed=2)
    log_miss, _, log_det, (_, _, log_rho, _, _) = f.single_target_hypotheses(Z3)
    _, problem = f.association_problem(0, log_miss, log_det, log_rho)
    assert len(f._generate(problem, 1.0)[1]) >= 4 and len(f._generate(problem, 0.01)[1]) <= 2


def test_undetected_prior_is_spread_as_the_births_and_thinned():
    """Williams 2015's scenario starts with 3 expected undetected objects: after an empty scan they are
    3 p_S (1 − p_D), plus the births (1 − p_D) — split over the birth terms as their weights 0.1 : 0.3."""
    f = pmbm(p_survive=0.9, undetected_prior=3.0, birth_means=[[0.0, 0, 0, 0], [10.0, 0, 0, 0]],
             birth_covs=[np.eye(4)] * 2, birth_weights=[0.1, 0.3])
    assert f.posterior().undetected_mean == pytest.approx(3.0, abs=1e-12)
    np.testing.assert_allclose(np.exp(f.undetected.log_w), [0.75, 2.25], atol=1e-12)
    post = f.step(np.zeros((0, 2)), 1.0)
    assert post.undetected_mean == pytest.approx(3 * 0.9 * 0.2 + 0.4 * 0.2, abs=1e-12)
    with pytest.raises(ValueError, match="undetected_prior"):
        pmbm(undetected_prior=1.0)


# ------------------------------------------------------------------------------------ empty, bad input
def test_no_objects_no_births_and_empty_scans():
    f = pmbm()
    for t in range(3):
        post = f.step(np.zeros((0, 2)), float(t + 1))
    assert post.cardinality.tolist() == [1.0] and post.undetected_mean == 0.0
    assert len(f.estimates()) == 0
    f.step(np.array([[1.0, 2.0]]), 4.0)  # a return with nothing to explain it but clutter
    assert [len(h.existence) for h in f.global_hypotheses()] == [0]


@pytest.mark.parametrize("kw, match", [
    (dict(birth_weights=[-0.1], birth_means=[[0.0, 0, 0, 0]], birth_covs=[np.eye(4)]), "Poisson weights"),
    (dict(birth_weights=[np.inf], birth_means=[[0.0, 0, 0, 0]], birth_covs=[np.eye(4)]), "Poisson weights"),
    (dict(birth="bernoulli", birth_weights=[1.0], birth_means=[[0.0, 0, 0, 0]], birth_covs=[np.eye(4)]), "r_B"),
    (dict(birth_weights=[0.1], birth_means=[[0.0, 0, 0, 0]], birth_covs=[-np.eye(4)]), "covs"),
    (dict(p_survive=0.0), "p_survive"),
    (dict(p_survive=1.5), "p_survive"),
    (dict(max_hypotheses=0), "max_hypotheses"),
    (dict(hypothesis_threshold=1.0), "hypothesis_threshold"),
    (dict(existence_threshold=-0.1), "existence_threshold"),
    (dict(gate_probability=1.0), "gate_probability"),
    (dict(estimator="mean"), "estimator"),
    (dict(collapse="gibbs"), "collapse"),
    (dict(birth="uniform"), "birth"),
    (dict(allocation="sqrt"), "allocation"),
    (dict(undetected_prior=-1.0), "undetected_prior"),
])
def test_bad_options_name_the_parameter(kw, match):
    with pytest.raises(ValueError, match=match):
        pmbm(**kw)


def test_detection_probability_must_lie_in_the_open_unit_interval():
    with pytest.raises(ValueError, match="p_D"):
        pmbm(p_D=1.0)  # a missed object of r = 1 would have weight 0: the miss option must be possible
    with pytest.raises(ValueError, match="p_D"):
        DetectionModel(1.2)


def test_poisson_intensity_refuses_negative_weights():
    with pytest.raises(ValueError, match="Poisson weights must be finite numbers >= 0"):
        PoissonIntensity.from_weights([0.3, -1e-3], np.zeros((2, 4)), np.stack([np.eye(4)] * 2))


def test_a_failed_step_leaves_the_filter_as_it_was():
    f = pmbm(birth_means=[[0.0, 5, 0, 0]], birth_covs=[np.eye(4)], birth_weights=[0.5])
    f.initialise([[0.0, 0, 0, 0]], [np.eye(4)])
    f.step(np.array([[0.1, 0.0]]), 1.0)
    before = (f.log_w.copy(), f.r.copy(), f.time, len(f.undetected))
    with pytest.raises(ValueError, match="Z"):
        f.step(np.zeros((2, 3)), 2.0)
    with pytest.raises(ValueError):
        f.step(np.zeros((0, 2)), 0.5)  # backwards in time
    assert np.array_equal(f.log_w, before[0]) and np.array_equal(f.r, before[1])
    assert (f.time, len(f.undetected)) == before[2:]


# ------------------------------------------------------------------------------------ registry
def problem(births="lmb"):
    s = sensor(0.9, 2.0)
    terms = [GaussianBirthTerm([x, y, 0, 0], np.diag([25.0, 25, 4, 4]), s.measurement.H, s.measurement.R)
             for x, y in ((-30, -30), (30, 30))]
    b = LabeledMultiBernoulliPopulation(terms, r_birth=0.05, p_survive=0.98) if births == "lmb" else births
    return TrackingProblem(ConstantVelocity(0.1), s, means=[[0, 0, 1, 0], [10, 0, -1, 0]],
                           covs=np.stack([np.eye(4)] * 2), labels=[7, 9], births=b)


@pytest.mark.parametrize("kind", ["pmbm_murty", "pmbm_gibbs", "pmb_lbp"])
def test_registry_kinds_build_and_track(kind):
    tr = build({"kind": kind, "max_hypotheses": 20}, problem(), seed=4)
    assert isinstance(tr, HypothesisTracker) and tr.birth == "poisson" and len(tr.birth_intensity) == 2
    for t in range(1, 4):
        tr.step(np.array([[t * 1.0, 0.1], [10 - t * 1.0, -0.1], [30.0, 31.0]]), float(t))
    est = tr.estimates()
    assert est.time == 3.0 and {7, 9} <= set(est.labels.tolist())
    assert len(tr.posterior().log_weights) <= 20
    # the birth near (30, 30) was detected three times: a track of existence near 1 at the return
    near = np.hypot(est.x[:, 0] - 30, est.x[:, 1] - 31) < 1.5
    assert near.sum() == 1


def test_registry_defaults_are_the_python_defaults():
    import inspect

    from hypotrack.hypotheses import presets
    opts = TrackerSpec.from_config({"kind": "pmbm_murty"}).options
    sig = inspect.signature(PMBMFilter).parameters
    for name in FAMILIES["poisson_mb"]:
        if name != "birth":
            assert opts[name] == sig[name].default, name
    assert opts["birth"] == inspect.signature(presets.pmbm_murty).parameters["birth"].default
    assert opts["k"] == inspect.signature(presets.pmbm_murty).parameters["k"].default
    assert opts["allocation"] == sig["allocation"].default
    assert TrackerSpec.from_config({"kind": "pmbm_gibbs"}).options["n_sweeps"] == \
        inspect.signature(presets.pmbm_gibbs).parameters["n_sweeps"].default
    assert set(kinds("poisson_mb")) == {"pmbm_murty", "pmbm_gibbs", "pmb_lbp"}


def test_registry_refuses_what_the_pmbm_cannot_take():
    with pytest.raises(SpecError, match="'x.factored'"):
        TrackerSpec.from_config({"kind": "pmbm_murty", "factored": {}}, "x")
    with pytest.raises(SpecError, match="'x.estimator'"):
        TrackerSpec.from_config({"kind": "pmb_lbp", "estimator": "mean"}, "x")
    from hypotrack.hypotheses.factored import AdaptiveBirth
    with pytest.raises(ValueError, match="measurement-driven births"):
        build({"kind": "pmbm_murty"}, problem(MeasurementBirths(AdaptiveBirth(), r_birth=0.1)))
    from hypotrack.models.population import SingleEventBirthDeath
    from hypotrack.models.sensors import FieldOfView
    uniform = SingleEventBirthDeath(0.01, 0.02, 2, fov=FieldOfView(0, 90, 1, 15))  # uniform birth regions
    with pytest.raises(ValueError, match="Gaussian birth terms"):
        build({"kind": "pmb_lbp"}, problem(uniform))



def test_a_step_failing_in_the_generator_is_undone_and_the_retry_equals_a_run_that_never_failed():
    class Failing(GibbsGenerator):
        def generate(self, problem, rng=None, keep=None):
            rng.integers(10)  # draws, then fails: the draw must be undone too
            raise RuntimeError("budget exhausted")

    def run(fail):
        f = PMBMFilter(ConstantVelocity(0.1), sensor(), GibbsGenerator(n_sweeps=50), birth_means=[[0.0, 5, 0, 0]],
                       birth_covs=[np.diag([30.0, 30, 1, 1])], birth_weights=[0.5], seed=11)
        f.initialise([[0.0, 0, 0, 0], [4.0, 0, 0, 0]], [np.eye(4), np.eye(4)])
        f.step(Z3, 1.0)
        if fail:
            good, f.generator = f.generator, Failing(n_sweeps=50)
            with pytest.raises(RuntimeError, match="budget"):
                f.step(Z3 + 1.0, 2.0)
            f.generator = good
        f.step(Z3 + 1.0, 2.0)
        return f

    a, b = run(False), run(True)
    assert a.rng.bit_generator.state == b.rng.bit_generator.state
    for name in PMBMFilter._STATE:
        if name != "last_stats":
            va, vb = getattr(a, name), getattr(b, name)
            if isinstance(va, PoissonIntensity):
                va, vb = va.log_w, vb.log_w
            if name == "last_prediction":  # NaN marks tracks started from the Poisson part
                assert all(np.array_equal(x, y, equal_nan=True) for x, y in zip(va, vb)), name
                continue
            assert np.array_equal(va, vb), name

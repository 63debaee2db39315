"""Catalogue of bad input at every public entry point, and of awkward input that must work.

Each bad case must raise ``ValueError`` or ``TypeError`` (never a bare ``LinAlgError`` or a numpy
broadcasting error from deep inside) whose message contains the given fragment — the parameter's
name, and where useful its allowed range. Each awkward case (empty scans, zero objects, a single
track, a singular but valid covariance) must return finite numbers and no negative variance.
"""

import numpy as np
import pytest

from hypotrack import gaussian as g
from hypotrack.association import (
    best_assignment,
    count_associations,
    enumerate_associations,
    find_clusters,
    gate_measurements,
    gate_threshold,
    murty_k_best,
    validation_matrix,
)
from hypotrack.association.lbp import lbp_marginals
from hypotrack.association.marginals import jpda_marginals
from hypotrack.association.mcmc import mcmc_search
from hypotrack.hypotheses import (
    BinomialPopulation,
    ExhaustiveGenerator,
    FISSTPoissonWeights,
    HFISSTWeights,
    HypothesisFilter,
    MCMCGenerator,
    MurtyGenerator,
    ReidWeights,
    hfisst,
    homht,
    rfisst,
)
from hypotrack.metrics import gospa, ospa, ospa_series
from hypotrack.metrics_trajectory import trajectory_gospa
from hypotrack.models import ConstantVelocity, OrnsteinUhlenbeck
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from hypotrack.trackers import (
    CardinalityTracker,
    ClassicalCountMHT,
    CountModel,
    ECMHTFilter,
    MOfNInitiator,
    PDAFilter,
    ScanModel,
    SingleHypothesisTracker,
    exact_count_dp,
)

I2, I4 = np.eye(2), np.eye(4)
X4 = np.array([0.0, 0.0, 1.0, 0.0])
H24 = np.hstack([I2, np.zeros((2, 2))])
NAN2 = np.array([np.nan, 0.0])
INDEF = np.array([[1.0, 2.0], [2.0, 1.0]])  # eigenvalues 3 and -1
REGION = Box([-50.0, -50.0], [50.0, 50.0])
CV = ConstantVelocity(0.1)
OU = OrnsteinUhlenbeck(0.01, 0.005)


def sensor(p_D=0.9, R=I2, ndim=4, rate=1.0):
    return Sensor(LinearPositionSensor(R, ndim), DetectionModel(p_D, REGION), PoissonClutter(rate, REGION))


def scan_model(**kw):
    args = {"H": H24, "R": I2, "p_D": 0.9, "p_gate": 0.99, "clutter_density": 1e-3}
    args.update(kw)
    return ScanModel(**args)


def sht(**kw):
    return SingleHypothesisTracker(CV, scan_model(), **kw)


def hf(**kw):
    return hfisst(CV, sensor(), means=X4[None], covs=I4[None], **kw)


def _sht_initialised():
    tr = sht()
    tr.initialise(X4[None], I4[None], time=0.0)
    return tr


def _step(tracker, *scan):
    return lambda: tracker().step(*scan)


BAD = [
    # ---------------------------------------------------------------- gaussian
    ("predict Q = -I", lambda: g.predict(np.zeros(2), I2, I2, -I2), "Q (process-noise covariance) must be positive semi"),
    ("predict indefinite P", lambda: g.predict(np.zeros(2), INDEF, I2, I2), "P (state covariance) must be positive semi"),
    ("predict NaN mean", lambda: g.predict(NAN2, I2, I2, I2), "x must be finite"),
    ("predict inf in F", lambda: g.predict(np.zeros(2), I2, np.array([[np.inf, 0], [0, 1.0]]), I2), "F must be finite"),
    ("predict F wrong shape", lambda: g.predict(np.zeros(2), I2, np.eye(3), I2), "F must have shape (2, 2)"),
    ("predict Q wrong shape", lambda: g.predict(np.zeros(2), I2, I2, np.eye(3)), "Q must have shape (2, 2)"),
    ("predict x/P mismatch", lambda: g.predict(np.zeros(3), I2, I2, I2), "do not match"),
    ("predict asymmetric P", lambda: g.predict(np.zeros(2), np.array([[1.0, 0.5], [0.0, 1.0]]), I2, I2),
     "P (state covariance) must be symmetric"),
    ("predict_with NaN P", lambda: g.predict_with(CV, X4, np.full((4, 4), np.nan), 1.0), "P must be finite"),
    ("update indefinite P", lambda: g.update(np.zeros(2), INDEF, np.zeros(2), I2, I2), "P (state covariance)"),
    ("update P = -I", lambda: g.update(np.zeros(2), -I2, np.zeros(2), I2, I2), "P (state covariance) must be positive"),
    ("update R = -0.5 I", lambda: g.update(np.zeros(2), I2, np.zeros(2), I2, -0.5 * I2),
     "R (measurement-noise covariance) must be positive semi"),
    ("update NaN state", lambda: g.update(NAN2, I2, np.zeros(2), I2, I2), "x must be finite"),
    ("update NaN return", lambda: g.update(np.zeros(2), I2, NAN2, I2, I2), "z must be finite"),
    ("update H wrong shape", lambda: g.update(X4, I4, np.zeros(2), np.eye(3), I2), "H must have shape (p, 4)"),
    ("update R wrong shape", lambda: g.update(X4, I4, np.zeros(2), H24, np.eye(3)), "R must have shape (2, 2)"),
    ("update z wrong length", lambda: g.update(X4, I4, np.zeros(3), H24, I2), "z must have shape (2,)"),
    ("update singular S", lambda: g.update(X4, np.diag([0.0, 1.0, 1.0, 1.0]), np.zeros(2), H24, np.diag([0.0, 1.0])),
     "S = H P Hᵀ + R (innovation covariance) must be positive definite"),
    ("innovation NaN H", lambda: g.innovation(X4, I4, np.full((2, 4), np.nan), I2), "H must be finite"),
    ("joseph indefinite P", lambda: g.joseph_covariance(INDEF, np.zeros((2, 2)), I2, I2), "P (state covariance)"),
    ("joseph K wrong shape", lambda: g.joseph_covariance(I2, np.zeros((3, 2)), I2, I2), "K must have shape"),
    ("log_likelihood non-PD S", lambda: g.log_likelihood(np.zeros(2), np.zeros(2), -I2), "S (innovation covariance)"),
    ("log_likelihood NaN z", lambda: g.log_likelihood(NAN2, np.zeros(2), I2), "z must be finite"),
    ("log_likelihood NaN z_pred", lambda: g.log_likelihood(np.zeros(2), NAN2, I2), "z_pred must be finite"),
    ("log_likelihood dim mismatch", lambda: g.log_likelihood(np.zeros(3), np.zeros(2), I2), "z must have 2 components"),
    ("mahalanobis indefinite S", lambda: g.mahalanobis2_matrix(np.zeros((2, 2)), np.zeros((1, 2)), INDEF[None]),
     "S (innovation covariance) must be positive definite"),
    ("loglik matrix NaN Z", lambda: g.log_likelihood_matrix(NAN2[None], np.zeros((1, 2)), I2[None]), "Z must be finite"),
    ("GaussianState indefinite", lambda: g.GaussianState(np.zeros(2), INDEF), "cov must be positive definite"),
    # ---------------------------------------------------------------- models
    ("CV negative q", lambda: ConstantVelocity(-1.0), "q must be a finite number >= 0"),
    ("OU negative gamma", lambda: OrnsteinUhlenbeck(0.01, -0.1), "gamma must be a finite number > 0"),
    ("sensor p_D > 1", lambda: DetectionModel(1.5, REGION), "p_D must lie in (0, 1]"),
    ("sensor p_D NaN", lambda: DetectionModel(float("nan"), REGION), "p_D must lie in (0, 1]"),
    ("clutter negative rate", lambda: PoissonClutter(-1.0, REGION), "rate must be a finite number >= 0"),
    ("sensor R indefinite", lambda: LinearPositionSensor(INDEF, 4), "R must be positive definite"),
    ("box high <= low", lambda: Box([0.0, 0.0], [0.0, 1.0]), "high must exceed low"),
    ("single-event alpha > 1", lambda: SingleEventBirthDeath(1.5, 0.01, 1), "alpha must lie in [0, 1]"),
    ("single-event beta < 0", lambda: SingleEventBirthDeath(0.01, -0.1, 1), "beta must lie in [0, 1]"),
    ("single-event M_b alpha >= 1", lambda: SingleEventBirthDeath(0.6, 0.0, 2), "n_birth_regions * alpha must be < 1"),
    ("binomial alpha = 1", lambda: BinomialPopulation((), alpha=1.0), "alpha must lie in [0, 1)"),
    ("binomial p_survive = 0", lambda: BinomialPopulation((), p_survive=0.0), "p_survive must lie in (0, 1]"),
    ("birth density bad velocity cov", lambda: UniformBirthDensity(REGION, -I2), "velocity_cov must be positive definite"),
    # ---------------------------------------------------------------- association
    ("count negative M", lambda: count_associations(-1, 2), "M must be an integer in [0, inf]"),
    ("enumerate negative budget", lambda: enumerate_associations(2, 2, max_events=0), "max_events must be an integer in [1"),
    ("enumerate allowed wrong shape", lambda: enumerate_associations(2, 2, allowed=np.ones((3, 2), bool)), "allowed must have shape"),
    ("best_assignment NaN", lambda: best_assignment(np.array([[np.nan, 0.0]])), "NaN and +inf are not allowed"),
    ("murty k < 0", lambda: murty_k_best(np.zeros((2, 2)), -1), "k must be an integer in [0, inf]"),
    ("gate p_gate = 0", lambda: gate_threshold(0.0, 2), "p_gate must lie in (0, 1]"),
    ("validation NaN d2", lambda: validation_matrix(np.array([[np.nan]]), 9.0), "d2 must hold squared distances"),
    ("gate_measurements non-PD S", lambda: gate_measurements(np.zeros((1, 2)), np.zeros((1, 2)), -I2[None], 0.99),
     "S must be positive definite"),
    ("jpda_marginals NaN", lambda: jpda_marginals(np.array([[np.nan, 0.0]])), "log_weights must not contain NaN"),
    ("jpda_marginals wrong shape", lambda: jpda_marginals(np.zeros(3)), "log_weights must have shape (n, m + 1)"),
    ("lbp_marginals NaN", lambda: lbp_marginals(np.array([[np.nan, 0.0]])), "log_weights must not contain NaN"),
    ("lbp_marginals zero missed weight", lambda: lbp_marginals(np.array([[-np.inf, 0.0]])),
     "log_weights[:, 0] (missed) must be finite"),
    ("lbp_marginals tol 0", lambda: lbp_marginals(np.zeros((1, 2)), tol=0.0), "tol must be a finite number > 0"),
    ("lbp_marginals max_iter 0", lambda: lbp_marginals(np.zeros((1, 2)), max_iter=0), "max_iter must be an integer in [1"),
    ("mcmc negative steps", lambda: mcmc_search(np.zeros((1, 2)), 1, 1, np.zeros((2, 1)), n_steps=-1, seed=0),
     "n_steps must be an integer in [0"),
    ("mcmc temperature 0", lambda: mcmc_search(np.zeros((1, 2)), 1, 1, np.zeros((2, 1)), n_steps=1, seed=0,
                                               temperature=0.0), "temperature must be a finite number > 0"),
    ("clusters non-boolean", lambda: find_clusters(np.full((2, 2), 0.5)), "validation must be a boolean"),
    # ---------------------------------------------------------------- hypotheses
    ("MCMCGenerator temperature 0", lambda: MCMCGenerator(temperature=0), "temperature must be a finite number > 0"),
    ("MCMCGenerator temperature NaN", lambda: MCMCGenerator(temperature=float("nan")), "temperature must be a finite number > 0"),
    ("MCMCGenerator variant", lambda: MCMCGenerator(variant="hastings"), "variant must be one of"),
    ("MCMCGenerator completion 1", lambda: MCMCGenerator(completion_threshold=1.0), "completion_threshold"),
    ("MurtyGenerator k = 0", lambda: MurtyGenerator(k=0), "k must be an integer in [1"),
    ("ExhaustiveGenerator budget 0", lambda: ExhaustiveGenerator(max_events=0), "max_events must be an integer in [1"),
    ("Reid negative birth intensity", lambda: ReidWeights(birth_intensity=-1.0), "birth_intensity"),
    ("filter 2-D motion, 4-D sensor", lambda: hfisst(ConstantVelocity(0.1, n_spatial=1), sensor()),
     "states are 2-dimensional but the sensor (H of shape (2, 4)) expects 4"),
    ("filter p_D = 1", lambda: hfisst(CV, sensor(p_D=1.0)), "p_D must lie in (0, 1)"),
    ("filter no clutter", lambda: hfisst(CV, Sensor(LinearPositionSensor(I2, 4), DetectionModel(0.9, REGION))),
     "sensor.clutter"),
    ("filter H-inf 0", lambda: hf(max_hypotheses=0), "max_hypotheses"),
    ("filter cap", lambda: hf(cap="bottom"), "cap must be 'top' or 'sample'"),
    ("filter dt < 0", lambda: hf(dt=-1.0), "dt must be a finite number > 0"),
    ("filter gate 1", lambda: hf(gate_probability=1.0), "gate_probability must lie in (0, 1)"),
    ("filter NaN mean", lambda: hfisst(CV, sensor(), means=np.full((1, 4), np.nan), covs=I4[None]), "means must be finite"),
    ("filter indefinite covs", lambda: hfisst(CV, sensor(), means=X4[None], covs=-I4[None]), "covs must be positive"),
    ("filter means wrong dim", lambda: hfisst(CV, sensor(), means=np.zeros((1, 2)), covs=I2[None]), "means must have shape"),
    ("filter weights type", lambda: HypothesisFilter(CV, sensor(), "hfisst", ExhaustiveGenerator()), "weights must be a"),
    ("filter step NaN scan", lambda: hf().step(np.array([[np.nan, 0.0]])), "Z must be finite"),
    ("filter step 3-D returns", lambda: hf().step(np.zeros((2, 3))), "Z must have shape (m, 2)"),
    ("filter step dt < 0", lambda: hf().step(np.zeros((0, 2)), dt=-1.0), "dt must be a finite number >= 0"),
    ("filter step time before the filter's", lambda: hf().step(np.zeros((0, 2)), -0.5), "time must be >= the filter's time"),
    ("rfisst n_steps 0", lambda: rfisst(CV, sensor(), n_steps=0), "n_steps must be an integer in [1"),
    ("homht births without density", lambda: homht(CV, sensor(), birth_intensity=1.0), "birth_density"),
    # ---------------------------------------------------------------- trackers
    ("ScanModel p_gate 1", lambda: scan_model(p_gate=1.0), "p_gate must lie in (0, 1)"),
    ("ScanModel clutter 0", lambda: scan_model(clutter_density=0.0), "clutter_density must be a finite number > 0"),
    ("ScanModel R indefinite", lambda: scan_model(R=INDEF), "R must be positive definite"),
    ("ScanModel R wrong size", lambda: scan_model(R=np.eye(3)), "R must be 2x2"),
    ("SHT 2-D motion, 4-D model", lambda: SingleHypothesisTracker(ConstantVelocity(0.1, n_spatial=1), scan_model()),
     "states are 2-dimensional but the scan model"),
    ("SHT association", lambda: sht(association="mht"), "association must be one of"),
    ("SHT max_misses 0", lambda: sht(max_misses=0), "max_misses must be an integer in [1"),
    ("SHT missed distance < 0", lambda: sht(gnn_score="mahalanobis", missed_distance=-1.0), "missed_distance must be a finite number > 0"),
    ("SHT initialise NaN", lambda: sht().initialise(np.full((1, 4), np.nan), I4[None], time=0.0), "means must be finite"),
    ("SHT initialise indefinite P", lambda: sht().initialise(X4[None], -I4[None], time=0.0), "covs must be positive"),
    ("SHT initialise float labels", lambda: sht().initialise(X4[None], I4[None], 0.5), "labels must"),
    ("SHT initialise repeated labels", lambda: sht().initialise(np.stack([X4, X4]), np.stack([I4, I4]), [3, 3]),
     "labels must be distinct"),
    ("SHT step time backwards", _step(_sht_initialised, np.zeros((0, 2)), -1.0), "scan times must not decrease"),
    ("SHT step NaN time", _step(_sht_initialised, np.zeros((0, 2)), np.nan), "time must be finite"),
    ("SHT step NaN return", _step(_sht_initialised, NAN2[None], 1.0), "Z must be finite"),
    ("SHT step old (time, Z) pair", _step(_sht_initialised, (1.0, np.zeros((2, 2)))), "got a (time, Z) pair"),
    ("SHT step no time", _step(_sht_initialised, np.zeros((3, 2))), "time is required"),
    ("initiator m > n", lambda: MOfNInitiator(CV, scan_model(), m=4, n=3), "m must be an integer in [1, 3]"),
    ("initiator velocity std 0", lambda: MOfNInitiator(CV, scan_model(), initial_velocity_std=0.0),
     "initial_velocity_std must be a finite number > 0"),
    ("initiator 2-D motion", lambda: MOfNInitiator(ConstantVelocity(0.1, n_spatial=1), scan_model()), "2-dimensional"),
    ("ECMHT R < 0", lambda: ECMHTFilter(OU, -1.0, 3, rng=0), "R must be a finite number > 0"),
    ("ECMHT no rng", lambda: ECMHTFilter(OU, 1.0, 3), "rng must be given"),
    ("ECMHT NaN scan", lambda: ECMHTFilter(OU, 1.0, 3, rng=0).step(np.full((3, 2), np.nan)), "Z must be finite"),
    ("ECMHT scan wrong sensors", lambda: ECMHTFilter(OU, 1.0, 3, rng=0).step(np.zeros((4, 2))),
     "Z must have shape (n_runs, 3, 2)"),
    ("PDAF variant", lambda: PDAFilter(OU, 1.0, 3, variant="joint"), "variant must be one of"),
    ("CountModel p_chi 1", lambda: CountModel(0.9, 1.0, 1.0, 10.0), "p_chi must lie in (0, 1)"),
    ("CountModel lambda_fa 0", lambda: CountModel(0.9, 0.01, 1.0, 0.0), "lambda_fa must be a finite number > 0"),
    ("cardinality negative count", lambda: CardinalityTracker(0.9, 0.01, 1.0, 10.0).step(-1), "r_k must be an integer in [0"),
    ("cardinality variant", lambda: CardinalityTracker(0.9, 0.01, 1.0, 10.0, variant="greedy"), "variant must be 'row_dp' or 'group'"),
    ("classical MHT max_alive < 0", lambda: ClassicalCountMHT(0.9, 0.01, 1.0, 10.0, max_alive=-1), "max_alive must be an integer in [0"),
    ("count DP non-integer counts", lambda: exact_count_dp([1.5, 2], CountModel(0.9, 0.01, 1.0, 10.0)),
     "r must hold non-negative integers"),
    # ---------------------------------------------------------------- metrics
    ("ospa c = 0", lambda: ospa(np.zeros((1, 2)), np.zeros((1, 2)), 0.0), "c must be a finite number > 0"),
    ("ospa p < 1", lambda: ospa(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, p=0.5), "p must be >= 1"),
    ("ospa NaN point", lambda: ospa(NAN2[None], np.zeros((1, 2)), 1.0), "X must be finite"),
    ("ospa dimension mismatch", lambda: ospa(np.zeros((1, 2)), np.zeros((1, 3)), 1.0), "same dimension"),
    ("gospa alpha 3", lambda: gospa(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, alpha=3.0), "alpha must lie in (0, 2]"),
    ("ospa_series lengths", lambda: ospa_series([np.zeros((1, 2))], [], 1.0), "same length"),
    ("trajectory_gospa 2-D input", lambda: trajectory_gospa(np.zeros((1, 2)), np.zeros((1, 1, 2)), c=1.0),
     "X must be an (n, T, d) array"),
    ("trajectory_gospa partly NaN state", lambda: trajectory_gospa(np.array([[[0.0, np.nan]]]), np.zeros((1, 1, 2)), c=1.0),
     "X[0, 0] is partly NaN"),
    ("trajectory_gospa T mismatch", lambda: trajectory_gospa(np.zeros((1, 2, 1)), np.zeros((1, 3, 1)), c=1.0),
     "same time steps T"),
    ("trajectory_gospa gamma 0", lambda: trajectory_gospa(np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), c=1.0, gamma=0.0),
     "gamma must be a finite number > 0"),
    ("trajectory_gospa p = inf", lambda: trajectory_gospa(np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), c=1.0, p=np.inf),
     "p must lie in [1, inf)"),
]


@pytest.mark.parametrize("make, fragment", [pytest.param(f, frag, id=name) for name, f, frag in BAD])
def test_bad_input_is_refused_with_a_named_error(make, fragment):
    with pytest.raises((ValueError, TypeError)) as info:
        make()
    assert not isinstance(info.value, np.linalg.LinAlgError), info.value
    assert fragment in str(info.value), str(info.value)


def _finite_and_psd(*arrays):
    for a in arrays:
        a = np.asarray(a, dtype=float)
        assert np.all(np.isfinite(a))
        if a.ndim >= 2 and a.shape[-1] == a.shape[-2] and a.size:
            assert np.all(np.linalg.eigvalsh(a) >= -1e-12)  # no negative variance


def _work_filter_empty_and_zero():
    f = hfisst(CV, sensor())  # zero objects
    post = f.step(np.zeros((0, 2)))
    assert post.expected_number == 0.0
    f.step([])
    return [post.log_weights]


def _work_filter_objects_empty_scan():
    f = hf()
    post = f.step(np.zeros((0, 2)))
    return [post.log_weights, f.store.covs]


def _work_sht_zero_tracks_and_empty_scans():
    tr = SingleHypothesisTracker(CV, scan_model(), association="jpda", initiator=MOfNInitiator(CV, scan_model()))
    for t in range(3):
        est = tr.step(np.zeros((0, 2)), float(t))
    assert len(est) == 0
    est = tr.step(np.array([[1.0, 1.0]]), 3.0)
    return [est.x, est.P]


def _work_singular_q_and_r():
    x, P = g.predict(X4, I4, CV.F(1.0), np.zeros((4, 4)))  # Q = 0: no process noise is valid
    x, P = g.update(x, P, np.zeros(2), H24, np.zeros((2, 2)))  # R = 0 with P PD: S still PD
    return [x, P]


def _work_count_and_metrics_empty():
    tr = CardinalityTracker(0.9, 0.01, 1.0, 10.0)
    assert len(tr.estimates()) == 0
    tr.step(0)
    return [tr.estimates(), [ospa(np.zeros((0, 2)), np.zeros((0, 2)), 5.0)],
            [gospa(np.zeros((0, 2)), np.zeros((1, 2)), 5.0).value],
            [trajectory_gospa([], np.zeros((1, 3, 2)), c=5.0).value, trajectory_gospa([], [], c=5.0).value]]


def _work_association_empty():
    assert count_associations(0, 0) == 1
    ev = enumerate_associations(0, 3)
    np.testing.assert_array_equal(ev, -np.ones((1, 3)))
    d2, logdet = g.mahalanobis2_matrix(np.zeros((0, 2)), np.zeros((1, 2)), I2[None])
    assert d2.shape == (0, 1)
    lbp_none, lbp_no_returns = lbp_marginals(np.zeros((0, 3))).beta, lbp_marginals(np.zeros((2, 1))).beta
    assert lbp_none.shape == (0, 3) and (lbp_no_returns == 1).all()
    return [ev, logdet, lbp_none, lbp_no_returns]


def _work_generators_zero_returns():
    out = []
    for gen in (ExhaustiveGenerator(), MurtyGenerator(k=3), MCMCGenerator(n_steps=10)):
        f = HypothesisFilter(CV, sensor(), HFISSTWeights(), gen, means=X4[None], covs=I4[None], seed=0)
        out.append(f.step(np.zeros((0, 2))).log_weights)
    f = HypothesisFilter(CV, sensor(), FISSTPoissonWeights(), ExhaustiveGenerator(), seed=0)
    out.append(f.step(np.array([[0.0, 0.0]])).log_weights)
    return out


WORK = [
    ("filter, zero objects, empty scans", _work_filter_empty_and_zero),
    ("filter, objects, empty scan", _work_filter_objects_empty_scan),
    ("SHT, zero tracks, empty scans then a return", _work_sht_zero_tracks_and_empty_scans),
    ("gaussian, Q = 0 and R = 0", _work_singular_q_and_r),
    ("count tracker and metrics, empty", _work_count_and_metrics_empty),
    ("association, zero objects / returns", _work_association_empty),
    ("generators, zero returns", _work_generators_zero_returns),
]


@pytest.mark.parametrize("run", [pytest.param(f, id=name) for name, f in WORK])
def test_awkward_but_valid_input_works(run):
    _finite_and_psd(*run())


def test_catalogue_size():
    assert len(BAD) + len(WORK) >= 60

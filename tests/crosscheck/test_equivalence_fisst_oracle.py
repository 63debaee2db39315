"""(f) Brute-force oracle: two targets, two returns, the FISST posterior by numerical integration.

Document 000's appendix writes the FISST multi-target likelihood of two returns given two targets
(Eq. 39: seven association terms with the 1/(C(m,k) k!) factors), the symmetrised predicted pdf
(Eq. 37) and the Bayes update with its set-integral normaliser (Eq. 40–45). Here every
integral is done numerically (scipy.integrate.dblquad) on a 1-D state, independently of the
Kalman filter, and compared with the H-FISST engine: the normaliser, every hypothesis weight,
and the posterior density at scattered points of the state space.

The integrals use the trapezoid rule on a fine grid (scipy.integrate.trapezoid); for smooth,
rapidly decaying integrands such as these Gaussian products it converges geometrically in the
grid step, far below the tolerances asserted (checked against scipy.integrate.dblquad once,
in test_f_quadrature_is_converged).
"""

import math

import numpy as np
import pytest
from scipy import integrate

from hypotrack.hypotheses import hfisst
from hypotrack.models import OrnsteinUhlenbeck
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

P_D = 0.8
R = 0.5
L_HALF = 20.0  # clutter over [-20, 20]
G = 1.0 / (2 * L_HALF)
MEANS = np.array([[-1.0], [1.5]])
VARS = np.array([0.8, 1.3])
Z = np.array([[-0.4], [2.6]])
DT = 1.0
MOTION = OrnsteinUhlenbeck(sigma2=0.2, gamma=0.1)


def engine():
    sensor = Sensor(LinearPositionSensor(np.array([[R]]), ndim_state=1, position_indices=(0,)),
                    DetectionModel(P_D), PoissonClutter(1.0, Box([-L_HALF], [L_HALF])))
    return hfisst(MOTION, sensor, dt=DT, max_hypotheses=100, means=MEANS, covs=VARS[:, None, None])


def predicted_priors():
    """The two predicted pdfs (document 000 Eq. 7) as functions of the state."""
    F = MOTION.F(DT)[0, 0]
    Q = MOTION.Q(DT)[0, 0]
    return [lambda x, mu=F * mu, v=F * F * v + Q: gauss(x, mu, v) for mu, v in zip(MEANS[:, 0], VARS)]


def gauss(x, mean, var):
    return np.exp(-0.5 * (x - mean) ** 2 / var) / math.sqrt(2 * math.pi * var)


def lik(z, x):
    return gauss(z, x, R)


# The seven association terms of Eq. 39 as functions of (x1, x2), x1 the state of the target whose
# prior is p1 (engine object 0), with the engine's event (return -> object, -1 clutter).
z1, z2 = Z[:, 0]
TERMS = {
    (0, 1): lambda x1, x2: P_D**2 / 2 * lik(z1, x1) * lik(z2, x2),
    (1, 0): lambda x1, x2: P_D**2 / 2 * lik(z1, x2) * lik(z2, x1),
    (0, -1): lambda x1, x2: P_D * (1 - P_D) / 2 * lik(z1, x1) * G,
    (-1, 0): lambda x1, x2: P_D * (1 - P_D) / 2 * lik(z2, x1) * G,
    (1, -1): lambda x1, x2: P_D * (1 - P_D) / 2 * lik(z1, x2) * G,
    (-1, 1): lambda x1, x2: P_D * (1 - P_D) / 2 * lik(z2, x2) * G,
    (-1, -1): lambda x1, x2: (1 - P_D) ** 2 * G * G,
}


def set_likelihood(x1, x2):
    """Eq. 39: symmetric in (x1, x2) — the sum of the seven terms."""
    return sum(t(x1, x2) for t in TERMS.values())


LO, HI = -12.0, 14.0
GRID = np.linspace(LO, HI, 1301)


def integrate2(f):
    X1, X2 = np.meshgrid(GRID, GRID, indexing="ij")
    return integrate.trapezoid(integrate.trapezoid(f(X1, X2), GRID, axis=1), GRID)


def test_f_quadrature_is_converged():
    p1, p2 = predicted_priors()
    f = lambda x1, x2: TERMS[(1, 0)](x1, x2) * p1(x1) * p2(x2)
    ref, _ = integrate.dblquad(lambda x2, x1: f(x1, x2), LO, HI, LO, HI, epsabs=1e-13, epsrel=1e-9)
    assert integrate2(f) == pytest.approx(ref, rel=1e-9)


@pytest.fixture(scope="module")
def oracle():
    p1, p2 = predicted_priors()
    prior_sym = lambda x1, x2: p1(x1) * p2(x2) + p1(x2) * p2(x1)  # Eq. 37
    eta = 0.5 * integrate2(lambda x1, x2: set_likelihood(x1, x2) * prior_sym(x1, x2))  # Eq. 40, set integral
    term_mass = {ev: integrate2(lambda x1, x2, t=t: t(x1, x2) * p1(x1) * p2(x2)) for ev, t in TERMS.items()}
    return eta, term_mass, prior_sym


def test_f_normaliser_equals_sum_of_child_weights(oracle):
    eta, term_mass, _ = oracle
    f = engine()
    children = f.expand(Z)
    assert len(children) == 7  # A(2, 2) = 7 associations (Eq. 4)
    assert np.log(eta) == pytest.approx(np.logaddexp.reduce(children.log_weights), abs=1e-10)  # Eq. 43
    assert sum(term_mass.values()) == pytest.approx(eta, rel=1e-9)


def test_f_hypothesis_weights_equal_fisst_by_integration(oracle):
    eta, term_mass, _ = oracle
    f = engine()
    f.step(Z)
    weights = dict(zip(map(tuple, f.last_kept.events.tolist()), np.exp(f.log_weights)))
    assert weights.keys() == term_mass.keys()
    for ev, mass in term_mass.items():
        assert weights[ev] == pytest.approx(mass / eta, rel=1e-10)  # Eq. 44–45


def test_f_posterior_density_equals_fisst_posterior(oracle):
    eta, _, prior_sym = oracle
    f = engine()
    post = f.step(Z)
    rng = np.random.default_rng(0)
    points = rng.uniform(-4.0, 5.0, size=(25, 2))
    for x1, x2 in points:
        fisst = set_likelihood(x1, x2) * prior_sym(x1, x2) / eta
        mixture = 0.0
        for h in post.top:
            (m1, m2), (v1, v2) = h.means[:, 0], h.covs[:, 0, 0]
            a = gauss(x1, m1, v1) * gauss(x2, m2, v2)
            b = gauss(x2, m1, v1) * gauss(x1, m2, v2)
            mixture += h.weight * (a + b)  # the symmetrised H-FISST pdf (Eq. 45)
        assert mixture == pytest.approx(fisst, rel=1e-10)

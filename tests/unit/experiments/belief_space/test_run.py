"""The belief_space experiment (hypotrack.experiments.belief_space.run): document 001's Eq. 39, Eq. 43
and FISST = HOMHT, each computed from the engine's weights and checked against an oracle that does
not use the code under test (hand formulas, scipy's multivariate normal, numerical quadrature)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy import integrate
from scipy.stats import multivariate_normal

from hypotrack.config import ConfigError, validate_config
from hypotrack.experiments.belief_space import claims as bc
from hypotrack.experiments.belief_space import run as bs
from hypotrack.hypotheses.population_events import birth_prior_gaussian
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from hypotrack.reporting.ledger import read_claims, write_claims

ROOT = Path(__file__).resolve().parents[4]

RATIO = dict(p_D=[0.6, 0.95], alpha=[1e-3, 0.2], n_pixels=3, pixel_size=10.0, velocity_std=0.5, beta=1e-4,
             measurement_var=0.25, clutter_rate=1.0, q=0.01)
EQ43 = dict(p_D=0.9, alpha=1e-3, n_pixels=3, pixel=1, pixel_size=10.0, velocity_std=0.5, q=0.01, dt=1.0,
            clutter_rate=1.0, measurement_std=0.5, n_offsets=5, noise_sweep=[0.2, 1.0, 4.0])
EQUIV = dict(n_runs=2, n_scans=3, n_targets=3, max_hypotheses=200, p_D=0.85, clutter_rate=2.0, measurement_var=0.5)


@pytest.fixture(scope="module")
def ratio():
    return bs.ratio_table(RATIO)


def test_eq39_engine_ratio_equals_formulas(ratio):
    p, a = ratio["p_D"].to_numpy(), ratio["alpha"].to_numpy()
    # Hand formulas, not the table's own formula columns.
    np.testing.assert_allclose(ratio["engine_poisson_limit"], (1 - p) * a, rtol=1e-12)
    np.testing.assert_allclose(ratio["engine_binomial"], (1 - p) * a / (1 - a), rtol=1e-12)
    np.testing.assert_allclose(ratio["engine_single_event"], (1 - p) * a / (1 - 3 * a - 2 * 1e-4), rtol=1e-12)
    # Many twin pairs per scan (with 0, 1 and 2 detected births), all with the same ratio.
    assert ratio["engine_poisson_limit_pairs"].min() > 100 and ratio["engine_single_event_pairs"].min() > 20
    assert ratio[[c for c in ratio if c.endswith("_spread")]].to_numpy().max() < 1e-12
    # Eq. 39 is exact only under Eq. 33: at alpha = 0.2 the exact binomial is 25 % higher.
    big = ratio[ratio["alpha"] == 0.2]
    np.testing.assert_allclose(big["engine_binomial"] / big["eq39"], 1.25, rtol=1e-12)


def _oracle_gaussian_ratio(offset, measurement_std):
    """(1 - p_D) Vbar N(z*; H F m, H (F P F' + Q) H' + R) with scipy, for the engine's birth pdf."""
    size = EQ43["pixel_size"]
    pixel = Box([size, 0.0], [2 * size, size])
    mean, cov = birth_prior_gaussian(UniformBirthDensity(pixel, np.eye(2) * EQ43["velocity_std"] ** 2))
    motion = ConstantVelocity(EQ43["q"])
    F, Q = motion.F(EQ43["dt"]), motion.Q(EQ43["dt"])
    m_pred, P_pred = F @ mean, F @ cov @ F.T + Q
    z = np.array([1.5 * size + offset * size, 0.5 * size])
    S = P_pred[:2, :2] + np.eye(2) * measurement_std**2
    return (1 - EQ43["p_D"]) * size**2 * multivariate_normal(m_pred[:2], S).pdf(z)


@pytest.mark.parametrize("offset", [-0.4, 0.0, 0.25])
def test_eq42_engine_ratio_equals_scipy_oracle(offset):
    engine = bs.engine_gamma_ratio(EQ43, 0.5, [offset])[0]
    assert engine == pytest.approx(_oracle_gaussian_ratio(offset, 0.5), rel=1e-9)
    assert bs.gaussian_formula_ratio(EQ43, 0.5, [offset])[0] == pytest.approx(engine, rel=1e-9)


def test_uniform_pixel_formula_equals_quadrature():
    """Vbar * int p(z*|x) p_b^-(x) dx for a uniform square pixel convolved with N(0, s^2 I)."""
    s2 = bs._position_spread_var(EQ43, 2.0)
    L = EQ43["pixel_size"]
    for offset in (0.0, 0.3, 0.5):
        z = np.array([offset * L, 0.0])
        dens = lambda y, x: multivariate_normal(np.zeros(2), np.eye(2) * s2).pdf(z - np.array([x, y]))  # noqa: E731
        quad, _ = integrate.dblquad(dens, -L / 2, L / 2, -L / 2, L / 2, epsabs=1e-12, epsrel=1e-10)
        expected = (1 - EQ43["p_D"]) * quad  # Vbar * (1/Vbar) * integral over the pixel
        assert bs.uniform_formula_ratio(EQ43, 2.0, [offset])[0] == pytest.approx(expected, rel=1e-8)


def test_eq43_bound_fails_for_small_noise_and_holds_for_large():
    table = bs.eq43_noise_table(EQ43)
    threshold = (6 / np.pi - 1) / 12
    small, large = table.iloc[0], table.iloc[-1]
    assert small["spread_over_pixel_area"] < threshold < large["spread_over_pixel_area"]
    assert small["engine"] > 1.5 and large["engine"] < 1  # ratio / (1 - p_D)
    assert (table["uniform_formula"] <= 1).all() and (table["uniform_deficit_at_centre"] > 0).all()
    np.testing.assert_allclose(table["engine"], table["gaussian_formula"], rtol=1e-9)
    # The engine's sampled moment match is within 1 % of the analytic L^2/12 Gaussian.
    np.testing.assert_allclose(table["engine"], table["variance_matched_analytic"], rtol=1e-2)


@pytest.fixture(scope="module")
def equivalence():
    return bs.equivalence_table(EQUIV, seed=7)


def test_fisst_equals_reid_and_hfisst_does_not(equivalence):
    assert equivalence["same_hypotheses"].all()
    assert equivalence["max_abs_dlogw_fisst_reid"].max() < 1e-9
    assert equivalence["max_abs_dmean_fisst_reid"].max() < 1e-9
    assert equivalence["n_hypotheses"].min() > 10  # a real comparison, many hypotheses
    assert equivalence["tv_hfisst_reid"].max() > 1e-3


def test_equivalence_is_reproducible(equivalence):
    again = bs.equivalence_table(EQUIV, seed=7)
    assert again.equals(equivalence)
    assert not bs.equivalence_table({**EQUIV, "n_runs": 1}, seed=8).iloc[:3].equals(equivalence.iloc[:3])


def test_checks_and_claims(ratio, equivalence, tmp_path):
    offsets = bs.eq43_offsets_table(EQ43)
    noise = bs.eq43_noise_table(EQ43)
    checks = bc.checks_table(ratio, offsets, noise, equivalence, {"eq43": EQ43, "ratio": RATIO})
    assert checks["engine_matches_formula"].all()
    holds = dict(zip(checks["check"], checks["claim_holds"]))
    assert holds["Eq. 43 bound, uniform pixel births"]
    assert not holds["Eq. 43 bound with the engine's Gaussian undetected-birth pdf"]
    assert holds["FISST (Eq. 18) = HOMHT (Eq. 30) for a fixed number of targets"]
    path = tmp_path / "claims.csv"
    write_claims(bc.claims_from_checks(checks), path)
    status = dict(zip(*read_claims([path])[["item", "status"]].to_numpy().T))
    assert status["undetected-birth weight ratio in the engine"] == "consistency check"  # engine vs its own formula: never a reproduction
    assert status["Eq. 43 bound, Gaussian undetected-birth pdf (engine)"] == "not reproduced"
    assert status["FISST = HOMHT for a fixed number of targets (engine)"] == "consistency check"
    evidence = dict(zip(*read_claims([path])[["item", "evidence"]].to_numpy().T))
    # engine-vs-formula rows share the code path under test: never a reproduction on their own
    assert evidence["undetected-birth weight ratio in the engine"] == "identity of the implementation"
    assert evidence["FISST = HOMHT for a fixed number of targets (engine)"] == "identity of the implementation"
    assert all(evidence.values())


def test_bad_input():
    with pytest.raises(ValueError, match="pixel"):
        bs.engine_gamma_ratio({**EQ43, "pixel": 3}, 0.5, [0.0])
    with pytest.raises(ValueError, match="model"):
        bs.engine_twin_ratios(0.9, 1e-3, "poisson", RATIO)
    schemas = ROOT / "workflows/config/schema"
    oracle = {"n_scenes": 2, "max_objects": 2, "max_returns": 2, "p_D": 0.8, "clutter_rate": 1.5, "alpha": 0.05,
              "p_survive": 0.9, "pixel_size": 200.0, "measurement_std": 1.0, "q": 0.1, "tolerance": 1e-9}
    good = {"belief_space": {"seed": 1, "ratio": RATIO, "eq43": EQ43, "equivalence": EQUIV, "oracle": oracle}}
    validate_config({k: dict(v) for k, v in good.items()}, schemas)
    with pytest.raises(ConfigError, match="belief_space.ratio.p_D"):
        validate_config({"belief_space": {**good["belief_space"], "ratio": {**RATIO, "p_D": [1.0]}}}, schemas)
    with pytest.raises(ConfigError, match="theory.notebooks"):
        validate_config({"theory": {"notebooks": ["no_such_notebook"], "timeout_s": 60}}, schemas)

"""Independent oracle for FISST = HOMHT and Eq. 39: the engine's one-scan posterior against the
seeds' densities evaluated by brute force (:mod:`hypotrack.experiments.belief_space.fisst_oracle`, which shares
no code with the weight models). Mutations of the engine's birth and clutter terms must make the
comparison fail."""

import ast
import inspect
import math

import numpy as np
import pytest
from scipy import integrate, stats

import hypotrack.experiments.belief_space.fisst_oracle as fo
from hypotrack.experiments.belief_space.oracle import (_oracle_scene, engine_children, oracle_table,
                                                       random_scene)
from hypotrack.hypotheses import FISSTPoissonWeights, ReidWeights
from hypotrack.hypotheses.population_events import BinomialPopulation

CFG = dict(n_scenes=8, max_objects=4, max_returns=4, p_D=0.8, clutter_rate=1.5, alpha=0.05, p_survive=0.9,
           pixel_size=200.0, measurement_std=1.0, q=0.1)
TOL = 1e-9


def _max_dlogp(a, b):
    assert a.keys() == b.keys()
    pa, pb = fo.normalise(a), fo.normalise(b)
    return max(abs(pa[k] - pb[k]) for k in pa)


@pytest.fixture(scope="module")
def table():
    return oracle_table(CFG, 20261122)


def test_oracle_imports_nothing_from_the_engine():
    tree = ast.parse(inspect.getsource(fo))
    modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    modules |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert modules <= {"__future__", "itertools", "math", "dataclasses", "numpy", "scipy", "scipy.special"}


def test_engine_fisst_posterior_equals_the_multi_object_density(table):
    """Births (one pixel) and deaths, M, m up to 4: the same children, posteriors and normaliser."""
    assert table["fisst_same_children"].all()
    assert table["fisst_max_abs_dlogp"].max() < TOL
    assert table["fisst_abs_dlog_normaliser"].max() < TOL
    big = table.iloc[0]
    assert (big["n_objects"], big["n_returns"]) == (4, 4)
    # A(4, 4) = 209 associations, plus a birth column, undetected-birth and death twins
    assert big["n_children"] > 209


def test_engine_reid_and_fisst_equal_reids_formula(table):
    assert table["reid_same_children"].all()
    assert table["reid_max_abs_dlogp"].max() < TOL
    assert table["oracle_fisst_vs_reid_max_abs_dlogp"].max() < TOL


def test_undetected_birth_ratio_follows_from_the_density(table):
    """Eq. 39: every undetected-birth twin weighs (1 − p_D) α times its association twin."""
    assert table["eq39_pairs"].sum() > 50
    assert table["eq39_oracle_rel_dev"].max() < TOL
    assert table["eq39_engine_vs_oracle_rel_dev"].max() < TOL


def test_oracle_birth_integral_is_exact_near_the_pixel_edge():
    """∫ N(z; x, R) U(x; pixel) dx by quadrature, for a return 1 s.d. inside the edge (where 1/V̄ is wrong)."""
    scene = {"means": np.zeros((0, 4)), "covs": np.zeros((0, 4, 4)), "Z": np.array([[1.0, 100.0]])}
    s = _oracle_scene(CFG, scene, births=True)
    L = CFG["pixel_size"]
    q = integrate.dblquad(lambda y, x: stats.norm.pdf(1.0 - x) * stats.norm.pdf(100.0 - y), 0, 12, 80, 120)[0]
    assert math.exp(fo._log_birth_likelihood(s)[0]) == pytest.approx(q / L**2, rel=1e-7)
    assert q == pytest.approx(stats.norm.cdf(1.0), rel=1e-6)  # 16 % below the engine's 1/V̄


def _scene():
    return random_scene(CFG, np.random.default_rng(5), (3, 4))


def test_mutated_birth_probability_fails(monkeypatch):
    scene = _scene()
    oracle = fo.fisst_children(_oracle_scene(CFG, scene, births=True))
    assert _max_dlogp(engine_children(CFG, scene, "fisst"), oracle) < TOL
    original = BinomialPopulation._log_birth
    monkeypatch.setattr(BinomialPopulation, "_log_birth", lambda self, b: original(self, b) + 0.1 * np.asarray(b))
    assert _max_dlogp(engine_children(CFG, scene, "fisst"), oracle) > 0.05


def test_mutated_birth_likelihood_fails(monkeypatch):
    import hypotrack.hypotheses.population_events as pe

    scene = _scene()
    oracle = fo.fisst_children(_oracle_scene(CFG, scene, births=True))
    original = pe._region_loglik
    monkeypatch.setattr(pe, "_region_loglik", lambda d, Z: original(d, Z) + math.log(1.2))
    assert _max_dlogp(engine_children(CFG, scene, "fisst"), oracle) > 0.05


def test_mutated_fisst_clutter_term_fails(monkeypatch):
    scene = _scene()
    oracle = fo.fisst_children(_oracle_scene(CFG, scene, births=True))
    original = FISSTPoissonWeights.count_term

    def mutated(self, ctx, n_objects, n_births):  # one factor k'! too many (Eq. 6 and 7 not cancelling)
        phi = original(self, ctx, n_objects, n_births)
        k = np.arange(n_objects + 1)[:, None] + np.arange(n_births + 1)[None, :]
        return phi + np.log(np.maximum(ctx.n_returns - k, 1))

    monkeypatch.setattr(FISSTPoissonWeights, "count_term", mutated)
    assert _max_dlogp(engine_children(CFG, scene, "fisst"), oracle) > 0.05


def test_mutated_reid_clutter_density_fails(monkeypatch):
    scene = _scene()
    beta_nt = CFG["alpha"] * CFG["p_D"] / CFG["pixel_size"] ** 2
    oracle = fo.reid_children(_oracle_scene(CFG, scene, births=False, new_target_density=beta_nt))
    assert _max_dlogp(engine_children(CFG, scene, "reid"), oracle) < TOL
    original = ReidWeights.option_scores
    monkeypatch.setattr(ReidWeights, "option_scores",
                        lambda self, ctx: original(self, ctx) + np.array([math.log(2.0), 0.0]))
    assert _max_dlogp(engine_children(CFG, scene, "reid"), oracle) > 0.05


def test_oracle_claims_follow_the_table(table):
    from hypotrack.experiments.belief_space.oracle import oracle_claims

    claims = oracle_claims(table, TOL)
    assert {c.evidence for c in claims} == {"independent oracle"}
    assert [c.status for c in claims] == ["reproduced"] * 3
    broken = table.assign(fisst_max_abs_dlogp=table["fisst_max_abs_dlogp"] + 1e-6)
    assert oracle_claims(broken, TOL)[0].status == "not reproduced"

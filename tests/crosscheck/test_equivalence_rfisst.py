"""(c) R-FISST against exhaustive H-FISST (document 000 Sec. III).

On seeded random small problems (M, m <= 5) the MCMC search must find every child whose
exhaustive posterior weight exceeds 1e-6, weigh what it found exactly (the exhaustive weights,
renormalised), and a filter run must stay within total-variation 1e-3 of exhaustive H-FISST
after capping. The paper's chain alone (no neighbour completion) is also measured: it finds the
heavy children but not all of those above 1e-6 in 10⁵ steps — see test_paper_chain_alone.
"""

import numpy as np
import pytest
from scipy.special import logsumexp

from hypotrack.hypotheses import ExhaustiveGenerator, MCMCGenerator, hfisst, rfisst
from hypotrack.hypotheses.problems import synthetic_problem
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.hypotheses.population_events import SingleEventPopulation
from hypotrack.models.sensors import Box
from hypotrack.scenarios.cluttered import simulate_cv_targets


def random_problems(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        M, m = int(rng.integers(0, 6)), int(rng.integers(0, 6))
        yield synthetic_problem(M, m, rng, weights="hfisst", spacing=float(rng.uniform(1.0, 6.0)))


@pytest.mark.parametrize("variant", ["paper", "symmetric", "gibbs"])
def test_c_search_finds_every_child_above_1e_6_and_weighs_it_exactly(variant):
    for q, sp in enumerate(random_problems(25, seed=10)):
        ev, lw = ExhaustiveGenerator().generate(sp.problem)
        post = np.exp(lw - logsumexp(lw))
        found, found_lw = MCMCGenerator(n_steps=100_000, variant=variant).generate(sp.problem, np.random.default_rng(q))
        exhaustive = {e.tobytes(): w for e, w in zip(ev, lw)}
        found_keys = [e.tobytes() for e in found]
        assert {e.tobytes() for e in ev[post > 1e-6]} <= set(found_keys)
        # weights on what was found = exhaustive weights renormalised over the found set
        ref = np.array([exhaustive[k] for k in found_keys])
        np.testing.assert_allclose(found_lw - logsumexp(found_lw), ref - logsumexp(ref), rtol=0, atol=1e-10)


def test_paper_chain_alone_finds_the_map_but_misses_light_children():
    """Measured, not tuned: the paper's Metropolis chain at 10⁵ steps reaches the MAP child of
    every problem, but on some problems misses children above 1e-6 (their expected number of
    visits is below one) — the reason the engine completes the chain's search."""
    missed_problems = 0
    for q, sp in enumerate(random_problems(25, seed=10)):
        ev, lw = ExhaustiveGenerator().generate(sp.problem)
        post = np.exp(lw - logsumexp(lw))
        gen = MCMCGenerator(n_steps=100_000, completion_rounds=0)
        found, _ = gen.generate(sp.problem, np.random.default_rng(q))
        keys = {e.tobytes() for e in found}
        assert ev[np.argmax(lw)].tobytes() in keys
        missed_problems += not {e.tobytes() for e in ev[post > 1e-6]} <= keys
    assert missed_problems > 0


def tv_by_lineage(fa, fb):
    pa = dict(zip(fa.lineage_keys, np.exp(fa.log_weights)))
    pb = dict(zip(fb.lineage_keys, np.exp(fb.log_weights)))
    return 0.5 * sum(abs(pa.get(k, 0.0) - pb.get(k, 0.0)) for k in set(pa) | set(pb))


def test_c_filter_total_variation_to_exhaustive_hfisst_after_capping():
    region = Box([-10.0, -10.0], [20.0, 20.0])
    X0 = np.array([[0.0, 0.0, 1.0, 0.4], [3.0, 1.0, 0.5, 0.8], [8.0, 6.0, -0.6, 0.1]])
    P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], 3, axis=0)
    scen = simulate_cv_targets(X0, n_scans=5, dt=1.0, q_truth=0.05, R=np.eye(2) * 0.6, p_D=0.9,
                               clutter_rate=1.5, region=region, rng=21)
    halves = [Box([-10.0, -10.0], [5.0, 20.0]), Box([5.0, -10.0], [20.0, 20.0])]
    pop = SingleEventPopulation(SingleEventBirthDeath(1e-3, 1e-3, 2),
                                birth_densities=[UniformBirthDensity(b, np.eye(2)) for b in halves])
    opts = dict(population=pop, dt=1.0, max_hypotheses=30, means=X0, covs=P0)
    fe = hfisst(scen.motion, scen.sensor, seed=0, **opts)
    fr = rfisst(scen.motion, scen.sensor, n_steps=100_000, seed=1, **opts)
    worst = 0.0
    for _, Z in scen.scan_list()[1:]:
        fe.step(Z)
        fr.step(Z)
        worst = max(worst, tv_by_lineage(fe, fr))
    assert worst < 1e-3
    # births and deaths were in play (undetected-birth and death children were weighed)
    assert fe.last_stats["n_twin_children"] > 0

"""The sampler head-to-head: one problem written two ways, and its measurements."""

import numpy as np

from hypotrack.experiments.samplers.run import object_indexed, run_problem, to_return_indexed
from hypotrack.hypotheses import ExhaustiveGenerator
from hypotrack.hypotheses.problems import synthetic_problem


def test_object_indexed_problem_has_the_same_children_and_weights():
    sp = synthetic_problem(4, difficulty="2sigma", seed=3, weights="reid")
    ev, lw = ExhaustiveGenerator().generate(sp.problem)
    g, lw_obj = ExhaustiveGenerator().generate(object_indexed(sp.problem))
    back = to_return_indexed(g, sp.problem.n_returns)
    a = {e.tobytes(): w for e, w in zip(ev.astype(np.int32), lw)}
    b = {e.tobytes(): w for e, w in zip(back, lw_obj)}
    assert a.keys() == b.keys() and len(a) > 50
    for k in a:
        assert abs(a[k] - b[k]) < 1e-10


def test_run_problem_masses_are_fractions_and_murty_finds_the_map():
    sp = synthetic_problem(4, difficulty="1sigma", seed=5, weights="reid")
    rows = run_problem(sp, [40], np.random.default_rng(0))
    assert {r["sampler"] for r in rows} == {"rfisst_chain", "rfisst_completion", "gibbs", "murty"}
    for r in rows:
        assert 0.0 < r["mass_captured"] <= 1.0 + 1e-12
        assert r["n_distinct"] <= r["n_children_total"]
    murty = next(r for r in rows if r["sampler"] == "murty")
    assert murty["map_found"] and murty["n_distinct"] == 10  # ceil(40 / 4) ranked events


def test_sampler_tables_macros_and_claims_from_a_small_sweep(tmp_path):
    from hypotrack.experiments.samplers.run import samplers_sweep, summarise
    from hypotrack.experiments.samplers.summary import sampler_claims, sampler_macros
    from hypotrack.reporting.ledger import write_claims, write_macros

    raw = samplers_sweep({"difficulties": ["1sigma", "8sigma"], "n_problems": 2, "n_objects": 3, "budgets": [6, 30]},
                         np.random.SeedSequence(0))
    det, timing = summarise(raw)
    values, times = sampler_macros(det, timing)
    write_macros("samplers", values, tmp_path / "m.csv")  # names must be valid macro keys
    write_macros("samplers", times, tmp_path / "t.csv")
    assert values["At1SigmaMurtyMap"] == "100"  # Murty's first event is the best assignment: the MAP
    claims = write_claims(sampler_claims(det, timing), tmp_path / "c.csv")
    assert list(claims.key) == ["Mass1Sigma", "Mass8Sigma"]
    assert {r.split(":")[0] for r in claims.reproduced} <= {"rfisst_chain", "rfisst_completion", "gibbs", "murty"}
    assert values["MostMass1Sigma"] in {"R-FISST chain (paper proposal)", "R-FISST + completion",
                                        "GLMB Gibbs (systematic scan)", "Murty k-best"}

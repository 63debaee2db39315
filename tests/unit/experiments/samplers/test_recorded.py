"""Association problems recorded from the GLMB benchmark: counted, saved and scored exactly."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.experiments.samplers.run import summarise, timed_run
from hypotrack.experiments.glmb_benchmark.recorded import load_problems, n_children, record_problems, save_problems
from hypotrack.experiments.samplers.recorded import run_recorded_problem
from hypotrack.experiments.samplers.summary import compute_claims, sampler_claims, time_to_mass
from hypotrack.hypotheses import ExhaustiveGenerator

CFG = dict(sigma_r=10.0, half_width=1000.0, p_D=0.98, clutter_rate=30.0, sigma_v=5.0, p_S=0.99, r_birth=0.03,
           birth_means=[[0.1, 0.1, 0, 0], [400, -600, 0, 0]], birth_std=10.0, n_scans=4,
           truth=[[1, 101, 0.0, 0.0, 5.0, 0.0], [1, 101, 400.0, -600.0, 0.0, 5.0], [2, 101, 2.0, 2.0, 0.0, 1.0]])
GLMB = {"max_hypotheses": 5, "n_sweeps": 20, "gate_probability": 0.9999999}


@pytest.fixture(scope="module")
def recorded():
    return record_problems(CFG, GLMB, np.random.SeedSequence(3), 2)


def test_recorded_problems_are_the_engines_labeled_problems_counted_exactly(recorded):
    problems, table = recorded
    assert len(problems) == 2 and list(table.scan) == sorted(table.scan)
    for p, row in zip(problems, table.itertuples()):
        # one row per track and birth term, the two row options "missed" and "died / not born"
        assert p.n_options == 2 and p.n_returns == row.n_rows and p.n_exclusive == row.n_returns
        ev, _ = ExhaustiveGenerator().generate(p)
        assert n_children(p) == len(ev) == row.n_children  # brute force: every child enumerated


def test_save_load_round_trip_keeps_every_array(recorded, tmp_path):
    problems, _ = recorded
    save_problems(problems, tmp_path / "p.npz")
    back = load_problems(tmp_path / "p.npz")
    for a, b in zip(problems, back):
        np.testing.assert_array_equal(a.target_scores, b.target_scores)
        np.testing.assert_array_equal(a.option_scores, b.option_scores)
        np.testing.assert_array_equal(a.count_term, b.count_term)
        assert (a.n_objects, a.constant) == (b.n_objects, b.constant)


def test_mass_is_exact_when_enumerable_and_an_upper_bound_beyond(recorded):
    problem = recorded[0][-1]
    exact = pd.DataFrame(run_recorded_problem(problem, [20, 200], np.random.default_rng(0), max_events=10**7,
                                              reference_k=50, timed_run=timed_run))
    beyond = pd.DataFrame(run_recorded_problem(problem, [20, 200], np.random.default_rng(0), max_events=1,
                                               reference_k=50, timed_run=timed_run))
    assert exact.mass_exact.all() and not beyond.mass_exact.any()
    ev, lw = ExhaustiveGenerator().generate(problem)
    assert (exact.n_children_total == len(lw)).all()
    # Murty at 200 proposals: its ceil(200 / rows) best children, exactly their share of the total
    k = -(-200 // problem.n_returns)
    top = np.sort(lw)[::-1][:k]
    murty = exact[(exact.sampler == "murty") & (exact.budget == 200)].iloc[0]
    assert murty.mass_captured == pytest.approx(np.exp(np.logaddexp.reduce(top) - np.logaddexp.reduce(lw)))
    assert murty.map_found
    # same seeds, same children: the reference is a subset of all children, so fractions only grow
    assert (beyond.mass_captured.to_numpy() >= exact.mass_captured.to_numpy() - 1e-12).all()


def test_recorded_difficulty_in_claims_and_time_to_mass():
    raw = pd.DataFrame({"difficulty": "recorded", "problem": [0, 0, 1, 1] * 2,
                        "sampler": ["gibbs", "murty"] * 4, "budget": [10] * 4 + [100] * 4,
                        "mass_captured": [0.5, 0.95, 0.7, 0.97, 0.99, 0.999, 0.995, 0.999],
                        "map_found": True, "n_distinct": 3, "time_s": [1.0, 2.0, 1.0, 2.0, 3.0, 9.0, 3.0, 9.0],
                        "mass_exact": False})
    det, timing = summarise(raw)
    ttm = time_to_mass(det, timing).set_index("sampler")
    assert ttm.loc["murty", "time_to_mass_s"] == 9.0  # mean mass 0.96 at 10: not yet; 0.999 at 100: 9 s
    assert ttm.loc["gibbs", "time_to_mass_s"] == 3.0 and ttm.loc["gibbs", "budget"] == 100  # mean 0.9925
    claims, macros = compute_claims(det, timing)
    (c,) = claims
    assert c.reproduced == "gibbs: 3e+03 ms per problem" and macros["FastestRecorded"].startswith("GLMB Gibbs")
    assert macros["TimeToMassRecordedGibbsMs"] == "3e+03"
    (m,) = sampler_claims(det, timing)
    assert m.key == "MassRecorded" and m.evidence == "measurement"
    assert m.reproduced == "murty: 0.999 +/- 0 of the mass (2 problems)"

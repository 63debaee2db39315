"""The difficulty sweep of Fig. 15: exact reference, per-method outcomes, reach and claims."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.association import count_associations
from hypotrack.experiments.generation_time.difficulty import (
    OUTCOME_COLUMNS,
    difficulty_claims,
    difficulty_point,
    difficulty_problem,
    difficulty_summary,
    exact_reference,
    exact_top_k_claims,
    reach,
)
from hypotrack.hypotheses.generators import ExhaustiveGenerator, top_k
from hypotrack.hypotheses.problems import truth_rank

PARAMS = {"mcmc_steps": 20_000, "mcmc_burn_in": 2000, "mcmc_variant": "paper", "mcmc_init": "random",
          "completion_rounds": 2, "completion_max_moves": 10**6, "keep": 20, "reference_k": 50,
          "exhaustive_max_events": 10**5, "repeats": 1, "n_problems": 1}


@pytest.mark.parametrize("difficulty, M, seed", [("1sigma", 5, 0), ("2sigma", 6, 3), ("paper", 4, 1)])
def test_exact_reference_is_enumeration(difficulty, M, seed):
    sp = difficulty_problem(difficulty, M, seed)
    p = sp.problem
    ev, lw = ExhaustiveGenerator().generate(p)
    ref = exact_reference(p, sp.truth, max_events=10**6, reference_k=10)
    assert ref["reference"] == "all children"
    assert ref["map_lw"] == pytest.approx(lw.max(), abs=1e-9)
    assert np.array_equal(ref["map_event"], ev[np.argmax(lw)])
    assert ref["log_mass"] == pytest.approx(np.logaddexp.reduce(lw), abs=1e-9)
    assert ref["truth_rank_exact"] == truth_rank(ev, lw, sp.truth)
    small = exact_reference(p, sp.truth, max_events=1, reference_k=10)  # beyond the cap: exact best 10
    assert small["reference"] == "top 10"
    assert small["log_mass"] == pytest.approx(np.logaddexp.reduce(lw[top_k(lw, 10)]), abs=1e-9)


def test_point_outcomes_against_enumeration():
    """Mass captured of the exact best 20 = their share of the total, MAP found by all on an easy problem."""
    rows, timing = difficulty_point("4sigma", 5, 0, PARAMS, seed=7)
    assert [r["method"] for r in rows] == ["chain", "chain_completion", "murty"] == [t["method"] for t in timing]
    sp = difficulty_problem("4sigma", 5, int(np.random.SeedSequence(7).spawn(2)[0].generate_state(1)[0]))
    assert rows[0]["n_returns"] == sp.problem.n_returns
    ev, lw = ExhaustiveGenerator().generate(sp.problem)
    assert len(lw) == count_associations(5, sp.problem.n_returns)
    share = np.exp(np.logaddexp.reduce(lw[top_k(lw, 20)]) - np.logaddexp.reduce(lw))
    murty = rows[2]
    assert murty["run"] == "ok" and murty["n_generated"] == 20 and murty["mass_captured"] == pytest.approx(share)
    assert murty["map_found"] and murty["map_gap_nats"] == 0.0
    for r in rows:
        assert r["reference"] == "all children" and 0 <= r["mass_captured"] <= 1
    assert rows[1]["mass_captured"] >= rows[0]["mass_captured"]  # completion only adds to the chain's children


def test_completion_over_budget_is_recorded():
    rows, _ = difficulty_point("1sigma", 8, 0, dict(PARAMS, completion_max_moves=10), seed=3)
    comp = rows[1]
    assert comp["run"] == "over_budget" and comp["n_generated"] == 0 and np.isnan(comp["mass_captured"])


def test_point_is_deterministic():
    a, _ = difficulty_point("2sigma", 6, 0, PARAMS, seed=11)
    b, _ = difficulty_point("2sigma", 6, 0, PARAMS, seed=11)
    assert pd.DataFrame(a).equals(pd.DataFrame(b))


def _table(rows):
    base = {c: 0 for c in OUTCOME_COLUMNS}
    return pd.DataFrame([dict(base, **r) for r in rows])


def test_reach_and_claims_hand_made():
    t = _table([
        {"difficulty": "4sigma", "method": "chain", "run": "ok", "log10_hypotheses": 2.0, "n_objects": 2,
         "truth_found": True, "map_found": True, "n_returns": 2},
        {"difficulty": "4sigma", "method": "chain", "run": "ok", "log10_hypotheses": 40.0, "n_objects": 30,
         "truth_found": True, "map_found": False, "n_returns": 31},
        {"difficulty": "4sigma", "method": "chain", "run": "ok", "log10_hypotheses": 60.0, "n_objects": 40,
         "truth_found": False, "map_found": True, "n_returns": 41},
        {"difficulty": "4sigma", "method": "chain_completion", "run": "ok", "log10_hypotheses": 2.0, "n_objects": 2,
         "truth_found": True, "map_found": True, "n_returns": 2},
        {"difficulty": "4sigma", "method": "chain_completion", "run": "over_budget", "log10_hypotheses": 40.0,
         "n_objects": 30, "n_returns": 31},
    ])
    assert reach(t, "4sigma", "chain", "truth_found")[0] == 40.0
    value, fail = reach(t, "4sigma", "chain", "map_found")
    assert value == 2.0 and int(fail["n_objects"]) == 30
    assert reach(t, "4sigma", "chain_completion", "map_found") == (2.0, None)
    claims, macros = difficulty_claims(t, dict(PARAMS, n_problems=1))
    chain = next(c for c in claims if c.key == "diffChainReachFourSigma")
    # a stress problem of this project (000 gives no geometry): the paper's claim tested beyond it, an extension
    assert chain.reproduced == "1e40" and chain.status == "extension" and "1e2" in chain.note
    assert chain.note.startswith("000's claim tested beyond its problem: holds up to 1e40")
    assert macros["chainMapReachFourSigma"] == "1e2" and macros["completionRunFourSigma"] == "1 of 2"
    bench = [{"difficulty": "4sigma", "k": 100, "n_objects": 100, "cpu_seconds": 0.4, "seconds": 0.9},
             {"difficulty": "1sigma", "k": 100, "n_objects": 100, "cpu_seconds": 0.7, "seconds": 0.8}]
    (timed,), tmacros = exact_top_k_claims(bench)
    assert timed.reproduced == "0.7 s" and tmacros["sweepExactTopKSeconds"] == "0.7" and "0.9 s" in timed.note
    summary = difficulty_summary(t)
    comp = summary[summary["method"] == "chain_completion"].set_index("n_objects")
    assert comp.loc[2, "problems_run"] == 1 and comp.loc[2, "map_found_rate"] == 1.0
    assert comp.loc[30, "problems"] == 1 and comp.loc[30, "problems_run"] == 0  # over budget: no rate
    assert np.isnan(comp.loc[30, "map_found_rate"])

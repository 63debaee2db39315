"""Synthetic Fig. 15 problems, truth ranking and the generation-time driver."""

import numpy as np
import pytest

from hypotrack.association import count_associations
from hypotrack.hypotheses import ExhaustiveGenerator
from hypotrack.experiments.generation_time import generation_time_point
from hypotrack.hypotheses.problems import synthetic_problem, truth_rank

PARAMS = dict(exhaustive_max_events=10**4, exhaustive_chunk_size=1 << 10, mcmc_steps=20_000, mcmc_burn_in=2000,
              mcmc_variant="paper", mcmc_init="random", mcmc_completion_rounds=0, keep=20, repeats=1, p_D=0.95,
              clutter_rate=1.0, spacing=8.0)


@pytest.mark.parametrize("M, m", [(0, 3), (3, 0), (4, 4), (6, 3), (2, 5)])
def test_synthetic_problem_truth(M, m):
    sp = synthetic_problem(M, m, np.random.default_rng(M * 10 + m), weights="hfisst")
    assert sp.truth.shape == (m,) and sp.problem.n_returns == m and sp.problem.n_objects == M
    assert np.sum(sp.truth >= 0) == min(M, m)  # min(M, m) detections, the rest clutter
    ev, lw = ExhaustiveGenerator().generate(sp.problem)
    assert len(ev) == count_associations(M, m)
    assert truth_rank(ev, lw, sp.truth) is not None
    if m <= M:  # well separated objects and no clutter: the true association is the heaviest child
        assert truth_rank(ev, lw, sp.truth) == 1
        assert np.all(ev[np.argmax(lw)] == sp.truth)


def test_truth_rank():
    events = np.array([[0, 1], [1, 0], [-1, -1]])
    lw = np.array([-1.0, -0.5, -1.0])
    assert truth_rank(events, lw, [1, 0]) == 1
    assert truth_rank(events, lw, [0, 1]) == 2
    assert truth_rank(events, lw, [-1, -1]) == 3  # tie with an earlier child counts against it
    assert truth_rank(events, lw, [0, -1]) is None


def test_generation_time_point_rows():
    ok = generation_time_point("homht", 4, 4, PARAMS, seed=1)
    assert not ok["broken"] and ok["truth_found"] and ok["truth_rank"] == 1 and ok["n_generated"] == 20
    broken = generation_time_point("homht", 7, 7, PARAMS, seed=1)  # A(7,7) = 130922 > 1e4
    assert broken["broken"] and np.isnan(broken["seconds"]) and not broken["truth_found"]
    mc = generation_time_point("rfisst", 12, 12, PARAMS, seed=1)
    assert mc["map_is_truth"] and mc["log10_hypotheses"] == pytest.approx(np.log10(count_associations(12, 12)))
    kb = generation_time_point("homht_kbest", 12, 12, PARAMS, seed=1)
    assert kb["map_is_truth"] and kb["n_generated"] == 20

"""(d) Murty's k best children equal the top k of exhaustive enumeration.

For HOMHT (Reid's weights: a pure row sum) Murty ranks children exactly; for H-FISST the
count term −log(C(m,k) k!) is not a row sum and the generator grows its k-best list until the
top k are proven (a bound on every unseen child) — both must agree with brute force.
"""

import numpy as np
import pytest

from hypotrack.hypotheses import ExhaustiveGenerator, MurtyGenerator, ReidWeights
from hypotrack.hypotheses.problems import synthetic_problem
from hypotrack.hypotheses.generators import top_k
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box


def check_top_k(problem, k):
    ev, lw = ExhaustiveGenerator().generate(problem)
    order = top_k(lw, k)
    mev, mlw = MurtyGenerator(k=k).generate(problem)
    assert len(mlw) == min(k, len(lw))
    np.testing.assert_allclose(mlw, lw[order], rtol=0, atol=1e-9)
    assert np.all(np.diff(mlw) <= 1e-12)  # best first
    ranked = np.sort(lw)[::-1]
    if len(lw) <= k or ranked[k - 1] - ranked[k] > 1e-9:  # no tie at the boundary: same events
        assert {e.tobytes() for e in mev} == {e.tobytes() for e in ev[order]}


@pytest.mark.parametrize("weights", ["reid", "hfisst", "fisst_poisson"])
def test_d_murty_equals_exhaustive_top_k(weights):
    rng = np.random.default_rng(30)
    for _ in range(12):
        M, m = int(rng.integers(0, 6)), int(rng.integers(1, 6))
        sp = synthetic_problem(M, m, rng, weights=weights, spacing=float(rng.uniform(1.0, 5.0)))
        for k in (1, 5, 20):
            check_top_k(sp.problem, k)


def test_d_murty_with_seeded_births():
    """HOMHT with births seeded at returns (a second row option besides clutter)."""
    rng = np.random.default_rng(31)
    for _ in range(6):
        M, m = int(rng.integers(0, 4)), int(rng.integers(1, 5))
        sp = synthetic_problem(M, m, rng, weights="reid", spacing=2.0)
        density = UniformBirthDensity(Box([-1e3, -1e3], [1e3, 1e3]), np.eye(2))
        problem = ReidWeights(birth_intensity=sp.context.clutter_intensity * 0.5,
                              birth_density=density).problem(sp.context, np.arange(M))
        assert problem.n_options == 2
        check_top_k(problem, 10)

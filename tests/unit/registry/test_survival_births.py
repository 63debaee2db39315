"""The problem's per-track survival (``MeasurementBirths.survival``) reaches every preset: HOMHT with births seeded at
the returns gets a binomial population holding only the deaths, R-FISST its binomial population with the survival;
a problem without survival builds what it built before (HOMHT no population, R-FISST ``p_S = 1``)."""

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, UnconfirmedDecay
from hypotrack.hypotheses.factored import AdaptiveBirth
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from hypotrack.registry import MeasurementBirths, TrackingProblem, build
from scenes import position_sensor

VIEW = Box([-100.0, -100.0], [100.0, 100.0])
MOTION = ConstantVelocity(q=0.01)
DECAY = UnconfirmedDecay(p_tentative=0.6, velocity_std=1.0, p_confirmed=0.9, velocity_components=(2, 3))
FACTORED = {"lazy": True, "replay": True, "min_weight": 1e-3, "gate_out_of_view": False, "bernoulli_lane": True}
SPECS = {"homht_kbest": {"kind": "homht_kbest", "population": True, "max_hypotheses": 20, "factored": FACTORED},
         "rfisst": {"kind": "rfisst", "n_steps": 100, "max_hypotheses": 20, "factored": FACTORED}}
# a confirmed track in view with no return (p_D 0.8, p_S 0.9) and one out of view
X0 = np.array([[0.0, 0.0, 0.0, 0.0], [500.0, 0.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([0.5, 0.5, 0.01, 0.01])[None], 2, axis=0)


def _problem(survival):
    births = MeasurementBirths(AdaptiveBirth(velocity_std=2.0, r_birth=0.05, gate_probability=0.999), r_birth=0.05,
                               seeded_intensity=0.5 / VIEW.area, seeded_density=UniformBirthDensity(VIEW, np.eye(2) * 4.0),
                               survival=survival)
    return TrackingProblem(MOTION, position_sensor(R=0.25, p_D=0.8, view=VIEW, clutter_rate=1.0), X0, P0, dt=1.0,
                           births=births)


def test_without_survival_the_presets_build_what_they_built():
    problem = _problem(None)
    assert "population" not in problem.reid_births()
    homht, rf = (build(SPECS[k], problem, seed=0) for k in ("homht_kbest", "rfisst"))
    assert homht.engine.population is None and homht.engine.weights.seeded_births
    pop = rf.engine.population
    assert type(pop) is BinomialPopulation and pop.p_survive == 1.0 and pop.survival is None and pop.alpha == 0.05
    assert not homht._bern and not rf._bern  # silent populations: the lane's plain singletons


@pytest.mark.parametrize("kind", sorted(SPECS))
def test_survival_reaches_homht_and_rfisst(kind):
    """Two empty scans: the confirmed track in view (p_S 0.9, p_D 0.8) is missed, r' = r p_S (1 − p_D) / (1 − r p_S
    p_D): 0.18 / 0.28 = 0.64285714, then 0.11571429 / 0.53714286 = 0.21542553; the one out of view 0.9, 0.81."""
    f = build(SPECS[kind], _problem(DECAY), seed=0)
    pop = f.engine.population
    assert type(pop) is BinomialPopulation and pop.survival is DECAY and pop.n_birth_regions == 0
    assert f._bern  # its lone tracks are the lane's Bernoulli singletons
    if kind == "homht_kbest":  # the seeded births are HOMHT's only births: no adaptive terms, α unused
        assert f.engine.weights.seeded_births and f.options.adaptive_birth is None and pop.alpha == 0.0
    else:
        assert f.options.adaptive_birth is not None and pop.alpha == 0.05
    for k, (near, far) in enumerate([(0.64285714, 0.9), (0.21542553, 0.81)], start=1):
        f.step(np.zeros((0, 2)), float(k))
        lane = f.state().lane
        r = dict(zip(lane.store.labels.tolist(), lane.r.tolist()))
        assert r[0] == pytest.approx(near, abs=1e-8) and r[1] == pytest.approx(far, rel=1e-12)

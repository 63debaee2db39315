"""HOMHT k-best on the catalogue (the default section as it is: admissible births, plausibility, the decaying
survival, the fast path) with the one-return k best (:mod:`...hypotheses.one_return`) and the quiet groups' scalar
closed form (:mod:`...factored.sleeping`, on Python floats) against the same tracker taking Murty's solver for every problem and
its array form (``tests/sleeping_arrays.py``): bit for bit the same posterior at every scan (groups, weights,
moments, labels, track lists, lineage keys), with both replacements exercised many times."""

import pytest
from scenes import catalogue_scene, default_catalogue_config
from sleeping_arrays import sleeping_step as array_step

import hypotrack.hypotheses.factored.planner as planner
import hypotrack.hypotheses.generators as generators
import hypotrack.hypotheses.one_return_children as one_return_children
from hypotrack.experiments.ssa_catalogue.run import make_tracker

N_SCANS = 40


@pytest.fixture(scope="module")
def catalogue():
    cfg = default_catalogue_config(N_SCANS)
    scene = catalogue_scene(cfg, 300)
    return cfg, scene.problem(), scene.sensor, scene.scans


def test_the_posterior_is_the_solver_s_bit_for_bit(catalogue, monkeypatch):
    cfg, problem, tsensor, scans = catalogue
    new, ref = (make_tracker("homht_kbest", cfg, problem, 1, fast_path=True) for _ in range(2))
    used = {"one_return": 0, "scalar": 0}
    one, scalar = generators.one_return_k_best, planner.sleeping_step

    def counted_one(p, k):
        out = one(p, k)
        used["one_return"] += out is not None
        return out

    def counted_scalar(*a):
        out = scalar(*a)
        used["scalar"] += out is not None
        return out

    for t, Z, theta in scans:
        tsensor.at(theta)
        with monkeypatch.context() as m:  # the reference: Murty's solver and the array closed form
            m.setattr(generators, "one_return_k_best", lambda p, k: None)
            m.setattr(one_return_children, "one_return_k_best", lambda p, k: None)  # (its direct call for Reid's)
            m.setattr(planner, "sleeping_step", array_step)
            ref.step(Z, t)
        with monkeypatch.context() as m:
            m.setattr(generators, "one_return_k_best", counted_one)
            m.setattr(one_return_children, "one_return_k_best", counted_one)
            m.setattr(planner, "sleeping_step", counted_scalar)
            new.step(Z, t)
        assert new.same_posterior(ref)
        ga, gb = new.groups, ref.groups
        assert len(ga) == len(gb) and all(a.keys == b.keys for a, b in zip(ga, gb))
        assert all(a.log_w.tobytes() == b.log_w.tobytes() for a, b in zip(ga, gb))
    # the run holds what the check is for (74 one-return problems and 458 quiet-group steps when written)
    assert used["one_return"] > N_SCANS and used["scalar"] > 5 * N_SCANS
    assert new.next_label > len(problem.labels)  # births took labels

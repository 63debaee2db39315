"""The factored trackers' replay through the compiled J2 kernel (:meth:`~hypotrack.models.orbit3d.J2Orbit3D.replay_each`)
against the array passes it replaces, on catalogue scans at a steady-state start: the scans begin an orbit (5,700 s)
after the priors' epoch (:mod:`hypotrack.experiments.ssa_catalogue.scale`, ``start_after_s``), so each object first
seen is predicted over ≥ 570 scan-long EKF steps before its first return. δ-GLMB and R-FISST with the fast path,
stepped both ways: every component's weights to 1e-12, its means and covariances to 1e-12 of their scale, the
labels and the lane's existences equal, at every scan — and the whole posterior bit for bit where numpy and its BLAS
round as the kernel does (``rounds_as_numpy``: this machine)."""

from dataclasses import dataclass, fields

import numpy as np
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.run import initial_tracks, make_motion, make_problem, make_tracker, tracker_sensor
from hypotrack.experiments.ssa_catalogue.scale import clone_scenario
from hypotrack.models.orbit3d import J2Orbit3D
from hypotrack.models.orbit3d_replay import rounds_as_numpy

AFTER, N_SCANS = 5700.0, 12


@dataclass(frozen=True)
class ArrayPasses(J2Orbit3D):
    """The same model without the compiled replay: the lane's replay takes its array passes, one batch a step."""

    replay_each = None


def array_passes(model):
    return ArrayPasses(**{f.name: getattr(model, f.name) for f in fields(model)})


@pytest.fixture(scope="module")
def steady():
    with open("workflows/config/default.yaml") as fh:
        cfg = yaml.safe_load(fh)["ssa_catalogue"]
    objects, unknown, sc, init_seed = clone_scenario(cfg, 1500, 3, n_scans=N_SCANS, chunk=500, start_after_s=AFTER)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed, at=-AFTER)
    scans = []
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        scans.append((float(t_k) + AFTER, tsensor.returns(Z)))
    return cfg, tsensor, means, covs, labels, scans


def _close(a, b, rel=1e-12):
    scale = max(np.abs(b).max(initial=0.0), 1e-300)
    assert np.abs(a - b).max(initial=0.0) <= rel * scale


@pytest.mark.parametrize("name", ["glmb", "rfisst"])
def test_every_component_agrees_with_the_array_passes(steady, name):
    cfg, tsensor, means, covs, labels, scans = steady
    motion = make_motion(cfg)
    assert motion.replay_each is not None and cfg["trackers"][name]["factored"]["replay"]
    compiled, arrays = (make_tracker(name, cfg, make_problem(cfg, tsensor, m, means, covs, labels), 1, fast_path=True)
                        for m in (motion, array_passes(motion)))
    n_woken, bitwise = 0, rounds_as_numpy()
    for t, Z in scans:
        n_woken += int(np.sum(compiled._lane.times == 0.0))  # asleep since the epoch before this scan
        compiled.step(Z, t)
        arrays.step(Z, t)
        n_woken -= int(np.sum(compiled._lane.times == 0.0))
        ga, gb = compiled.groups, arrays.groups
        assert len(ga) == len(gb) and compiled.next_label == arrays.next_label
        for s, u in zip(ga, gb):
            # the weights (not their logs: a log-likelihood of a track replayed over 570 steps moves by a few 1e-12
            # with its covariance's rounding, measured 4.5e-12 on R-FISST's, its weight by 4e-14)
            np.testing.assert_allclose(np.exp(s.log_w), np.exp(u.log_w), rtol=0, atol=1e-12)
            np.testing.assert_array_equal(s.store.labels, u.store.labels)
            for x, y in zip(s.store.means, u.store.means):
                _close(x, y)
            for x, y in zip(s.store.covs, u.store.covs):
                _close(x, y)
            assert all(np.array_equal(x, y) for x, y in zip(s.tracks, u.tracks))
        np.testing.assert_allclose(compiled._lane.r, arrays._lane.r, rtol=0, atol=1e-12)
        if bitwise:
            assert compiled.same_posterior(arrays) and compiled._lane.same_as(arrays._lane)
    # the run holds what the check is for: priors woken after the whole gap (570 steps each) and stepped
    assert n_woken > 20 and compiled.last_stats["n_predicted"] > 0

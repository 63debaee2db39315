"""The experiments' shared timing module: clocks, best of repeats, and steppers timed side by side."""

from __future__ import annotations

import time

import numpy as np
import pytest
import yaml
from pathlib import Path

from hypotrack.experiments.perf_sht.run import HypotrackStepper, formation, prior_covariance, scan_model
from hypotrack.experiments.ssa_catalogue.run import CatalogueSHTStepper, PeerScenario
from hypotrack.experiments.stepping import (BenchmarkRun, Clocks, SHTStepper, best_time, max_abs_difference,
                                            run_side_by_side)
from hypotrack.models.motion import ConstantVelocity

ROOT = Path(__file__).resolve().parents[3]


def test_clocks_tell_wall_time_from_cpu_time():
    with Clocks() as idle:
        time.sleep(0.05)
    assert idle.wall >= 0.05 and idle.cpu < 0.04  # asleep: wall time passes, this process's CPU time hardly
    with Clocks() as busy:
        x = 0
        for i in range(200_000):
            x += i
    assert busy.cpu > 0 and busy.wall > 0
    assert np.isnan(Clocks().wall) and np.isnan(Clocks().cpu)  # never entered: no time


def test_best_time_keeps_the_fastest_run_and_the_last_result():
    delays = iter([0.03, 0.001, 0.02])
    calls = []

    def fn():
        d = next(delays)
        calls.append(d)
        time.sleep(d)
        return len(calls)

    result, best = best_time(fn, 3)
    assert result == 3 and calls == [0.03, 0.001, 0.02]
    assert 0.001 <= best < 0.02
    assert best_time(lambda: "once", 0)[0] == "once"  # at least one run
    with pytest.raises(ZeroDivisionError):
        best_time(lambda: 1 / 0, 3)
    _, cpu_best = best_time(lambda: time.sleep(0.03), 2, cpu=True)
    assert cpu_best < 0.02  # CPU time of this process: sleeping costs next to none


class _Fake:
    """Steps cost nothing; records which scans it saw and in which order the steppers went."""

    def __init__(self, name, order):
        self.name, self.order, self.seen = name, order, []

    def step(self, k):
        self.order.append((k, self.name))
        self.seen.append(k)

    def record(self, run):
        run.outputs.append(np.array([self.seen[-1]]))
        run.states.append((np.zeros((1, 2)), np.zeros((1, 2, 2))))


def test_run_side_by_side_alternates_skips_the_warm_up_and_stops_each_implementation():
    order = []
    steppers = {"a": _Fake("a", order), "b": _Fake("b", order)}
    runs = run_side_by_side(steppers, 6, max_scans=3)
    assert order[:4] == [(1, "a"), (1, "b"), (2, "b"), (2, "a")]  # even scans reversed: each goes first in turn
    assert [int(o[0]) for o in runs["a"].outputs] == [2, 3, 4]  # scan 0 is the start, scan 1 the untimed warm-up
    assert len(runs["a"].times) == 3 and runs["a"].done and steppers["a"].seen == [1, 2, 3, 4]
    runs = run_side_by_side({"a": _Fake("a", [])}, 6, warmup=False, budget_s=-1.0)
    assert len(runs["a"].times) == 1  # over its budget after the first timed scan


def test_max_abs_difference_over_the_scans_both_timed():
    a, b = BenchmarkRun(), BenchmarkRun()
    assert all(np.isnan(max_abs_difference(a, b)))
    x, P = np.zeros((2, 4)), np.repeat(np.eye(4)[None], 2, 0)
    a.outputs, b.outputs = [np.array([0, 1]), np.array([1, 0])], [np.array([0, 1])]
    a.states, b.states = [(x, P), (x, P)], [(x + 0.5, P * 2)]
    assert max_abs_difference(a, b) == (0.0, 1.0)  # only the first scan compared; state: max(0.5, |2 - 1|)
    assert np.isnan(BenchmarkRun().median_ms)


def test_sht_stepper_rejects_an_unknown_algorithm():
    with pytest.raises(ValueError, match="algorithm must be 'gnn' or 'jpda'"):
        SHTStepper(ConstantVelocity(1.0), None, "pdaf", np.zeros((0, 4)), np.zeros((0, 4, 4)), 0.0, [])


@pytest.mark.parametrize("algorithm", ["gnn", "jpda"])
def test_both_experiments_steppers_are_the_one_sht_stepper(algorithm):
    """perf_sht's HypotrackStepper and ssa_catalogue's CatalogueSHTStepper built on the same scans, motion,
    scan model and prior step identically (they are SHTStepper with their experiment's inputs)."""
    cfg_all = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())["perf_sht"]
    cfg = {**cfg_all["scenario"], **cfg_all["tracker"], "n_scans": 8}
    sc = formation(6, 10.0, cfg, 3)
    n = len(sc.initial_states)
    times, returns = zip(*sc.scan_list())
    peer = PeerScenario(np.asarray(sc.initial_states), np.broadcast_to(prior_covariance(cfg), (n, 4, 4)).copy(),
                        np.array(times), list(returns), scan_model(sc, cfg), ConstantVelocity(cfg["q"]))
    runs = run_side_by_side({"perf_sht": HypotrackStepper(sc, algorithm, cfg),
                             "ssa_catalogue": CatalogueSHTStepper(peer, algorithm)}, len(sc.times))
    a, b = runs["perf_sht"], runs["ssa_catalogue"]
    assert len(a.outputs) == len(b.outputs) == 6
    assert max_abs_difference(a, b) == (0.0, 0.0)
    assert a.max_cluster >= 1 and b.max_cluster == 0  # only perf_sht records its clusters

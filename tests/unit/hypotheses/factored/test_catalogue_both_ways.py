"""Two ways of holding the same numbers, as the trackers use them: the default configuration's δ-GLMB (documented
radar, second-order EKF in ``(ρ, az, el, ρ̇)``, admissible-region births, decaying existence in the Bernoulli lane,
the fast path) on the real catalogue (N = 2,000) stepped both ways holds the same posterior bit for bit at every scan
(weights, labels, moments, the lane's rows and existences), through births, multi-hypothesis groups, deaths and
objects out of view:

* the scan's scores in the sensor frame as gated pairs (:func:`~hypotrack.hypotheses.factored.scores.sensor_frame_pairs`,
  taken from :data:`~hypotrack.hypotheses.factored.scores.DENSE_PAIRS` pairs on: at 10⁵–10⁶ objects) or as the
  engine's dense matrices at every scan;
* the lane's moments appended to scan after scan (:class:`~hypotrack.hypotheses.factored.lane.Lane`, compacted when
  their garbage passes the bound) or compacted at every scan (every row copied: the lane rebuilt)."""

import pytest
from scenes import catalogue_scene, default_catalogue_config

import hypotrack.hypotheses.factored.lane as lane_module
import hypotrack.hypotheses.factored.scores as scores_module
from hypotrack.experiments.ssa_catalogue.run import make_tracker

N_SCANS = 30


@pytest.fixture(scope="module")
def catalogue():
    cfg = default_catalogue_config(N_SCANS)
    scene = catalogue_scene(cfg, 2000, snr=False)
    return cfg, scene.problem(), [(t, Z) for t, Z, _ in scene.scans]


def test_gated_pairs_and_dense_matrices_give_the_same_posterior(catalogue, monkeypatch):
    cfg, problem, scans = catalogue
    dense, pairs = (make_tracker("glmb", cfg, problem, 1) for _ in range(2))
    label0 = first = dense.next_label
    n_pairs = n_groups = n_dropped = 0
    calls = dict(pairs=0)
    frame_pairs = scores_module.sensor_frame_pairs

    def counted(*args, **kw):
        calls["pairs"] += 1
        return frame_pairs(*args, **kw)

    monkeypatch.setattr(scores_module, "sensor_frame_pairs", counted)
    for t, Z in scans:
        monkeypatch.setattr(scores_module, "DENSE_PAIRS", 10**12)
        before = dense.n_objects_held
        dense.step(Z, t)
        monkeypatch.setattr(scores_module, "DENSE_PAIRS", -1)  # every scan's scores as gated pairs
        pairs.step(Z, t)
        assert dense.same_posterior(pairs)
        assert dense.next_label == pairs.next_label
        n_pairs += dense.last_stats["n_predicted"] * len(Z)
        n_groups += len(dense.state().groups.states)
        n_dropped += dense.n_objects_held < before + dense.next_label - label0
        label0 = dense.next_label
    # the run holds what the check is for: scored pairs (as pairs at every scan of the second run), births,
    # multi-hypothesis groups, tracks that died
    assert n_pairs > 10_000 and calls["pairs"] == N_SCANS and dense.next_label > first
    assert n_groups > 0 and n_dropped > 0


def test_appended_and_rebuilt_lanes_give_the_same_posterior(catalogue, monkeypatch):
    cfg, problem, scans = catalogue
    rebuilt, appended = (make_tracker("glmb", cfg, problem, 1) for _ in range(2))
    n_appended = n_rebuilt = 0
    for t, Z in scans:
        monkeypatch.setattr(lane_module, "COMPACT_SHARE", 0.0)  # every scan: garbage above the bound, compacted
        monkeypatch.setattr(lane_module, "COMPACT_ROWS", 0)
        held = rebuilt.state().lane
        rebuilt.step(Z, t)
        n_rebuilt += rebuilt.state().lane._buf is not held._buf
        monkeypatch.undo()
        before = appended.state().lane
        appended.step(Z, t)
        lane = appended.state().lane
        n_appended += lane._buf is before._buf
        assert rebuilt.same_posterior(appended)
        assert rebuilt.next_label == appended.next_label
    # both ways taken: the one compacted at (nearly) every scan, the other appended at most and compacted now and then
    assert n_rebuilt >= len(scans) - 2 and n_appended > len(scans) // 2

"""HOMHT k-best on the catalogue (the default section as it is: admissible births, plausibility, the decaying
survival, the fast path) with the one-return children on Python floats (:mod:`...hypotheses.one_return_children`)
and the few-children duplicate merge (:func:`...hypotheses.duplicates.merge_few`) against the same tracker taking
the general path for both: bit for bit the same posterior at every scan (groups, weights, moments, labels, track
lists, lineage keys), with both replacements exercised many times; and the δ-GLMB, whose parents generate their
own children (silent-event sets, merged by :func:`...hypotheses.duplicates.merge_few` too), and R-FISST (its MCMC
search's draws from the same problems)."""

import pytest
from scenes import catalogue_scene, default_catalogue_config

import hypotrack.hypotheses.duplicates as duplicates
import hypotrack.hypotheses.filter as filter_mod
from hypotrack.experiments.ssa_catalogue.run import make_tracker

N_SCANS = 40


@pytest.fixture(scope="module")
def catalogue():
    cfg = default_catalogue_config(N_SCANS)
    scene = catalogue_scene(cfg, 300)
    return cfg, scene.problem(), scene.sensor, scene.scans


@pytest.mark.parametrize("tracker", ["homht_kbest", "glmb", "rfisst"])
def test_the_posterior_is_the_general_path_s_bit_for_bit(catalogue, monkeypatch, tracker):
    cfg, problem, tsensor, scans = catalogue
    new, ref = (make_tracker(tracker, cfg, problem, 1, fast_path=True) for _ in range(2))
    used = {"children": 0, "merged_few": 0}
    applies, merge_few = filter_mod.applies, filter_mod.merge_few

    def counted_applies(*a):
        out = applies(*a)
        used["children"] += out
        return out

    def counted_merge(*a):
        out = merge_few(*a)  # its own path: at most FEW children, no silent-event set
        used["merged_few"] += 2 <= len(a[0]) <= duplicates.FEW
        return out

    for t, Z, theta in scans:
        tsensor.at(theta)
        with monkeypatch.context() as m:  # the reference: the general children and the hashing merge
            m.setattr(filter_mod, "applies", lambda *a: False)
            m.setattr(filter_mod, "merge_few", lambda *a: (*duplicates.merge_duplicates(*a), None))
            ref.step(Z, t)
        with monkeypatch.context() as m:
            m.setattr(filter_mod, "applies", counted_applies)
            m.setattr(filter_mod, "merge_few", counted_merge)
            new.step(Z, t)
        assert new.same_posterior(ref)
        ga, gb = new.groups, ref.groups
        assert len(ga) == len(gb) and all(a.keys == b.keys for a, b in zip(ga, gb))
        assert all(a.log_w.tobytes() == b.log_w.tobytes() for a, b in zip(ga, gb))
    if tracker == "homht_kbest":  # the run holds what the check is for
        assert used["children"] > N_SCANS and used["merged_few"] > 5, used
    elif tracker == "glmb":  # the δ-GLMB's parents make their own children (silent-event sets): not built here
        assert used["children"] == 0, used
    assert new.next_label > len(problem.labels)  # births took labels

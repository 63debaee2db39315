"""The catalogue's operator's scorecard: one run gives the catalogue's own tables unchanged (against
:func:`run_tracker`, the peer) and the scorecard row; the table, ledger rows and macros on a fabricated table by
hand; the evaluated seed and window apart from the tuning ones."""

import copy
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.run import build_scenario, check_tuning, evaluated_on, run_tracker
from hypotrack.experiments.ssa_catalogue.scorecard import (COLUMNS, run_with_scorecard, scorecard_claims,
                                                           scorecard_macros, scorecard_table)
from hypotrack.scenarios.catalogue import reference_epoch

ROOT = Path(__file__).resolve().parents[4]
NAMES = ["glmb", "homht_kbest", "rfisst", "gnn", "jpda"]


def quick_section(**over):
    default = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())["ssa_catalogue"]
    quick = yaml.safe_load((ROOT / "workflows" / "config" / "quick.yaml").read_text())["ssa_catalogue"]
    return copy.deepcopy({**default, **quick, **over})


@pytest.fixture(scope="module")
def small():
    cfg = quick_section(n_scans=12)
    seed = evaluated_on(cfg, 0)[0]
    return cfg, seed, build_scenario(cfg, 30, seed)


@pytest.mark.parametrize("name", ["glmb", "gnn"])
def test_one_run_gives_the_catalogue_tables_of_run_tracker(small, name):
    cfg, seed, scenario = small
    ps, a, card = run_with_scorecard(name, cfg, 30, seed, scenario)
    ps0, a0, _ = run_tracker(name, cfg, 30, seed, scenario=scenario)
    pd.testing.assert_frame_equal(ps.drop(columns="cpu_s"), ps0.drop(columns="cpu_s"))
    pd.testing.assert_frame_equal(a, a0)
    # the scorecard row of the same run: every object return counted once, in one of the four outcomes
    sc = scenario[2]
    assert card["n_objects"] == 30 and card["n_scans"] == 12
    assert card["object_returns"] == sum(int((np.asarray(o) >= 0).sum()) for _, _, o in sc.scan_list(0, with_origin=True))
    if card["object_returns"]:
        total = card["correct_per_1e4"] + card["cross_tags_per_1e4"] + card["orphan_per_1e4"] + card["uncorrelated_per_1e4"]
        assert total == pytest.approx(1e4)
    assert card["unknown"] == len(scenario[1])
    assert card["unphysical_hypotheses_max"] >= card["unphysical_hypotheses_per_scan"] >= 0


def test_evaluated_window_starts_at_the_offset_and_differs_from_the_tuning_one():
    cfg = quick_section(n_scans=2)
    seed, off = evaluated_on(cfg, 7)
    assert (seed, off) == (cfg["tuning"]["evaluated_on"]["seed"], cfg["tuning"]["evaluated_on"]["start_offset_s"])
    assert seed != cfg["tuning"]["tuned_on"]["seed"] and off != cfg["tuning"]["tuned_on"]["start_offset_s"]
    objects, _, sc, _ = build_scenario(cfg, 30, seed)
    assert sc.start == reference_epoch(objects) + pd.Timedelta(seconds=off)
    # without a tuning block: the pipeline's seed from the catalogue's epoch
    bare = {k: v for k, v in cfg.items() if k != "tuning"}
    assert evaluated_on(bare, 7) == (7, 0.0)
    objects, _, sc, _ = build_scenario(bare, 30, seed)
    assert sc.start == reference_epoch(objects)


def test_check_tuning_refuses_evaluating_on_the_tuning_run():
    cfg = quick_section()
    check_tuning(cfg)
    same_seed = copy.deepcopy(cfg)
    same_seed["tuning"]["evaluated_on"]["seed"] = cfg["tuning"]["tuned_on"]["seed"]
    with pytest.raises(ValueError, match="evaluated_on.seed must differ"):
        check_tuning(same_seed)
    same_window = copy.deepcopy(cfg)
    same_window["tuning"]["evaluated_on"]["start_offset_s"] = cfg["tuning"]["tuned_on"]["start_offset_s"]
    with pytest.raises(ValueError, match="start_offset_s must differ"):
        check_tuning(same_window)


def fabricated():
    """Two sizes; at N = 300 GNN has 2 cross-tags per 1e4, realism 0.90, completeness 0.40; the factored
    trackers 1, 2, 0 cross-tags, realism 1.0, 0.99, 0.97, completeness 0.40, 0.45, 0.30."""
    rows = []
    vals = {"glmb": (1.0, 1.0, 0.40), "homht_kbest": (2.0, 0.99, 0.45), "rfisst": (0.0, 0.97, 0.30),
            "gnn": (2.0, 0.90, 0.40), "jpda": (3.0, 0.80, 0.35)}
    for n in (300, 100):
        for t in reversed(NAMES):
            ct, re, co = vals[t]
            r = {c: 1.0 for c in COLUMNS}
            r.update(tracker=t, n_objects=n, n_scans=720, object_returns=2000, cross_tags_per_1e4=ct, realism_95=re,
                     completeness=co, correct_per_1e4=1e4 - ct - 100.0, uncorrelated_per_1e4=100.0, orphan_per_1e4=0.0,
                     reacquisitions=5, unknown_with_orbit=2, unknown=4, gospa_per_object_km={"gnn": 1.5}.get(t, 0.5),
                     false_per_1000={"gnn": 100.0, "jpda": 90.0}.get(t, 4.0), time_to_orbit_unknown_s=np.nan,
                     cpu_s=3.0)
            rows.append(r)
    return pd.DataFrame(rows)


def test_table_claims_and_macros_by_hand():
    tab = scorecard_table(fabricated())
    assert list(tab.columns) == COLUMNS  # no CPU time: the table is byte-reproducible
    assert list(zip(tab["tracker"], tab["n_objects"]))[:3] == [("glmb", 100), ("glmb", 300), ("homht_kbest", 100)]
    claims = scorecard_claims(tab, "gnn")
    assert len(claims) == 15 and {c.status for c in claims} == {"extension"}
    by = {c.key: c for c in claims}
    assert by["card_crosstags_homht_kbest"].reproduced == "2"
    assert by["card_realism_rfisst"].reproduced == "0.97" and "GNN: 0.9" in by["card_realism_rfisst"].note
    assert by["card_completeness_gnn"].reproduced == "0.4" and "GNN:" not in by["card_completeness_gnn"].note
    m = scorecard_macros(tab, "gnn")
    assert m["CardN"] == 300 and m["CardReacqglmb"] == 5 and m["CardTimeToOrbitglmb"] == "n/a"
    # the largest |factored − GNN|: cross-tags |0 − 2| = 2; completeness |0.30 − 0.40| = 0.1; realism
    # |1.0 − 0.9| = 0.1; GOSPA |0.5 − 1.5| = 1; false |4 − 100| = 96 (JPDA is not a factored tracker)
    assert (m["CardMaxDiffCrossTags"], m["CardMaxDiffCompleteness"], m["CardMaxDiffRealism"], m["CardMaxDiffGospa"],
            m["CardMaxDiffFalse"]) == ("2", "0.1", "0.1", "1", "96")
    # in words: cross-tags 1, 2, 0 against 2 -> below (one equal, none above); realism 1.0, 0.99, 0.97 against
    # 0.90 -> above; completeness 0.40, 0.45, 0.30 against 0.40 -> both sides
    assert (m["CardCmpCrossTags"], m["CardCmpRealism"], m["CardCmpCompleteness"]) == ("below", "above",
                                                                                      "on both sides of")


def test_every_claim_row_is_placed_in_the_extension_group():
    doc = yaml.safe_load((ROOT / "src" / "hypotrack" / "reporting" / "document_claims.yaml").read_text())
    placed = {r for g in doc["extensions"] if g["id"] == "extension.catalogue_scorecard" for r in g["rows"]}
    keys = {f"ssa_catalogue/{c.key}" for c in scorecard_claims(scorecard_table(fabricated()), "gnn")}
    assert keys == placed


def test_orbit_checks_find_the_next_pass_and_score_the_prediction():
    """Oracle: the scenario's own in-view truth over two hours (pass_ends). A track equal to the SGP4 state at the
    end of an object's first pass re-acquires it at its second pass (J2 against SGP4 over one orbit: well inside
    5 km); the same track 10 km off does not. On a 10-s grid the next instant in view is the second pass's first
    scan exactly."""
    from types import SimpleNamespace

    from hypotrack.experiments.ssa_breakup.run import pass_ends
    from hypotrack.experiments.ssa_catalogue.run import make_motion
    from hypotrack.experiments.ssa_catalogue.scorecard import orbit_checks

    cfg = quick_section(n_scans=720)
    seed = evaluated_on(cfg, 0)[0]
    _, _, sc, _ = build_scenario(cfg, 100, seed)
    pe = pass_ends(sc.truth)
    two = pe[pe["pass_no"] == 1]
    assert len(two), "the two-hour run must bring an object back"
    p1 = two.iloc[0]
    p0 = pe[(pe["target"] == p1.target) & (pe["pass_no"] == 0)].iloc[0]
    tv = sc.truth[(sc.truth["target"] == p1.target) & (sc.truth["scan"] == p0.last_scan)]
    x = tv[[f"state_{i}" for i in range(6)]].to_numpy()[0]
    off = x + np.r_[10.0, 0, 0, 0, 0, 0]
    run = SimpleNamespace(ends=[dict(target=int(p1.target), pass_no=0, time=p0.t_last, x=x, t_x=p0.t_last),
                                dict(target=int(p1.target), pass_no=0, time=p0.t_last, x=off, t_x=p0.t_last),
                                dict(target=-5, pass_no=0, time=p0.t_last, x=x, t_x=p0.t_last),  # not asked about
                                dict(target=int(p1.target), pass_no=-1, time=7190.0, x=x, t_x=p0.t_last)])  # run end
    out = orbit_checks(run, sc, make_motion(cfg), [int(p1.target)], 10800.0, 5.0, step_s=10.0)
    assert out["target"].tolist() == [int(p1.target)] * 2
    assert out["t_next"].tolist() == [p1.t_first, p1.t_first]
    assert out["ok"].tolist() == [True, False]
    assert len(orbit_checks(run, sc, make_motion(cfg), [], 10800.0, 5.0)) == 0


def test_compare_in_words_as_printed():
    from hypotrack.experiments.ssa_catalogue.scorecard import compare

    assert compare([0.0, 0.0, 0.0], 0.0) == "equal to"
    assert compare([0.1581, 0.1582], 0.158) == "equal to"  # the same at 3 significant digits
    assert compare([0.158, 0.16], 0.187) == "below"
    assert compare([2.35, 5.35, 40.0], 30.9) == "on both sides of"
    assert compare([1.0, 2.0], 0.5) == "above"
    assert compare([1.0, float("nan")], 0.5) == "not comparable with"
    assert compare([], 0.5) == "not comparable with"


def test_tuning_sweep_rows_are_the_scorecard_of_each_window_and_q():
    """The sweep's evaluated-window row at the configured q is the pipeline's own scorecard of that run; its
    tuning-window rows use the tuning seed and window."""
    from hypotrack.experiments.ssa_catalogue.scorecard import tuning_sweep

    cfg = quick_section(n_scans=4)
    q0 = cfg["model"]["process_noise_q"]
    sweep = tuning_sweep(cfg, [q0, 10 * q0], 30, 4, trackers=("gnn",))
    assert sweep[["window", "q"]].values.tolist() == [["tuned_on", q0], ["tuned_on", 10 * q0],
                                                      ["evaluated_on", q0], ["evaluated_on", 10 * q0]]
    assert sweep["seed"].tolist() == [cfg["tuning"]["tuned_on"]["seed"]] * 2 + [cfg["tuning"]["evaluated_on"]["seed"]] * 2
    seed = evaluated_on(cfg, 0)[0]
    _, _, card = run_with_scorecard("gnn", cfg, 30, seed, build_scenario(cfg, 30, seed))
    row = sweep.iloc[2]
    for k in ("completeness", "gospa_per_object_km", "reacquisitions", "cross_tags_per_1e4"):
        assert row[k] == pytest.approx(card[k], nan_ok=True), k

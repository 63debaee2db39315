"""The ambiguity output's tuning protocol: the rule on hand-made sweeps, the tuning section, the evaluated rows at
the tuned p_min, and a small end-to-end run scoring every candidate p_min from one tracker run."""

import copy
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_breakup.tuning import (TUNING_COLUMNS, chosen_p_min, output_p_mins, select_output,
                                                      tuning_section, tuning_table, used_p_min)

CONFIG = Path(__file__).resolve().parents[4] / "workflows" / "config" / "default.yaml"


def _sweep(values):
    """Sweep rows (breakup, withhold) from ``{(tracker, seed, p_min): (cross-tags, untagged)}`` plus fresh-mode
    rows that would win if the mode were ignored."""
    rows = [dict(scenario="breakup", seed=k, mode="withhold", p_min=p, tracker=t, cross_tags_per_1e4=x,
                 uncorrelated_per_1e4=u) for (t, k, p), (x, u) in values.items()]
    rows += [dict(scenario="breakup", seed=k, mode="fresh", p_min=p, tracker=t, cross_tags_per_1e4=0.0,
                  uncorrelated_per_1e4=0.0) for (t, k, p) in values]
    return pd.DataFrame(rows)


def _gnn(xt):
    return pd.DataFrame([dict(scenario="breakup", seed=k, tracker="gnn", cross_tags_per_1e4=v) for k, v in xt.items()])


# two trackers, two tuning seeds, three candidates. Scores X + 0.1 U by hand:
#   p=0.6: a: 10+4=14, 12+4=16; b: 8+4=12, 10+4=14  -> mean 14.0
#   p=0.7: a:  4+6=10,  6+6=12; b: 5+6=11,  5+6=11  -> mean 11.0  (least)
#   p=0.9: a:  1+12=13, 1+12=13; b: 1+12=13, 1+12=13 -> mean 13.0
# and with lambda = 0.01: 0.6 -> 10.4, 0.7 -> 5.6, 0.9 -> 2.2: 0.9 wins (cross-tags alone decide).
HAND = {("a", 1, 0.6): (10.0, 40.0), ("a", 12, 0.6): (12.0, 40.0), ("b", 1, 0.6): (8.0, 40.0),
        ("b", 12, 0.6): (10.0, 40.0), ("a", 1, 0.7): (4.0, 60.0), ("a", 12, 0.7): (6.0, 60.0),
        ("b", 1, 0.7): (5.0, 60.0), ("b", 12, 0.7): (5.0, 60.0), ("a", 1, 0.9): (1.0, 120.0),
        ("a", 12, 0.9): (1.0, 120.0), ("b", 1, 0.9): (1.0, 120.0), ("b", 12, 0.9): (1.0, 120.0)}


def test_rule_picks_the_least_mean_cost_by_hand():
    t = tuning_table(_sweep(HAND), _gnn({1: 8.0, 12: 0.0}), "withhold", 0.1)
    assert chosen_p_min(t) == 0.7
    allp = t[(t["tracker"] == "all") & (t["seed"] == -1)].set_index("p_min")
    np.testing.assert_allclose(allp["score"].to_numpy(), [14.0, 11.0, 13.0])
    a = t[(t["tracker"] == "a") & (t["seed"] == -1)].set_index("p_min")
    np.testing.assert_allclose(a["score"].to_numpy(), [15.0, 11.0, 13.0])
    one = t[(t["tracker"] == "b") & (t["seed"] == 1) & (t["p_min"] == 0.7)].iloc[0]
    assert one["score"] == pytest.approx(11.0) and one["xtag_ratio"] == pytest.approx(5.0 / 8.0)
    # GNN with no cross-tags on seed 12: no ratio there, and the per-tracker mean is over seed 1 alone
    assert np.isnan(t[(t["tracker"] == "b") & (t["seed"] == 12)]["xtag_ratio"]).all()
    assert a.loc[0.7, "xtag_ratio"] == pytest.approx(4.0 / 8.0)
    assert t.loc[t["chosen"], "p_min"].unique().tolist() == [0.7]
    assert len(t) == 12 + 3 * 3  # per seed, then per tracker and over all


def test_rule_follows_lambda_and_breaks_ties_to_the_smallest_p_min():
    assert chosen_p_min(tuning_table(_sweep(HAND), _gnn({1: 8.0, 12: 4.0}), "withhold", 0.01)) == 0.9
    # lambda = 0: cross-tags alone; the fresh rows (all zero) are another mode and never enter
    assert chosen_p_min(tuning_table(_sweep(HAND), _gnn({1: 8.0}), "withhold", 0.0)) == 0.9
    tie = {(t, k, p): (10.0 - 10 * p, 100 * p) for t in ("a", "b") for k in (1, 12) for p in (0.6, 0.8)}
    # X + 0.1 U = 10 - 10p + 10p = 10 at both: the smaller p_min (withholds less)
    assert chosen_p_min(tuning_table(_sweep(tie), _gnn({1: 1.0}), "withhold", 0.1)) == 0.6
    with pytest.raises(ValueError, match="untagged_weight"):
        tuning_table(_sweep(HAND), _gnn({1: 8.0}), "withhold", -1.0)
    with pytest.raises(ValueError, match="mode 'other'"):
        tuning_table(_sweep(HAND), _gnn({1: 8.0}), "other", 0.1)


def _section(tuning):
    return dict(seeds=[2, 3], scenarios=["breakup", "catalogue"],
                ambiguity=dict(mode="withhold", p_min=0.7, p_min_sweep=[0.8, 0.6, 0.9], **tuning))


def test_tuning_section_and_the_p_min_used():
    sec = _section(dict(tuning=dict(seeds=[1, 12], trackers=["glmb_murty", "gnn"], untagged_weight=0.1)))
    t = tuning_section(sec)
    assert t["seeds"] == [1, 12] and t["scenarios"] == ["breakup"] and sec["seeds"] == [2, 3]
    assert output_p_mins(sec["ambiguity"]) == [0.6, 0.8, 0.9]  # every candidate, the fixed 0.7 not among them
    table = tuning_table(_sweep(HAND), _gnn({1: 8.0}), "withhold", 0.1)
    assert used_p_min(sec, table) == 0.7 and used_p_min(sec, table.assign(chosen=table["p_min"] == 0.9)) == 0.9
    with pytest.raises(ValueError, match="tuning table"):
        used_p_min(sec)
    with pytest.raises(ValueError, match=r"disjoint from ssa_breakup.seeds.*\[3\]"):
        tuning_section(_section(dict(tuning=dict(seeds=[1, 3], trackers=["gnn"], untagged_weight=0.1))))
    off = _section({})
    assert output_p_mins(off["ambiguity"]) == [0.7] and used_p_min(off) == 0.7
    with pytest.raises(ValueError, match="tuning.seeds"):
        tuning_section(off)
    with pytest.raises(ValueError, match="p_min_sweep"):
        output_p_mins(dict(p_min=0.7, tuning=dict(seeds=[1])))
    with pytest.raises(ValueError, match="exactly one"):
        chosen_p_min(table.assign(chosen=False))


def test_select_output_keeps_the_plain_rows_and_the_tuned_ones():
    cards = pd.DataFrame(dict(tracker=["glmb_murty", "glmb_murty_amb", "glmb_murty_amb", "gnn"], seed=2,
                              p_min=[np.nan, 0.7, 0.8, np.nan], cross_tags_per_1e4=[5.0, 2.0, 1.0, 3.0]))
    out = select_output(cards, 0.8)
    assert out["tracker"].tolist() == ["glmb_murty", "glmb_murty_amb", "gnn"] and "p_min" not in out
    assert out["cross_tags_per_1e4"].tolist() == [5.0, 1.0, 3.0]
    with pytest.raises(ValueError, match="glmb_murty_amb"):
        select_output(cards, 0.9)
    assert select_output(cards.drop(columns="p_min"), 0.9).equals(cards.drop(columns="p_min"))


def test_every_candidate_scored_in_full_from_one_run():
    """With a tuning block, a factored run's cards hold one ambiguity row per candidate p_min, each equal on the
    identity columns to the sweep's row of the configured mode (one tracker run)."""
    from hypotrack.experiments.ssa_breakup.jobs import score_tracker_outputs

    full = yaml.safe_load(CONFIG.read_text())
    cfg = copy.deepcopy(full["ssa_breakup"])
    cfg.update(seeds=[5], scenarios=["breakup"], window={"obs_start_s": 7200.0, "obs_end_s": 7800.0})
    cfg["event"]["lc_min_m"] = 0.2
    cfg["ambiguity"] = dict(mode="withhold", p_min=0.7, p_min_sweep=[0.5, 0.9],
                            tuning=dict(seeds=[1], trackers=["glmb_murty", "gnn"], untagged_weight=0.1))
    cards, sweep = score_tracker_outputs("glmb_murty", cfg, full["ssa_catalogue"])
    assert cards["tracker"].tolist() == ["glmb_murty", "glmb_murty_amb", "glmb_murty_amb"]
    assert np.isnan(cards["p_min"].iloc[0]) and cards["p_min"].iloc[1:].tolist() == [0.5, 0.9]
    w = sweep[sweep["mode"] == "withhold"].set_index("p_min")
    for p in (0.5, 0.9):
        row = select_output(cards, p).iloc[1]
        for c in ("cross_tags_per_1e4", "uncorrelated_per_1e4", "id_switches"):
            assert row[c] == w.loc[p, c]


def test_the_evaluated_ledger_row_uses_the_tuned_p_min():
    """The evaluated seeds' ambiguity outputs at every candidate; the tuning table (other seeds) chooses 0.9 where
    ambiguity.p_min says 0.7: the ratio row and the ledger's row are the 0.9 output's, by hand: per seed
    glmb_murty_amb cross-tags over GNN's, 1/2 and 2/4 -> 0.5 (s.e. 0), meeting the goal (0.7's: 3/2, 6/4 -> 1.5)."""
    from hypotrack.experiments.ssa_breakup.summary import breakup_claims, breakup_ratios, scorecard_summary
    from hypotrack.experiments.ssa_breakup.tuning import evaluated_cards

    xt = {("gnn", None): (2.0, 4.0), ("glmb_murty", None): (5.0, 8.0), ("glmb_murty_amb", 0.7): (3.0, 6.0),
          ("glmb_murty_amb", 0.9): (1.0, 2.0)}
    cards = pd.DataFrame([dict(scenario="breakup", seed=k, tracker=t, p_min=np.nan if p is None else p,
                               cross_tags_per_1e4=v[j], id_switches_per_1e4=1.0, uncorrelated_per_1e4=10.0 * v[j])
                          for (t, p), v in xt.items() for j, k in enumerate((2, 3))])
    sec = _section(dict(tuning=dict(seeds=[1, 12], trackers=["glmb_murty", "gnn"], untagged_weight=0.1)))
    sec["ambiguity"]["p_min_sweep"] = [0.7, 0.9]
    table = tuning_table(_sweep(HAND), _gnn({1: 8.0}), "withhold", 0.01)  # the hand table at lambda 0.01: 0.9
    out, p = evaluated_cards(cards, sec, table)
    assert p == 0.9
    r = breakup_ratios(out, ["glmb_murty", "gnn"], "gnn", 0.5)
    amb = r[(r["tracker"] == "glmb_murty_amb") & (r["metric"] == "cross_tags_per_1e4")].iloc[0]
    assert amb["ratio"] == pytest.approx(0.5) and amb["ratio_se"] == pytest.approx(0.0) and amb["meets_goal"]
    cards_off, p_off = evaluated_cards(cards, _section({}))  # no tuning: ambiguity.p_min, 0.7
    r_off = breakup_ratios(cards_off, ["glmb_murty", "gnn"], "gnn", 0.5)
    assert p_off == 0.7 and r_off.loc[r_off["tracker"] == "glmb_murty_amb", "ratio"].iloc[0] == pytest.approx(1.5)
    summary, _ = scorecard_summary(out.assign(cpu_s=1.0, completeness=1.0, duplicate_per_1000=0.0,
                                              false_per_1000=0.0, nn_in_gate_share=0.0, reacquisitions=1.0))
    claims = {c.key: c for c in breakup_claims(summary, r, pd.DataFrame(dict(seed=[])), "gnn")}
    assert claims["ratio_breakup_glmb_murty_amb"].reproduced.startswith("0.5 ± 0")
    with pytest.raises(ValueError, match="tuning table"):
        evaluated_cards(cards, sec)


def _results(tmp_path, seeds=(2, 3), tuning_seeds=(1, 12)):
    """A record run's tables by hand: GNN 2 and 4 cross-tags per 1e4, the δ-GLMB's ambiguity output 1 and 1."""
    src = tmp_path / "res" / "ssa_breakup"
    src.mkdir(parents=True)
    xt = {"gnn": (2.0, 4.0), "glmb_murty": (4.0, 4.0), "glmb_murty_amb": (1.0, 1.0)}
    unc = {"gnn": 40.0, "glmb_murty": 30.0, "glmb_murty_amb": 70.0}
    cat = {"gnn": (8.0, 4.0), "glmb_murty": (2.0, 2.0), "glmb_murty_amb": (1.0, 3.0)}  # catalogue cross-tags
    cards = pd.DataFrame([dict(scenario="breakup", tracker=t, seed=k, cross_tags_per_1e4=v[j], id_switches_per_1e4=2.0,
                               uncorrelated_per_1e4=unc[t], completeness=0.9, catalogue_cross_tags_per_1e4=cat[t][j])
                          for t, v in xt.items() for j, k in enumerate(seeds)])
    from hypotrack.experiments.ssa_breakup.summary import breakup_ratios, scorecard_summary
    summary, _ = scorecard_summary(cards)
    summary.to_csv(src / "summary.csv", index=False)
    breakup_ratios(cards, ["glmb_murty", "gnn"], "gnn", 0.5).to_csv(src / "ratios.csv", index=False)
    cards.to_csv(src / "scorecard.csv", index=False)
    hand = {(t, k, p): v for (t, k, p), v in HAND.items()}
    hand = {(t, dict(zip((1, 12), tuning_seeds))[k], p): v for (t, k, p), v in hand.items()}
    tuning_table(_sweep(hand), _gnn({tuning_seeds[0]: 8.0}), "withhold", 0.1).to_csv(src / "tuning.csv", index=False)
    return tmp_path / "res"


def _workflow(tmp_path, seeds, tuning_seeds):
    """A workflow folder whose record overlay names ``seeds`` and ``tuning_seeds`` (the repository's configs
    otherwise)."""
    import shutil
    root = Path(__file__).resolve().parents[4] / "workflows" / "config"
    wf = tmp_path / "wf"
    shutil.copytree(root, wf / "config")
    over = yaml.safe_load((root / "breakup_record.yaml").read_text())
    over["ssa_breakup"]["seeds"] = list(seeds)
    over["ssa_breakup"]["ambiguity"] = dict(tuning=dict(seeds=list(tuning_seeds), trackers=["glmb_murty", "gnn"],
                                                        untagged_weight=0.1))
    over["ssa_breakup"]["trackers_run"] = ["glmb_murty", "gnn"]
    (wf / "config" / "breakup_record.yaml").write_text(yaml.safe_dump(over))
    return wf


def test_record_table_claims_and_macros_by_hand(tmp_path):
    from hypotrack.experiments.ssa_breakup.record import (record_claims, record_config, record_macros,
                                                          update_breakup_record)

    wf = _workflow(tmp_path, (2, 3), (1, 12))
    assert record_config(wf)["ambiguity"]["p_min"] == 0.7  # the default's and full.yaml's keys merged under it
    paths = update_breakup_record(_results(tmp_path), tmp_path / "record", wf)
    table = pd.read_csv(paths[0])
    assert table["tracker"].tolist() == ["gnn", "glmb_murty", "glmb_murty_amb"]
    amb = table.set_index("tracker").loc["glmb_murty_amb"]
    # per seed 1/2 and 1/4: mean 0.375, s.e. 0.125; the plain output 4/2, 4/4: 1.5 ± 0.5
    assert amb["ratio"] == pytest.approx(0.375) and amb["ratio_se"] == pytest.approx(0.125) and amb["meets_goal"]
    assert amb["p_min"] == 0.7 and amb["tuning_seeds"] == "1 12" and amb["seeds"] == "2 3"
    assert pd.read_csv(paths[1])["chosen"].any()
    md = paths[3].read_text()
    assert "`p_min` = 0.7, chosen on tuning seeds 1 and 12" in md and "untagged returns (per 10⁴) of the ambiguity outputs of a and b, then" in md and "evaluated on seeds 2 and 3 (2 seeds)" in md
    assert "| 0.7 | 5 | 60 | 11 | yes |" in md and "| 0.6 | 10 | 40 | 14 |  |" in md  # the hand table's means
    # the spread beside the verdict: median of 1/2 and 1/4, both at most 0.5, and (1 + 1) / (2 + 4)
    assert "| δ-GLMB (Murty), ambiguity output | 2 | 1 ± 0 | 0.375 ± 0.12 | met | 0.375 | 2 of 2 | 0.333 | 70 ± 0 |" in md
    assert amb["ratio_median"] == pytest.approx(0.375) and amb["n_at_goal"] == 2
    assert amb["ratio_of_means"] == pytest.approx(1 / 3, rel=1e-5)  # the record CSV keeps 6 digits
    plain = table.set_index("tracker").loc["glmb_murty"]
    assert plain["n_at_goal"] == 0 and plain["ratio_of_means"] == pytest.approx(8 / 6, rel=1e-5)  # 4/2, 4/4: neither at 0.5
    # catalogue cross-tags: per seed 2/8, 2/4 (mean 0.375, s.e. 0.125, both at goal, 4/12) and 1/8, 3/4 (0.4375 ±
    # 0.3125, one at goal, 4/12)
    assert (plain["cat_ratio"], plain["cat_ratio_se"], plain["cat_n_at_goal"]) == pytest.approx((0.375, 0.125, 2))
    assert (amb["cat_ratio"], amb["cat_ratio_se"], amb["cat_ratio_median"]) == pytest.approx((0.4375, 0.3125, 0.4375))
    assert amb["cat_n_at_goal"] == 1 and amb["cat_ratio_of_means"] == pytest.approx(1 / 3, rel=1e-5)
    assert "| δ-GLMB (Murty) | 2 ± 0 | 0.375 ± 0.12 | met | 0.375 | 2 of 2 | 0.333 |" in md
    assert "| δ-GLMB (Murty), ambiguity output | 2 ± 1 | 0.438 ± 0.31 | met | 0.438 | 1 of 2 | 0.333 |" in md
    keys = {c.key: c for c in record_claims(table)}
    assert set(keys) == {"record_pmin", "record_ratio_glmb_murty", "record_ratio_glmb_murty_amb",
                         "record_cat_ratio_glmb_murty", "record_cat_ratio_glmb_murty_amb"}
    assert keys["record_cat_ratio_glmb_murty_amb"].reproduced == "0.438 ± 0.31"
    assert "median 0.438, ratio of means 0.333" in keys["record_cat_ratio_glmb_murty_amb"].note
    assert keys["record_pmin"].reproduced == "0.7" and "tuning seeds 1 and 12" in keys["record_pmin"].note
    assert keys["record_ratio_glmb_murty_amb"].reproduced == "0.375 ± 0.12"
    assert "untagged 70 per 10^4 returns against 30 for the MAP output and 40 for GNN" in \
        keys["record_ratio_glmb_murty_amb"].note
    assert "misses" in keys["record_ratio_glmb_murty"].note
    m = record_macros(table)
    assert m["record_pmin"] == 0.7 and m["record_tuning_seeds"] == "1 and 12" and m["record_n_seeds"] == 2
    assert m["record_seeds"] == "2 and 3"
    assert m["record_goal_glmb_murty_amb"] == "met" and m["record_goal_glmb_murty"] == "not met"
    assert m["record_n_at_goal_glmb_murty_amb"] == 2 and m["record_ratio_median_glmb_murty_amb"] == pytest.approx(0.375)
    assert "record_goal_gnn" not in m and m["record_uncorrelated_gnn"] == 40.0
    assert m["record_cat_goal_glmb_murty_amb"] == "met" and m["record_cat_n_at_goal_glmb_murty_amb"] == 1
    assert m["record_cat_n_ratio_glmb_murty_amb"] == 2
    assert m["record_catxtags_gnn"] == 6.0 and "record_cat_goal_gnn" not in m
    assert record_claims(pd.DataFrame()) == [] and record_macros(pd.DataFrame()) == {}


def test_record_refuses_another_runs_tables(tmp_path):
    from hypotrack.experiments.ssa_breakup.record import update_breakup_record

    res = _results(tmp_path, seeds=(2, 3), tuning_seeds=(1, 12))
    with pytest.raises(ValueError, match=r"evaluated seeds \[2, 3\] for \[2, 3, 4\]"):
        update_breakup_record(res, tmp_path / "record", _workflow(tmp_path / "a", (2, 3, 4), (1, 12)))
    with pytest.raises(ValueError, match=r"tuning seeds \[1, 12\] for \[1, 13\]"):
        update_breakup_record(res, tmp_path / "record", _workflow(tmp_path / "b", (2, 3), (1, 13)))
    assert update_breakup_record(res, tmp_path / "record", _workflow(tmp_path / "c", (2, 3, 4), (1, 12)), force=True)
    with pytest.raises(FileNotFoundError, match="tuning.csv"):
        (res / "ssa_breakup" / "tuning.csv").unlink()
        update_breakup_record(res, tmp_path / "record", _workflow(tmp_path / "d", (2, 3), (1, 12)))


def test_the_choice_is_over_the_mean_of_every_tracker_not_one_tracker():
    """One seed, λ = 0: tracker a costs 0 at p_min 0.5 and 10 at 0.8, b 20 and 2. The mean over both, 10 at 0.5 and 6
    at 0.8, chooses 0.8, though a alone would choose 0.5."""
    vals = {("a", 1, 0.5): (0.0, 0.0), ("a", 1, 0.8): (10.0, 0.0), ("b", 1, 0.5): (20.0, 0.0), ("b", 1, 0.8): (2.0, 0.0)}
    t = tuning_table(_sweep(vals), _gnn({1: 4.0}), "withhold", 0.0)
    assert chosen_p_min(t) == 0.8
    # a's and b's rows at 0.8, their two means and the overall one
    assert t.loc[t["chosen"], "p_min"].tolist() == [0.8] * 5


def test_the_table_layout_mode_seed_dtype_and_row_order():
    """Seeds given as floats (as read back from a CSV) come out as integers; every row, means included, carries the
    mode; the mean rows follow the per-seed ones tracker by tracker in increasing p_min (seed 1 has 0.7 and 0.9,
    seed 2 only 0.6), then the overall ones; a reference value in (0, 1] gives a ratio (4 / 0.5 = 8)."""
    vals = {("b", 1, 0.7): (4.0, 0.0), ("b", 1, 0.9): (1.0, 0.0), ("b", 2, 0.6): (6.0, 0.0),
            ("a", 1, 0.7): (2.0, 0.0), ("a", 1, 0.9): (3.0, 0.0), ("a", 2, 0.6): (5.0, 0.0)}
    sweep = _sweep(vals).astype({"seed": float})
    t = tuning_table(sweep, _gnn({1: 0.5, 2: 1.0}), "withhold", 0.0)
    assert list(t.columns) == TUNING_COLUMNS and t.index.tolist() == list(range(len(t)))
    assert t["seed"].dtype == np.int64 and set(t["mode"]) == {"withhold"}
    assert list(zip(t["tracker"], t["seed"], t["p_min"])) == [
        ("a", 1, 0.7), ("a", 1, 0.9), ("a", 2, 0.6), ("b", 1, 0.7), ("b", 1, 0.9), ("b", 2, 0.6),
        ("a", -1, 0.6), ("a", -1, 0.7), ("a", -1, 0.9), ("b", -1, 0.6), ("b", -1, 0.7), ("b", -1, 0.9),
        ("all", -1, 0.6), ("all", -1, 0.7), ("all", -1, 0.9)]
    assert t.loc[3, "xtag_ratio"] == 8.0 and t.loc[5, "xtag_ratio"] == 6.0
    # the overall means: 0.6 -> 5.5, 0.7 -> 3, 0.9 -> 2 (chosen)
    assert t["score"].tolist()[-3:] == [5.5, 3.0, 2.0] and chosen_p_min(t) == 0.9


def test_no_reference_ratio_gives_nan_means_without_a_warning_and_other_cards_are_ignored():
    """GNN has cross-tags on no tuning seed: every xtag_ratio NaN, quietly. Cards of other trackers and of the
    catalogue scenario (GNN's there included) do not enter the reference."""
    cards = pd.concat([_gnn({3: 5.0}), _gnn({1: 7.0}).assign(scenario="catalogue"),
                       _gnn({1: 9.0, 12: 9.0}).assign(tracker="glmb_murty")], ignore_index=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = tuning_table(_sweep(HAND), cards, "withhold", 0.1)
    assert t["xtag_ratio"].isna().all() and chosen_p_min(t) == 0.7


def test_candidates_closer_than_the_default_tolerances_stay_apart():
    """p_min 0.9 and 0.9 + 5e-9 are two candidates: the choice and the selection match exactly one (np.isclose's
    default rtol 1e-5 and atol 1e-8 would join them)."""
    q = 0.9 + 5e-9
    vals = {("a", 1, 0.9): (1.0, 0.0), ("a", 1, q): (2.0, 0.0)}
    t = tuning_table(_sweep(vals), _gnn({1: 1.0}), "withhold", 0.0)
    assert chosen_p_min(t) == 0.9 and int(t["chosen"].sum()) == 3
    cards = pd.DataFrame(dict(tracker=["gnn", "glmb_murty_amb", "glmb_murty_amb"], seed=2, p_min=[np.nan, 0.9, q],
                              cross_tags_per_1e4=[3.0, 1.0, 2.0]), index=[5, 6, 7])
    out = select_output(cards, q)
    assert list(out.columns) == ["tracker", "seed", "cross_tags_per_1e4"] and out.index.tolist() == [0, 1]
    assert out["cross_tags_per_1e4"].tolist() == [3.0, 2.0]


def test_an_empty_tuning_seed_list_is_no_tuning_and_the_messages_are_exact():
    sec = _section(dict(tuning=dict(seeds=[], trackers=["gnn"], untagged_weight=0.1)))
    assert used_p_min(sec) == 0.7 and output_p_mins(sec["ambiguity"]) == [0.7]
    with pytest.raises(ValueError, match=r"^ssa_breakup\.ambiguity\.tuning\.seeds must name at least one tuning seed$"):
        tuning_section(sec)
    with pytest.raises(ValueError, match=r"^ssa_breakup\.ambiguity\.p_min_sweep must hold the candidate p_min values "
                                         r"when ambiguity\.tuning is set$"):
        output_p_mins(dict(p_min=0.7, tuning=dict(seeds=[1])))
    with pytest.raises(ValueError, match=r"^ssa_breakup\.ambiguity\.tuning is set: the evaluated p_min comes from its "
                                         r"tuning table$"):
        used_p_min(_section(dict(tuning=dict(seeds=[1], trackers=["gnn"], untagged_weight=0.1))))

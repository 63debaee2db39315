"""The SSA Monte Carlo over seeds (hypotrack.experiments.ssa_seeds.run): seeds, distribution, verdicts."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_seeds import claims as sc
from hypotrack.experiments.ssa_seeds import run as ss

ROOT = Path(__file__).resolve().parents[4]


def _config(n_seeds=3, n_scans=6):
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    config["ssa_seeds"].update(n_seeds=n_seeds, n_scans=n_scans, n_steps=200)
    for case in ("ssa50", "ssa15"):
        config[case]["max_hypotheses"] = 3
    return config


def test_seed_i_is_the_same_whatever_the_number_of_seeds_and_seeds_differ():
    a = ss.seed_scenario(_config(n_seeds=2), "ssa15", 1)
    b = ss.seed_scenario(_config(n_seeds=7), "ssa15", 1)
    c = ss.seed_scenario(_config(n_seeds=7), "ssa15", 2)
    pd.testing.assert_frame_equal(a.scans, b.scans)
    assert len(a.times) == 6 and not a.scans.equals(c.scans)
    with pytest.raises(ValueError, match="case"):
        ss.seed_scenario(_config(), "ssa20", 0)


def test_tracker_settings_take_the_case_trackers_with_the_seeds_proposals():
    s = ss.tracker_settings(_config(), "ssa15")
    assert list(s) == ["homht", "rfisst_chain", "rfisst", "rfisst_fixed", "homht_births"]
    assert (s["rfisst_chain"].n_steps, s["rfisst_chain"].completion_rounds, s["rfisst"].completion_rounds) == (200, 0, 2)
    # the apples-to-apples pair: R-FISST with a fixed number of objects, like HOMHT
    assert not s["rfisst_fixed"].population and s["rfisst_fixed"].n_steps == 200
    assert s["homht"].kind == "homht" and s["homht"].max_hypotheses == 3 and not s["homht"].population
    # ... and with births and deaths on both sides: HOMHT (defined in ssa_seeds) with ssa15's Eq. 30 population
    hb, rf = s["homht_births"], s["rfisst"]
    assert (hb.kind, hb.population, hb.k, hb.max_hypotheses) == ("homht_kbest", True, 100, 3)
    assert (hb.alpha, hb.beta, hb.n_birth_regions) == (rf.alpha, rf.beta, rf.n_birth_regions) == (1e-3, 1e-4, 10)
    assert (hb.label, s["homht"].label) == ("HOMHT with births and deaths", "HOMHT")
    config = _config()
    config["ssa_seeds"]["extra_trackers"] = {"ssa15": {"homht": {"kind": "homht"}}}
    with pytest.raises(ValueError, match="ssa_seeds.extra_trackers.ssa15 must not redefine ssa15.trackers"):
        ss.tracker_settings(config, "ssa15")
    config = _config()
    config["ssa_seeds"]["births_reference"] = {"ssa15": "homht"}
    with pytest.raises(ValueError, match="must run with births and deaths"):
        ss.run_seed(config, 0, progress=None)


def test_run_seed_rows_on_a_short_realisation():
    config = _config(n_scans=5)
    config["ssa_seeds"]["trackers"] = {"ssa15": ["homht", "rfisst"]}
    rows, timing = ss.run_seed(config, 0, progress=None)
    # the two trackers and the blind tracker (the negative control, not timed: it runs no search)
    assert list(rows.columns) == ss.SEED_COLUMNS and len(rows) == 3 and len(timing) == 2
    r = rows.set_index("tracker")
    # the blind tracker keeps the 15 known objects: all weight on 15, no births; compared with HOMHT
    assert (r.loc["blind", "p_n_end"], r.loc["blind", "expected_number_end"]) == (1.0, 15.0)
    assert r.loc["blind", "reference"] == "homht" and r.loc["blind", "children_per_scan_mean"] == 0
    assert r.loc["homht", "reference"] == "" and np.isnan(r.loc["homht", "map_agreement"])
    assert r.loc["rfisst", "reference"] == "homht" and 0 <= r.loc["rfisst", "map_agreement"] <= 1
    # HOMHT runs with a fixed number of objects: all 15 known objects, all weight on 15.
    assert r.loc["homht", "n_catalogue_end"] == 15
    assert (r.loc["homht", "p_n_end"], r.loc["homht", "expected_number_error"]) == pytest.approx((1.0, 0.0), abs=1e-12)
    again, _ = ss.run_seed(config, 0, progress=None)
    pd.testing.assert_frame_equal(rows, again)


def test_run_seed_compares_the_trackers_with_births_and_deaths_with_homht_with_births_and_deaths():
    config = _config(n_scans=5)
    config["ssa_seeds"]["trackers"] = {"ssa15": ["homht", "rfisst", "rfisst_fixed", "homht_births"]}
    rows, timing = ss.run_seed(config, 0, progress=None)
    r = rows.set_index("tracker")
    assert len(timing) == 4
    # only the trackers with births and deaths (and the blind control) are compared with HOMHT with births
    assert r["births_reference"].to_dict() == {"homht": "", "rfisst": "homht_births", "rfisst_fixed": "",
                                               "homht_births": "", "blind": "homht_births"}
    assert np.isnan(r.loc[["homht", "rfisst_fixed", "homht_births"], "map_agreement_births"]).all()
    assert 0 <= r.loc["rfisst", "map_agreement_births"] <= 1
    # the births reference is a reference, not compared with the fixed-number HOMHT
    assert r.loc["homht_births", "reference"] == "" and np.isnan(r.loc["homht_births", "map_agreement"])
    # the blind tracker never uses a measurement: the same MAP as either HOMHT at the first scan only
    assert r.loc["blind", "map_agreement_births"] == r.loc["blind", "map_agreement"] == pytest.approx(0.2)
    # HOMHT with births and deaths may hold extra objects: E[N] >= 15, the 15 known objects still tracked
    assert r.loc["homht_births", "expected_number_end"] >= 15.0 - 1e-9
    again, _ = ss.run_seed(config, 0, progress=None)
    pd.testing.assert_frame_equal(rows, again)


def _per_seed(p_end, agreement):
    rows = []
    for i, (p, a) in enumerate(zip(p_end, agreement)):
        rows.append({"case": "ssa50", "seed_index": i, "tracker": "chain", "label": "R-FISST, paper chain",
                     "n_catalogue_end": 50, "expected_number_end": 49 + p, "expected_number_error": p - 1,
                     "p_n_end": p, "births": 5, "births_tracked_end": 5 - (i == 0), "birth_latency_mean": 2.0 + i,
                     "birth_latency_max": 3.0 + i, "reference": "", "map_agreement": np.nan,
                     "ospa_in_view_mean": 1.0, "ospa_catalogue_mean": 2.0, "children_per_scan_mean": 10.0})
        rows.append({"case": "ssa15", "seed_index": i, "tracker": "homht", "label": "HOMHT", "n_catalogue_end": 15,
                     "expected_number_end": 15.0, "expected_number_error": 0.0, "p_n_end": 1.0, "births": 0,
                     "births_tracked_end": 0, "birth_latency_mean": np.nan, "birth_latency_max": np.nan,
                     "reference": "", "map_agreement": np.nan, "ospa_in_view_mean": 1.0, "ospa_catalogue_mean": 2.0,
                     "children_per_scan_mean": 5.0})
        rows.append({**rows[-1], "tracker": "chain", "label": "R-FISST, paper chain", "reference": "homht",
                     "map_agreement": a})
    return pd.DataFrame(rows)


def test_distribution_table_quantiles_by_hand():
    d = ss.distribution_table(_per_seed([0.9, 1.0, 0.5, 0.7, 0.9], [1.0] * 5))
    row = d[(d["case"] == "ssa50") & (d["metric"] == "p_n_end")].iloc[0]
    # sorted 0.5 0.7 0.9 0.9 1.0: median 0.9, quartiles 0.7 and 0.9 (linear), q10 = 0.5 + 0.4 * 0.2
    assert (row["n"], row["min"], row["median"], row["max"]) == (5, 0.5, 0.9, 1.0)
    assert (row["q25"], row["q75"]) == pytest.approx((0.7, 0.9))
    assert row["q10"] == pytest.approx(0.58) and row["mean"] == pytest.approx(0.8)
    assert row["se"] == pytest.approx(np.std([0.9, 1.0, 0.5, 0.7, 0.9], ddof=1) / np.sqrt(5))
    assert d[(d["case"] == "ssa15") & (d["tracker"] == "homht") & (d["metric"] == "birth_latency_mean")].empty


def test_claims_apply_the_monte_carlo_rule_over_seeds():
    claims = {c.key: c for c in sc.ssa_seeds_claims(_per_seed([0.99, 1.0, 0.98, 1.0], [1.0, 1.0, 0.9, 1.0]))}
    p = claims["ssa50_chain_PEnd"]  # mean 0.9925, se 0.0048: interval +/- 5.51 * 0.0048 reaches below 0.95
    assert (p.status, p.n, p.evidence) == ("inconclusive", "4", "published number")
    assert float(p.z) == pytest.approx((0.9925 - 1) / (np.std([0.99, 1.0, 0.98, 1.0], ddof=1) / 2), abs=0.01)
    births = claims["ssa50_chain_Births"]
    assert births.status == "not reproduced" and births.reproduced.startswith("19 of 20 births")
    assert claims["ssa15_chain_Agreement"].status == "inconclusive"
    assert "ssa15_homht_Agreement" not in claims
    # ten seeds: the rule decides
    p_end = [0.99, 1.0, 0.98, 1.0, 0.99, 1.0, 0.98, 1.0, 0.99, 1.0]  # mean 0.993, se 0.0026: z = -2.69
    agree = [1.0, 1.0, 0.9, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]  # mean 0.99, se 0.01: z = -1
    ten = {c.key: c for c in sc.ssa_seeds_claims(_per_seed(p_end, agree))}
    assert (ten["ssa50_chain_PEnd"].status, ten["ssa50_chain_PEnd"].n) == ("reproduced", "10")
    ag = ten["ssa15_chain_Agreement"]
    # 0.99 +/- 4.094 * 0.01 straddles 1 - 0.01: |z| = 1 no longer reproduces; the note says what would decide
    assert ag.status == "inconclusive" and "HOMHT" in ag.item and float(ag.z) == pytest.approx(-1.0, abs=0.01)
    assert "runs would decide it" in ag.note
    # the single runs' rows of the same claims are illustrations with the same claim id (one verdict per claim)
    assert ag.claim == "000 ssa15, chain: same MAP hypothesis"
    assert ten["ssa50_chain_PEnd"].claim == "000 ssa50, chain: P(N = true number) at the end"
    bad = {c.key: c for c in sc.ssa_seeds_claims(_per_seed([0.5, 0.52, 0.48] * 4, [1.0] * 12))}["ssa50_chain_PEnd"]
    assert bad.status == "not reproduced"
    one = {c.key: c for c in sc.ssa_seeds_claims(_per_seed([1.0], [1.0]))}["ssa50_chain_PEnd"]
    assert one.status == "inconclusive" and "too few" in one.note


def _with_blind(per_seed, p_end=0.0, agreement=0.0):
    """Fabricated per-seed rows plus a blind tracker (the negative control) on every seed."""
    blind = per_seed[per_seed["tracker"] == "chain"].assign(tracker="blind", label="blind tracker")
    blind = blind.assign(p_n_end=np.where(blind["case"] == "ssa50", p_end, blind["p_n_end"]),
                         expected_number_end=np.where(blind["case"] == "ssa50", 45.0, blind["expected_number_end"]),
                         births_tracked_end=0, map_agreement=np.where(blind["case"] == "ssa15", agreement, np.nan))
    return pd.concat([per_seed, blind], ignore_index=True)


def test_over_seed_rows_name_the_blind_control_and_are_demoted_when_it_passes():
    p_end = [0.99, 1.0, 0.98, 1.0, 0.99, 1.0, 0.98, 1.0, 0.99, 1.0]
    agree = [1.0] * 10
    claims = {c.key: c for c in sc.ssa_seeds_claims(_with_blind(_per_seed(p_end, agree)))}
    assert not any(k.startswith(("ssa50_blind", "ssa15_blind")) for k in claims)  # the control has no rows
    p = claims["ssa50_chain_PEnd"]
    # the blind tracker keeps 45 objects: P(N = 50) = 0 on every seed, which the same rule rejects
    assert p.status == "reproduced" and p.control.endswith("-> fails") and "mean 0 over 10 seeds" in p.control
    e = claims["ssa50_chain_ExpectedEnd"]
    assert "mean 45" in e.control and e.control.endswith("-> fails")
    assert claims["ssa50_chain_Births"].control.endswith("no births): 0 of 50 births -> fails")
    assert claims["ssa15_chain_Agreement"].status == "reproduced"
    # a control that also passes (here: a "blind" agreeing with HOMHT at every scan) demotes the row
    demoted = {c.key: c for c in sc.ssa_seeds_claims(_with_blind(_per_seed(p_end, agree), p_end=1.0,
                                                                  agreement=1.0))}
    assert demoted["ssa15_chain_Agreement"].status == "uninformative"
    assert demoted["ssa15_chain_Agreement"].control.endswith("-> also passes")
    assert demoted["ssa50_chain_PEnd"].status == "uninformative"


def _with_births_pair(per_seed, agree_births, blind_births=0.0):
    """Fabricated rows of HOMHT with births and deaths and the chain's agreement with it."""
    per_seed = _with_blind(per_seed).assign(births_reference="", map_agreement_births=np.nan)
    ssa15 = per_seed["case"] == "ssa15"
    chain = ssa15 & (per_seed["tracker"] == "chain")
    blind = ssa15 & (per_seed["tracker"] == "blind")
    per_seed.loc[chain | blind, "births_reference"] = "homht_births"
    per_seed.loc[chain, "map_agreement_births"] = agree_births
    per_seed.loc[blind, "map_agreement_births"] = blind_births
    hb = per_seed[ssa15 & (per_seed["tracker"] == "homht")].assign(tracker="homht_births",
                                                                   label="HOMHT with births and deaths")
    return pd.concat([per_seed, hb], ignore_index=True)


def test_the_pair_with_births_and_deaths_on_both_sides_is_one_row_per_tracker():
    p_end = [0.99, 1.0, 0.98, 1.0, 0.99, 1.0, 0.98, 1.0, 0.99, 1.0]
    agree = [1.0, 0.9, 1.0, 1.0, 0.8, 1.0, 1.0, 1.0, 1.0, 1.0]  # against the fixed-number HOMHT
    births = [1.0] * 9 + [0.995]  # against HOMHT with births and deaths: mean 0.9995, se 0.0005
    claims = sc.ssa_seeds_claims(_with_births_pair(_per_seed(p_end, agree), births))
    by_key = {c.key: c for c in claims}
    assert len(by_key) == len(claims)  # one row per claim
    c = by_key["ssa15_chain_AgreementBirths"]
    assert c.item == "ssa15, R-FISST, paper chain: same MAP hypothesis as HOMHT with births and deaths (fraction of scans)"
    assert (c.n, float(c.mean), float(c.se)) == ("10", pytest.approx(0.9995), pytest.approx(0.0005))
    # interval 0.9995 +/- 4.094 * 0.0005 lies within 1 +/- 0.01: reproduced; the blind control (0) fails
    assert c.status == "reproduced" and c.control.endswith("-> fails") and "mean 0 over 10 seeds" in c.control
    assert c.claim == "000 ssa15, chain: same MAP hypothesis as HOMHT with births and deaths"
    assert "this project's construction" in c.note
    # the pair against the fixed-number HOMHT compares unlike models once the tracker has births and deaths:
    # an extension row (its numbers kept, mean 0.97), no verdict on document 000's claim, no cause
    unlike = by_key["ssa15_chain_Agreement"]
    assert (unlike.status, unlike.cause, float(unlike.mean)) == ("extension", "", pytest.approx(0.97))
    assert (unlike.published, unlike.tolerance, unlike.z, unlike.evidence) == ("--", "--", "", "measurement")
    assert "unlike population models" in unlike.note and unlike.note.endswith("against HOMHT with births and deaths)")
    # without the births reference (a tracker with a fixed number, or an old table) the same numbers get a verdict
    assert {c.key: c for c in sc.ssa_seeds_claims(_with_blind(_per_seed(p_end, agree)))}[
        "ssa15_chain_Agreement"].status == "inconclusive"
    # the births reference is not compared with anything; the fixed-number HOMHT has no row either
    assert not [k for k in by_key if k.startswith(("ssa15_homht", "ssa15_blind"))]
    # a control that also agrees demotes the row
    demoted = {c.key: c for c in sc.ssa_seeds_claims(_with_births_pair(_per_seed(p_end, agree), births,
                                                                        blind_births=1.0))}
    assert demoted["ssa15_chain_AgreementBirths"].status == "uninformative"
    # a table from before the pair existed gives the same rows as before
    old = {c.key for c in sc.ssa_seeds_claims(_with_blind(_per_seed(p_end, agree)))}
    assert old == set(by_key) - {"ssa15_chain_AgreementBirths"}

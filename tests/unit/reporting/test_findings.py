"""The findings' macros computed from results tables, on hand-made tables with hand-computed values."""

import pandas as pd
import pytest

from hypotrack.reporting.findings import (brute_jpda_macros, cause_count_macros, effect_macros, effect_words, interop_macros,
                                          paired_difference_macros, percent_text, rows_text, seed_spread_macros)


def test_seed_spread_is_the_range_over_seeds_of_the_larger_case_only():
    per_seed = pd.DataFrame({
        "case": ["ssa50"] * 6 + ["ssa15"] * 2,
        "seed_index": [0, 0, 1, 1, 2, 2, 0, 0],
        "tracker": ["rfisst_chain", "rfisst"] * 4,
        "p_n_end": [0.97, 0.93, 0.099, 0.87, 0.58, 0.9, 0.01, 0.02],  # ssa15's values must not count
    })
    m = seed_spread_macros(per_seed)
    assert m == {"htFindingsSeedsN": "3", "htFindingsSeedsChainPEndMin": "0.099", "htFindingsSeedsChainPEndMax": "0.97",
                 "htFindingsSeedsCompletionPEndMin": "0.87", "htFindingsSeedsCompletionPEndMax": "0.93"}
    with pytest.raises(ValueError, match="ssa99"):
        seed_spread_macros(per_seed, case="ssa99")


def test_causes_are_counted_with_their_noun_zero_and_one_included():
    ledger = pd.DataFrame({"status": ["not reproduced", "inconclusive", "inconclusive", "uninformative", "reproduced",
                                      "not reproduced"],
                           "cause": ["document", "", "too few runs", "", "", ""]})
    m = cause_count_macros(ledger)
    # the inconclusive row without a cause counts as too few runs, the uninformative one as no power, the
    # undiagnosed failure as open; the reproduced row is no failing row
    assert m["htFindingsCauseDocument"] == "one row" and m["htFindingsCauseTooFewRuns"] == "2 rows"
    assert m["htFindingsCauseNoPower"] == "one row" and m["htFindingsCauseOpen"] == "one row"
    assert m["htFindingsCauseUnstatedParameter"] == "no rows" and m["htFindingsFailingRows"] == "5 rows"
    assert [rows_text(n) for n in (0, 1, 2)] == ["no rows", "one row", "2 rows"]


def test_the_effect_is_described_by_its_numbers():
    assert effect_words(5.38, 7.2) == "a real but small effect"
    assert effect_words(5.38, 25) == "a real effect of this size"
    assert effect_words(-2.9, 7.2) == "no effect the runs can tell from noise"
    power = pd.DataFrame({"name": ["PowerRandomEveryDiff", "PowerRandomEveryDiffZ"], "value": ["+0.0106", "5.38"]})
    claims = pd.DataFrame({"key": ["MospaIdeal", "MospaMht"], "mean": ["0.04", "0.14728"]})
    # 0.0106 / 0.14728 = 7.197 %
    assert effect_macros(power, claims) == {"htFindingsRandomEffectPercent": "7.2",
                                            "htFindingsRandomEffectWords": "a real but small effect"}


def test_interop_overhead_in_percent_of_the_own_api():
    timing = pd.DataFrame({"algorithm": ["gnn", "homht"], "n_targets": [10, 10], "own_api_ms_per_scan": [0.0967603, 5.45],
                           "overhead": [2.43149, 0.102864]})
    m = interop_macros(timing)
    assert m["htFindingsInteropOverheadGnn"] == "243" and m["htFindingsInteropOverheadHomht"] == "10"
    assert m["htFindingsInteropOwnMsGnn"] == "0.097" and m["htFindingsInteropTargets"] == "10"
    assert [percent_text(x) for x in (243.149, 9.87, -0.44)] == ["243", "9.9", "-0.44"]


def test_brute_force_jpda_reach_is_the_largest_formation_it_was_run_on():
    timings = pd.DataFrame({"implementation": ["JPDA", "JPDA", "JPDA", "JPDA", "hypotrack"],
                            "n_targets": [4, 12, 12, 16, 24], "median_ms": [1.0, 8000.0, 9500.0, None, 0.3]})
    assert brute_jpda_macros(timings) == {"htFindingsBruteJpdaTargets": "12", "htFindingsBruteJpdaMs": "9500"}


def test_paired_differences_from_the_glmb_are_read_from_the_benchmark_notes():
    claims = pd.DataFrame({"key": ["OspaRfisstCompletion", "OspaGlmbReference", "OspaGlmb", ""],
                           "note": ["mean OSPA 13.16 +/- 0.22 m; OSPA minus glmb: +0.65 +/- 0.27 m",
                                    "OSPA minus glmb: -0.78 +/- 0.26 m", "mean OSPA 12.51 +/- 0.2 m",
                                    "OSPA minus glmb: +1 +/- 1 m"]})  # no key: no macro name, left out
    m = paired_difference_macros(claims)
    assert m == {"htFindingsGlmbDiffOspaRfisstCompletion": "+0.65", "htFindingsGlmbDiffSeOspaRfisstCompletion": "0.27",
                 "htFindingsGlmbDiffZOspaRfisstCompletion": "2.4",  # 0.65 / 0.27 = 2.41
                 "htFindingsGlmbDiffOspaGlmbReference": "-0.78", "htFindingsGlmbDiffSeOspaGlmbReference": "0.26",
                 "htFindingsGlmbDiffZOspaGlmbReference": "-3.0"}

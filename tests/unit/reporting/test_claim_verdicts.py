"""Claims, not rows: the verdict rule on hand-made ledgers, and the committed record against the README."""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd
import pytest
import yaml

from hypotrack.reporting.claim_sensitivity import FACTORS, sensitivity_summary, tolerance_sensitivity, write_sensitivity
from hypotrack.reporting.claim_tables import (claim_count_macros, claims_summary_tex, headline_text,
                                              sensitivity_tex)
from hypotrack.reporting.claim_verdicts import (CLAIM_VERDICTS, TOLERANCE_SOURCES, claim_verdicts, evidence_table,
                                                headline, load_claims_file, monte_carlo_mismatches,
                                                monte_carlo_status, placement_problems, row_key)
from hypotrack.reporting.claims import CLAIM_COLUMNS
from hypotrack.reporting.ledger_io import read_claims

ROOT = Path(__file__).resolve().parents[3]
RECORD = ROOT / "paper" / "record"
FAILS = "control: 1 -> fails"
PASSES = "control: 1 -> also passes"


def _row(key, status, evidence="published number", control=FAILS, experiment="x", **more) -> dict:
    row = dict.fromkeys(CLAIM_COLUMNS, "")
    row.update(experiment=experiment, item=key, key=key, status=status, evidence=evidence, control=control,
               source="000", published="1", reproduced="1", tolerance="exact")
    row.update(more)
    return row


def _spec(*claims, extensions=(), notes=()) -> dict:
    return {"claims": [{"id": cid, "document": "000", "where": "Eq. 1", "words": cid,
                        "tolerance": {"source": "chosen here"}, "evidence": list(ev)} for cid, ev in claims],
            "extensions": [{"id": gid, "words": gid, "rows": list(rows)} for gid, rows in extensions],
            "note_monte_carlo": list(notes)}


def _verdict(rows, evidence) -> str:
    ledger = pd.DataFrame(rows, columns=CLAIM_COLUMNS)
    return claim_verdicts(ledger, _spec(("c", evidence))).set_index("id").loc["c", "verdict"]


def test_a_calibration_only_claim_is_not_reproduced():
    rows = [_row("cal", "reproduced", evidence="calibration"), _row("ident", "consistency check",
                                                                    evidence="identity of the implementation")]
    assert _verdict(rows, ["x/cal", "x/ident"]) == "consistency only"
    # a comparison with the project's own closed form, declared in the claims file, is not a reproduction either
    assert _verdict([_row("own", "reproduced", evidence="independent oracle")],
                    [{"row": "x/own", "role": "own closed form"}]) == "consistency only"
    # one independent reproduced row next to the calibrations makes it reproduced
    assert _verdict(rows + [_row("ind", "reproduced")], ["x/cal", "x/ident", "x/ind"]) == "reproduced"


def test_reproduced_and_not_reproduced_under_the_same_reading_are_contested():
    rows = [_row("a", "reproduced"), _row("b", "not reproduced")]
    assert _verdict(rows, ["x/a", "x/b"]) == "contested"
    # under two readings the claim holds in part
    assert _verdict(rows, [{"row": "x/a", "reading": "uniform"}, {"row": "x/b", "reading": "Gaussian"}]) == \
        "reproduced in part"


def test_the_remaining_branches():
    assert _verdict([_row("a", "not reproduced"), _row("b", "inconclusive")], ["x/a", "x/b"]) == "not reproduced"
    assert _verdict([_row("a", "qualitative"), _row("b", "inconclusive")], ["x/a", "x/b"]) == "qualitative"
    assert _verdict([_row("a", "inconclusive"), _row("b", "uninformative", control=PASSES)], ["x/a", "x/b"]) == \
        "inconclusive"
    assert _verdict([_row("a", "uninformative", control=PASSES)], ["x/a"]) == "uninformative"
    # a reproduced row without a failing control, or with a vacuous one, decides nothing
    assert _verdict([_row("a", "reproduced", control="")], ["x/a"]) == "uninformative"
    assert _verdict([_row("a", "inconclusive")], [{"row": "x/a", "role": "vacuous"}]) == "uninformative"
    # illustrations carry no verdict; a claim without rows in the ledger was not run
    assert _verdict([_row("a", "illustration"), _row("b", "reproduced")], ["x/a", "x/b"]) == "reproduced"
    assert _verdict([_row("a", "reproduced")], ["x/missing"]) == "not run"


def test_extension_rows_are_never_counted_among_the_documents_verdicts():
    ledger = pd.DataFrame([_row("a", "reproduced"), _row("g", "reproduced", experiment="glmb_benchmark"),
                           _row("h", "not reproduced", experiment="glmb_benchmark")], columns=CLAIM_COLUMNS)
    spec = _spec(("c", ["x/a"]), extensions=[("extension.delta_glmb", ["glmb_benchmark/g", "glmb_benchmark/h"])])
    verdicts = claim_verdicts(ledger, spec)
    counts = headline(verdicts, ledger, spec)
    assert counts["claims"] == 1 and counts["reproduced"] == 1 and counts["not reproduced"] == 0
    assert counts["extension_rows"] == 2 and counts["extension_groups"] == 1
    assert placement_problems(ledger, spec) == []
    assert "1 claims of the five documents: **1 reproduced**" in headline_text(counts)


def test_placement_names_rows_left_out_and_rows_placed_twice():
    ledger = pd.DataFrame([_row("a", "reproduced"), _row("b", "extension")], columns=CLAIM_COLUMNS)
    problems = placement_problems(ledger, _spec(("c", ["x/a"]), ("d", ["x/a", "x/gone"])))
    assert "row x/b is placed in no claim and no extension group" in problems
    assert "row x/a is placed in 2 places (c, d)" in problems
    assert "row x/gone is named by d but is not in the ledger" in problems


def test_a_monte_carlo_row_takes_the_rules_status_and_its_numbers_may_sit_in_the_note():
    mc = _row("m", "reproduced", n="10", mean="0.134", se="0.015", published="0.1",
              tolerance="99.73 % interval within +/- 0.05", z="2.27")
    # 0.134 +/- 4.09 * 0.015 straddles 0.15: inconclusive, whatever the row says
    assert monte_carlo_status(mc) == "inconclusive" and monte_carlo_status(mc, factor=4) == "reproduced"
    ledger = pd.DataFrame([mc], columns=CLAIM_COLUMNS)
    assert monte_carlo_mismatches(ledger, _spec()).to_dict("records") == [
        {"row": "x/m", "recorded": "reproduced", "recomputed": "inconclusive", "why": ""}]
    note = {"row": "x/n", "n": 100, "mean": 0.134, "se": 0.015, "published": 0, "tolerance": 0.1, "why": "straddles"}
    ledger = pd.DataFrame([_row("n", "not reproduced", evidence="measurement")], columns=CLAIM_COLUMNS)
    spec = _spec(("c", ["x/n"]), notes=[note])
    assert evidence_table(ledger, spec)["status"].tolist() == ["inconclusive"]
    assert monte_carlo_mismatches(ledger, spec)["why"].tolist() == ["straddles"]


def test_the_sensitivity_table_recomputes_chosen_tolerances(tmp_path):
    mc = _row("m", "reproduced", n="1000", mean="1.02", se="0.001", published="1",
              tolerance="99.73 % interval within +/- 0.05", z="20")
    ledger = pd.DataFrame([mc], columns=CLAIM_COLUMNS)
    table = write_sensitivity(ledger, tmp_path / "sensitivity.csv", _spec(("c", ["x/m"])))
    by = table.set_index("factor")["verdict"]
    assert by[1.0] == "reproduced" and by[0.25] == "not reproduced" and by[4.0] == "reproduced"
    assert sorted(table["factor"]) == sorted(FACTORS)
    assert pd.read_csv(tmp_path / "sensitivity.csv")["verdict"].tolist() == table["verdict"].tolist()
    assert sensitivity_summary(table).set_index("factor")["changed"].to_dict() == {
        0.25: 1, 0.5: 0, 1.0: 0, 2.0: 0, 4.0: 0}
    assert r"\emph{not reproduced}" in sensitivity_tex(table)


# ------------------------------------------------------------------ the committed record


@pytest.fixture(scope="module")
def record():
    ledger = read_claims([RECORD / "ledger.csv"])
    timing = read_claims([RECORD / "ledger_timing.csv"])
    spec = load_claims_file()
    return ledger, timing, spec, claim_verdicts(ledger, spec, timing)


def test_every_non_timing_row_belongs_to_exactly_one_claim_or_extension_group(record):
    ledger, timing, spec, _ = record
    assert placement_problems(ledger, spec, timing) == []


def test_the_readme_headline_is_the_records_counts_per_claim(record):
    ledger, timing, spec, verdicts = record
    counts = headline(verdicts, ledger, spec, timing)
    readme = (ROOT / "README.md").read_text()
    assert headline_text(counts) in readme
    stated = re.search(r"(\d+) claims of the five documents: (.*?); beyond them", readme)
    assert int(stated.group(1)) == counts["claims"] == len(spec["claims"])
    for n, verdict in re.findall(r"\*\*(\d+) ([a-z ]+)\*\*", stated.group(2)):
        assert int(n) == int((verdicts["verdict"] == verdict).sum()), verdict
    assert sum(counts[v] for v in CLAIM_VERDICTS) == counts["claims"]


def test_no_reproduced_claim_rests_only_on_calibration_identity_or_own_closed_form(record):
    ledger, timing, spec, verdicts = record
    table = evidence_table(ledger, spec, timing)
    positive = verdicts[verdicts["verdict"].isin(("reproduced", "reproduced in part", "qualitative"))]
    for cid in positive["id"]:
        ev = table[table["claim"] == cid]
        assert ((ev["role"] == "independent") & ev["status"].isin(("reproduced", "qualitative"))).any(), cid
    # Table 6.1's ideal value: calibrations and the project's own closed form only
    assert verdicts.set_index("id").loc["003.table6.1.ideal", "verdict"] == "consistency only"


def test_no_row_status_contradicts_the_monte_carlo_rule_unless_explained(record):
    ledger, timing, spec, _ = record
    mismatches = monte_carlo_mismatches(pd.concat([ledger, timing]), spec)
    unexplained = mismatches[mismatches["why"] == ""]
    assert unexplained.empty, unexplained.to_string()
    # the two GLMB cardinality rows (0.106 +/- 0.029 and 0.134 +/- 0.015 against 0.1, their numbers in the note):
    # intervals straddling the threshold are inconclusive; the record made before the experiment followed the
    # rule says not reproduced
    notes = {e["row"]: e for e in spec["note_monte_carlo"]}
    assert set(mismatches["row"]) <= set(notes) == {"glmb_benchmark/FollowsGlmb", "glmb_benchmark/FollowsGlmbReference"}
    assert set(mismatches["recomputed"]) <= {"inconclusive"}
    table = evidence_table(ledger, spec, timing)
    assert table[table["row"].isin(notes)].empty  # extensions: in no claim
    # both are extensions (delta-GLMB): never among the documents' verdicts
    ext = {r for g in spec["extensions"] for r in g["rows"]}
    assert set(mismatches["row"]) <= ext


def test_a_vacuous_check_is_not_evidence(record):
    ledger, timing, spec, verdicts = record
    table = evidence_table(ledger, spec, timing).set_index("row")
    assert table.loc["generation_time/diffChainHardPaper", "status"] == "uninformative"
    assert verdicts.set_index("id").loc["000.fig15.rfisst_reach", "verdict"] == "uninformative"


def test_every_claim_names_its_tolerance_source_and_every_extension_stays_out(record):
    ledger, timing, spec, verdicts = record
    assert set(verdicts["tolerance_source"]) <= set(TOLERANCE_SOURCES)
    assert all(c["tolerance"].get("reason") for c in spec["claims"])
    named = {e if isinstance(e, str) else e["row"] for c in spec["claims"] for e in c["evidence"]}
    rows = {row_key(r): r for r in ledger.to_dict("records")}
    for key in named & set(rows):
        r = rows[key]
        assert not r["source"].startswith("extension") and "GLMB" not in r["item"], key
    assert not {"glmb_benchmark", "ssa_catalogue", "samplers"} & {k.split("/")[0] for k in named}


def test_the_sensitivity_table_and_the_papers_claims_table_from_the_record(record, tmp_path):
    ledger, timing, spec, verdicts = record
    table = tolerance_sensitivity(ledger, spec, timing)
    assert {"003.table6.1.mht", "003.table6.1.ecmht", "000.fig11.p_end"} <= set(table["claim"])
    assert not table[table["factor"] == 1.0]["changed"].any()
    counts = headline(verdicts, ledger, spec, timing)
    tex = claims_summary_tex(verdicts, counts)
    macros = claim_count_macros(verdicts, counts)
    used = set(re.findall(r"\\htval\{(\w+)\}", tex))
    assert used <= set(macros) and len(macros) == len(set(macros))
    assert not re.search(r"(?<![\\\w{])\d+ (?:reproduced|claims)", tex)  # counts only through macros


def test_the_papers_claim_counts_are_generated_macros(record):
    ledger, timing, spec, verdicts = record
    macros = claim_count_macros(verdicts, headline(verdicts, ledger, spec, timing))
    sections = ROOT / "paper" / "sections"
    used = {m for p in sections.rglob("*.tex") for m in re.findall(r"\\ht(?:val|n)\{(htDocumentClaims?\w*)\}", p.read_text())}
    assert {"htDocumentClaimsTotal", "htDocumentClaimsReproduced", "htDocumentClaimsNotReproduced"} <= used <= set(macros)
    # distinct from the ledger's row counts (htClaims<Status>): the paper's build refuses a macro defined twice
    from hypotrack.reporting.macros import claim_macros

    assert not set(macros) & set(claim_macros(pd.concat([ledger, timing])))
    assert r"\input{generated/claims_summary.tex}" in (ROOT / "paper" / "ms.tex").read_text()


def test_a_table_reproduces_only_under_one_reading_of_all_its_entries():
    """Two entries of one table, each reproduced under a different scoring window and inconclusive under the
    other: no one reading reproduces the table, so neither entry is reproduced; with one common reading
    that reproduces both, both are reproduced (and judged on that reading's rows only)."""
    def verdicts(statuses):
        rows = [_row(f"{e}_{r}", s) for (e, r), s in statuses.items()]
        spec = _spec(*[(e, [{"row": f"x/{e}_{r}", "reading": r} for (e2, r) in statuses if e2 == e])
                       for e in ("mht", "ecmht")])
        for c in spec["claims"]:
            c["table"] = "T"
        v = claim_verdicts(pd.DataFrame(rows, columns=CLAIM_COLUMNS), spec).set_index("id")["verdict"]
        return v["mht"], v["ecmht"]

    crossed = {("mht", "all"): "inconclusive", ("mht", "late"): "reproduced",
               ("ecmht", "all"): "reproduced", ("ecmht", "late"): "inconclusive"}
    assert verdicts(crossed) == ("inconclusive", "inconclusive")
    common = {("mht", "all"): "inconclusive", ("mht", "late"): "reproduced",
              ("ecmht", "all"): "reproduced", ("ecmht", "late"): "reproduced"}
    assert verdicts(common) == ("reproduced", "reproduced")
    failing = {("mht", "all"): "not reproduced", ("mht", "late"): "reproduced",
               ("ecmht", "all"): "reproduced", ("ecmht", "late"): "reproduced"}
    assert verdicts(failing) == ("reproduced", "reproduced")  # the late window reproduces the table


def test_joint_rows_decide_together_a_verdict_over_two_sources_of_randomness(tmp_path):
    def joint(*rows):
        return [{"row": f"x/{r}", "joint": "j"} for r in rows]

    # reproduced over one source, not over the other: the claim is not reproduced (not merely contested)
    rows = [_row("seeds", "reproduced"), _row("chains", "not reproduced")]
    assert _verdict(rows, joint("seeds", "chains")) == "not reproduced"
    assert _verdict(rows, ["x/seeds", "x/chains"]) == "contested"
    # an undecided source leaves the claim undecided: the positive member takes its status
    rows = [_row("seeds", "reproduced"), _row("chains", "inconclusive")]
    assert _verdict(rows, joint("seeds", "chains")) == "inconclusive"
    assert _verdict(rows, ["x/seeds", "x/chains"]) == "reproduced"
    ev = evidence_table(pd.DataFrame(rows, columns=CLAIM_COLUMNS), _spec(("c", joint("seeds", "chains"))))
    assert ev[["row", "ledger_status", "status"]].values.tolist() == [["x/seeds", "reproduced", "inconclusive"],
                                                                      ["x/chains", "inconclusive", "inconclusive"]]
    # positive over both: reproduced; a row outside the joint keeps its own say
    rows = [_row("seeds", "reproduced"), _row("chains", "reproduced"), _row("other", "reproduced")]
    assert _verdict(rows, joint("seeds", "chains")) == "reproduced"
    rows = [_row("seeds", "reproduced"), _row("chains", "not reproduced"), _row("other", "reproduced")]
    assert _verdict(rows, [*joint("seeds", "chains"), {"row": "x/other", "reading": "other"}]) == "reproduced in part"
    # an illustration in the group decides nothing
    rows = [_row("seeds", "reproduced"), _row("single", "illustration")]
    assert _verdict(rows, joint("seeds", "single")) == "reproduced"
    # a joint naming one entry is a mistake of the claims file
    path = tmp_path / "claims.yaml"
    path.write_text(yaml.safe_dump(_spec(("c", joint("seeds")))))
    with pytest.raises(ValueError, match="c: joint 'j' must name at least two evidence entries"):
        load_claims_file(path)

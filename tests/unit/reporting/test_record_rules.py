"""The committed record (``paper/record/``) against the report's rules, and the headline counts recomputed
by hand from the ledger's claim keys against every place that prints them (README block, generated LaTeX)."""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pandas as pd
import pytest
import yaml

from hypotrack.reporting.claim_tables import claim_count_macros, claims_summary_tex
from hypotrack.reporting.claim_verdicts import (CLAIM_VERDICTS, TOLERANCE_SOURCES, claim_verdicts, evidence_table,
                                                headline, load_claims_file)
from hypotrack.reporting.claims import NEEDS_CONTROL
from hypotrack.reporting.ledger_io import read_claims
from hypotrack.reporting.macros import macro_name
from hypotrack.reporting.readme import BEGIN, END

ROOT = Path(__file__).resolve().parents[3]
RECORD = ROOT / "paper" / "record"
@pytest.fixture(scope="module")
def record():
    ledger = read_claims([RECORD / "ledger.csv"])
    timing = read_claims([RECORD / "ledger_timing.csv"])
    return ledger, timing, load_claims_file()


def _recount(ledger: pd.DataFrame, timing: pd.DataFrame, spec: dict) -> Counter:
    """The verdict of every claim of the claims file, recounted from the ledger's claim keys: each claim's
    evidence rows are looked up by ``experiment/key`` in the ledger, and the claim counted once under the
    verdict the rule gives it (claims without a row count as 'not run'; timing rows are rows too)."""
    keys = {f"{r['experiment']}/{r['key'] or r['item']}" for r in pd.concat([ledger, timing]).to_dict("records")}
    verdicts = claim_verdicts(ledger, spec, timing).set_index("id")["verdict"]
    counted = Counter()
    for claim in spec["claims"]:
        rows = {e if isinstance(e, str) else e["row"] for e in claim["evidence"]}
        counted[verdicts[claim["id"]] if rows & keys else "not run"] += 1
    return counted


def test_headline_counts_recomputed_from_claim_keys_match_the_readme_and_the_generated_tex(record):
    ledger, timing, spec = record
    counted = _recount(ledger, timing, spec)
    assert sum(counted.values()) == len(spec["claims"]) == len({c["id"] for c in spec["claims"]})
    verdicts = claim_verdicts(ledger, spec, timing)
    counts = headline(verdicts, ledger, spec, timing)
    assert {v: counts[v] for v in CLAIM_VERDICTS} == {v: counted.get(v, 0) for v in CLAIM_VERDICTS}
    # the README block: its headline and its table's verdicts, one row per claim
    readme = (ROOT / "README.md").read_text()
    block = readme.split(BEGIN)[1].split(END)[0]
    stated = re.search(r"(\d+) claims of the five documents: (.*?);", block)
    assert int(stated.group(1)) == len(spec["claims"])
    for n, verdict in re.findall(r"\*\*(\d+) ([a-z ]+)\*\*", stated.group(2)):
        assert int(n) == counted.get(verdict, 0), verdict
    table = Counter(re.findall(r"^\| 00[0-4] \|.*\| \*\*([a-z ]+)\*\* \|$", block, re.M))
    assert table == Counter({v: n for v, n in counted.items() if n})
    # the report: the macros the abstract and page one quote, and the first-page table's rows
    macros = claim_count_macros(verdicts, counts)
    assert int(macros[macro_name("document claims", "total")]) == len(spec["claims"])
    for v in CLAIM_VERDICTS:
        assert int(macros[macro_name("document claims", v)]) == counted.get(v, 0), v
    tex = claims_summary_tex(verdicts, counts)
    rows = re.findall(r"& ([a-z ]+) & \\htval\{htDocumentClaimRows\w+\}\\tabularnewline", tex)
    assert Counter(rows) == Counter({v: n for v, n in counted.items() if n})
    abstract = (ROOT / "paper" / "sections" / "abstract.tex").read_text()
    for v in ("total", "reproduced", "not reproduced"):
        assert macro_name("document claims", v) in abstract, v


def test_no_reproduced_row_rests_on_a_calibration_an_identity_or_the_projects_own_closed_form(record):
    ledger, timing, spec = record
    evidence = evidence_table(ledger, spec, timing)
    calibration_rows = set(ledger.loc[ledger["evidence"].isin(["calibration", "identity of the implementation"]),
                                      "experiment"] + "/" + ledger.loc[ledger["evidence"].isin(
                                          ["calibration", "identity of the implementation"]), "key"])
    reproduced = set(ledger.loc[ledger["status"] == "reproduced", "experiment"] + "/"
                     + ledger.loc[ledger["status"] == "reproduced", "key"])
    assert not calibration_rows & reproduced  # a calibration that passes has its own status, 'calibration'
    assert {k for k in calibration_rows if k.startswith('closely_spaced/')} >= {
        'closely_spaced/MospaIdeal', 'closely_spaced/MospaIdealLabelled', 'closely_spaced/IdealSteadyState'}
    # the claims table never counts such a row as a reproduction, whatever its recorded status
    dependent = evidence[evidence["role"].isin(["calibration", "identity", "own closed form"])]
    assert not dependent.empty and not dependent["status"].isin(["reproduced", "qualitative"]).any()
    # and a claim with a positive verdict has an independent row that reproduces it
    verdicts = claim_verdicts(ledger, spec, timing).set_index("id")["verdict"]
    for cid, verdict in verdicts.items():
        if verdict in ("reproduced", "reproduced in part", "qualitative"):
            own = evidence[evidence["claim"] == cid]
            assert ((own["role"] == "independent") & own["status"].isin(["reproduced", "qualitative"])).any(), cid


def test_every_row_with_a_verdict_has_a_tolerance_and_a_failing_control_and_every_claim_a_tolerance_source(record):
    ledger, _, spec = record
    judged = ledger[ledger["status"].isin(["reproduced", "not reproduced", "inconclusive", "uninformative",
                                           "qualitative"])]
    assert not judged.empty
    for r in judged.to_dict("records"):
        assert r["tolerance"] not in ("", "--"), f"{r['experiment']}/{r['key']}: no tolerance"
        assert r["evidence"], f"{r['experiment']}/{r['key']}: no evidence"
    for r in ledger[ledger["status"].isin(NEEDS_CONTROL)].to_dict("records"):
        assert "fails" in r["control"] and "also passes" not in r["control"], f"{r['experiment']}/{r['key']}"
    raw = yaml.safe_load((ROOT / "src" / "hypotrack" / "reporting" / "document_claims.yaml").read_text())
    for claim in raw["claims"]:
        tol = claim["tolerance"]
        assert tol["source"] in TOLERANCE_SOURCES and tol.get("reason"), claim["id"]

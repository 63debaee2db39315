"""The report's generated text: status counts that add up, every status defined, every failing row discussed."""

from __future__ import annotations

import pandas as pd

from hypotrack.reporting.ledger import STATUSES, numeric_claim, read_claims, write_claims
from hypotrack.reporting.sections import gap_label, FAILING, gaps_tex, monte_carlo_rule_tex, status_summary_tex
from hypotrack.reporting.verdict import with_control


def _ledger(tmp_path) -> pd.DataFrame:
    rows = [with_control(numeric_claim("theory", "A(10, 5)", "000 Eq. 4", 63591, 63591, abs_tol=0,
                                       evidence="brute force", key="count"), "without n!", "638", passes=False),
            numeric_claim("closely_spaced", "PDAF MOSPA", "003 Table 6.1", 0.8518, 0.2198, rel_tol=0.1,
                          note="the multi-sensor PDAF is unstated", key="pdaf"),
            with_control(numeric_claim("ssa15", "no red stars", "000 Figs 12-14", 15, 15, abs_tol=0, key="stars"),
                         "blind tracker", "15/15", passes=True)]
    write_claims(rows, tmp_path / "claims.csv")
    return read_claims([tmp_path / "claims.csv"])


def test_status_counts_add_up_and_every_status_is_defined(tmp_path):
    ledger = _ledger(tmp_path)
    text = status_summary_tex(ledger)
    assert text.startswith(r"Of the ledger's 3 rows, \textbf{1 reproduced}, \textbf{1 not reproduced}, "
                           r"\textbf{0 inconclusive}, \textbf{1 uninformative}")
    assert sum(int(text.split(rf"{s}}}")[0].rsplit(r"\textbf{", 1)[1].split()[0]) for s in STATUSES) == 3
    for status in STATUSES:
        assert rf"\item[{status}]" in text
    assert "99.73" in text and "4.09 for ten" in monte_carlo_rule_tex()


def test_every_failing_row_is_discussed(tmp_path):
    ledger = _ledger(tmp_path)
    text = gaps_tex(ledger)
    for r in ledger[ledger["status"].isin(FAILING)].to_dict("records"):
        assert rf"\textbf{{{r['item']}}}\label{{{gap_label(r)}}}" in text
    assert "PDAF MOSPA" in text and "The multi-sensor PDAF is unstated" in text and "closely\\_spaced; 003 Table 6.1" in text
    assert "no red stars" in text and r"blind tracker: 15/15 \ensuremath{\to} also passes" in text
    assert "A(10, 5)" not in text  # a reproduced row is not a gap


def test_the_committed_record_has_a_discussion_for_every_failing_row():
    from pathlib import Path

    record = Path(__file__).resolve().parents[3] / "paper" / "record"
    ledger = read_claims([record / "ledger.csv", record / "ledger_timing.csv"])
    text = gaps_tex(ledger)
    failing = ledger[ledger["status"].isin(FAILING)]
    assert all(gap_label(r) in text for r in failing.to_dict("records"))

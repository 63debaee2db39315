"""The report's generated text: mathematics typeset, every failing row discussed, no garbled phrase."""

import pandas as pd
import pytest

from hypotrack.reporting.latex_text import ASCII_MATH, latex_text
from hypotrack.reporting.ledger import CAUSES, Claim, claims_table_tex, ledger_problems, read_claims
from hypotrack.reporting.paper import text_problems
from hypotrack.reporting.sections import FAILING, gap_cause, gap_label, gaps_tex


@pytest.mark.parametrize("plain, tex", [
    ("P[Bin(M, p_D) <= m]", r"P[Bin(M, \ensuremath{p_{D}}) \ensuremath{\le} m]"),
    ("1 - p_D**3", r"1 \ensuremath{-} \ensuremath{p_{D}}\ensuremath{^{3}}"),
    ("(1 - 3.9e-22) (1 - p_D)", r"(1 \ensuremath{-} \ensuremath{3.9\times10^{-22}}) (1 \ensuremath{-} \ensuremath{p_{D}})"),
    ("target >= 1e+06", r"target \ensuremath{\ge} \ensuremath{10^{6}}"),
    ("0.37 +/- 0.11 m", r"0.37 \ensuremath{\pm} 0.11 m"),
    ("H_inf = 100", r"\ensuremath{H_{\infty}} = 100"),
    ("λ_b/p_χ", r"\ensuremath{\lambda_{b}}/\ensuremath{p_{\chi}}"),
    ("mean |N̂ − N|", r"mean |\ensuremath{\hat{N}} \ensuremath{-} N|"),
    ("10⁶ runs, x₀", r"10\ensuremath{^{6}} runs, x\ensuremath{_{0}}"),
    ("45 -> 46", r"45 \ensuremath{\to} 46"),
    ("the constant e^(-lambda V)", r"the constant e\ensuremath{^{-{\lambda} V}}"),
    ("normalising e^(-λV)", r"normalising e\ensuremath{^{-{\lambda}V}}"),
    ("alpha*(1 - p_D), 2^k", r"\ensuremath{\alpha}*(1 \ensuremath{-} \ensuremath{p_{D}}), 2\ensuremath{^{k}}"),
    # the ledger notes' ASCII forms: hats, bars, exp(), sqrt, infinity, and a hyphen used as a minus sign
    ("mean |n-hat - n|", r"mean |\ensuremath{\hat{n}} \ensuremath{-} n|"),
    ("binomial limit exp(-lambdaV) vs 1", r"binomial limit \ensuremath{e^{-{\lambda V}}} vs 1"),
    ("exp(-V*lambda)", r"\ensuremath{e^{-V {\lambda}}}"),
    ("1/Vbar, limit M -> oo", r"1/\ensuremath{\bar{V}}, limit M \ensuremath{\to} \ensuremath{\infty}"),
    ("2 sqrt(2)", r"2 \ensuremath{\surd}(2)"),
    ("z = -1.37, -49 %", r"z = \ensuremath{-}1.37, \ensuremath{-}49 \%"),
    ("well-known x-1", "well-known x-1"),
    # code names, percentages and hashes stay text
    ("rfisst_chain at 50 % (c_in_view)", r"rfisst\_chain at 50 \% (c\_in\_view)"),
    ("commit 95e7490", "commit 95e7490"),
])
def test_latex_text_typesets_plain_mathematics(plain, tex):
    assert latex_text(plain) == tex
    assert not ASCII_MATH.search(latex_text(plain))


def test_ascii_math_pattern_finds_what_latex_text_removes():
    for plain in ("p_D <= 1", "1e+06", "x**2", "+/- 3", "n-hat", "Vbar", "exp(-lambdaV)", "sqrt(2)", "M -> oo",
                  "lambdaV"):
        from hypotrack.reporting.latex_text import latex_escape
        assert ASCII_MATH.search(latex_escape(plain)), plain


def _claim(key, status, claim="", cause="", item=None, n="", note="a note"):
    return Claim("exp", item or f"item {key}", "000 Eq. 9", "1", "0.5", "+/- 0.1", status, note=note,
                 evidence="published number", key=key, claim=claim, cause=cause, n=n,
                 mean="0.5" if n else "", se="0.1" if n else "", z="-5" if n else "")


def _frame(claims):
    from dataclasses import asdict
    return pd.DataFrame([asdict(c) for c in claims]).fillna("")


def test_every_failing_row_is_discussed_by_its_label():
    rows = _frame([_claim("A", "not reproduced", cause="document"), _claim("B", "reproduced"),
                   _claim("C", "inconclusive", claim="c1"), _claim("D", "not reproduced", claim="c1",
                                                                     cause="unstated parameter"),
                   _claim("E", "uninformative"), _claim("F", "not reproduced")])
    tex = gaps_tex(rows)
    for r in rows.to_dict("records"):
        assert (gap_label(r) in tex) == (r["status"] in FAILING), r["key"]
    # grouped by cause, the cause defaults for inconclusive/uninformative, an undiagnosed row is said so
    assert gap_cause(rows.iloc[2]) == "too few runs" and gap_cause(rows.iloc[4]) == "no power"
    assert tex.index("the document's own claim"[1:]) < tex.index("parameter the document does not state")
    assert "Not yet diagnosed" in tex
    assert tex.count(r"\paragraph{}") == 5


def test_every_failing_row_of_the_committed_ledger_is_discussed():
    ledger = read_claims(["paper/record/ledger.csv"])
    tex = gaps_tex(ledger)
    failing = ledger[ledger["status"].isin(FAILING)]
    assert len(failing) > 0
    for r in failing.to_dict("records"):
        assert gap_label(r) in tex, r["item"]
    assert not ASCII_MATH.search(tex)


def test_rows_of_one_claim_share_one_paragraph():
    rows = _frame([_claim("C", "inconclusive", claim="c1"), _claim("D", "inconclusive", claim="c1"),
                   _claim("G", "inconclusive")])
    assert gaps_tex(rows).count(r"\paragraph{}") == 2


def test_cause_is_checked():
    with pytest.raises(ValueError, match="cause must be one of"):
        _claim("A", "not reproduced", cause="bad luck")
    problems = ledger_problems(_frame([_claim("A", "not reproduced")]))
    assert any("names no cause" in p for p in problems)
    assert set(CAUSES) >= {"document", "unstated parameter", "project choice", "too few runs", "no power"}


def test_ledger_table_is_captioned_numbered_and_unhyphenated():
    tex = claims_table_tex(_frame([_claim("A", "not reproduced", cause="document", note="1 - p_D**3 for M <= m")]))
    assert r"\caption{" in tex and r"\label{tab:ledger}" in tex and r"\endfirsthead" in tex
    assert r"\hyphenpenalty=10000\textcolor" in tex  # the verdict cell only
    assert not ASCII_MATH.search(tex)


@pytest.mark.parametrize("garbled, rule", [
    ("the crossover with enumeration is at crossover at A = 1e5.1", "'at ... at'"),
    ("a streamed run peaks at peak 8.3 MiB over", "echoed"),
    ("which is the the point", "repeated word"),
    ("equals P[Bin(M, p_D) <= m] exactly", "ASCII"),
    ("target >= 1e+06 proposals", "ASCII"),
    ("as shown in [lec, n.d.] and", "citation"),
    ("the R-FISST reach (seed 000 Fig 15)", "seed 000"),
    ("value {name} left", "template"),
    # ASCII notation copied from the ledger's notes, and templates that neither pluralise nor guard a value
    ("mean |n-hat - n| 11.7", "ASCII mathematics from a note"),
    ("binomial limit exp(-lambdaV) vs 1", "ASCII mathematics from a note"),
    ("the limit M -> oo of", "ASCII mathematics from a note"),
    ("peak density <= 1/Vbar, or", "ASCII mathematics from a note"),
    ("erf(2 sqrt(2 (Q + R)))", "ASCII mathematics from a note"),
    ("the literal p\\_D in text", "ASCII mathematics from a note"),
    ("z = -1.37 against", "minus sign"),
    ("OSPA minus glmb: -0.78 m", "minus sign"),
    ("as shown [Faber et al., n.d.] and", "without a date"),
    ("[untitled in the source text] a randomized", "without a date"),
    ("1 distinct objects came into view", "wrong number"),
    ("at about 1 runs per", "wrong number"),
    ("born at scan – moving at – m/s", "value missing"),
])
def test_text_problems_catch_garbled_phrases(garbled, rule):
    found = text_problems("Some text. " + garbled + " More text.")
    assert any(rule in f for f in found), found


def test_clean_text_has_no_problems():
    text = ("The R-FISST reach on document 000's problem is 10^52; a streamed run peaks at 8.3 MiB. "
            "Crossover with enumeration: A = 10^5.1 (document: near 10^4–10^5). rfisst and HOMHT agree at "
            "every scan; p D ≤ 1 [Orguner, 2010]; z = −1.37 over 1 run, about 1 run, 2 runs; the well-known "
            "x-ray; the object born at scan 20 moving at 12 m/s.")
    assert text_problems(text) == []

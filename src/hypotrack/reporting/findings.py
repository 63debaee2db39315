r"""Numbers the report's findings and discussion quote that no experiment writes as a macro.

Every number in the report comes from ``results/``; a few the findings section needs are spreads over
the rows of a results table rather than a single value, so they are computed here from the tables the
experiments already wrote and become macros like any other (``\htFindings...``):

* :func:`seed_spread_macros`: over the scenario seeds of ``ssa_seeds/per_seed.csv``, the least and
  the largest probability the larger SSA run ends with the true number of objects, per R-FISST
  variant (document 000's Fig. 11 claims 1 at the end);
* :func:`chain_spread_macros`: the same range over the chain seeds of ``ssa_seeds/per_chain.csv`` (the
  report's realisation, a new MCMC stream per chain seed): how far the chain's own randomness alone moves it;
* :func:`cause_count_macros`: how many failing ledger rows (not reproduced, inconclusive,
  uninformative) each cause of :data:`~.claims.CAUSES` explains, as text with its noun
  (:func:`rows_text`), so the discussion by cause quotes its counts from the ledger.

* :func:`effect_macros`: how large the paired effect of keeping a random joint hypothesis in document
  003's MHT is, relative to the MHT's MOSPA, and the words that describe it, chosen by the numbers
  (:func:`effect_words`), never a fixed adjective.

* :func:`interop_macros`: what the Stone Soup adapter adds to each algorithm's time per scan
  (``perf/stonesoup_adapter_timing.csv``), as a percentage of the algorithm's own API.

* :func:`brute_jpda_macros`: the largest formation Stone Soup's brute-force JPDA was run on in
  ``perf/sht_timings.csv`` (larger ones are skipped with a note) and its slowest median time per scan there.

* :func:`paired_difference_macros`: each tracker's paired OSPA difference from the $\\delta$-GLMB filter on
  its benchmark (the ``OSPA minus glmb`` of the benchmark rows' notes), with its standard error and z.

A table that is absent (a run without that experiment) gives no macro; the report then fails on the
missing macro by name, never on a silent default.
"""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd

from .claims import CAUSES, format_value
from .macros import macro_name

__all__ = ["EFFECT_SMALL_PERCENT", "EFFECT_Z", "cause_count_macros", "effect_macros", "effect_words", "brute_jpda_macros",
           "chain_spread_macros", "findings_macros", "interop_macros", "paired_difference_macros", "percent_text", "rows_text",
           "seed_spread_macros"]

#: A paired difference is real when it lies at least this many of its standard errors from zero ...
EFFECT_Z = 3.0
#: ... and small when it is below this percentage of the quantity it changes.
EFFECT_SMALL_PERCENT = 10.0

#: The trackers of the larger SSA run whose spread over seeds the findings quote (macro word -> tracker).
SEED_TRACKERS = {"Chain": "rfisst_chain", "Completion": "rfisst"}


def _spread_macros(table: pd.DataFrame, case: str, index: str, kind: str) -> dict:
    """The range over the seeds of column ``index`` of ``p_n_end`` per tracker of ``case``, and the number of seeds:
    macros ``\\htFindings<Kind><Tracker>PEnd{Min,Max}`` and ``\\htFindings<Kind>N`` (``kind``: "seeds", "chain seeds")."""
    rows = table[table["case"] == case]
    if rows.empty:
        raise ValueError(f"the {kind} table has no rows for case {case!r}")
    values = {macro_name("findings", kind, "n"): str(rows[index].nunique())}
    for word, tracker in SEED_TRACKERS.items():
        p = pd.to_numeric(rows.loc[rows["tracker"] == tracker, "p_n_end"], errors="raise")
        if p.empty:
            raise ValueError(f"the {kind} table has no {tracker!r} rows for case {case!r}")
        values[macro_name("findings", kind, word, "p end min")] = format_value(float(p.min()), 2)
        values[macro_name("findings", kind, word, "p end max")] = format_value(float(p.max()), 2)
    return values


def seed_spread_macros(per_seed: pd.DataFrame, case: str = "ssa50") -> dict:
    """``\\htFindingsSeeds<Tracker>PEnd{Min,Max}`` and ``\\htFindingsSeedsN``: the range over seeds of
    ``p_n_end`` (posterior probability of the true number at the last scan) for ``case``."""
    return _spread_macros(per_seed, case, "seed_index", "seeds")


def chain_spread_macros(per_chain: pd.DataFrame, case: str = "ssa50") -> dict:
    """``\\htFindingsChainSeeds<Tracker>PEnd{Min,Max}`` and ``\\htFindingsChainSeedsN``: the range over chain
    seeds (one realisation, the report's; a new MCMC stream each) of ``p_n_end`` for ``case``."""
    return _spread_macros(per_chain, case, "chain_index", "chain seeds")


def cause_count_macros(ledger: pd.DataFrame) -> dict:
    """``\\htFindingsCause<Cause>`` for every cause (zero included) and ``\\htFindingsCauseOpen`` for
    failing rows with no diagnosed cause, counted as :func:`.sections.gap_cause` assigns them."""
    from .sections import FAILING, gap_cause

    bad = ledger[ledger["status"].isin(FAILING)].to_dict("records")
    counts = {cause: 0 for cause in CAUSES}
    counts[""] = 0
    for row in bad:
        counts[gap_cause(row)] = counts.get(gap_cause(row), 0) + 1
    values = {macro_name("findings", "cause", cause or "open"): rows_text(n) for cause, n in counts.items()}
    values["htFindingsFailingRows"] = rows_text(len(bad))
    return values


def effect_words(z: float, percent: float) -> str:
    """Words for a paired difference of ``z`` standard errors that is ``percent`` % of the baseline:
    "a real but small effect", "a real effect of this size" or "no effect the runs can tell from noise"."""
    if abs(z) < EFFECT_Z:
        return "no effect the runs can tell from noise"
    return "a real but small effect" if abs(percent) < EFFECT_SMALL_PERCENT else "a real effect of this size"


def effect_macros(power_macros: pd.DataFrame, claims: pd.DataFrame) -> dict:
    """``\\htFindingsRandomEffectPercent`` and ``...Words``: the MHT's paired MOSPA increase when it keeps a
    random joint hypothesis (``PowerRandomEveryDiff``, ``...DiffZ`` of ``mht_power_macros.csv``) as a
    percentage of the MHT's mean MOSPA (row ``MospaMht`` of ``closely_spaced/claims.csv``)."""
    value = dict(zip(power_macros["name"], power_macros["value"]))
    diff, z = float(value["PowerRandomEveryDiff"]), float(value["PowerRandomEveryDiffZ"])
    mht = claims.loc[claims["key"] == "MospaMht", "mean"]
    if mht.empty:
        raise ValueError("closely_spaced claims have no MospaMht row")
    percent = 100 * diff / float(mht.iloc[0])
    return {"htFindingsRandomEffectPercent": percent_text(percent),
            "htFindingsRandomEffectWords": effect_words(z, percent)}


def interop_macros(timing: pd.DataFrame) -> dict:
    """``\\htFindingsInteropOverhead<Algorithm>``: the adapter's extra time per scan in % of the algorithm's own
    API (column ``overhead`` = adapter / own - 1) and ``...OwnMs<Algorithm>``, the own API's ms per scan."""
    values = {}
    for r in timing.to_dict("records"):
        values[macro_name("findings", "interop overhead", r["algorithm"])] = percent_text(100 * float(r["overhead"]))
        values[macro_name("findings", "interop own ms", r["algorithm"])] = format_value(float(r["own_api_ms_per_scan"]), 2)
    values["htFindingsInteropTargets"] = format_value(int(timing["n_targets"].iloc[0]), 2)
    return values


def brute_jpda_macros(timings: pd.DataFrame) -> dict:
    """``\\htFindingsBruteJpdaTargets`` (most targets timed) and ``...Ms`` (slowest median ms per scan there, over
    clutter rates) for Stone Soup's ``JPDA`` (implementation name), from the rows that were run."""
    run = timings[(timings["implementation"] == "JPDA") & timings["median_ms"].notna()]
    if run.empty:
        raise ValueError("sht_timings has no timed row of Stone Soup's JPDA")
    largest = int(run["n_targets"].max())
    ms = float(run.loc[run["n_targets"] == largest, "median_ms"].max())
    return {"htFindingsBruteJpdaTargets": str(largest), "htFindingsBruteJpdaMs": format_value(ms, 2)}


_PAIRED = re.compile(r"OSPA minus glmb: ([+-]?\d+(?:\.\d+)?) \+/- (\d+(?:\.\d+)?) m")


def paired_difference_macros(claims: pd.DataFrame) -> dict:
    """``\\htFindingsGlmbDiff<Key>``, ``...Se<Key>``, ``...Z<Key>`` for every benchmark row whose note gives its
    paired OSPA difference from the GLMB filter ("OSPA minus glmb: +0.65 +/- 0.27 m"); z = difference / s.e."""
    values = {}
    for r in claims.to_dict("records"):
        m = _PAIRED.search(r.get("note", "") or "")
        if not m or not r.get("key"):
            continue
        diff, se = float(m.group(1)), float(m.group(2))
        values[macro_name("findings", "glmb diff", r["key"])] = m.group(1)
        values[macro_name("findings", "glmb diff se", r["key"])] = m.group(2)
        values[macro_name("findings", "glmb diff z", r["key"])] = f"{diff / se:.1f}" if se > 0 else "--"
    return values


def percent_text(x: float) -> str:
    """A percentage as text: whole numbers from 10 on (240, not 2.4e+02), two significant digits below."""
    return str(int(round(x))) if abs(x) >= 10 else format_value(x, 2)


def rows_text(n: int) -> str:
    """``"no rows"``, ``"one row"``, ``"3 rows"``: a count with its noun, never "1 rows"."""
    return {0: "no rows", 1: "one row"}.get(n, f"{n} rows")


def findings_macros(results_dir, ledger: pd.DataFrame) -> dict:
    """All of the above from a results directory (tables that exist) and the non-timing ledger."""
    values = cause_count_macros(ledger)
    per_seed = Path(results_dir) / "ssa_seeds" / "per_seed.csv"
    if per_seed.exists():
        values.update(seed_spread_macros(pd.read_csv(per_seed)))
    per_chain = Path(results_dir) / "ssa_seeds" / "per_chain.csv"
    if per_chain.exists() and per_chain.stat().st_size:  # a run without chain seeds writes an empty table
        chains = pd.read_csv(per_chain)
        if (chains["case"] == "ssa50").any():
            values.update(chain_spread_macros(chains))
    interop = Path(results_dir) / "perf" / "stonesoup_adapter_timing.csv"
    if interop.exists():
        values.update(interop_macros(pd.read_csv(interop)))
    sht = Path(results_dir) / "perf" / "sht_timings.csv"
    if sht.exists():
        values.update(brute_jpda_macros(pd.read_csv(sht)))
    glmb = Path(results_dir) / "glmb_benchmark" / "claims.csv"
    if glmb.exists():
        values.update(paired_difference_macros(pd.read_csv(glmb, dtype=str, keep_default_na=False)))
    power = Path(results_dir) / "closely_spaced" / "mht_power_macros.csv"
    if power.exists():
        values.update(effect_macros(pd.read_csv(power, dtype=str, keep_default_na=False),
                                    pd.read_csv(Path(results_dir) / "closely_spaced" / "claims.csv", dtype=str,
                                                keep_default_na=False)))
    return values

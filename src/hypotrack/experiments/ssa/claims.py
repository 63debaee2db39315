"""SSA experiments, step 5: what was and was not reproduced (document 000 Sec. IV-A and V-A), and what
this project's completion step (a deterministic neighbour search after R-FISST's chain) changes."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim, numeric_claim
from .controls import attach_controls, every_scan_verdict
from .evaluation import AGREEMENT_TOLERANCE_KM
from .run import percent_of_run as _percent

__all__ = ["completion_claims", "completion_pair", "completion_table", "completion_timing", "expected_start_claim",
           "labelled",
           "ssa15_claims", "ssa50_claims"]


def _snapshot_verdict(matched: pd.DataFrame, scans, n_scans) -> tuple[str, bool]:
    parts, ok = [], True
    for k in scans:
        g = matched[matched["scan"] == k]
        es = g[g["role"] == "estimate"]
        n_ok = int((es["status"] == "correct").sum())
        n_missed = int(((g["role"] == "truth") & (g["status"] == "missed")).sum())
        ok &= n_ok == len(es) and n_missed == 0
        parts.append(f"{_percent(k, n_scans):.0f} %: {n_ok}/{len(es)} correct, {n_missed} missed")
    return "; ".join(parts), bool(ok)


def expected_start_claim(expected_number: pd.Series, n_start: int, first_birth: int, last: int, note: str = ""):
    """E[N] at the scan before the first birth enters equals the initial hypothesis's size (000 Fig. 11);
    ``expected_number`` is indexed by scan (a run's summary, or a control's that stops there)."""
    scan = max(first_birth - 1, 0)
    return numeric_claim("ssa50", "expected number of objects before the first birth enters", "000 Fig. 11", n_start,
                         float(expected_number.loc[scan]), abs_tol=0.1, digits=5,
                         note=f"scan {scan} of {last}; {note}".strip("; "), key="ExpectedStart")


def ssa50_claims(metrics: pd.DataFrame, cardinality: pd.DataFrame, weights: pd.DataFrame,
                 matched: pd.DataFrame, births: pd.DataFrame, *, estimate_scans, n_scans: int,
                 error_bound_probability: float, note: str = "", tracker: str = "R-FISST",
                 per_object_death: bool = False) -> list:
    """The ssa50 reproduction claims (document 000 Sec. IV-A, Figs 6, 8–11).

    ``metrics`` is the merged per-scan table (run summary and :func:`evaluate_map` metrics);
    ``tracker`` names the tracker in the rows that state what it does; ``per_object_death`` says
    whether its population lets any object die (labeled multi-Bernoulli) rather than only objects
    in view (Eq. 30), which changes the explanation of ``P(N > 50)``.
    """
    ex = "ssa50"
    m = metrics.set_index("scan")
    last = int(m.index.max())
    first_birth = int(births.loc[births["first_in_view_scan"] >= 0, "first_in_view_scan"].min()) \
        if len(births) else last
    n_start, n_end = int(m.loc[0, "n_catalogue"]), int(m.loc[last, "n_catalogue"])
    claims = [
        expected_start_claim(m["expected_number"], n_start, first_birth, last, note=note),
        numeric_claim(ex, "expected number of objects at the end", "000 Fig. 11", n_end,
                      float(m.loc[last, "expected_number"]), abs_tol=0.1, digits=5,
                      note="all births have entered the field of view", key="ExpectedEnd"),
    ]
    card_end = cardinality[cardinality["scan"] == last]
    p_end = float(card_end.loc[card_end["n_objects"] == n_end, "probability"].sum())
    p_more = float(card_end.loc[card_end["n_objects"] > n_end, "probability"].sum())
    p_less = float(card_end.loc[card_end["n_objects"] < n_end, "probability"].sum())
    claims.append(numeric_claim(
        ex, f"P(N = {n_end}) at the end (the {n_end}-object assumption holds all weight)", "000 Fig. 11", 1.0,
        p_end, abs_tol=0.05, digits=4,
        note=f"P(N > {n_end}) = {p_more:.3g}: hypotheses holding an extra object seeded by clutter (or an "
             + ("undetected birth); every object may die at every scan (labeled multi-Bernoulli survival)"
                if per_object_death else "undetected birth) that has left the FOV, where Eq. 30 neither "
                "penalises nor kills it (only objects in view can die)")
             + f"; P(N < {n_end}) = {p_less:.3g}", key="PEnd"))
    seq = m["map_n_objects"].to_numpy()
    changes = seq[np.r_[True, seq[1:] != seq[:-1]]]
    single_file = bool(np.all(np.diff(changes) == 1)) and changes[0] == n_start and changes[-1] == n_end
    claims.append(Claim(ex, "weight handed off single file 45 -> 46 -> ... -> 50 (MAP cardinality)",
                        "000 Fig. 11",
                        f"{n_start} -> ... -> {n_end} in unit steps", " -> ".join(map(str, changes)),
                        "exact sequence", "qualitative" if single_file else "not reproduced",
                        "sequence of MAP cardinalities over the run; "
                        "a step back or a jump of two is a failure", "published number", key="SingleFile"))
    n_tracked = int(births["tracked_at_end"].sum())
    delays = ", ".join(f"{d}" for d in births["delay_scans"])
    claims.append(Claim(ex, f"{tracker} recognises every birth", "000 Sec. IV-A", f"{len(births)} births",
                        f"{n_tracked} tracked at the end", "all", "reproduced" if n_tracked == len(births)
                        else "not reproduced", f"scans from first in view to a correct MAP track: {delays}",
                        "published number", key="BirthsTracked"))
    verdict, ok = _snapshot_verdict(matched, estimate_scans, n_scans)
    claims.append(Claim(ex, "no red stars: every top-hypothesis estimate within its error bound",
                        "000 Figs 8-10",
                        "all correct", verdict, f"truth in the {100 * error_bound_probability:g} % ellipse",
                        "reproduced" if ok else "not reproduced", evidence="published number", key="NoRedStars"))
    wsc = sorted(weights["scan"].unique())
    if wsc:
        w0 = weights[(weights["scan"] == wsc[0]) & (weights["rank"] == 1)]["weight"].iloc[0]
        claims.append(numeric_claim(
            ex, "in the beginning the initial hypothesis carries (almost) all the weight", "000 Fig. 6", 1.0,
            float(w0), abs_tol=0.1, digits=4,
            note=f"MAP weight at the first snapshot ({_percent(wsc[0], n_scans):.0f} %)", key="InitialWeight"))
    eff = m["effective_hypotheses"]
    varies = eff.max() > 1.5 * eff.min()
    claims.append(Claim(ex, "the number of maintained hypotheses varies with the ambiguities in view",
                        "000 Fig. 6",
                        "varies", f"effective number 1/sum(w^2) from {eff.min():.3g} to {eff.max():.3g}",
                        "max > 1.5 min", "qualitative" if varies else "not reproduced",
                        "the engine always keeps H_inf hypotheses; "
                        "their effective number measures the spread", "published number", key="HypothesesVary"))
    claims.append(Claim(ex, "mean OSPA of the MAP estimates, objects in view", "extension", "--",
                        f"{metrics['ospa_in_view'].mean():.3g} km", "--", "extension",
                        f"catalogue OSPA mean {metrics['ospa_catalogue'].mean():.3g} km", "measurement",
                        key="MeanOspa"))
    return claims


def _same_map_claim(ex, label_a, label_b, agreement: pd.DataFrame, note: str = "") -> Claim:
    frac = float(agreement["agree"].mean())
    bad = agreement.loc[~agreement["agree"], "scan"].to_numpy()
    n_diff_objects = int((~agreement["same_objects"]).sum())
    more = " ..." if len(bad) > 10 else ""
    diff = (f"differ at scans {', '.join(map(str, bad[:10]))}{more}: {n_diff_objects} of them with "
            "different objects (e.g. a newborn object in one MAP only)" if len(bad) else "")
    return Claim(ex, f"{label_a} and {label_b} give the same estimates (same MAP hypothesis)",
                 "000 Sec. V-A, Figs 12-14", "100 % of scans", f"{100 * frac:.1f} % of {len(agreement)} scans",
                 "exact", "reproduced" if frac == 1.0 else "not reproduced", "; ".join(x for x in (diff, note) if x),
                 "published number", key="SameMap")


def _not_worse_claim(ex, label_a, label_b, ospa_a: pd.Series, ospa_b: pd.Series) -> Claim:
    worse = float(np.mean(ospa_a > ospa_b + AGREEMENT_TOLERANCE_KM))
    return Claim(ex, f"{label_a} accuracy equal to or better than {label_b}, never worse",
                 "000 Sec. V", "0 % of scans worse", f"{100 * worse:.1f} % of scans worse",
                 f"catalogue OSPA, {AGREEMENT_TOLERANCE_KM * 1e3:g} m",
                 "reproduced" if worse == 0 else "not reproduced",
                 f"mean catalogue OSPA {ospa_a.mean():.4g} km ({label_a}) vs {ospa_b.mean():.4g} km ({label_b})",
                 "published number", key="AccuracyNotWorse",
                 # the paper's pair runs R-FISST with births and deaths against a fixed-number HOMHT; document 000
                 # does not say which population R-FISST used (the like-for-like pair is an ssa_seeds row)
                 cause="" if worse == 0 else "unstated parameter")


def _no_red_stars_claim(ex, label, key, matched, metrics, *, estimate_scans, n_scans, error_bound_probability,
                        tolerance, max_ospa_km=None) -> Claim:
    """No red stars at every scan (000 Sec. V-A: "maintained the correct hypothesis throughout the
    simulation"); the start / middle / end snapshots of Figs 12-14 are in the note."""
    snap, _ = _snapshot_verdict(matched, estimate_scans, n_scans)
    text, ok = every_scan_verdict(matched, metrics, tolerance=tolerance, max_ospa_km=max_ospa_km)
    accuracy = "" if max_ospa_km is None else f"; in-view OSPA ≤ {max_ospa_km:.3g} km (one return's RMS error)"
    return Claim(ex, f"{label}: no red stars, every estimate within its error bound at every scan",
                 "000 Sec. V-A, Figs 12-14", "correct hypothesis throughout", text,
                 f"truth in the {100 * error_bound_probability:g} % ellipse; ≤ {100 * tolerance:g} % of scans "
                 f"with a red star or a missed object{accuracy}", "reproduced" if ok else "not reproduced",
                 f"the figures' snapshots (start, middle, end): {snap}", "published number", key=key)


def ssa15_claims(metrics: pd.DataFrame, agreements: Mapping, matched: pd.DataFrame, *, estimate_scans,
                 n_scans: int, error_bound_probability: float, labels: Mapping, red_star_tolerance: float = 0.01,
                 max_ospa_km: float | None = None, control: str | None = None, control_agreement: pd.DataFrame | None = None) -> list:
    """The ssa15 reproduction claims (document 000 Sec. V-A, Figs 12–14).

    ``agreements`` maps ``(tracker_a, tracker_b)`` to :func:`map_agreement` tables; the first
    pair is the paper's comparison (R-FISST vs HOMHT), further pairs are extensions.
    ``labels`` maps tracker names to display names; every tracker gets a "no red stars" claim,
    checked at every scan (:func:`~.controls.every_scan_verdict` with ``red_star_tolerance`` and, when
    given, the accuracy bound ``max_ospa_km`` on the mean in-view OSPA).

    ``control``: the name of a negative control (the blind tracker, :func:`~.controls.blind_run`)
    whose rows ``metrics`` and ``matched`` also hold, and ``control_agreement`` its
    :func:`map_agreement` with the paper pair's second tracker: every check is run on it too and
    fills the ``control`` column (:func:`~.controls.attach_controls`).
    """
    ex = "ssa15"
    claims = []
    others = "; ".join(f"{labels[a]} vs {labels[b]}: {100 * ag['agree'].mean():.1f} %"
                       for (a, b), ag in list(agreements.items())[1:])
    ospa = {tr: g.set_index("scan")["ospa_catalogue"] for tr, g in metrics.groupby("tracker")}
    pair = next(iter(agreements))
    for i, ((a, b), agreement) in enumerate(agreements.items()):
        if i == 0:
            claims.append(_same_map_claim(ex, labels[a], labels[b], agreement, others))
            claims.append(_not_worse_claim(ex, labels[a], labels[b], ospa[a], ospa[b]))
        else:
            frac = float(agreement["agree"].mean())
            same = _same_map_claim(ex, labels[a], labels[b], agreement)
            claims.append(Claim(ex, f"{labels[a]} and {labels[b]}: same MAP hypothesis", "extension", "--",
                                f"{100 * frac:.1f} % of {len(agreement)} scans", "exact", "extension", same.note,
                                "measurement", key=f"SameMapPair{i}"))
    kw = dict(estimate_scans=estimate_scans, n_scans=n_scans, error_bound_probability=error_bound_probability,
              tolerance=red_star_tolerance, max_ospa_km=max_ospa_km)
    for tr, label in labels.items():
        claims.append(_no_red_stars_claim(ex, label, f"NoRedStars{_key_part(tr)}", matched[matched["tracker"] == tr],
                                          metrics[metrics["tracker"] == tr], **kw))
    means = ", ".join(f"{label} {metrics.loc[metrics['tracker'] == tr, 'ospa_in_view'].mean():.3g} km"
                      for tr, label in labels.items())
    claims.append(Claim(ex, "mean OSPA of the MAP estimates, objects in view", "extension", "--", means, "--",
                        "extension", evidence="measurement", key="MeanOspa"))
    if control is None:
        return claims
    c_matched, c_metrics = matched[matched["tracker"] == control], metrics[metrics["tracker"] == control]
    red = _no_red_stars_claim(ex, control, "NoRedStars", c_matched, c_metrics, **kw)
    ctl = {f"NoRedStars{_key_part(tr)}": red for tr in labels}
    ctl["AccuracyNotWorse"] = _not_worse_claim(ex, control, labels[pair[1]], ospa[control], ospa[pair[1]])
    if control_agreement is not None:
        ctl["SameMap"] = _same_map_claim(ex, control, labels[pair[1]], control_agreement)
    return attach_controls(claims, ctl)


#: Claims of 000 that ssa_seeds decides over scenario seeds: (case, key of the single-run row) -> what.
#: The single run of ssa50 / ssa15 then illustrates the claim and carries no verdict of its own.
OVER_SEEDS = {("ssa50", "ExpectedEnd"): "E[N] at the end", ("ssa50", "PEnd"): "P(N = true number) at the end",
              ("ssa50", "BirthsTracked"): "every birth tracked", ("ssa15", "SameMap"): "same MAP hypothesis"}


def seed_claim_id(case: str, tracker: str, what: str) -> str:
    """The ledger's ``claim`` id shared by a single-run row and the over-seed row deciding the same claim."""
    return f"000 {case}, {tracker}: {what}"


def one_verdict(claims, case: str, tracker: str, *, seed_trackers=(), extension: bool = False) -> list:
    """One tracker's single-run rows of ``case``, so that every claim of 000 gets one verdict.

    * a claim that ssa_seeds decides over seeds for this tracker (:data:`OVER_SEEDS`, ``tracker`` in
      ``seed_trackers``) becomes an *illustration* naming the verdict row (same ``claim`` id);
    * ``extension``: a tracker 000 never ran (this project's δ-GLMB) scored against 000's claims: its
      rows are *extensions*, not reproductions.
    """
    out = []
    for c in claims:
        what = OVER_SEEDS.get((case, c.key))
        if extension and c.status not in ("extension", "consistency check"):
            c = replace(c, status="extension", source=f"extension ({c.source}'s claim)",
                        note=("this project's filter, which 000 never ran, scored against 000's claim; "
                              + c.note).rstrip("; "))
        elif what and tracker in seed_trackers:
            c = replace(c, status="illustration", claim=seed_claim_id(case, tracker, what),
                        note=("one realisation; the verdict is the ssa_seeds row over scenario seeds; "
                              + c.note).rstrip("; "))
        out.append(c)
    return out


def _key_part(name: str) -> str:
    """A tracker name as part of a macro key (``rfisst_chain`` -> ``RfisstChain``)."""
    return "".join(w[:1].upper() + w[1:] for w in str(name).split("_") if w)


def labelled(claims, label: str, key_prefix: str) -> list:
    """One tracker's claims among several trackers': the item names the tracker (unless it starts
    with its name already), keys get a prefix."""
    return [replace(c, item=c.item if c.item.startswith(label) else f"{label}: {c.item}",
                    key=f"{key_prefix}{c.key}" if c.key else "") for c in claims]


def completion_pair(settings: Mapping):
    """``(chain, completion)``: the first R-FISST tracker (with births and deaths) without and the
    first with the completion step, among ``settings`` (name -> :class:`TrackerSettings`);
    ``None`` when the section does not run both."""
    rf = {n: s for n, s in settings.items() if s.kind == "rfisst" and s.population}  # kinds with a completion step
    chain = next((n for n, s in rf.items() if s.completion_rounds == 0), None)
    comp = next((n for n, s in rf.items() if s.completion_rounds > 0), None)
    return (chain, comp) if chain and comp else None


def completion_table(summaries: Mapping, settings: Mapping, agreements: Mapping | None = None,
                     reference: str = "") -> pd.DataFrame:
    """Per tracker: the children found per scan (summed over parents; scan 0 is the initial
    hypothesis and is left out), the effective number of hypotheses, E[N] at the end, and — for
    the trackers in ``agreements`` (name -> :func:`map_agreement` table against ``reference``) —
    the fraction of scans with the same MAP hypothesis as the reference."""
    rows = []
    for tr, s in summaries.items():
        run = s[s["scan"] > 0]
        ch = run["n_children"]
        ag = agreements.get(tr) if agreements else None
        rows.append({
            # 0 for a kind without a completion step (the exhaustive HOMHT)
            "tracker": tr, "label": settings[tr].label,
            "completion_rounds": int(settings[tr].spec.options.get("completion_rounds", 0)),
            "children_total": int(ch.sum()), "children_per_scan_mean": float(ch.mean()),
            "children_per_scan_median": float(ch.median()), "children_per_scan_max": int(ch.max()),
            "effective_hypotheses_mean": float(run["effective_hypotheses"].mean()),
            "expected_number_end": float(s["expected_number"].iloc[-1]),
            "reference": reference if ag is not None else "",
            "map_agreement": float(ag["agree"].mean()) if ag is not None else np.nan,
        })
    return pd.DataFrame(rows)


def completion_timing(timings: Mapping, settings: Mapping) -> pd.DataFrame:
    """Per tracker: wall-clock and CPU seconds of the whole run (``*_timing.csv`` tables)."""
    return pd.DataFrame([{"tracker": tr, "label": settings[tr].label, "seconds": float(t["seconds"].sum()),
                          "cpu_seconds": float(t["cpu_seconds"].sum()),
                          "median_scan_seconds": float(t.loc[t["scan"] > 0, "seconds"].median())}
                         for tr, t in timings.items()])


def completion_claims(experiment: str, table: pd.DataFrame, timing: pd.DataFrame, pair, *, reference_label: str):
    """The completion step's measured effect: claims and macros of the deterministic results, and
    the run-time claim and macros (kept apart: timings are not byte-identical between runs).

    ``pair`` is :func:`completion_pair`; ``table`` :func:`completion_table`, ``timing``
    :func:`completion_timing`. Returns ``(claims, macros, timing_claims, timing_macros)``.
    """
    chain, comp = pair
    t, tm = table.set_index("tracker"), timing.set_index("tracker")
    c0, c1 = t.loc[chain, "children_per_scan_mean"], t.loc[comp, "children_per_scan_mean"]
    a0, a1 = t.loc[chain, "map_agreement"], t.loc[comp, "map_agreement"]
    what = "this project's completion step (heavy single-move neighbours of the chain's children)"
    agree = (f"{100 * a1:.1f} % of scans" if np.isnan(a0) else
             f"{100 * a0:.1f} % (paper chain) vs {100 * a1:.1f} % (chain + completion) of scans")
    claims = [
        Claim(experiment, "completion step: children found per scan (all parents)", "extension", "--",
              f"{c0:.4g} (paper chain) vs {c1:.4g} (chain + completion)", "--", "extension",
              f"{what}; medians {t.loc[chain, 'children_per_scan_median']:.4g} vs "
              f"{t.loc[comp, 'children_per_scan_median']:.4g}", "measurement", key="CompletionChildren"),
        Claim(experiment, f"completion step: same MAP hypothesis as {reference_label}", "extension", "--", agree,
              "exact", "extension", f"E[N] at the end {t.loc[chain, 'expected_number_end']:.5g} (paper chain) vs "
              f"{t.loc[comp, 'expected_number_end']:.5g} (chain + completion)", "measurement",
              key="CompletionAgreement"),
    ]
    macros = {"CompletionChildrenChain": float(c0), "CompletionChildrenCompletion": float(c1),
              "CompletionChildrenRatio": float(c1 / c0) if c0 else float("nan"),
              "CompletionAgreement": f"{100 * a1:.1f}"}
    if not np.isnan(a0):
        macros["CompletionAgreementChain"] = f"{100 * a0:.1f}"
    s0, s1 = tm.loc[chain, "seconds"], tm.loc[comp, "seconds"]
    p0, p1 = tm.loc[chain, "cpu_seconds"], tm.loc[comp, "cpu_seconds"]
    timing_claims = [Claim(experiment, "completion step: run time of the whole run", "extension", "--",
                           f"{s0:.0f} s (paper chain) vs {s1:.0f} s (chain + completion)", "--", "extension",
                           f"CPU {p0:.0f} s vs {p1:.0f} s; machine shared, wall-clock times vary with its load",
                           "measurement", key="CompletionTime")]
    timing_macros = {"CompletionSecondsChain": f"{s0:.0f}", "CompletionSecondsCompletion": f"{s1:.0f}",
                     "CompletionCpuRatio": float(p1 / p0) if p0 else float("nan")}
    return claims, macros, timing_claims, timing_macros

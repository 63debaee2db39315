"""SSA experiments, step 5: what was and was not reproduced (seed 000 Sec. IV-A and V-A)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ...report import Claim, numeric_claim
from .evaluation import AGREEMENT_TOLERANCE_KM
from .run import percent_of_run as _percent

__all__ = ["ssa15_claims", "ssa50_claims"]


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


def ssa50_claims(metrics: pd.DataFrame, cardinality: pd.DataFrame, weights: pd.DataFrame,
                 matched: pd.DataFrame, births: pd.DataFrame, *, estimate_scans, n_scans: int,
                 error_bound_probability: float, note: str = "") -> list:
    """The ssa50 reproduction claims (seed 000 Sec. IV-A, Figs 6, 8–11).

    ``metrics`` is the merged per-scan table (run summary and :func:`evaluate_map` metrics).
    """
    ex = "ssa50"
    m = metrics.set_index("scan")
    last = int(m.index.max())
    first_birth = int(births.loc[births["first_in_view_scan"] >= 0, "first_in_view_scan"].min()) \
        if len(births) else last
    n_start, n_end = int(m.loc[0, "n_catalogue"]), int(m.loc[last, "n_catalogue"])
    claims = [
        numeric_claim(ex, "expected number of objects before the first birth enters", "000 Fig. 11", n_start,
                      float(m.loc[max(first_birth - 1, 0), "expected_number"]), abs_tol=0.1, digits=5,
                      note=f"scan {max(first_birth - 1, 0)} of {last}; {note}".strip("; ")),
        numeric_claim(ex, "expected number of objects at the end", "000 Fig. 11", n_end,
                      float(m.loc[last, "expected_number"]), abs_tol=0.1, digits=5,
                      note="all births have entered the field of view"),
    ]
    card_end = cardinality[cardinality["scan"] == last]
    p_end = float(card_end.loc[card_end["n_objects"] == n_end, "probability"].sum())
    p_more = float(card_end.loc[card_end["n_objects"] > n_end, "probability"].sum())
    p_less = float(card_end.loc[card_end["n_objects"] < n_end, "probability"].sum())
    claims.append(numeric_claim(
        ex, f"P(N = {n_end}) at the end (the {n_end}-object assumption holds all weight)", "000 Fig. 11", 1.0,
        p_end, abs_tol=0.05, digits=4,
        note=f"P(N > {n_end}) = {p_more:.3g}: hypotheses holding an extra object seeded by clutter (or an "
             f"undetected birth) that has left the FOV, where Eq. 30 neither penalises nor kills it (only "
             f"objects in view can die); P(N < {n_end}) = {p_less:.3g}"))
    seq = m["map_n_objects"].to_numpy()
    changes = seq[np.r_[True, seq[1:] != seq[:-1]]]
    single_file = bool(np.all(np.diff(changes) == 1)) and changes[0] == n_start and changes[-1] == n_end
    claims.append(Claim(ex, "weight handed off single file 45 -> 46 -> ... -> 50 (MAP cardinality)",
                        "000 Fig. 11",
                        f"{n_start} -> ... -> {n_end} in unit steps", " -> ".join(map(str, changes)),
                        "exact sequence", "qualitative" if single_file else "not reproduced",
                        "sequence of MAP cardinalities over the run; "
                        "a step back or a jump of two is a failure"))
    n_tracked = int(births["tracked_at_end"].sum())
    delays = ", ".join(f"{d}" for d in births["delay_scans"])
    claims.append(Claim(ex, "R-FISST recognises every birth", "000 Sec. IV-A", f"{len(births)} births",
                        f"{n_tracked} tracked at the end", "all", "reproduced" if n_tracked == len(births)
                        else "not reproduced", f"scans from first in view to a correct MAP track: {delays}"))
    verdict, ok = _snapshot_verdict(matched, estimate_scans, n_scans)
    claims.append(Claim(ex, "no red stars: every top-hypothesis estimate within its error bound",
                        "000 Figs 8-10",
                        "all correct", verdict, f"truth in the {100 * error_bound_probability:g} % ellipse",
                        "reproduced" if ok else "not reproduced"))
    wsc = sorted(weights["scan"].unique())
    if wsc:
        w0 = weights[(weights["scan"] == wsc[0]) & (weights["rank"] == 1)]["weight"].iloc[0]
        claims.append(numeric_claim(
            ex, "in the beginning the initial hypothesis carries (almost) all the weight", "000 Fig. 6", 1.0,
            float(w0), abs_tol=0.1, digits=4,
            note=f"MAP weight at the first snapshot ({_percent(wsc[0], n_scans):.0f} %)"))
    eff = m["effective_hypotheses"]
    varies = eff.max() > 1.5 * eff.min()
    claims.append(Claim(ex, "the number of maintained hypotheses varies with the ambiguities in view",
                        "000 Fig. 6",
                        "varies", f"effective number 1/sum(w^2) from {eff.min():.3g} to {eff.max():.3g}",
                        "max > 1.5 min", "qualitative" if varies else "not reproduced",
                        "the engine always keeps H_inf hypotheses; "
                        "their effective number measures the spread"))
    claims.append(Claim(ex, "mean OSPA of the MAP estimates, objects in view", "extension", "--",
                        f"{metrics['ospa_in_view'].mean():.3g} km", "--", "extension",
                        f"catalogue OSPA mean {metrics['ospa_catalogue'].mean():.3g} km"))
    return claims


def ssa15_claims(metrics: pd.DataFrame, agreements: Mapping, matched: pd.DataFrame, *, estimate_scans,
                 n_scans: int, error_bound_probability: float, labels: Mapping) -> list:
    """The ssa15 reproduction claims (seed 000 Sec. V-A, Figs 12–14).

    ``agreements`` maps ``(tracker_a, tracker_b)`` to :func:`map_agreement` tables; the first
    pair is the paper's comparison (R-FISST vs HOMHT), further pairs are extensions.
    ``labels`` maps tracker names to display names; every tracker gets a "no red stars" claim.
    """
    ex = "ssa15"
    claims = []
    others = "; ".join(f"{labels[a]} vs {labels[b]}: {100 * ag['agree'].mean():.1f} %"
                       for (a, b), ag in list(agreements.items())[1:])
    for i, ((a, b), agreement) in enumerate(agreements.items()):
        frac = float(agreement["agree"].mean())
        bad = agreement.loc[~agreement["agree"], "scan"].to_numpy()
        n_diff_objects = int((~agreement["same_objects"]).sum())
        more = " ..." if len(bad) > 10 else ""
        note = (f"differ at scans {', '.join(map(str, bad[:10]))}{more}: {n_diff_objects} of them with "
                "different objects (e.g. a newborn object in one MAP only)" if len(bad) else "")
        if i == 0 and others:
            note = f"{note}; {others}" if note else others
        if i == 0:
            claims.append(Claim(ex,
                                f"{labels[a]} and {labels[b]} give the same estimates (same MAP hypothesis)",
                                "000 Sec. V-A, Figs 12-14", "100 % of scans",
                                f"{100 * frac:.1f} % of {len(agreement)} scans", "exact",
                                "reproduced" if frac == 1.0 else "not reproduced", note))
            ma = metrics[metrics["tracker"] == a].set_index("scan")["ospa_catalogue"]
            mb = metrics[metrics["tracker"] == b].set_index("scan")["ospa_catalogue"]
            worse = float(np.mean(ma > mb + AGREEMENT_TOLERANCE_KM))
            claims.append(Claim(ex, f"{labels[a]} accuracy equal to or better than {labels[b]}, never worse",
                                "000 Sec. V", "0 % of scans worse", f"{100 * worse:.1f} % of scans worse",
                                f"catalogue OSPA, {AGREEMENT_TOLERANCE_KM * 1e3:g} m",
                                "reproduced" if worse == 0 else "not reproduced",
                                f"mean catalogue OSPA {ma.mean():.4g} km ({labels[a]}) vs "
                                f"{mb.mean():.4g} km ({labels[b]})"))
        else:
            claims.append(Claim(ex, f"{labels[a]} and {labels[b]}: same MAP hypothesis", "extension", "--",
                                f"{100 * frac:.1f} % of {len(agreement)} scans", "exact", "extension", note))
    for tr, label in labels.items():
        verdict, ok = _snapshot_verdict(matched[matched["tracker"] == tr], estimate_scans, n_scans)
        claims.append(Claim(ex, f"{label}: no red stars at the start, middle and end", "000 Figs 12-14",
                            "all correct", verdict,
                            f"truth in the {100 * error_bound_probability:g} % ellipse",
                            "reproduced" if ok else "not reproduced"))
    means = ", ".join(f"{label} {metrics.loc[metrics['tracker'] == tr, 'ospa_in_view'].mean():.3g} km"
                      for tr, label in labels.items())
    claims.append(Claim(ex, "mean OSPA of the MAP estimates, objects in view", "extension", "--", means, "--",
                        "extension"))
    return claims

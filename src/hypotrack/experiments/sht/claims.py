"""The sht ledger rows (worked example's clusters, JPDA coalescence, crossing Monte Carlo) and the
worked example's counts the paper quotes, from the tables of :mod:`.run`."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...association import find_clusters
from ...reporting.ledger import Claim, monte_carlo_claim
from ...reporting.verdict import with_control
from .run import LABELS, LECTURE_VALIDATION, METHODS

__all__ = ["lecture_macros", "sht_claims"]


def lecture_macros(summary: pd.DataFrame) -> dict:
    """The worked example's counts the paper quotes (``results/sht/macros.csv``): targets, returns,
    association hypotheses with FA and NT kept apart and with both merged into EX."""
    v = summary.set_index("quantity")["value"]
    return {"lecture_targets": int(v["targets"]), "lecture_returns": int(v["returns"]),
            "lecture_hypotheses_fa_nt": int(v["hypotheses_FA_NT"]), "lecture_hypotheses_ex": int(v["hypotheses_EX"])}


def _lag(curves: pd.DataFrame, method: str) -> tuple[float, float]:
    """Largest mean shortfall ``truth_separation − separation`` of one method's two tracks after the
    closest approach, and its standard error over the runs at that scan."""
    c = curves[curves["method"] == method].sort_values("scan")
    after = c[c["scan"] >= c.loc[c["truth_separation"].idxmin(), "scan"]]
    short = after["truth_separation"] - after["separation"]
    at = short.idxmax()
    return float(short.loc[at]), float(after.loc[at, "separation_se"])


def sht_claims(clusters: pd.DataFrame, curves: pd.DataFrame, summary: pd.DataFrame, *,
               validation=LECTURE_VALIDATION, min_lag: float) -> list:
    """The reproduction-ledger rows of the ``sht`` experiment.

    * the lecture's clusters for its worked example ({T1, T2} and {T3}), against the slide; control:
      the same clustering behind a broken gate that validates every return for every track;
    * JPDA's track coalescence on crossing targets (qualitative in the lecture): after the closest
      approach, the mean separation of JPDA's two tracks lags the true separation by more than
      ``min_lag`` metres and by more than 3 standard errors at the scan of largest lag; control: GNN
      (hard assignments, no coalescence) through the same check;
    * the crossing Monte Carlo itself (an extension: the lecture gives no numbers): per method the
      time-averaged OSPA of the tracks started on the targets and the track-loss fraction, each with
      the number of runs and its standard error (:func:`hypotrack.reporting.ledger.monte_carlo_claim` without a
      published value).
    """
    groups = sorted("{" + ", ".join(str(t).split()) + "}" for t in clusters["tracks"].dropna() if str(t).strip())
    want = ["{T1, T2}", "{T3}"]
    valid = np.asarray(validation, dtype=bool)
    broken = ["{" + ", ".join(f"T{t + 1}" for t in c.tracks) + "}" for c in find_clusters(np.ones_like(valid))]
    claims = [with_control(
        Claim("sht", "clusters of the worked example", "004, JPDA clustering slide", "; ".join(want),
              "; ".join(groups), "exact", "reproduced" if groups == want else "not reproduced",
              "targets sharing gated returns; y2 (gated by no track) goes to initiation", "published number",
              key="clusters"),
        "a broken gate that validates every return for every track", "; ".join(sorted(broken)),
        sorted(broken) == want)]
    lags = {m: _lag(curves, m) for m in METHODS if (curves["method"] == m).any()}

    def coalesces(method):
        lag, se = lags.get(method, (float("nan"), float("nan")))
        return bool(lag > min_lag and lag > 3 * se)

    jl, js = lags.get("jpda", (float("nan"), float("nan")))
    gl, gs = lags.get("gnn", (float("nan"), float("nan")))
    claims.append(with_control(Claim(
        "sht", "JPDA tracks coalesce on crossing targets", "004, track coalescence slide", "coalescence",
        f"JPDA lags the true separation by up to {jl:.1f} ± {js:.1f} m after the crossing",
        f"lag > {min_lag:g} m and > 3 s.e.", "qualitative" if coalesces("jpda") else "not reproduced",
        "mean over the Monte Carlo runs of the crossing scenario", "measurement", key="coalescence"),
        "GNN (hard assignments) through the same check", f"lag {gl:.1f} ± {gs:.1f} m", coalesces("gnn")))
    s = summary.set_index("method")
    for method in METHODS:
        if method not in s.index:
            continue
        label, r = LABELS[method], s.loc[method]
        n = int(r["n_runs"])
        claims.append(monte_carlo_claim(
            "sht", f"{label} on crossing targets: time-averaged OSPA of the tracks started on the targets (m)",
            "extension", None, n=n, mean=float(r["mospa_targets"]), se=float(r["mospa_targets_se"]), digits=3,
            key=f"{method}_crossing_ospa"))
        claims.append(monte_carlo_claim(
            "sht", f"{label} on crossing targets: track-loss fraction", "extension", None, n=n,
            mean=float(r["track_loss"]), se=float(r["track_loss_se"]), digits=3,
            note="n runs; binomial s.e. over every target of every run", key=f"{method}_track_loss"))
    return claims


"""The ``sht`` experiment (lecture notes 004): the worked example, GNN vs JPDA on crossing targets.

Three parts, each a pure function of its configuration and seed, writing tidy tables that the
figures are drawn from:

1. **The lecture's worked example** — tracks T1–T3, returns y1–y4 with the validation matrix of
   the "Gating" slide. :func:`lecture_hypotheses` lists every association hypothesis
   ``θ: {y_i} → {FA, T_j, NT}`` (one-to-one on targets, only gated pairs), with the event it
   becomes when false alarms and new targets are merged into external sources (GNN's assignment
   matrix) — which is also JPDA's joint event (no NT). :func:`lecture_summary` counts them and
   gives the clusters {T1, T2}, {T3} and the return y2 that goes to initiation.
2. **Crossing targets** — two targets on straight lines crossing at a small angle in Poisson
   clutter, tracked from known initial tracks by the complete GNN and JPDA trackers
   (:class:`hypotrack.trackers.tracker.SingleHypothesisTracker`, M-of-N initiation and deletion
   after misses running too). Recorded per scan: OSPA between confirmed-track positions and the
   truth, and the distance between the two tracks started on the targets — JPDA's tracks stay
   together after the crossing (*track coalescence*, lecture 004 / Fitzgerald 1986), GNN's do not.
3. **Clutter sweep** — the same runs at several clutter rates: time-averaged OSPA and track loss.

Conventions (stated here and in the figures): OSPA on positions with cut-off ``c`` and order ``p``
over every confirmed track (false tracks from initiation count as cardinality errors), averaged
over scans 1..K−1 and runs (MOSPA). A target's track is *lost* when the track started on it has
been deleted by the end of the run or ends farther than ``loss_distance`` from the target, so a
swap counts as two losses. Every run ``r`` draws from ``SeedSequence`` child ``r`` of the
experiment, so results do not depend on how runs are sharded.

This module runs the parts and returns their tables; the figures are drawn in :mod:`.figures`,
the ledger rows and the worked example's macros are in :mod:`.claims`.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd

from ...association import count_gated_associations, enumerate_associations, find_clusters, unassociated_measurements
from ...metrics import ospa
from ...models.motion import ConstantVelocity
from ...scenarios.cluttered import crossing_targets
from ...registry import TrackingProblem, build
from ..seeds import experiment_seeds

__all__ = [
    "LECTURE_VALIDATION",
    "lecture_hypotheses",
    "lecture_summary",
    "run_crossing",
    "crossing_runs",
    "sweep_runs",
    "summarise_crossing",
    "summarise_sweep",
]

LECTURE_VALIDATION = np.array([[0, 0, 1], [0, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=bool)
"""Lecture 004 "Gating": rows y1–y4, columns T1–T3."""

METHODS = ("gnn", "jpda")
LABELS = {"gnn": "GNN", "jpda": "JPDA"}
COLORS = {"gnn": "tab:blue", "jpda": "tab:red"}


# ---------------------------------------------------------------- 1. the worked example
def _names(prefix, k):
    return [f"{prefix}{i + 1}" for i in range(k)]


def lecture_hypotheses(validation=LECTURE_VALIDATION) -> pd.DataFrame:
    """Every association hypothesis of a validation matrix, with FA and NT told apart.

    Parameters
    ----------
    validation : (m, n) bool
        Rows returns ``y_i``, columns targets ``T_j``.

    Returns
    -------
    DataFrame
        One row per hypothesis: ``hypothesis`` (index), ``event`` (index of the EX-merged event,
        i.e. the GNN assignment / JPDA joint event it belongs to), one column per return with
        ``"T<j>"``, ``"FA"`` or ``"NT"``, and the counts ``n_detected``, ``n_FA``, ``n_NT``.
    """
    valid = np.asarray(validation, dtype=bool)
    m, n = valid.shape
    events = enumerate_associations(n, m, allowed=valid).astype(np.int64)
    rows = []
    for e_idx, event in enumerate(events):
        external = np.flatnonzero(event < 0)
        # Each return not on a target is either a false alarm or a new target.
        for sources in itertools.product(("FA", "NT"), repeat=len(external)):
            labels = [f"T{j + 1}" if j >= 0 else "" for j in event]
            for i, s in zip(external, sources):
                labels[i] = s
            rows.append([e_idx, *labels, int((event >= 0).sum()), sources.count("FA"), sources.count("NT")])
    df = pd.DataFrame(rows, columns=["event", *_names("y", m), "n_detected", "n_FA", "n_NT"])
    df.insert(0, "hypothesis", np.arange(len(df)))
    return df


def lecture_summary(validation=LECTURE_VALIDATION):
    """Counts of the worked example and its clusters.

    Returns
    -------
    summary : DataFrame with columns ``quantity``, ``value``, ``note``.
    clusters : DataFrame with one row per cluster: ``cluster``, ``tracks``, ``returns``,
        ``events`` (joint events of the cluster alone) — and a last row for the returns in no
        gate, which go to initiation.
    """
    valid = np.asarray(validation, dtype=bool)
    m, n = valid.shape
    hyps = lecture_hypotheses(valid)
    n_events = count_gated_associations(valid)
    if n_events != hyps["event"].nunique():
        raise AssertionError("enumeration and count_gated_associations disagree")
    cl_rows = []
    product = 1
    for k, c in enumerate(find_clusters(valid)):
        sub_events = count_gated_associations(valid[np.ix_(c.measurements, c.tracks)])
        product *= sub_events
        cl_rows.append([k + 1, " ".join(f"T{t + 1}" for t in c.tracks),
                        " ".join(f"y{i + 1}" for i in c.measurements), sub_events])
    free = unassociated_measurements(valid)
    cl_rows.append(["initiation", "", " ".join(f"y{i + 1}" for i in free), 1])
    clusters = pd.DataFrame(cl_rows, columns=["cluster", "tracks", "returns", "events"])
    summary = pd.DataFrame(
        [
            ["targets", n, "T1..T%d" % n],
            ["returns", m, "y1..y%d" % m],
            ["hypotheses_FA_NT", len(hyps), "theta: y_i -> {FA, T_j, NT}, one-to-one on targets, gated pairs only"],
            ["hypotheses_EX", n_events, "FA and NT merged into EX: rows of GNN's assignment problem = JPDA joint events"],
            ["product_over_clusters", product, "events of the clusters solved separately (equals hypotheses_EX)"],
            ["clusters", len(cl_rows) - 1, "; ".join("{" + r[1].replace(" ", ", ") + "}" for r in cl_rows[:-1])],
        ],
        columns=["quantity", "value", "note"],
    )
    return summary, clusters


# ---------------------------------------------------------------- 2. crossing targets
def _scenario(cfg, clutter_rate, seed):
    s = cfg["scenario"]
    return crossing_targets(
        s["n_targets"], speed=s["speed"], crossing_angle_deg=s["crossing_angle_deg"], n_scans=s["n_scans"],
        dt=s["dt"], q_truth=s["q_truth"], sigma=s["sigma"], p_D=s["p_D"], clutter_rate=clutter_rate,
        margin=s["margin"], rng=np.random.default_rng(seed),
    )


def _tracker(association, scenario, cfg):
    """The GNN or JPDA tracker (:mod:`hypotrack.registry`, options ``cfg["tracker"]``) on the scenario, started
    from the known initial states with the ``model`` block's prior spreads."""
    m = cfg["model"]
    n = len(scenario.initial_states)
    P0 = np.diag([m["prior_position_std"] ** 2] * 2 + [m["prior_velocity_std"] ** 2] * 2)
    problem = TrackingProblem(ConstantVelocity(m["q"]), scenario.sensor, scenario.initial_states,
                              np.broadcast_to(P0, (n, 4, 4)), time=scenario.times[0])
    return build({"kind": association, **cfg["tracker"]}, problem, where="sht.tracker")


def run_crossing(cfg, association, scenario, *, keep_estimates=False):
    """Run one tracker over one scenario from known initial tracks.

    Returns
    -------
    per_scan : DataFrame
        ``scan``, ``time``, ``ospa`` (all confirmed tracks), ``ospa_targets`` (only the tracks
        started on the targets: the association's share, without initiation's false tracks),
        ``n_tracks``, ``separation`` (distance between the tracks started on targets 0 and 1;
        NaN once either is gone), ``truth_separation``.
    lost : int
        Targets whose track was lost (see the module docstring).
    estimates : DataFrame or None
        With ``keep_estimates``: ``scan``, ``track``, ``x``, ``y`` of every confirmed track.
    """
    tr = _tracker(association, scenario, cfg)
    c, p = cfg["ospa"]["c"], cfg["ospa"]["p"]
    rows, est_rows = [], []
    scans, truths = scenario.scan_list(), scenario.truth_list()
    for k in range(1, len(scans)):
        est = tr.step(scans[k][1], scans[k][0])
        X = truths[k][2][:, :2]
        pos = dict(zip(est.ids.tolist(), est.x[:, :2]))
        sep = np.linalg.norm(pos[0] - pos[1]) if (0 in pos and 1 in pos) else np.nan
        tsep = np.linalg.norm(X[0] - X[1]) if len(X) > 1 else np.nan
        own = est.x[est.ids < len(X), :2]
        rows.append((k, scans[k][0], ospa(est.x[:, :2], X, c=c, p=p), ospa(own, X, c=c, p=p), len(est), sep, tsep))
        if keep_estimates:
            est_rows += [(k, int(i), float(xy[0]), float(xy[1])) for i, xy in pos.items()]
    final = dict(zip(est.ids.tolist(), est.x[:, :2]))
    X = truths[-1][2][:, :2]
    lost = sum(1 for i in range(len(X)) if i not in final or np.linalg.norm(final[i] - X[i]) > cfg["loss_distance"])
    per_scan = pd.DataFrame(
        rows, columns=["scan", "time", "ospa", "ospa_targets", "n_tracks", "separation", "truth_separation"]
    )
    estimates = pd.DataFrame(est_rows, columns=["scan", "track", "x", "y"]) if keep_estimates else None
    return per_scan, lost, estimates


def crossing_runs(cfg, seed, runs):
    """Crossing-target Monte Carlo runs ``runs`` (indices) for both methods on the same scenarios.

    Returns
    -------
    per_scan : DataFrame (method, run, scan, time, ospa, n_tracks, separation, truth_separation)
    per_run : DataFrame (method, run, mean_ospa, lost, n_targets)
    """
    seeds = experiment_seeds(seed, "sht_crossing", cfg["n_runs"])
    scans, per_run = [], []
    for r in runs:
        sc = _scenario(cfg, cfg["scenario"]["clutter_rate"], seeds[r])
        for method in METHODS:
            df, lost, _ = run_crossing(cfg, method, sc)
            df.insert(0, "run", r)
            df.insert(0, "method", method)
            scans.append(df)
            per_run.append((method, r, df["ospa"].mean(), df["ospa_targets"].mean(), lost, len(sc.initial_states)))
        print(f"sht crossing: run {r} done", flush=True)
    return pd.concat(scans, ignore_index=True), pd.DataFrame(
        per_run, columns=["method", "run", "mean_ospa", "mean_ospa_targets", "lost", "n_targets"]
    )


def sweep_runs(cfg, seed, runs):
    """Clutter-rate sweep: per (rate, method, run) time-averaged OSPAs, tracks and lost tracks."""
    seeds = experiment_seeds(seed, "sht_sweep", cfg["sweep"]["n_runs"])
    rows = []
    for rate in cfg["sweep"]["clutter_rates"]:
        for r in runs:
            sc = _scenario(cfg, rate, seeds[r])
            for method in METHODS:
                df, lost, _ = run_crossing(cfg, method, sc)
                rows.append((rate, method, r, df["ospa"].mean(), df["ospa_targets"].mean(), df["n_tracks"].mean(),
                             lost, len(sc.initial_states)))
        print(f"sht sweep: clutter rate {rate} done ({len(runs)} runs)", flush=True)
    return pd.DataFrame(
        rows, columns=["clutter_rate", "method", "run", "mean_ospa", "mean_ospa_targets", "mean_tracks", "lost", "n_targets"]
    )


def _mean_se(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    se = x.std(ddof=1) / np.sqrt(len(x)) if len(x) > 1 else np.nan
    return (x.mean() if len(x) else np.nan), se


def summarise_crossing(per_scan, per_run):
    """Per-scan means over runs (OSPA, separation) and the per-method summary table."""
    curves = []
    for (method, scan), g in per_scan.groupby(["method", "scan"], sort=True):
        o, o_se = _mean_se(g["ospa"])
        ot, ot_se = _mean_se(g["ospa_targets"])
        s, s_se = _mean_se(g["separation"])
        curves.append((method, scan, g["time"].iloc[0], o, o_se, ot, ot_se, s, s_se, g["truth_separation"].mean(),
                       len(g)))
    curves = pd.DataFrame(curves, columns=["method", "scan", "time", "mospa", "mospa_se", "mospa_targets",
                                           "mospa_targets_se", "separation", "separation_se", "truth_separation",
                                           "n_runs"])
    summary = []
    for method, g in per_run.groupby("method", sort=True):
        o, o_se = _mean_se(g["mean_ospa"])
        ot, ot_se = _mean_se(g["mean_ospa_targets"])
        loss = g["lost"].sum() / g["n_targets"].sum()
        summary.append((method, len(g), o, o_se, ot, ot_se, loss, np.sqrt(loss * (1 - loss) / g["n_targets"].sum())))
    summary = pd.DataFrame(summary, columns=["method", "n_runs", "mospa", "mospa_se", "mospa_targets",
                                             "mospa_targets_se", "track_loss", "track_loss_se"])
    return curves, summary


def summarise_sweep(per_run):
    """Mean OSPAs, tracks and track-loss fraction (with standard errors) per clutter rate and method."""
    rows = []
    for (rate, method), g in per_run.groupby(["clutter_rate", "method"], sort=True):
        o, o_se = _mean_se(g["mean_ospa"])
        ot, ot_se = _mean_se(g["mean_ospa_targets"])
        n_t = g["n_targets"].sum()
        loss = g["lost"].sum() / n_t
        rows.append((rate, method, len(g), o, o_se, ot, ot_se, g["mean_tracks"].mean(), loss,
                     np.sqrt(loss * (1 - loss) / n_t)))
    return pd.DataFrame(rows, columns=["clutter_rate", "method", "n_runs", "mospa", "mospa_se", "mospa_targets",
                                       "mospa_targets_se", "mean_tracks", "track_loss", "track_loss_se"])


def crossing_example(cfg, seed):
    """Run 0 of the crossing Monte Carlo, with truth, returns and both methods' tracks (one table)."""
    sc = _scenario(cfg, cfg["scenario"]["clutter_rate"], experiment_seeds(seed, "sht_crossing", cfg["n_runs"])[0])
    parts = []
    t = sc.truth
    parts.append(pd.DataFrame({"kind": "truth", "method": "", "id": t["target"], "scan": t["scan"],
                               "x": t["state_0"], "y": t["state_1"]}))
    s = sc.scans
    parts.append(pd.DataFrame({"kind": np.where(s["origin"] >= 0, "target_return", "clutter"), "method": "",
                               "id": s["origin"], "scan": s["scan"], "x": s["z_0"], "y": s["z_1"]}))
    for method in METHODS:
        _, _, est = run_crossing(cfg, method, sc, keep_estimates=True)
        parts.append(pd.DataFrame({"kind": "track", "method": method, "id": est["track"], "scan": est["scan"],
                                   "x": est["x"], "y": est["y"]}))
    return pd.concat(parts, ignore_index=True)

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
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd

from ...association import count_gated_associations, enumerate_associations, find_clusters, unassociated_measurements
from ...metrics import ospa
from ...models.motion import ConstantVelocity
from ...scenarios.cluttered import crossing_targets
from ...reporting.ledger import Claim, monte_carlo_claim
from ...reporting.verdict import with_control
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
    "plot_crossing",
    "plot_sweep",
    "sht_claims",
    "lecture_macros",
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


# ---------------------------------------------------------------- figures
def _save(fig, pdf, png, width: float = 1.0):
    from ...reporting import figure_style

    figure_style.save(fig, pdf, png, width=width)


def _band(ax, x, y, se, color, **kw):
    ax.plot(x, y, color=color, **kw)
    ax.fill_between(x, y - 2 * se, y + 2 * se, color=color, alpha=0.15)


def plot_crossing(example, curves, cfg, pdf, png):
    """Coalescence figure: one run's tracks (GNN, JPDA) near the crossing (top, shared legend below
    them), MC track separation and MC OSPA (bottom, each with its legend below it)."""
    from ...reporting import figure_style

    figure_style.use()
    import matplotlib.pyplot as plt

    s = cfg["scenario"]
    n_t = s["n_targets"]
    fig = plt.figure(figsize=(figure_style.TEXT_WIDTH_IN, figure_style.MAX_HEIGHT_IN - 0.05), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.0, 1.05])
    half = s["speed"] * s["dt"] * s["n_scans"] / 4  # zoom on the middle half of the run
    y_half = half * np.tan(np.deg2rad(s["crossing_angle_deg"] / 2)) + 6 * s["sigma"]
    merged = {}
    for ax, method in zip(top.subplots(1, len(METHODS), squeeze=False)[0], METHODS):
        cl = example[example["kind"] == "clutter"]
        tr = example[example["kind"] == "target_return"]
        ax.plot(cl["x"], cl["y"], ".", color="0.75", ms=3, label="clutter returns")
        ax.plot(tr["x"], tr["y"], "x", color="0.35", ms=4, label="target returns")
        for tid, g in example[example["kind"] == "truth"].groupby("id"):
            ax.plot(g["x"], g["y"], "k--", lw=1, label="true paths" if tid == 0 else None)
            inside = g[g["x"] >= -half].iloc[0]
            ax.annotate(f"target {tid}", (inside["x"], inside["y"]), textcoords="offset points", xytext=(4, 6))
        tracks = example[(example["kind"] == "track") & (example["method"] == method)]
        for tid, g in tracks.groupby("id"):
            if tid < n_t:
                ax.plot(g["x"], g["y"], ".-", ms=3, lw=1.8, color=f"C{tid}",
                        label=f"track {tid} (started on target {tid})")
            else:
                ax.plot(g["x"], g["y"], ".-", ms=2, lw=0.8, alpha=0.6, color="tab:gray",
                        label="tracks from initiation" if tid == n_t else None)
        ax.set_xlim(-half, half)
        ax.set_ylim(-y_half, y_half)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        ax.set_title(f"{LABELS[method]}: Monte Carlo run 0,\nmiddle half of the run")
        for h, lab in zip(*ax.get_legend_handles_labels()):
            merged.setdefault(lab, h)
    top.legend(list(merged.values()), list(merged), loc="outside lower center", ncol=3)
    n_runs = int(curves["n_runs"].max())
    left, right = bottom.subfigures(1, 2)
    ax = left.subplots()
    for method in METHODS:
        g = curves[curves["method"] == method]
        _band(ax, g["time"], g["separation"], g["separation_se"], COLORS[method], label=f"{LABELS[method]} tracks 0 and 1")
    g = curves[curves["method"] == METHODS[0]]
    ax.plot(g["time"], g["truth_separation"], "k--", label="true targets")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("distance between the two tracks (m)")
    ax.set_title(f"Track separation, mean ± 2 s.e. over {n_runs} runs:\nJPDA coalescence")
    left.legend(loc="outside lower center", ncol=2)
    ax = right.subplots()
    for method in METHODS:
        g = curves[curves["method"] == method]
        _band(ax, g["time"], g["mospa"], g["mospa_se"], COLORS[method], label=f"{LABELS[method]}, all confirmed tracks")
        _band(ax, g["time"], g["mospa_targets"], g["mospa_targets_se"], COLORS[method], ls=":",
              label=f"{LABELS[method]}, tracks started on the targets")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"OSPA (m), c = {cfg['ospa']['c']:g} m, p = {cfg['ospa']['p']:g}")
    ax.set_title(f"Mean OSPA ± 2 s.e. over {n_runs} runs")
    right.legend(loc="outside lower center", ncol=1)
    fig.suptitle(figure_style.wrap(
        f"Two targets crossing at {s['crossing_angle_deg']:g}° in clutter ({s['clutter_rate']:g} false returns/scan, "
        f"$P_D$ = {s['p_D']:g}, σ = {s['sigma']:g} m): GNN vs JPDA", fig))
    _save(fig, pdf, png)


def plot_sweep(table, cfg, pdf, png):
    """Clutter sweep: mean OSPA, confirmed tracks and track-loss fraction vs clutter rate, GNN vs JPDA,
    stacked, each panel's legend beside it."""
    from ...reporting import figure_style

    fig, axes = figure_style.subplots(3, 1, height=6.4, sharex=True)
    for method in METHODS:
        g = table[table["method"] == method]
        kw = dict(marker="o", capsize=3, color=COLORS[method])
        axes[0].errorbar(g["clutter_rate"], g["mospa"], yerr=2 * g["mospa_se"], label=f"{LABELS[method]}, all tracks", **kw)
        axes[0].errorbar(g["clutter_rate"], g["mospa_targets"], yerr=2 * g["mospa_targets_se"], ls=":",
                         label=f"{LABELS[method]}, tracks\nstarted on the targets", **kw)
        axes[1].plot(g["clutter_rate"], g["mean_tracks"], marker="o", color=COLORS[method], label=LABELS[method])
        axes[2].errorbar(g["clutter_rate"], g["track_loss"], yerr=2 * g["track_loss_se"], label=LABELS[method], **kw)
    axes[1].axhline(cfg["scenario"]["n_targets"], color="k", ls="--", lw=1, label="true number of targets")
    axes[0].set_ylabel(f"time-averaged OSPA (m)\nc = {cfg['ospa']['c']:g} m, p = {cfg['ospa']['p']:g}")
    axes[1].set_ylabel("mean number of\nconfirmed tracks")
    axes[2].set_ylabel(f"track-loss fraction\n(deleted or > {cfg['loss_distance']:g} m\noff at the end)")
    axes[-1].set_xlabel("expected clutter returns per scan")
    for ax in axes:
        figure_style.legend_right(ax)
    n = int(table["n_runs"].max())
    axes[0].set_title(f"Mean OSPA ± 2 s.e. ({n} runs per point)")
    axes[1].set_title("Confirmed tracks (false ones come from initiation)")
    axes[2].set_title(f"Track loss ± 2 s.e. ({n} runs per point)")
    fig.suptitle(figure_style.wrap(
        f"Crossing targets ({cfg['scenario']['crossing_angle_deg']:g}°): GNN vs JPDA against clutter rate", fig))
    _save(fig, pdf, png)


# ---------------------------------------------------------------- ledger
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

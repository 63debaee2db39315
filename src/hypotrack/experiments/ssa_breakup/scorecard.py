"""The operator's scorecard of one scored run (:func:`.run.run_scored`), built from
:mod:`hypotrack.metrics_scorecard`.

* **re-acquisition** (:func:`reacquisitions`): each object's track at the last scan of a pass (as held,
  :func:`.run.run_scored`) predicted by the trackers' EKF (``x' = f(x)``, ``P' = Φ P Φ^T + Q(Δt)``) to the
  first scan of the object's next pass, against the truth there: the RIC error, the squared Mahalanobis
  distance of the position error under ``P'`` (realism: the share inside ``χ²₃(0.95)``, and the mean of ``d²/3``,
  1 for a realistic covariance, below 1 for one too wide), whether it is
  within ``completeness_km`` (5 km), and whether the **nearest other object** in view then lies inside the
  track's gate (``(p_other − x')^T (P'_pos + σ² I)^-1 (p_other − x') ≤ χ²₃(P_G)``) — the share of
  re-acquisitions open to a cross-tag;
* **time to orbit** (:func:`~hypotrack.metrics_scorecard.time_to_orbit`): per object, from its first return to
  the end of the first pass whose track re-acquires it within ``completeness_km`` at its next pass (objects with
  such a pass only);
* **catalogue cross-tags** (``catalogue_cross_tags_per_1e4``): the cross-tags with each catalogued object's own
  label owned by that object (:func:`~hypotrack.metrics_scorecard.catalogue_owners`): a tracker that swaps two
  catalogued fragments for good is charged every return after the swap, which the track-purity owner calls correct;
* **completeness** (:func:`completeness`): every object of the scenario's catalogue, its track's state at the
  last scan predicted to the object's next pass after the run (first scan in view within
  ``next_pass_horizon_s``, else the horizon's end), within ``completeness_km`` of the truth; an object without
  a track counts as not complete.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.stats import chi2

from ...metrics_scorecard import (CROSS_TAG_CAUSES, catalogue_owners, chi2_share, cross_tag_causes,
                                  gospa_parts_per_object, id_switches, label_owners, mahalanobis2, per, return_tallies,
                                  ric_error, time_to_orbit)
from ...scenarios.catalogue.frames import gmst, teme_to_ef
from ...scenarios.catalogue.propagation import time_grid_jd
from .custody import first_return_own, reacquired_same_label
from .run import pass_ends

__all__ = ["predict", "reacquisitions", "next_pass", "completeness", "scorecard_row", "catalogued_ids", "identity_row"]


def predict(motion, x, P, dt):
    """EKF prediction of one state ``(6,)``, covariance ``(6, 6)`` by ``dt`` (s): ``(x', P')``, P' symmetrised."""
    if dt == 0:
        return x.copy(), P.copy()
    xp, Phi = motion.transition(x[None], float(dt))
    Pp = Phi[0] @ P @ Phi[0].T + motion.Q(abs(float(dt)))
    return xp[0], 0.5 * (Pp + Pp.T)


def reacquisitions(run, truth: pd.DataFrame, motion, sigma_km: float, gate_probability: float,
                   completeness_km: float) -> pd.DataFrame:
    """One row per (object, pass) whose end state is held and which has a next pass (module docstring)."""
    passes = pass_ends(truth)
    nxt = {(r.target, r.pass_no): r for r in passes.itertuples(index=False)}
    tv = truth[truth["in_view"]]
    by_scan = {k: g for k, g in tv.groupby("scan")}
    g2 = chi2.ppf(gate_probability, 3)
    ev = [(e, nxt[(e["target"], e["pass_no"] + 1)]) for e in run.ends
          if e["pass_no"] >= 0 and (e["target"], e["pass_no"] + 1) in nxt]
    rows = []
    if not ev:
        return pd.DataFrame(rows, columns=["target", "pass_no", "t_end", "gap_s", "err_r", "err_i", "err_c", "d2",
                                           "within", "nn_in_gate"])
    X0 = np.array([e["x"] for e, _ in ev])
    P0 = np.array([e["P"] for e, _ in ev])
    dt = np.array([p.t_first - e["t_x"] for e, p in ev])
    Xp, Phi = motion.transition_each(X0, dt)  # one batch: each row by its own interval (the EKF of predict)
    Pp = Phi @ P0 @ np.swapaxes(Phi, 1, 2) + motion.Q_each(np.abs(dt))
    Pp = 0.5 * (Pp + np.swapaxes(Pp, 1, 2))
    for (e, p), x, P in zip(ev, Xp, Pp):
        g = by_scan[p.first_scan]
        ids = g["target"].to_numpy(np.int64)
        pos = g[["state_0", "state_1", "state_2"]].to_numpy()
        xt = g[ids == e["target"]][[f"state_{i}" for i in range(6)]].to_numpy()[0]
        ric = ric_error(xt[None], x[None])[0]
        d2 = mahalanobis2((x[:3] - xt[:3])[None], P[None, :3, :3])[0]
        others = pos[ids != e["target"]]
        if len(others):
            j = np.argmin(np.linalg.norm(others - xt[:3], axis=1))
            S = P[:3, :3] + sigma_km**2 * np.eye(3)
            nn_in = bool(mahalanobis2((others[j] - x[:3])[None], S[None])[0] <= g2)
        else:
            nn_in = False
        rows.append(dict(target=e["target"], pass_no=e["pass_no"], t_end=e["time"], gap_s=p.t_first - e["time"],
                         err_r=ric[0], err_i=ric[1], err_c=ric[2], d2=d2,
                         within=bool(np.linalg.norm(ric) <= completeness_km), nn_in_gate=nn_in))
    return pd.DataFrame(rows, columns=["target", "pass_no", "t_end", "gap_s", "err_r", "err_i", "err_c", "d2", "within",
                                       "nn_in_gate"])


def next_pass(sc, after_s: float, horizon_s: float, step_s: float = 30.0):
    """Per catalogue object: the time (s since ``sc.start``) of its first instant in the radar's view after
    ``after_s`` within ``horizon_s`` on a ``step_s`` grid (else the horizon's end), its true state then, and
    whether that state is valid."""
    grid = after_s + np.arange(step_s, horizon_s + 1e-9, step_s)
    X, valid = sc.states(grid)
    jd, fr = time_grid_jd(sc.start, grid)
    r_ef, _ = teme_to_ef(X[..., :3], X[..., 3:], gmst(jd, fr))
    with np.errstate(invalid="ignore"):
        vis = sc.sensors[0].in_view(r_ef) & valid
    j = np.where(vis.any(axis=1), np.argmax(vis, axis=1), len(grid) - 1)
    n = np.arange(len(X))
    return grid[j], X[n, j], valid[n, j]


def completeness(run, sc, motion, horizon_s: float, completeness_km: float) -> tuple[int, int]:
    """``(complete, catalogued)`` (module docstring); the held tracks predicted in one batch, each by its own
    interval (:meth:`propagate_each`, the EKF mean of :func:`predict`)."""
    final = {e["target"]: e for e in run.ends if e["pass_no"] < 0}
    t_end = float(sc.times[-1])
    t_next, X_next, ok = next_pass(sc, t_end, horizon_s)
    ids = sc.catalogue["norad"].to_numpy(np.int64)
    rows = [i for i, tid in enumerate(ids) if ok[i] and int(tid) in final]
    if not rows:
        return 0, int(ok.sum())
    ev = [final[int(ids[i])] for i in rows]
    x = motion.propagate_each(np.array([e["x"] for e in ev]), np.array([t_next[i] - e["t_x"] for i, e in zip(rows, ev)]))
    done = int((np.linalg.norm(x[:, :3] - X_next[rows, :3], axis=1) <= completeness_km).sum())
    return done, int(ok.sum())


def _time_to_orbit(run, reacq: pd.DataFrame, scan_times) -> tuple[float, int]:
    """Mean time to orbit (:func:`~hypotrack.metrics_scorecard.time_to_orbit`; s) over the objects with one, and
    their number."""
    r = run.returns[run.returns["origin"] >= 0]
    _, dt = time_to_orbit(r["origin"], np.asarray(scan_times, float)[r["scan"].to_numpy(np.int64)], reacq["target"],
                          reacq["t_end"], reacq["within"])
    return (float(np.mean(dt)) if len(dt) else float("nan")), int(len(dt))


def scorecard_row(run, scenario, cfg, motion) -> dict:
    """The scorecard of one run (module docstring and :mod:`hypotrack.metrics_scorecard`) as one flat row."""
    _, unknown, sc, _ = scenario
    m = cfg["metrics"]
    ps = run.per_scan
    owners = label_owners(run.assign["target"], run.assign["label"])
    tal = return_tallies(run.returns["origin"], run.returns["label"], owners)
    n = tal["n_returns"]
    catalogued = catalogued_ids(scenario)
    cat_tal = return_tallies(run.returns["origin"], run.returns["label"], catalogue_owners(owners, catalogued))
    reacq = reacquisitions(run, sc.truth, motion, cfg["radar"]["sigma_km"], cfg["model"]["gate_probability"],
                           m["completeness_km"])
    done, cat_n = completeness(run, sc, motion, m["next_pass_horizon_s"], m["completeness_km"])
    t_orbit, n_orbit = _time_to_orbit(run, reacq, sc.times)
    n_est = int(ps["n_estimates"].sum())
    row = dict(tracker=run.tracker, n_objects=len(sc.catalogue), n_scans=len(ps), object_returns=n,
               correct_per_1e4=per(tal["correct"], n, 1e4), cross_tags_per_1e4=per(tal["cross_tags"], n, 1e4),
               orphan_per_1e4=per(tal["orphan"], n, 1e4), uncorrelated_per_1e4=per(tal["uncorrelated"], n, 1e4),
               cross_tags=tal["cross_tags"], catalogue_cross_tags_per_1e4=per(cat_tal["cross_tags"], n, 1e4),
               catalogue_cross_tags=cat_tal["cross_tags"], completeness=done / cat_n if cat_n else float("nan"),
               false_per_1000=per(int(ps["false"].sum()), n_est, 1e3),
               duplicate_per_1000=per(int(ps["duplicate"].sum()), n_est, 1e3),
               reacquisitions=len(reacq),
               reacq_within_km=float(reacq["within"].mean()) if len(reacq) else float("nan"),
               rms_radial_km=float(np.sqrt(np.mean(reacq["err_r"] ** 2))) if len(reacq) else float("nan"),
               rms_intrack_km=float(np.sqrt(np.mean(reacq["err_i"] ** 2))) if len(reacq) else float("nan"),
               rms_crosstrack_km=float(np.sqrt(np.mean(reacq["err_c"] ** 2))) if len(reacq) else float("nan"),
               realism_95=chi2_share(reacq["d2"], 0.95),
               realism_mean_d2=float(np.mean(reacq["d2"]) / 3) if len(reacq) else float("nan"), nn_in_gate_share=float(reacq["nn_in_gate"].mean())
               if len(reacq) else float("nan"), time_to_orbit_s=t_orbit, objects_with_orbit=n_orbit,
               unphysical_map_per_scan=float(ps["unphysical_map"].mean()),
               unphysical_hypotheses_per_scan=float(ps["unphysical_hypotheses"].mean()),
               unphysical_hypotheses_max=float(ps["unphysical_hypotheses"].max()),
               cpu_s=float(ps["cpu_s"].sum()))
    A, rt = run.assign, run.returns
    causes = cross_tag_causes(rt["scan"], rt["origin"], rt["label"], owners, A["scan"], A["target"], A["label"],
                              catalogued)
    row.update({f"xtag_{k}_per_1e4": per(causes[k], n, 1e4) for k in CROSS_TAG_CAUSES})
    n_view = int(ps["n_in_view"].sum())
    switches = id_switches(A["scan"], A["target"], A["label"])
    row.update(id_switches=switches, id_switches_per_1e4=per(switches, n_view, 1e4),
               first_return_own=first_return_own(rt, catalogued),
               reacquired_same_label=reacquired_same_label(A, pass_ends(sc.truth)))
    row.update(gospa_parts_per_object(ps["gospa_loc"], ps["gospa_missed"], ps["gospa_false"], ps["n_in_view"]))
    return row


def catalogued_ids(scenario) -> np.ndarray:
    """The NORAD numbers of a scenario's catalogued objects (those not unknown): the labels their initial tracks
    carry."""
    _, unknown, sc, _ = scenario
    ids = sc.catalogue["norad"].to_numpy(np.int64)
    return ids[~np.isin(ids, np.asarray(unknown, dtype=np.int64))]


def identity_row(run, catalogued=()) -> dict:
    """The scorecard's identity columns of one run alone (no prediction: the cheap part of :func:`scorecard_row`, for a
    sweep of the output policy, :meth:`.run.ScoredRun.with_output`): cross-tags per 10⁴ object returns and identity
    switches per 10⁴ object-scans in view, with their counts, and the uncorrelated returns per 10⁴ (those the policy
    withholds among them)."""
    owners = label_owners(run.assign["target"], run.assign["label"])
    tal = return_tallies(run.returns["origin"], run.returns["label"], owners)
    A, n_view = run.assign, int(run.per_scan["n_in_view"].sum())
    switches = id_switches(A["scan"], A["target"], A["label"])
    cat = return_tallies(run.returns["origin"], run.returns["label"], catalogue_owners(owners, catalogued))
    return dict(tracker=run.tracker, object_returns=tal["n_returns"], cross_tags=tal["cross_tags"],
                cross_tags_per_1e4=per(tal["cross_tags"], tal["n_returns"], 1e4),
                catalogue_cross_tags_per_1e4=per(cat["cross_tags"], tal["n_returns"], 1e4), id_switches=switches,
                id_switches_per_1e4=per(switches, n_view, 1e4),
                uncorrelated_per_1e4=per(tal["uncorrelated"], tal["n_returns"], 1e4))

"""The operator's scorecard of the sparse catalogue: the breakup experiment's, on the catalogue's runs.

:func:`run_with_scorecard` steps one tracker once over the scans of one population size through
:func:`hypotrack.experiments.ssa_breakup.run.run_scored` (which records what the scorecard needs: each return's
origin and the track it correlates to, purity, GOSPA's parts, the unphysical hypotheses held, each object's track
at the end of its passes), adding per scan the columns of the catalogue's own table (GOSPA and OSPA at the
config's order, groups, tracks held: :func:`.run.run_tracker`'s). From that one run come both the catalogue's
per-scan and assignment tables and the scorecard row (:func:`hypotrack.experiments.ssa_breakup.scorecard.
scorecard_row`: return correlation, completeness, purity, RIC error and covariance realism at re-acquisition,
GOSPA per object in view, unphysical hypotheses per scan).

**Time to orbit of the objects born from the data** (:func:`unknown_time_to_orbit`): a two-hour run rarely
sees an object born in one pass come back, so each pass end of an object unknown at the start is scored
against the object's next pass wherever it falls, inside the run or after it (:func:`orbit_checks`: the held
track predicted to the first instant the object is in the radar's view again, more than ``PASS_GAP_S`` after
the pass ended, within 5 km of the truth there), and
:func:`~hypotrack.metrics_scorecard.time_to_orbit` measures from the object's first return.

:func:`scorecard_table`, :func:`scorecard_claims`, :func:`scorecard_macros` turn the rows into the table, the
ledger rows (status *extension*) and the report's macros; ``cpu_s`` stays in the run's timing table.
:func:`tuning_sweep` measures what the process noise gives on the tuning run and on the evaluated one (the
configuration's ``tuning`` comment quotes it).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...hypotheses.factored import FactoredFilter
from ...metrics import gospa, ospa
from ...reporting.ledger import Claim
from ...metrics_scorecard import time_to_orbit
from ...scenarios.catalogue.frames import gmst, teme_to_ef
from ...scenarios.catalogue.propagation import propagate, time_grid_jd
from ..ssa_breakup.run import PASS_GAP_S, run_scored
from ..ssa_breakup.scorecard import scorecard_row
from .run import FACTORED, _n_tracks, build_scenario, make_motion
from .summary import TRACKER_NAMES

__all__ = ["run_with_scorecard", "orbit_checks", "unknown_time_to_orbit", "scorecard_table", "scorecard_claims",
           "scorecard_macros", "compare", "tuning_sweep", "COLUMNS"]

EXPERIMENT = "ssa_catalogue"
SOURCE = "extension (SSA at catalogue scale)"

#: The scorecard table's columns (deterministic given config and seed: no CPU times).
COLUMNS = ["tracker", "n_objects", "n_scans", "object_returns", "correct_per_1e4", "cross_tags_per_1e4",
           "orphan_per_1e4", "uncorrelated_per_1e4", "cross_tags", "completeness", "false_per_1000",
           "duplicate_per_1000", "reacquisitions", "reacq_within_km", "rms_radial_km", "rms_intrack_km",
           "rms_crosstrack_km", "realism_95", "realism_mean_d2", "nn_in_gate_share", "time_to_orbit_unknown_s", "unknown_with_orbit",
           "unknown_detected", "unknown", "unphysical_map_per_scan", "unphysical_hypotheses_per_scan",
           "unphysical_hypotheses_max",
           "gospa_localisation_per_object_km", "gospa_missed_per_object_km", "gospa_false_per_object_km",
           "gospa_per_object_km"]


def _catalogue_columns(cfg):
    """The ``on_scan`` hook of :func:`run_scored`: the columns :func:`.run.run_tracker` records beyond it."""
    c, p = cfg["metrics"]["cutoff_km"], cfg["metrics"]["order"]

    def cols(k, tracker, EX, TX):
        gr = gospa(EX, TX, c=c, p=p)
        st = tracker.last_stats if isinstance(tracker, FactoredFilter) else {}
        return dict(gospa_km=gr.value, gospa_missed_p=gr.missed, gospa_false_p=gr.false, ospa_km=ospa(EX, TX, c=c, p=p),
                    n_groups=st.get("n_groups", np.nan), largest_group=st.get("largest_group", np.nan),
                    n_tracks=_n_tracks(tracker))

    return cols


def run_with_scorecard(name: str, cfg, n: int, seed: int, scenario):
    """Tracker ``name`` once over the scans of ``scenario`` (size ``n``, a :func:`.run.build_scenario` tuple).

    Returns ``(per_scan, assign, card)``: the tables of :func:`.run.run_tracker` (same columns, same values) and
    the scorecard row (a dict, with the run's ``cpu_s``)."""
    run = run_scored(name, cfg, scenario, int(seed), on_scan=_catalogue_columns(cfg))
    ps = run.per_scan
    per_scan = pd.DataFrame(dict(tracker=name, n_objects=int(n), scan=ps["scan"], cpu_s=ps["cpu_s"],
                                 n_returns=ps["n_returns"], n_in_view=ps["n_in_view"], n_estimates=ps["n_estimates"],
                                 gospa_km=ps["gospa_km"], gospa_missed=ps["gospa_missed_p"],
                                 gospa_false=ps["gospa_false_p"], ospa_km=ps["ospa_km"], n_groups=ps["n_groups"],
                                 largest_group=ps["largest_group"], n_tracks=ps["n_tracks"]))
    a = run.assign
    unknown = set(np.asarray(scenario[1]).tolist())
    assign = pd.DataFrame(dict(tracker=name, n_objects=int(n), scan=a["scan"].astype(int), target=a["target"].astype(int),
                               label=a["label"].astype(int), unknown=[int(t) in unknown for t in a["target"]]))
    motion = make_motion(cfg)
    card = scorecard_row(run, scenario, cfg, motion)
    m = cfg["metrics"]
    card.update(unknown_time_to_orbit(run, scenario, motion, m["next_pass_horizon_s"], m["completeness_km"]))
    return per_scan, assign, card


def orbit_checks(run, sc, motion, objects, horizon_s: float, radius_km: float, step_s: float = 30.0) -> pd.DataFrame:
    """Per held pass end (``pass_no >= 0``) of the objects ``objects``: ``target``, ``t_end``, the time ``t_next`` of
    the object's next instant in view — on a ``step_s`` grid, the first after it has left the view and more than
    :data:`PASS_GAP_S` after ``t_end``, up to ``horizon_s`` after that (``NaN``: none) — and ``ok``: the track held at
    the pass end, predicted there (EKF mean), is within ``radius_km`` of the truth."""
    cols = ["target", "t_end", "t_next", "ok"]
    want = set(int(o) for o in np.asarray(objects).tolist())
    ends = [e for e in run.ends if e["pass_no"] >= 0 and int(e["target"]) in want]
    if not ends:
        return pd.DataFrame(columns=cols)
    cat = sc.catalogue[sc.catalogue["norad"].isin(want)]  # only the objects asked about (the whole catalogue in full.yaml)
    row = {int(t): i for i, t in enumerate(cat["norad"].to_numpy(np.int64))}
    t_end = np.array([e["time"] for e in ends])
    grid = np.arange(t_end.min() + step_s, t_end.max() + PASS_GAP_S + horizon_s + step_s / 2, step_s)
    p = propagate(cat, grid, sc.start)
    X, valid = np.concatenate([p.r, p.v], axis=-1), p.valid
    jd, fr = time_grid_jd(sc.start, grid)
    r_ef, _ = teme_to_ef(X[..., :3], X[..., 3:], gmst(jd, fr))
    with np.errstate(invalid="ignore"):
        vis = sc.sensors[0].in_view(r_ef) & valid
    j_next = np.full(len(ends), -1)
    for n, (e, t) in enumerate(zip(ends, t_end)):
        v = vis[row[int(e["target"])]]
        after = grid > t
        left = np.flatnonzero(after & ~v)  # the object must leave the view first (a pass cut by the run's end)
        if len(left) == 0:
            continue
        ok = np.flatnonzero((np.arange(len(grid)) > left[0]) & v & (grid > t + PASS_GAP_S)
                            & (grid <= t + PASS_GAP_S + horizon_s))
        if len(ok):
            j_next[n] = ok[0]
    have = np.flatnonzero(j_next >= 0)
    out = pd.DataFrame(dict(target=[int(e["target"]) for e in ends], t_end=t_end, t_next=np.nan, ok=False))
    if len(have):
        x0 = np.array([ends[n]["x"] for n in have])
        dt = np.array([grid[j_next[n]] - ends[n]["t_x"] for n in have])
        xp = motion.propagate_each(x0, dt)
        truth = X[[row[int(ends[n]["target"])] for n in have], j_next[have], :3]
        out.loc[have, "t_next"] = grid[j_next[have]]
        out.loc[have, "ok"] = np.linalg.norm(xp[:, :3] - truth, axis=1) <= radius_km
    return out[cols]


def unknown_time_to_orbit(run, scenario, motion, horizon_s: float, radius_km: float) -> dict:
    """Of the objects unknown at the start (the scenario's ``unknown``): how many were detected, how many have an
    orbit (:func:`orbit_checks`), and their mean time to orbit (s; NaN for none)."""
    _, unknown, sc, _ = scenario
    unknown = np.asarray(unknown, np.int64)
    r = run.returns[np.isin(run.returns["origin"].to_numpy(np.int64), unknown)]
    checks = orbit_checks(run, sc, motion, unknown, horizon_s, radius_km)
    _, dt = time_to_orbit(r["origin"], np.asarray(sc.times, float)[r["scan"].to_numpy(np.int64)], checks["target"],
                          checks["t_end"], checks["ok"].astype(bool))
    return dict(time_to_orbit_unknown_s=float(np.mean(dt)) if len(dt) else float("nan"), unknown_with_orbit=len(dt),
                unknown_detected=int(r["origin"].nunique()), unknown=int(len(unknown)))


def scorecard_table(cards: pd.DataFrame) -> pd.DataFrame:
    """The scorecard table (:data:`COLUMNS`) in tracker order (:data:`.summary.TRACKER_NAMES`), then by size."""
    order = {t: i for i, t in enumerate(TRACKER_NAMES)}
    t = cards.assign(_o=cards["tracker"].map(order).fillna(len(order)))
    return t.sort_values(["_o", "n_objects"], kind="stable")[COLUMNS].reset_index(drop=True)


def _fmt(x, digits=3):
    return "n/a" if not np.isfinite(x) else f"{x:.{digits}g}"


def scorecard_claims(table: pd.DataFrame, reference: str = "gnn") -> list[Claim]:
    """Extension rows at the largest size, per tracker: cross-tags per 10⁴ object returns (the correct and
    uncorrelated ones in the note), completeness at the next pass, and covariance realism at re-acquisition
    against its 95 % goal — each with ``reference``'s value in the note."""
    n = int(table["n_objects"].max())
    big = table[table["n_objects"] == n].set_index("tracker")
    ref = big.loc[reference] if reference in big.index else None
    out = []
    for name, r in big.iterrows():
        lab = TRACKER_NAMES.get(name, name)
        vs = f"; {TRACKER_NAMES.get(reference, reference)}: " if ref is not None and name != reference else None
        out.append(Claim(EXPERIMENT, f"scorecard: cross-tags per 10^4 object returns, {lab}, N = {n}", SOURCE, "--",
                         _fmt(r.cross_tags_per_1e4), "--", "extension",
                         f"{int(r.object_returns)} object returns over {int(r.n_scans)} scans: correct "
                         f"{_fmt(r.correct_per_1e4, 5)}, uncorrelated {_fmt(r.uncorrelated_per_1e4)}, to false or "
                         f"duplicate tracks {_fmt(r.orphan_per_1e4)} per 10^4" + (f"{vs}{_fmt(ref.cross_tags_per_1e4)}"
                                                                                    if vs else ""),
                         "measurement", key=f"card_crosstags_{name}"))
        out.append(Claim(EXPERIMENT, f"scorecard: completeness at the next pass, {lab}, N = {n}", SOURCE, "--",
                         _fmt(r.completeness), "--", "extension",
                         "share of all catalogued objects, in view or not, whose track predicted to the object's "
                         "next pass after the run is within 5 km of the truth" + (f"{vs}{_fmt(ref.completeness)}"
                                                                                    if vs else ""),
                         "measurement", key=f"card_completeness_{name}"))
        out.append(Claim(EXPERIMENT, f"scorecard: covariance realism at re-acquisition, {lab}, N = {n}", SOURCE,
                         "--", _fmt(r.realism_95), "--", "extension",
                         f"goal 0.95 (a realistic covariance); share of {int(r.reacquisitions)} squared Mahalanobis distances (3-D position, track "
                         f"predicted across the gap) inside chi2_3(0.95); RMS radial / in-track / cross-track "
                         f"{_fmt(r.rms_radial_km)} / {_fmt(r.rms_intrack_km)} / {_fmt(r.rms_crosstrack_km)} km"
                         + (f"{vs}{_fmt(ref.realism_95)}" if vs else ""),
                         "measurement", key=f"card_realism_{name}"))
    return out


def _v(x, digits=3):
    return f"{x:.{digits}g}" if np.isfinite(x) else "n/a"


def scorecard_macros(table: pd.DataFrame, reference: str = "gnn") -> dict:
    """Macros ``Card<Field><Tracker>`` at the largest size and the verdict's: per compared field, the largest
    difference of a multi-hypothesis tracker from ``reference`` (``CardMaxDiff<Field>``) and where they lie
    against it in words (``CardCmp<Field>``, :func:`compare`)."""
    n = int(table["n_objects"].max())
    big = table[table["n_objects"] == n].set_index("tracker")
    v = {"CardN": n, "CardScans": int(big["n_scans"].iloc[0])}
    fields = {"CrossTags": "cross_tags_per_1e4", "Correct": "correct_per_1e4", "Uncorrelated": "uncorrelated_per_1e4",
              "Orphan": "orphan_per_1e4", "Completeness": "completeness", "False": "false_per_1000",
              "Duplicate": "duplicate_per_1000", "Reacq": "reacquisitions", "ReacqWithin": "reacq_within_km",
              "Radial": "rms_radial_km", "Intrack": "rms_intrack_km", "Crosstrack": "rms_crosstrack_km",
              "Realism": "realism_95", "RealismDsq": "realism_mean_d2", "TimeToOrbit": "time_to_orbit_unknown_s", "UnknownOrbit": "unknown_with_orbit",
              "Unknown": "unknown", "UnknownDetected": "unknown_detected", "UnphysMean": "unphysical_hypotheses_per_scan",
              "UnphysMax": "unphysical_hypotheses_max", "UnphysMap": "unphysical_map_per_scan",
              "GospaLoc": "gospa_localisation_per_object_km", "GospaMissed": "gospa_missed_per_object_km",
              "GospaFalse": "gospa_false_per_object_km", "Gospa": "gospa_per_object_km"}
    ints = {"Reacq", "UnknownOrbit", "Unknown", "UnknownDetected"}
    for name, r in big.iterrows():
        k = name.replace("_", "")
        for f, col in fields.items():
            v[f"Card{f}{k}"] = int(r[col]) if f in ints else _v(float(r[col]), 5 if f == "Correct" else 3)
    v["CardObjectReturns"] = int(big["object_returns"].iloc[0])
    if reference in big.index:
        mht = [t for t in FACTORED if t in big.index]
        for f in ("CrossTags", "Completeness", "Realism", "Gospa", "False", "Duplicate", "Radial", "Intrack",
                  "UnknownOrbit"):
            ref, own = float(big.loc[reference, fields[f]]), [float(big.loc[t, fields[f]]) for t in mht]
            d = [abs(x - ref) for x in own if np.isfinite(x) and np.isfinite(ref)]
            v[f"CardMaxDiff{f}"] = _v(max(d)) if d else "n/a"  # a small run may have no re-acquisition
            v[f"CardCmp{f}"] = compare(own, ref)
    return v


def compare(values, reference) -> str:
    """Where ``values`` (the multi-hypothesis trackers') lie against ``reference`` (GNN's), in words for the
    report's verdict, compared as printed (3 significant digits): "equal to" (all), "below" (some below, none
    above), "above" (some above, none below), "on both sides of", or "not comparable with" (a value missing)."""
    r = float(reference)
    x = [float(a) for a in values]
    if not x or not np.isfinite(r) or not all(np.isfinite(x)):
        return "not comparable with"
    same = [_v(a) == _v(r) for a in x]
    if all(same):
        return "equal to"
    lo, hi = any(a < r and not s for a, s in zip(x, same)), any(a > r and not s for a, s in zip(x, same))
    return "on both sides of" if lo and hi else ("below" if lo else "above")


def tuning_sweep(cfg, qs, n: int, n_scans: int, trackers=("glmb", "gnn"), windows=("tuned_on", "evaluated_on")):
    """The process-noise choice measured on the tuning run and on the evaluated one: per window of
    ``cfg['tuning']`` (its seed and start offset), ``q`` of ``qs`` and tracker, one scorecard row at size ``n``
    over ``n_scans`` scans (with the scorecard's ``realism_mean_d2``, the mean of ``d²/3`` at re-acquisition: 1 for
    a realistic covariance, below 1 for one too wide)."""
    rows = []
    for w in windows:
        ev = cfg["tuning"][w]
        seed = int(ev["seed"])
        base = {**cfg, "n_scans": int(n_scans), "tuning": {"evaluated_on": dict(ev)}}
        scenario = build_scenario(base, int(n), seed)
        for q in qs:
            c = {**base, "model": {**cfg["model"], "process_noise_q": float(q)}}
            for name in trackers:
                run = run_scored(name, c, scenario, seed)
                motion = make_motion(c)
                card = scorecard_row(run, scenario, c, motion)
                rows.append(dict(window=w, seed=seed, start_offset_s=float(ev["start_offset_s"]), q=float(q),
                                 **{k: card[k] for k in ("tracker", "n_objects", "n_scans", "completeness",
                                                         "reacquisitions", "reacq_within_km", "rms_intrack_km",
                                                         "realism_95", "gospa_per_object_km", "cross_tags_per_1e4")},
                                 realism_mean_d2=card["realism_mean_d2"]))
    return pd.DataFrame(rows)

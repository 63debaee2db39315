"""SSA at catalogue scale: real objects (TLE, SGP4) seen by a ground radar, tracked by five trackers.

Scenario (config section ``ssa_catalogue``)
--------------------------------------------
* **truth**: a seeded sample of ``N`` objects from the active satellites and one debris cloud
  (:func:`select_population`), propagated by SGP4 (:func:`hypotrack.scenarios.catalogue.simulate_catalogue`);
* **sensor**: one ground radar (:class:`~hypotrack.scenarios.catalogue.GroundRadar`, its
  site, field of view, 10-s revisit, p_D and Poisson clutter from the config) reporting ENU
  positions with isotropic error σ — converted to TEME positions for the trackers
  (:mod:`hypotrack.scenarios.catalogue.tracking`) — or, with ``radar.measurement: rae_rate``, the
  documented radar's range, azimuth, elevation and range-rate (σ from ``sigma_range_km``,
  ``sigma_angle_deg``, ``sigma_range_rate_km_s``; :mod:`hypotrack.scenarios.catalogue.radar_model`),
  which the trackers use **in the sensor frame** (:func:`tracker_sensor`: an EKF update with
  ``z = h(x)``, a per-track Jacobian and a constant ``R``; births from ``model.birth``: ``one_point``
  or ``admissible``, the admissible-region mixture of :mod:`hypotrack.scenarios.catalogue.admissible`);
* **motion model** of every tracker (:func:`make_motion`, ``trackers.motion``): the EKF of
  two-body motion plus J2 (:class:`~hypotrack.models.orbit3d.J2Orbit3D`), which neglects the
  higher zonals, drag and third bodies (SGP4 has them), or of two-body motion alone
  (:class:`~hypotrack.models.orbit3d.TwoBodyOrbit3D`), which neglects J2 too and drifts tens of
  kilometres from SGP4 in an orbit — the process noise ``q`` covers the mismatch;
* **known objects** start at their SGP4 state at scan 0 plus a seeded Gaussian error (the
  catalogue's uncertainty, ``init_position_std``/``init_velocity_std``) with that covariance;
  a share ``unknown_share`` of the debris is **unknown** at the start and must be born from the data.

Trackers on the same scans: the δ-GLMB filter (Gibbs), HOMHT k-best (Murty) and R-FISST (MCMC)
on the factored engine (:class:`~hypotrack.hypotheses.factored.FactoredFilter`; GLMB and R-FISST
with measurement-driven births, :class:`~hypotrack.hypotheses.factored.AdaptiveBirth`, HOMHT
with Reid's births seeded at the returns), GNN and JPDA (M-of-N initiation; a track is deleted
after ``max_misses`` consecutive misses *in view* — out of view is not a miss).

Per tracker, population size and scan (:func:`run_tracker`): CPU seconds
(``time.process_time``), groups and the largest group, GOSPA and OSPA of the estimates in view
against the truth in view, and the estimate assigned to each true object (for continuity and
births, :func:`continuity`). The association samplers' compiled kernels are loaded before the first scan
(:func:`~hypotrack.hypotheses.warm.warm_samplers`), and the factored engine's (:func:`~hypotrack.hypotheses.warm.warm_engine`:
scan 0, timed here, would load them all); another kernel a tracker first calls inside the run (JPDA's
loopy belief propagation on its first cluster) is compiled in that scan when numba's cache is cold, as in a fresh
checkout: seconds of CPU in one scan of the first population size (its ``cpu_s_max``), which its mean per scan
and the cost slope then carry.
"""

from __future__ import annotations

import time
import tracemalloc
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from ...hypotheses.factored import AdaptiveBirth, FactoredFilter
from ...hypotheses.warm import warm_engine, warm_samplers
from ...metrics import gospa, ospa
from ...models.orbit3d import J2Orbit3D, TwoBodyOrbit3D
from ...scenarios.catalogue import (
    GroundRadar,
    GroundSite,
    RadarFieldOfView,
    load_catalogue,
    reference_epoch,
    select_groups,
    simulate_catalogue,
)
from ...scenarios.catalogue.admissible import AdmissibleRegionBirth, SeededAdmissibleBirth
from ...scenarios.catalogue.fov_edge import attach_soft_edge
from ...scenarios.catalogue.radar_model import RadarOnePointBirth, RadarTrackerSensor
from ...scenarios.catalogue.tracking import OnePointBirth, TrackerSensor
from ...registry import MeasurementBirths, TrackerSpec, TrackingProblem, build
from ...trackers import ScanModel, SingleHypothesisTracker
from ..stepping import SHTStepper, max_abs_difference
from .physics import attach_tracker_snr, model_survival, model_validity, object_sizes, radar_snr

__all__ = ["evaluated_on", "check_tuning", "MOTIONS", "REENTRY_GAP_SCANS", "BIRTHS", "tracker_sensor", "initial_tracks", "make_motion", "make_problem", "make_tracker", "FACTORED", "select_population", "make_radar", "build_scenario", "run_tracker",
           "continuity", "scan_rows", "parallel_timing", "same_posterior", "PeerScenario", "peer_scenario",
           "CatalogueSHTStepper", "peer_rows", "peer_config"]

#: The factored trackers of the committed configurations (names of ``ssa_catalogue.trackers``), for the summaries.
FACTORED = ("glmb", "homht_kbest", "rfisst")


def select_population(n: int, debris_group: str, debris_share: float, unknown_share: float, seed: int):
    """``n`` objects: ``round(debris_share n)`` from ``debris_group``, the rest active satellites,
    each a seeded simple random sample; a seeded ``unknown_share`` of the debris is unknown.
    ``n`` equal to the catalogue's size is the **whole catalogue**: every active satellite and
    every debris cloud (``debris_group`` and ``debris_share`` then do not apply).

    Returns ``(catalogue table, unknown NORAD numbers)``. Nested in ``n`` is not promised.
    """
    if not 0.0 <= debris_share <= 1.0:
        raise ValueError(f"debris_share must lie in [0, 1], got {debris_share!r}")
    if not 0.0 <= unknown_share <= 1.0:
        raise ValueError(f"unknown_share must lie in [0, 1], got {unknown_share!r}")
    cat = load_catalogue()
    rng = np.random.default_rng(seed)
    if n == len(cat):
        debris = cat["group"] != "active"
        unknown = cat["norad"].to_numpy(np.int64)[debris.to_numpy() & (rng.random(len(cat)) < unknown_share)]
        return cat.reset_index(drop=True), np.sort(unknown)
    debris, active = select_groups(cat, debris_group), select_groups(cat, "active")
    n_debris = int(round(debris_share * n))
    if n_debris > len(debris) or n - n_debris > len(active):
        raise ValueError(f"n = {n} needs {n_debris} {debris_group} objects (of {len(debris)}) and "
                         f"{n - n_debris} active (of {len(active)})")
    d = debris.iloc[np.sort(rng.choice(len(debris), n_debris, replace=False))]
    a = active.iloc[np.sort(rng.choice(len(active), n - n_debris, replace=False))]
    objects = pd.concat([a, d], ignore_index=True)
    unknown = d["norad"].to_numpy(np.int64)[rng.random(len(d)) < unknown_share]
    return objects, np.sort(unknown)


def make_radar(cfg) -> GroundRadar:
    """The radar of the config's ``radar`` block: ENU returns with isotropic σ (``sigma_km``; the default), or
    with ``measurement: rae_rate`` the documented radar's (ρ, az, el, ρ̇) with ``sigma_range_km``,
    ``sigma_angle_deg`` (azimuth and elevation) and ``sigma_range_rate_km_s`` (defaults 0.03 km, 0.05°, 0.01 km/s:
    :mod:`hypotrack.scenarios.catalogue.radar_model` cites them); optional SNR detection (:mod:`.physics`)."""
    r = cfg["radar"]
    site = GroundSite(r["lat_deg"], r["lon_deg"], r["alt_km"], "radar site")
    fov = RadarFieldOfView(r["az_center_deg"], r["az_width_deg"], r["el_min_deg"], r["el_max_deg"],
                           r["r_min_km"], r["r_max_km"])
    kind = r.get("measurement", "enu")
    if kind == "rae_rate":
        ang = float(r.get("sigma_angle_deg", 0.05))
        return GroundRadar(site, fov, revisit_s=r["revisit_s"], p_D=r["p_D"], clutter_rate=r["clutter_rate"],
                           measurement="rae_rate", sigma_range_km=float(r.get("sigma_range_km", 0.03)), sigma_az_deg=ang,
                           sigma_el_deg=ang, sigma_range_rate_km_s=float(r.get("sigma_range_rate_km_s", 0.01)),
                           range_rate_span_km_s=float(r.get("range_rate_span_km_s", 8.0)), snr=radar_snr(r))
    if kind != "enu":
        raise ValueError(f"radar.measurement must be 'enu' or 'rae_rate', got {kind!r}")
    return GroundRadar(site, fov, revisit_s=r["revisit_s"], p_D=r["p_D"], clutter_rate=r["clutter_rate"],
                       measurement="enu", sigma_enu_km=r["sigma_km"], snr=radar_snr(r))


def tracker_sensor(radar: GroundRadar):
    """The trackers' sensor of ``radar``: the ENU stand-in's TEME positions (:class:`TrackerSensor`, linear ``H``)
    or, for the documented radar (``measurement="rae_rate"``), :class:`RadarTrackerSensor` — the trackers then work
    in the sensor frame (its noise is Gaussian with a constant covariance there; a Cartesian conversion would need a
    covariance per return and could not carry the range-rate linearly)."""
    return RadarTrackerSensor(radar) if radar.measurement == "rae_rate" else TrackerSensor(radar)


#: The trackers' motion models (``trackers.motion``).
MOTIONS = {"two_body": TwoBodyOrbit3D, "j2": J2Orbit3D}


def make_motion(cfg):
    """The trackers' EKF motion model: ``model.motion`` (two-body, or two-body + J2) with white
    acceleration noise of intensity ``model.process_noise_q``."""
    m = cfg["model"]
    if m["motion"] not in MOTIONS:
        raise ValueError(f"model.motion must be one of {tuple(MOTIONS)}, got {m['motion']!r}")
    return MOTIONS[m["motion"]](q=m["process_noise_q"])


def evaluated_on(cfg, seed: int) -> tuple[int, float]:
    """``(seed, start offset s)`` of the evaluated run — another seed and time window than the ones the model was
    tuned on: ``tuning.evaluated_on`` of the section (its ``seed`` and ``start_offset_s``), else the pipeline's
    ``seed`` from the catalogue's epoch."""
    ev = (cfg.get("tuning") or {}).get("evaluated_on") or {}
    return int(ev.get("seed", seed)), float(ev.get("start_offset_s", 0.0))


def check_tuning(cfg) -> None:
    """The evaluated run must differ from the one the parameters were tuned on, in seed and in time window."""
    t = cfg.get("tuning")
    if not t:
        return
    a, b = t.get("tuned_on") or {}, t.get("evaluated_on") or {}
    if a.get("seed") == b.get("seed"):
        raise ValueError(f"ssa_catalogue.tuning.evaluated_on.seed must differ from tuned_on.seed, both {a.get('seed')!r}")
    if float(a.get("start_offset_s", 0.0)) == float(b.get("start_offset_s", 0.0)):
        raise ValueError("ssa_catalogue.tuning.evaluated_on.start_offset_s must differ from tuned_on.start_offset_s "
                         f"(another time window), both {a.get('start_offset_s', 0.0)!r}")


def build_scenario(cfg, n: int, seed: int):
    """Objects, unknown NORAD numbers and the simulated :class:`CatalogueScenario` for size ``n``; scan 0 at the
    catalogue's epoch plus the evaluated run's start offset (:func:`evaluated_on`; the seed is the caller's)."""
    ss = np.random.SeedSequence([int(seed), int(n)])
    pop_seed, sim_seed, init_seed = (int(s.generate_state(1)[0]) for s in ss.spawn(3))
    objects, unknown = select_population(n, cfg["debris_group"], cfg["debris_share"], cfg["unknown_share"], pop_seed)
    offset = evaluated_on(cfg, seed)[1]
    start = reference_epoch(objects) + pd.Timedelta(seconds=offset) if offset else None
    sc = simulate_catalogue(objects, make_radar(cfg), n_scans=cfg["n_scans"], seed=sim_seed, start=start,
                            sizes=object_sizes(cfg, objects))
    return objects, unknown, sc, init_seed


def initial_tracks(sc, unknown, cfg, init_seed, at: float = 0.0):
    """Known objects: SGP4 state at scan 0 (or ``at`` seconds from it) plus a seeded error, with its covariance."""
    X, valid = sc.states(np.array([float(at)]))
    X, valid = X[:, 0], valid[:, 0]
    norad = sc.catalogue["norad"].to_numpy(np.int64)
    known = valid & ~np.isin(norad, unknown)
    s = np.r_[np.full(3, cfg["init_position_std_km"]), np.full(3, cfg["init_velocity_std_km_s"])]
    err = np.random.default_rng(init_seed).standard_normal((int(known.sum()), 6)) * s
    P = np.broadcast_to(np.diag(s**2), (int(known.sum()), 6, 6)).copy()
    return X[known] + err, P, norad[known]


#: The births of ``model.birth``: one-point (position at the return, velocity ``N(0, birth_velocity_std²)``; with the
#: documented radar, across the line of sight, the range-rate measured along it) or the admissible region's mixture.
BIRTHS = ("one_point", "admissible")


def make_problem(cfg, tsensor, motion, means, covs, labels) -> TrackingProblem:
    """The catalogue as a :class:`~hypotrack.registry.TrackingProblem`: the known objects at scan 0, the radar
    (TEME returns, or the documented radar's in the sensor frame: :func:`tracker_sensor`), the EKF, the revisit
    interval, and births from the returns (``model`` block): adaptive birth terms (δ-GLMB, R-FISST), Reid's births
    seeded at the returns (HOMHT) and GNN/JPDA's ``β_NT``, all from ``homht_births_per_scan`` and the birth
    spreads; a miss counts in view only. ``model.birth: admissible`` (documented radar only) makes each adaptive
    birth the admissible-region mixture of its return (``model.admissible_blocks`` blocks per axis, default 3),
    its components terms of existence ``r_birth × weight``, HOMHT's seeded births one option per component
    (:mod:`hypotrack.hypotheses.seeded`) and GNN/JPDA's initiation one tentative track per component
    (:class:`~hypotrack.trackers.MOfNInitiator`), all from :class:`SeededAdmissibleBirth`; the optional death model and plausibility test of
    :mod:`.physics` (``unconfirmed_decay``, ``plausibility``). ``model.fov_edge: {margin_deg, margin_km}`` gives the
    sensor the soft-edged detection (:mod:`hypotrack.scenarios.catalogue.fov_edge`; absent: ``p_D`` decided at
    each track's mean), which only the factored filters read (GNN/JPDA gate every track whatever the view)."""
    m = cfg["model"]
    birth = m.get("birth", "one_point")
    if birth not in BIRTHS:
        raise ValueError(f"model.birth must be one of {BIRTHS}, got {birth!r}")
    radar = isinstance(tsensor, RadarTrackerSensor)
    if birth == "admissible" and not radar:
        raise ValueError("model.birth: admissible needs the documented radar (radar.measurement: rae_rate): the "
                         "admissible region is of a (range, azimuth, elevation, range-rate) return")
    mixture = AdmissibleRegionBirth(tsensor, n_blocks=int(m.get("admissible_blocks", 3))) if birth == "admissible" else None
    adaptive = AdaptiveBirth(position_std=m["birth_position_std_km"], velocity_std=m["birth_velocity_std_km_s"],
                             r_birth=m["r_birth"], gate_probability=m["gate_probability"], mixture=mixture)
    seeded = (SeededAdmissibleBirth(mixture) if mixture is not None else
              RadarOnePointBirth(tsensor.measurement, m["birth_velocity_std_km_s"], m["birth_position_std_km"]) if radar
              else OnePointBirth(m["birth_velocity_std_km_s"], m["birth_position_std_km"]))
    births = MeasurementBirths(adaptive, r_birth=m["r_birth"],
                               seeded_intensity=m["homht_births_per_scan"] / tsensor.clutter.region.area,
                               seeded_density=seeded, survival=model_survival(m))
    fov = tsensor.detection  # the true field of view: the problem's (scorecard, GNN/JPDA's miss rule)
    edge = m.get("fov_edge")
    if edge is not None:  # the factored filters' p_D: the edge integrated over each track (fov_edge.py)
        if not radar:
            raise ValueError("model.fov_edge needs the documented radar (radar.measurement: rae_rate)")
        attach_soft_edge(tsensor, edge["margin_deg"], edge["margin_km"])
    return TrackingProblem(motion, tsensor, means, covs, labels, time=0.0, dt=cfg["radar"]["revisit_s"],
                           births=births, in_view=lambda x: fov.in_view(x[:, :3]), validity=model_validity(m))


def tracker_spec(cfg, name: str, **factored) -> TrackerSpec:
    """The specification of tracker ``name`` (``ssa_catalogue.trackers``), with ``factored`` options overridden."""
    trackers = cfg["trackers"]
    if name not in trackers:
        raise ValueError(f"tracker must be one of {tuple(trackers)} (ssa_catalogue.trackers), got {name!r}")
    own = dict(trackers[name])
    if factored:
        if own.get("factored") is None:
            raise ValueError(f"tracker {name!r} is not factored (ssa_catalogue.trackers.{name}.factored)")
        own["factored"] = {**own["factored"], **factored}
    return TrackerSpec.from_config(own, f"ssa_catalogue.trackers.{name}")


def make_tracker(name: str, cfg, problem: TrackingProblem, seed: int, **factored):
    """Tracker ``name`` of the config on the problem (:func:`hypotrack.registry.build`)."""
    return build(tracker_spec(cfg, name, **factored), problem, seed=seed)


def _estimates(tracker, in_view):
    """(labels, TEME positions) of the tracker's estimates inside the field of view (the factored
    trackers' MAP means: their lazy lane's covariances are not predicted to the scan; GNN/JPDA's means
    alone, so that a lazy one does not predict its deferred tracks)."""
    e = tracker.estimates(covariances=False) if isinstance(tracker, SingleHypothesisTracker) else tracker.estimates()
    if len(e) == 0:
        return np.zeros(0, np.int64), np.zeros((0, 3))
    inv = in_view(e.x)
    return np.asarray(e.labels)[inv], e.x[inv, :3]


def _assign(truth_X, est_X, c):
    """Optimal assignment truth → estimate with distances below ``c``: (truth rows, est rows)."""
    if len(truth_X) == 0 or len(est_X) == 0:
        return np.zeros(0, int), np.zeros(0, int)
    D = np.linalg.norm(truth_X[:, None] - est_X[None], axis=-1)
    r, k = linear_sum_assignment(np.minimum(D, c))
    ok = D[r, k] < c
    return r[ok], k[ok]


def run_tracker(name: str, cfg, n: int, seed: int, *, memory: bool = False, scenario=None):
    """One tracker over the scans of population size ``n``.

    Returns ``(per_scan DataFrame, assignment DataFrame, info dict)``: per scan the CPU seconds of
    the tracker's step, returns, objects in view, estimates in view, GOSPA (with its missed/false
    parts) and OSPA, groups and the largest group (factored trackers); per (scan, true object in
    view) the label of the estimate assigned to it (−1: none). ``memory=True`` traces the peak
    memory of the run (tracemalloc; slower, for a separate pass) into ``info["peak_bytes"]``.
    """
    objects, unknown, sc, init_seed = scenario if scenario is not None else build_scenario(cfg, n, seed)
    radar = sc.sensors[0]
    tsensor = attach_tracker_snr(cfg, tracker_sensor(radar))
    motion = make_motion(cfg)
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    scans = sc.scan_list(0)
    truth = sc.truth[sc.truth["in_view"]]
    by_scan = {k: g for k, g in truth.groupby("scan")}
    c, p = cfg["metrics"]["cutoff_km"], cfg["metrics"]["order"]
    n_scans = cfg["memory_scans"] if memory else len(scans)
    if memory:
        tracemalloc.start()
    problem = make_problem(cfg, tsensor, motion, means, covs, labels)
    tracker = make_tracker(name, cfg, problem, int(seed))
    factored = isinstance(tracker, FactoredFilter)
    warm_samplers()  # the samplers' kernels loaded untimed: a first MCMC step would compile or load them in its scan
    warm_engine()  # the factored engine's kernels likewise: scan 0 (timed here) would load them all
    rows, assign = [], []
    for k in range(n_scans):
        t_k, Z = scans[k]
        tsensor.at(sc.theta[k])
        t0 = time.process_time()
        tracker.step(tsensor.returns(Z), float(t_k))  # scan 0 is at the tracks' epoch: an update without prediction
        cpu = time.process_time() - t0
        lab, EX = _estimates(tracker, problem.in_view)
        g = by_scan.get(k)
        TX = g[["state_0", "state_1", "state_2"]].to_numpy() if g is not None else np.zeros((0, 3))
        tid = g["target"].to_numpy(np.int64) if g is not None else np.zeros(0, np.int64)
        gr = gospa(EX, TX, c=c, p=p)
        st = tracker.last_stats if factored else {}
        rows.append(dict(tracker=name, n_objects=n, scan=k, cpu_s=cpu, n_returns=len(Z), n_in_view=len(TX),
                         n_estimates=len(EX), gospa_km=gr.value, gospa_missed=gr.missed, gospa_false=gr.false,
                         ospa_km=ospa(EX, TX, c=c, p=p), n_groups=st.get("n_groups", np.nan),
                         largest_group=st.get("largest_group", np.nan), n_tracks=_n_tracks(tracker)))
        r, q = _assign(TX, EX, c)
        lab_of = np.full(len(TX), -1, np.int64)
        lab_of[r] = lab[q]
        assign.extend(dict(tracker=name, n_objects=n, scan=k, target=int(t), label=int(x),
                           unknown=bool(t in set(unknown.tolist()))) for t, x in zip(tid, lab_of))
    info = {}
    if memory:
        info["peak_bytes"] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return pd.DataFrame(rows), pd.DataFrame(assign), info


def _n_tracks(tracker):
    if isinstance(tracker, FactoredFilter):
        return tracker.n_objects_held
    return len(tracker.ids)


#: Scans out of view after which an object's next scan in view is a *re-entry* (a new pass): 30 scans of
#: the default radar are 5 minutes, far longer than a pass's flicker at the edge of the field of view.
REENTRY_GAP_SCANS = 30


def continuity(assign: pd.DataFrame, reentry_gap: int = REENTRY_GAP_SCANS) -> dict:
    """Continuity and birth measures of one (tracker, size) from its assignment table.

    Per true object, in scan order over the scans it is in view: a **label switch** is an
    assigned label different from the last assigned label; a **fragmentation** is a return to
    assigned after one or more unassigned scans that followed an assigned one. An **unknown**
    object is *born from the data* when it is ever assigned an estimate; its **latency** is the
    number of scans from its first scan in view to its first assignment. A **re-entry** is a scan
    in view more than ``reentry_gap`` scans after the object's previous one (a new pass, after
    which its track was only predicted), counted when the object had a track before; it is
    **re-acquired** when the first label assigned in the new pass is the last one of the
    previous passes (the track kept custody through the gap).

    Returns a dict: ``objects_in_view`` (distinct objects ever in view), ``label_switches``,
    ``fragmentations``, ``unknown_in_view``, ``born``, ``latency_mean`` (scans; NaN when none
    born), ``reentries``, ``reacquired``.
    """
    switches = frags = 0
    born, lat = 0, []
    n_unknown = n_objects = reentries = reacquired = 0
    for (_, unk), g in assign.sort_values("scan").groupby(["target", "unknown"]):
        n_objects += 1
        labels = g["label"].to_numpy()
        scans = g["scan"].to_numpy()
        new_pass = np.r_[False, np.diff(scans) > reentry_gap]
        last, gap, was, pending = None, False, False, False
        for x, fresh in zip(labels, new_pass):
            if fresh and last is not None:
                reentries += 1
                pending = True
            if x < 0:
                gap = was
                continue
            if pending:
                reacquired += int(x == last)
                pending = False
            if last is not None and x != last:
                switches += 1
            if gap:
                frags += 1
            last, gap, was = x, False, True
        if unk:
            n_unknown += 1
            hit = np.flatnonzero(labels >= 0)
            if len(hit):
                born += 1
                lat.append(int(scans[hit[0]] - scans[0]))
    return dict(objects_in_view=n_objects, label_switches=switches, fragmentations=frags, unknown_in_view=n_unknown,
                born=born, latency_mean=float(np.mean(lat)) if lat else float("nan"), reentries=reentries,
                reacquired=reacquired)


def scan_rows(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Per (tracker, size): CPU per scan (mean), per object in view, mean GOSPA/OSPA, groups."""
    out = []
    for (name, n), g in per_scan.groupby(["tracker", "n_objects"], sort=False):
        view = g["n_in_view"].to_numpy(float)
        out.append(dict(tracker=name, n_objects=int(n), n_scans=len(g), cpu_s_per_scan=g["cpu_s"].mean(),
                        cpu_ms_per_object_in_view=1e3 * g["cpu_s"].sum() / max(view.sum(), 1.0),
                        mean_in_view=view.mean(), gospa_km=g["gospa_km"].mean(), ospa_km=g["ospa_km"].mean(),
                        groups_mean=g["n_groups"].mean(), largest_group_max=g["largest_group"].max()))
    return pd.DataFrame(out)


_WARM_SCANS = 2  # untimed scans of parallel_timing (pool start-up, first compiled calls)


def same_posterior(a: FactoredFilter, b: FactoredFilter) -> bool:
    """Whether two factored filters hold bit-for-bit the same posterior (groups, weights, labels,
    track moments, hypotheses, next label): their stored state — the multi-hypothesis groups and the
    lane of singletons as kept (means, covariances, labels, the times they were predicted to, the
    means at the scan) — so the lazy lane and lazy groups are compared without predicting them to the
    scan (:meth:`FactoredFilter.same_posterior`)."""
    return a.same_posterior(b)


def parallel_timing(name: str, cfg, n: int, seed: int, workers: int, pools, *, scenario=None) -> pd.DataFrame:
    """The same scans through one factored tracker with ``workers = 1`` and with ``workers`` in each
    pool kind of ``pools`` ("process", "thread"), stepped in lockstep (scan k of every filter in
    turn, the order rotated each scan, so a change of the machine's load hits all alike). The
    first two scans are stepped untimed with the pools started, so that neither the pools'
    start-up nor the first steps in a fresh process (kernel compilation) are timed.

    A further untimed ``workers = 1`` filter records the pickled bytes of every engine step's
    input (the group's hypotheses and track moments, the returns of its gate and their scores)
    and result: the state a distributed scheduler would move per scan.

    Returns one row per configuration: ``pool`` ("serial" for ``workers = 1``), ``workers``,
    scans, per scan the main process's CPU seconds, the pool processes' CPU seconds, wall seconds,
    wall seconds in the engine steps and the engine steps; the wall speed-up over serial;
    ``identical`` (same posterior as serial at every scan); the serial share of wall time in the
    engine steps and the Amdahl ceiling ``1 / (1 − s + s / workers)`` of the speed-up; and, on
    the serial row, bytes in and out per scan and per step.
    """
    pools = list(pools)
    if any(p not in ("process", "thread") for p in pools):
        raise ValueError(f"pools must hold 'process' and/or 'thread', got {pools!r}")
    objects, unknown, sc, init_seed = scenario if scenario is not None else build_scenario(cfg, n, seed)
    tsensor = tracker_sensor(sc.sensors[0])
    motion = make_motion(cfg)
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    problem = make_problem(cfg, tsensor, motion, means, covs, labels)
    confs = [("serial", 1)] + [(p, int(workers)) for p in pools]
    filters = [make_tracker(name, cfg, problem, int(seed), workers=w, measure_transfer=pool == "bytes",
                            parallel="process" if pool in ("serial", "bytes") else pool)
               for pool, w in confs + [("bytes", 1)]]
    acc = [dict(cpu=0.0, wcpu=0.0, wall=0.0, steps=0.0, jobs=0, identical=True) for _ in confs]
    b_in = b_out = 0
    scans = sc.scan_list(0)
    try:
        for k, (t_k, Z) in enumerate(scans):
            tsensor.at(sc.theta[k])
            Zt, t_k = tsensor.returns(Z), float(t_k)  # scan 0 is at the tracks' epoch (as run_tracker)
            if k < _WARM_SCANS:  # untimed: the pools start and every process runs (and compiles) its first steps
                for i in range(len(confs)):
                    if k == 0:
                        filters[i].warm_up()
                    filters[i].step(Zt, t_k)
            order = np.roll(np.arange(len(confs)), -k) if k >= _WARM_SCANS else []
            for i in order:
                c0, w0 = time.process_time(), time.perf_counter()
                filters[i].step(Zt, t_k)
                a = acc[i]
                a["cpu"] += time.process_time() - c0
                a["wall"] += time.perf_counter() - w0
                st = filters[i].last_stats
                a["wcpu"] += st.get("worker_cpu_s", 0.0)
                a["steps"] += st["time_steps"]
                a["jobs"] += st["n_jobs"]
            filters[-1].step(Zt, t_k)
            if k >= _WARM_SCANS:
                b_in += filters[-1].last_stats["bytes_to_workers"]
                b_out += filters[-1].last_stats["bytes_from_workers"]
            for i in range(1, len(confs)):
                acc[i]["identical"] &= same_posterior(filters[0], filters[i])
    finally:
        for f in filters:
            f.close()
    K = len(scans) - _WARM_SCANS
    rows = []
    for (pool, w), a in zip(confs, acc):
        rows.append(dict(tracker=name, n_objects=int(n), pool=pool, workers=w, n_scans=K, cpu_s_per_scan=a["cpu"] / K,
                         worker_cpu_s_per_scan=a["wcpu"] / K, wall_s_per_scan=a["wall"] / K,
                         steps_wall_s_per_scan=a["steps"] / K, steps_per_scan=a["jobs"] / K,
                         speedup_wall=acc[0]["wall"] / a["wall"], identical=bool(a["identical"])))
    share = acc[0]["steps"] / acc[0]["wall"]
    for r in rows:  # Amdahl: only the engine steps run in parallel
        r["steps_share_serial"] = share
        r["speedup_ceiling"] = 1.0 / (1.0 - share + share / r["workers"])
    jobs = acc[0]["jobs"]
    rows[0].update(bytes_in_per_scan=b_in / K, bytes_out_per_scan=b_out / K,
                   bytes_in_per_step=b_in / max(jobs, 1), bytes_out_per_step=b_out / max(jobs, 1))
    return pd.DataFrame(rows)


@dataclass(frozen=True)
class PeerScenario:
    """The scans of one population size as a peer tracker needs them: the known objects' initial
    TEME states and covariance, scan times (s) and TEME returns, the scan model and the motion."""

    initial_states: np.ndarray
    initial_covs: np.ndarray
    times: np.ndarray
    returns: list
    model: ScanModel
    motion: TwoBodyOrbit3D  # or J2Orbit3D (make_motion)

    def scan_list(self):
        return list(zip(self.times, self.returns))


_RADAR_FRAME_KEYS = ("measurement", "sigma_range_km", "sigma_angle_deg", "sigma_range_rate_km_s", "snr")


def peer_config(cfg) -> dict:
    """The section with its radar as the ENU stand-in (isotropic ``sigma_km``, the constant ``p_D``): the peer
    comparison checks two implementations of GNN/JPDA on one linear problem, which Stone Soup's linear
    updater and hypotrack's share (the documented radar's sensor-frame EKF and SNR detection have no
    counterpart on the peer's side of that harness)."""
    return {**cfg, "radar": {k: v for k, v in cfg["radar"].items() if k not in _RADAR_FRAME_KEYS}}


def peer_scenario(cfg, n: int, seed: int, scenario=None) -> PeerScenario:
    """:class:`PeerScenario` of size ``n`` (known objects only; the radar's returns in TEME). Without a
    ``scenario``, built on :func:`peer_config`'s stand-in radar."""
    if scenario is None:
        cfg = peer_config(cfg)
    objects, unknown, sc, init_seed = scenario if scenario is not None else build_scenario(cfg, n, seed)
    tsensor = tracker_sensor(sc.sensors[0])
    if isinstance(tsensor, RadarTrackerSensor):
        raise ValueError("the peer trackers run on a linear measurement: radar.measurement must be 'enu' for peer_scenario")
    means, covs, _ = initial_tracks(sc, unknown, cfg, init_seed)
    times, returns = [], []
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        times.append(float(t_k))
        returns.append(tsensor.returns(Z))
    model = ScanModel(tsensor.measurement.H, tsensor.measurement.R, tsensor.detection.p_D, cfg["model"]["gate_probability"],
                      max(tsensor.clutter.intensity, 1e-300))
    return PeerScenario(means, covs, np.array(times), returns, model, make_motion(cfg))


class CatalogueSHTStepper(SHTStepper):
    """hypotrack's GNN or JPDA on the known objects of a :class:`PeerScenario`, for the side-by-side
    peer timing (:func:`hypotrack.experiments.stepping.run_side_by_side`).

    As the peer runs them (:class:`~hypotrack.experiments.stepping.SHTStepper`): no initiation, no
    deletion, GNN on Stone Soup's unsquared-Mahalanobis criterion (missed distance the square root
    of the gate), so both solve the same problem."""

    def __init__(self, scenario: PeerScenario, algorithm: str):
        super().__init__(scenario.motion, scenario.model, algorithm, scenario.initial_states, scenario.initial_covs,
                         scenario.times[0], scenario.scan_list())


#: Largest output/state difference from the peer counted as the same association (rounding only).
PEER_AGREEMENT = 1e-9


def peer_rows(runs: dict, algorithm: str, n: int, n_tracks: int) -> pd.DataFrame:
    """Rows of the peer timing table from :func:`~hypotrack.experiments.stepping.run_side_by_side`
    runs (``"hypotrack"`` and each peer): median ms per scan, the peer's time over hypotrack's,
    the largest output (GNN: the track of each return; JPDA: the association probabilities) and
    state differences from hypotrack, the timed scans whose outputs agree within
    :data:`PEER_AGREEMENT`."""
    ref = runs["hypotrack"]
    rows = []
    for name, run in runs.items():
        d_out, d_state = max_abs_difference(ref, run) if name != "hypotrack" else (0.0, 0.0)
        k = min(len(ref.outputs), len(run.outputs))
        same = sum(np.asarray(a, float).shape == np.asarray(b, float).shape
                   and float(np.max(np.abs(np.asarray(a, float) - np.asarray(b, float)), initial=0.0)) <= PEER_AGREEMENT
                   for a, b in zip(ref.outputs[:k], run.outputs[:k]))
        rows.append(dict(algorithm=algorithm, implementation=name, n_objects=int(n), n_tracks=int(n_tracks),
                         scans_timed=len(run.times), median_ms=run.median_ms,
                         peer_over_hypotrack=run.median_ms / ref.median_ms, max_output_diff=d_out,
                         max_state_diff=d_state, scans_same_association=int(same), scans_compared=int(k)))
    return pd.DataFrame(rows)

"""A fresh breakup cloud tracked by the catalogue's five trackers, scored as an operator would.

Scenarios (config section ``ssa_breakup``)
------------------------------------------
* **breakup** — :func:`hypotrack.scenarios.catalogue.breakup.simulate_breakup`: a bundled parent orbit
  fragmented by the NASA standard breakup model (``event`` block), seen by a radar
  (``radar`` block: the catalogue experiment's radar model at another site) over ``window``;
* **catalogue** (the control) — the sparse catalogue of the ``ssa_catalogue`` experiment
  (:func:`hypotrack.experiments.ssa_catalogue.run.build_scenario`) at ``control.n_objects`` and
  ``control.n_scans``, where the trackers tie.

Every tracker is the ``ssa_catalogue`` experiment's (:func:`~hypotrack.experiments.ssa_catalogue.run.make_problem`,
:func:`~hypotrack.experiments.ssa_catalogue.run.make_tracker`, the ``model``/``trackers`` blocks of this
section) on the same scans. Known objects start at their true state at scan 0's epoch plus a seeded Gaussian
error with that covariance (``init_position_std_km``, ``init_velocity_std_km_s``: a cloud catalogued from
its first observations); a seeded ``unknown_share`` of them must be born from the data.

:func:`run_scored` steps one tracker and records, per scan, what the scorecard needs
(:mod:`.scorecard`): the returns with their origin and the track each correlates to, the assignment of
estimates to the truths in view, purity counts, GOSPA's parts, the CPU seconds of the step, the MAP tracks
that fail the plausibility test (:func:`hypotrack.models.plausibility.plausible_orbits`), and each object's
track (mean, covariance) at the end of each of its passes and at the last scan. For a factored filter it also
records, per scan, every MAP label's marginal probability (the total weight of the hypotheses holding the MAP's
association history for it, :func:`hypotrack.hypotheses.factored.marginals.map_label_marginals`) and whether its
track is in view: :meth:`ScoredRun.with_output` then reports the same run under the ambiguity output policy
(:mod:`.identities`: a label whose MAP track is ambiguous at a scan in view takes a fresh output identity instead of
being carried onto a neighbour), scored as tracker ``<name>_amb`` — no second tracker run.

Diagnosis of the cross-tags at the catalogue's process noise (q = 1e-9 km²/s³)
------------------------------------------------------------------------------
Seeds 2 and 3 of the default cloud, every label change (CLEAR-MOT switch) of the two multi-hypothesis trackers,
classified by the object's pass (0: acquisition, an hour after the catalogue; 1: re-acquisition after the
~95-min gap) and by the posterior of the object's group just after that scan: the probability of the
hypotheses that put the *old* label on the track nearest the object (the alternative the tracker did not pick)::

    label changes (2 seeds)                  HOMHT k-best        delta-GLMB (Murty)
                                             pass 0   pass 1     pass 0   pass 1
    near tie: alternative held, p >= 0.3       41       42         65       45
    alternative held, p < 0.3                   6       24          9       22
    alternative pruned, group at the cap (20)   3       17          3       24
    alternative never held, group below cap     7       15          4        6
    a lane singleton (one hypothesis)           9        4          8        3
    all                                        66      102         89      100

* The near ties (half of all changes) are two hypotheses that swap two neighbours' labels, at median
  probabilities 0.51 against 0.47, the MAP flipping between them scan after scan (most of them after the pass's
  first three scans). Every later scan fits either assignment as well (each hypothesis's tracks follow the
  objects), so neither more hypotheses nor another gate settles them: the prediction alone decides, and it
  barely did. The pruned alternatives (11-14 %), which a larger cap might have kept, are at re-acquisition.
  A newborn label goes onto the object in 6 of HOMHT's 168 changes and 6 of the delta-GLMB's 189 (birth and clutter
  settings matter little; GNN, by contrast, re-initiates: 122 of its 263 changes put a newborn label on the
  object).
* 93-97 % of the cross-tagged returns are pass-0 returns, right when made, charged after the label moved at
  re-acquisition and held the other object longer (the scorecard's ``own_label`` and ``carried_label``).
* Why the predictions barely decide: the covariance was three times too wide in sigma (mean d²/3 of the
  re-acquisition errors 0.09-0.12 against 1 for a realistic one; only 44-52 % re-acquired within 5 km) for a
  truth without process noise (two-body + J2, constants 59 m/h from the trackers'), so neighbours a median
  10 km apart sat well inside each other's gates with likelihood ratios near one. The process noise was the
  catalogue experiment's, untuned for the cloud; ``ssa_breakup.model`` in default.yaml gives the sweep on the
  tuning seed and the q chosen by covariance realism (not by the cross-tags). The defect the tuned q exposed
  (a diverged seeded birth stopping HOMHT's scan) is fixed in the factored planner (``scorable``).

With the tuned q (1e-12) every tracker's cross-tags fall by one to two orders of magnitude and the
multi-hypothesis trackers keep custody better (re-acquisitions that keep the label ~0.99 against GNN's ~0.96;
completeness ~0.98 against ~0.95; 0.55-0.6 of GNN's identity switches), yet their cross-tags exceed GNN's: what
remains is a few label swaps per run at acquisition or re-acquisition which the multi-hypothesis trackers then
keep to the end (cause ``carried_label``), while GNN mostly drops a confused track and starts a new one, and a
newborn label owned by its own object is no cross-tag. The operator's cross-tag charges a kept swap and not a
lost track; the identity switches charge both. On the tuning seed: 43 of GNN's 49 label changes put a newborn
label on the object and 1 another object's, against 8, 9 and 19 (back to its own) of HOMHT's 36.

Diagnosis of the remaining cross-tags (tuning seeds 1, 12 and 13 only)
-----------------------------------------------------------------------
Every cross-tag of the three tuning seeds at the record's settings, the factored step instrumented stage by stage
(merge, engine step, split, pruning), each charged to the event that put the label's returns under another owner
(its arrival on the object, or its move off its own). Returns over the three seeds; the δ-GLMB (Murty) and HOMHT
k-best gave the same counts (HOMHT's group was at the cap of 20 where the δ-GLMB's was not, with the same outcome)::

    cause                                                              ambiguity output  MAP output   GNN
    scorer: gone with the one-to-one correlation (below)                      5               9          7
    scorer: a neighbour's estimate nearer under the radar noise alone         2              10         15
    near tie at the event (marginal < p_min: the output withholds it)         0             113         --
    swap: the object's own return outside its track's 99.9 % gate            4 (1 event)     4         --
    swap, marginal >= 0.87 with the alternative held                          1              17         --
    label swap after acquisition (GNN, no marginals)                          --              --        35
    acquired on the wrong object (its own track off it, or not yet in view)   3 (3 events)   46         78
    a newborn label, or an untracked object's return                          0               0          4
    all, before the fix (per 1e4 returns, mean over the seeds)               15 (1.38)     199 (18.2)  139 (12.7)

* Every cross-tag of the ambiguity output was tagged with the label's marginal at or above p_min (0.82-1.0): all are
  confident. None comes from the output policy's bookkeeping, a birth, the split, a merge or pruning: over every
  (scan, label, object) the split changes no label's weight on an object (largest change 3e-16: the marginal
  product keeps each label's marginals, only the joint is lost), a capped merge at most 0.048 and min_weight
  pruning at most 0.0022 — none moved a label.
* The scorer credited each return to its nearest estimate on its own, so a neighbour's return went to an estimate
  that its own object's return went to as well (one estimate, two returns of a scan) and was charged as a
  cross-tag, though no tracker gives a track two returns of a scan: a defect, fixed (:func:`correlate_in_sensor_frame` is one-to-one). After it the ambiguity output's tuning-seed cross-tags
  are 8, 1 and 1 (0.92 per 1e4; GNN 52, 35, 45, 12.1; the MAP outputs 52, 49, 89, 17.3): ratio to GNN's 0.068
  (was 0.095). The two left to the scorer are two objects a few km apart whose returns the radar noise alone
  cannot tell apart.
* The confident swap (seed 1, scan 412): labels held 0.98 against 0.02 on two fragments 16.6 km apart, then one
  object's return fell outside its own track's gate (d^2 = 19.1 > chi2_4(0.999) = 18.47, a 3.8-sigma elevation
  draw) and inside the swapped hypothesis's: the right hypothesis paid a miss and a clutter return (~25 nats) and
  its children fell to 1.5e-9 at the engine step; the marginal of the swap read 1 from there on. A hard gate's
  cost, a modelling choice (the gate probability; measured below).
* Acquisitions: a label's first return was its neighbour's while the neighbour's own track was not a candidate
  (its predicted mean outside the field of view — seed 12: elevation 9.993 deg against the object's 10.016, the
  limit 10 — and a track is detectable only where its mean is in view) or lay
  several km off among closer neighbours (seed 13: eleven labels and nine returns at one scan, the group at the
  cap, the hypothesis with both labels on their own objects held at 0.018). The one confident swap with the alternative held (seed 1, scan
  988, one scan): an object first seen on its second pass, its track's sigma 24 km, lost its first return to a
  neighbour's alternative history of sigma 1 km (likelihood e^11.7 against e^5.6) — the model's answer, corrected a scan
  later.
* GNN's are acquisitions on the wrong object (78) and label swaps it kept (35), and the scorer's (22, 15 after the
  fix).
* The gate, measured on the same seeds (one-to-one scorer, the scorer's own gate unchanged): the two factored
  trackers' gate at 0.99999 instead of 0.999 (``trackers.<name>.gate_probability``) — ambiguity output 6, 1, 1
  cross-tags (0.73 per 1e4, was 0.92; the seed-1 pair now swaps for one scan instead of for good), 80 withheld
  returns per 1e4 (was 94) and fewer identity switches; MAP outputs 12.4 (δ-GLMB) and 11.8 (HOMHT) per 1e4, was
  17.3 (most of it one event on seed 13); 15-20 % more CPU. GNN at the same gate: 14.1 per 1e4, was 12.1. Not the
  default: a modelling choice, measured on three seeds.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from ...hypotheses.factored import FactoredFilter
from ...hypotheses.factored.marginals import map_label_marginals
from ...metrics import gospa
from ...metrics_scorecard import correlate_returns, purity_counts
from ...models.plausibility import plausible_orbits
from ...scenarios.catalogue.breakup import BreakupEvent, simulate_breakup
from ...association import gate_threshold
from ...scenarios.catalogue.radar_model import RadarTrackerSensor
from ..ssa_catalogue.physics import attach_tracker_snr
from .identities import output_identities, relabel
from ..ssa_catalogue.run import (build_scenario, initial_tracks, make_motion, make_problem, make_radar, make_tracker,
                                 tracker_sensor)

__all__ = ["SCENARIOS", "MEASUREMENT_KEYS", "control_radar", "build_breakup", "build_control", "build", "pass_ends", "ScoredRun", "run_scored", "correlate_in_sensor_frame",
           "PASS_GAP_S", "AMBIGUITY_SUFFIX"]

SCENARIOS = ("breakup", "catalogue")
#: An object's scans in view more than this apart (s) belong to different passes (5 min: longer than any flicker
#: at the edge of the field of view, shorter than the gap between two passes of a LEO object).
PASS_GAP_S = 300.0
#: The tracker name of a run's ambiguity output (:meth:`ScoredRun.with_output`): ``glmb_murty`` → ``glmb_murty_amb``.
AMBIGUITY_SUFFIX = "_amb"


def build_breakup(cfg, seed: int):
    """``(objects, unknown ids, BreakupScenario, init seed)`` of the ``ssa_breakup`` section ``cfg``."""
    sim_seed, pop_seed, init_seed = (int(s.generate_state(1)[0]) for s in np.random.SeedSequence(int(seed)).spawn(3))
    ev = cfg["event"]
    event = BreakupEvent(parent_norad=int(ev["parent_norad"]), kind=ev["kind"], parent_kind=ev["parent_kind"],
                         lc_min_m=float(ev["lc_min_m"]), scaling=float(ev.get("scaling", 1.0)),
                         mass_kg=ev.get("mass_kg"), event_offset_s=float(ev.get("event_offset_s", 0.0)))
    w = cfg["window"]
    sc = simulate_breakup(event, make_radar(cfg), obs_start_s=w["obs_start_s"], obs_end_s=w["obs_end_s"], seed=sim_seed)
    ids = sc.catalogue["norad"].to_numpy(np.int64)
    unknown = np.sort(ids[np.random.default_rng(pop_seed).random(len(ids)) < cfg["unknown_share"]])
    return sc.catalogue, unknown, sc, init_seed


def build_control(cfg_catalogue, control, seed: int, unknown_share: float = 0.0):
    """The sparse-catalogue control: ``ssa_catalogue``'s scenario at ``control.n_objects``, ``control.n_scans``, with
    ``unknown_share`` of its debris unknown (the breakup's share, so that both scenarios ask the same)."""
    c = {**cfg_catalogue, "n_scans": int(control["n_scans"]), "unknown_share": float(unknown_share)}
    return build_scenario(c, int(control["n_objects"]), int(seed))


#: The radar keys of the measurement model (not of the site, field of view or clutter).
MEASUREMENT_KEYS = ("measurement", "sigma_range_km", "sigma_angle_deg", "sigma_range_rate_km_s", "range_rate_span_km_s")


def control_radar(cfg, cfg_catalogue) -> dict:
    """The control's radar block: the catalogue experiment's site, field of view and clutter with this section's
    measurement model (:data:`MEASUREMENT_KEYS`), so that both scenarios are measured alike — by the ENU stand-in,
    or by the documented radar whose returns the trackers use in the sensor frame."""
    own = {k: cfg["radar"][k] for k in MEASUREMENT_KEYS if k in cfg["radar"]}
    return {**cfg_catalogue["radar"], **own}


def build(scenario: str, cfg, cfg_catalogue, seed: int):
    """The scenario tuple of ``scenario`` (one of :data:`SCENARIOS`)."""
    if scenario not in SCENARIOS:
        raise ValueError(f"scenario must be one of {SCENARIOS}, got {scenario!r}")
    if scenario == "breakup":
        return build_breakup(cfg, seed)
    return build_control({**cfg_catalogue, "radar": control_radar(cfg, cfg_catalogue)}, cfg["control"], seed,
                         cfg["unknown_share"])


def pass_ends(truth: pd.DataFrame, gap_s: float = PASS_GAP_S) -> pd.DataFrame:
    """One row per (object, pass) from a truth table's in-view rows: ``target``, ``pass_no``, ``first_scan``,
    ``last_scan``, ``t_first``, ``t_last`` (a new pass starts after more than ``gap_s`` out of view)."""
    tv = truth[truth["in_view"]].sort_values(["target", "scan"])
    rows = []
    for tid, g in tv.groupby("target", sort=True):
        s, t = g["scan"].to_numpy(), g["time"].to_numpy(float)
        cut = np.flatnonzero(np.diff(t) > gap_s)
        starts, ends = np.r_[0, cut + 1], np.r_[cut, len(t) - 1]
        rows.extend(dict(target=int(tid), pass_no=p, first_scan=int(s[a]), last_scan=int(s[b]),
                         t_first=float(t[a]), t_last=float(t[b])) for p, (a, b) in enumerate(zip(starts, ends)))
    return pd.DataFrame(rows, columns=["target", "pass_no", "first_scan", "last_scan", "t_first", "t_last"])


def correlate_in_sensor_frame(measurement, Z, labels, X, gate_probability: float) -> np.ndarray:
    """The sensor-frame counterpart of :func:`hypotrack.metrics_scorecard.correlate_returns` (the documented radar):
    the scan's returns correlated one-to-one with the estimates (means ``X``) by ``d² = νᵀ R⁻¹ ν`` — ``ν`` the
    return's (azimuth-wrapped) residual from the estimate's predicted return ``h(x̂)``, ``R`` the radar's noise —
    within the ``χ²₄(gate_probability)`` gate ``γ``; −1 for a return correlated with none. As the stand-in's
    Euclidean gate (``√χ²₃(0.999) σ``), the 99.9 % gate of the measurement noise alone (the estimates' own errors
    are smaller); a Euclidean km gate on the radar's returns would drop half of them (their cross-beam error is
    1.2–2.6 km at 1,400–3,000 km).

    One-to-one, because an object makes at most one return a scan and every tracker scored updates a track with at
    most one return a scan: the assignment of least ``Σ (d² − γ)`` over the gated pairs (a return left
    uncorrelated costs the gate: :mod:`hypotrack.trackers.gnn`'s assignment, lecture 004, with the radar noise alone), so a
    neighbour's return nearer the estimate than its own object's return is no longer charged to it as well.
    Correlating each return with its nearest estimate independently would give one estimate two returns of one
    scan, and charge a cross-tag for a return no tracker associated with that track. (The ENU stand-in's
    ``correlate_returns``, which no configured breakup radar uses, still takes each return's nearest estimate.)"""
    out = np.full(len(Z), -1, np.int64)
    if len(Z) == 0 or len(X) == 0:
        return out
    z_pred = measurement.h(np.asarray(X, dtype=float))
    S = np.broadcast_to(measurement.R, (len(z_pred), *measurement.R.shape))
    d2, _ = measurement.mahalanobis2(np.asarray(Z, dtype=float), z_pred, S)
    gamma = gate_threshold(gate_probability, measurement.dim)
    gated = d2 <= gamma
    # a pair outside the gate gains nothing over leaving both unassigned: the rectangular assignment's optimum is
    # the one with a dummy "uncorrelated" column of cost γ per return
    r, j = linear_sum_assignment(np.where(gated, d2 - gamma, 0.0))
    ok = gated[r, j]
    out[r[ok]] = np.asarray(labels, dtype=np.int64)[j[ok]]
    return out


def _held_moments(tracker, labels) -> dict:
    """``{label: (mean, covariance, time)}`` of the MAP tracks ``labels`` as the tracker holds them: GNN/JPDA at
    the scan; a factored filter's lane singletons and groups' MAP tracks at the time each was last predicted
    to (lazy ones are not predicted here: the scorecard predicts them with the same model)."""
    want = set(int(x) for x in labels)
    if not isinstance(tracker, FactoredFilter):
        e = tracker.estimates()
        return {int(a): (x.copy(), p.copy(), float(e.time)) for a, x, p in zip(e.labels, e.x, e.P) if int(a) in want}
    st = tracker.state()
    out = {}
    lane = st.lane
    for i, a in enumerate(lane.store.labels):
        if int(a) in want:
            out[int(a)] = (lane.store.means[i].copy(), lane.store.covs[i].copy(), float(lane.times[i]))
    for g, tg in zip(st.groups.states, st.groups.times):
        idx = g.tracks[int(np.argmax(g.log_w))]
        for i in idx:
            a = int(g.store.labels[i])
            if a in want:
                out[a] = (g.store.means[i].copy(), g.store.covs[i].copy(), float(tg))
    return out


@dataclass
class ScoredRun:
    """What one tracker run records (module docstring). Tables: ``per_scan``; ``returns`` (scan, origin,
    correlated label); ``assign`` (scan, target, label, −1 none); ``ends`` (target, pass_no, time, label, mean ``x``,
    covariance ``P`` and their time ``t_x`` of its track at the pass's last scan; ``pass_no = −1``: the last scan of the run, for every object with a
    track — its last assigned one, or a known object's own initial label if it was never assigned)."""

    tracker: str
    per_scan: pd.DataFrame
    returns: pd.DataFrame
    assign: pd.DataFrame
    ends: list = field(default_factory=list)
    #: a factored filter's MAP labels per scan with their marginals (scan, label, p, in_view), else None
    marginals: pd.DataFrame | None = None

    def with_output(self, p_min: float, mode: str = "fresh", suffix: str = AMBIGUITY_SUFFIX) -> "ScoredRun":
        """This run as the ambiguity output policy reports it (:mod:`.identities`): the returns' and assignments'
        labels replaced by their output identities at ``p_min`` in ``mode`` (withheld: −1, no label), tracker
        ``<name><suffix>``; the tracks' states (``ends``, ``per_scan``) are the same. Needs :attr:`marginals`."""
        if self.marginals is None:
            raise ValueError(f"run of {self.tracker!r} has no marginals (not a factored filter)")
        tab = output_identities(self.marginals, p_min, mode=mode)
        return ScoredRun(self.tracker + suffix, self.per_scan,
                         self.returns.assign(label=relabel(self.returns["scan"], self.returns["label"], tab)),
                         self.assign.assign(label=relabel(self.assign["scan"], self.assign["label"], tab)),
                         self.ends, self.marginals)


def _unphysical(tracker, X) -> tuple[int, float]:
    """MAP tracks failing the plausibility test (an orbit's energy and perigee do not change as it is predicted,
    so the test needs no prediction); hypotheses holding one — a factored filter's over its groups'
    hypotheses and lane singletons (one hypothesis each), a single-hypothesis tracker's 1 if any."""
    bad_map = int((~plausible_orbits(X)).sum()) if len(X) else 0
    if not isinstance(tracker, FactoredFilter):
        return bad_map, float(bad_map > 0)
    st = tracker.state()
    n = int((~plausible_orbits(st.lane.store.means)).sum()) if len(st.lane) else 0
    for g in st.groups.states:
        ok = plausible_orbits(g.store.means) if len(g.store.means) else np.ones(0, bool)
        n += sum(int(len(t) > 0 and not ok[t].all()) for t in g.tracks)
    return bad_map, float(n)


def run_scored(name: str, cfg, scenario, seed: int, *, count_hypotheses: bool = True, on_scan=None, tracker=None,
               step=None) -> ScoredRun:
    """Step tracker ``name`` over the scans of ``scenario`` (a :func:`build` tuple) and record the scorecard's
    inputs (module docstring). ``cfg``: the section holding ``model``, ``trackers``, ``metrics``, the initial
    errors and ``radar``. ``on_scan(k, tracker, est_pos, truth_pos)``, if given, returns further columns of scan
    ``k``'s ``per_scan`` row (the estimates and truths in view, TEME positions): an experiment that records more
    per scan does so in this one run. ``tracker`` and ``step(k, t_k, returns)``, if given, replace the tracker built
    here and its step with the scan's returns (several sensors fused: :mod:`hypotrack.experiments.ssa_catalogue.fused`);
    the scoring is of the scenario's radar (its returns, its view) either way."""
    objects, unknown, sc, init_seed = scenario
    tsensor = attach_tracker_snr(cfg, tracker_sensor(sc.sensors[0]))  # the scans' detection model, as run_tracker
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    problem = make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels)
    tracker = make_tracker(name, cfg, problem, int(seed)) if tracker is None else tracker
    c, gate = cfg["metrics"]["cutoff_km"], cfg["metrics"]["correlation_gate_km"]
    scans = sc.scan_list(0, with_origin=True)
    truth = sc.truth[sc.truth["in_view"]]
    by_scan = {k: g for k, g in truth.groupby("scan")}
    ends_at: dict = {}
    for r in pass_ends(sc.truth).itertuples(index=False):
        ends_at.setdefault(r.last_scan, []).append((r.target, r.pass_no))
    rows, ret_rows, assign, ends, marg = [], [], [], [], []
    last_label: dict = {}
    known = set(int(x) for x in labels)  # a known object's initial track carries its own id as label
    for k, scan in enumerate(scans):
        t_k, Z, origin = scan
        tsensor.at(sc.theta[k])
        Zt = tsensor.returns(Z)
        t0 = time.process_time()
        if step is None:
            tracker.step(Zt, float(t_k))
        else:
            step(k, float(t_k), Zt)
        cpu = time.process_time() - t0
        e = tracker.estimates()
        lab_all, X_all = np.asarray(e.labels, np.int64), np.asarray(e.x)
        inv = problem.in_view(X_all) if len(X_all) else np.zeros(0, bool)
        lab, EX = lab_all[inv], X_all[inv, :3]
        if isinstance(tracker, FactoredFilter):  # how sure the MAP is of each label's track (the ambiguity output)
            ml, mp = map_label_marginals(tracker.state())
            p_of = dict(zip(ml.tolist(), mp.tolist()))
            marg.append(pd.DataFrame(dict(scan=k, label=lab_all, p=[p_of[a] for a in lab_all.tolist()], in_view=inv)))
        g = by_scan.get(k)
        TX = g[["state_0", "state_1", "state_2"]].to_numpy() if g is not None else np.zeros((0, 3))
        tid = g["target"].to_numpy(np.int64) if g is not None else np.zeros(0, np.int64)
        if isinstance(tsensor, RadarTrackerSensor):
            cor = correlate_in_sensor_frame(tsensor.measurement, Zt, lab, X_all[inv], cfg["model"]["gate_probability"])
        else:
            cor = correlate_returns(Zt, lab, EX, gate)
        ret_rows.append(pd.DataFrame(dict(scan=k, origin=np.asarray(origin, np.int64), label=cor)))
        lab_of = np.full(len(TX), -1, np.int64)
        if len(TX) and len(EX):
            D = np.linalg.norm(TX[:, None] - EX[None], axis=-1)
            r, q = linear_sum_assignment(np.minimum(D, c))
            ok = D[r, q] < c
            lab_of[r[ok]] = lab[q[ok]]
        assign.append(pd.DataFrame(dict(scan=k, target=tid, label=lab_of)))
        for t, x in zip(tid, lab_of):
            if x >= 0:
                last_label[int(t)] = int(x)
        gr = gospa(EX, TX, c=c, p=1.0)
        pur = purity_counts(TX, EX, c)
        bad_map, bad_hyp = _unphysical(tracker, X_all) if count_hypotheses else (0, float("nan"))
        rows.append(dict(tracker=name, scan=k, time=float(t_k), cpu_s=cpu, n_returns=len(Z), n_in_view=len(TX),
                         n_estimates=len(EX), gospa_loc=gr.localisation, gospa_missed=gr.missed, gospa_false=gr.false,
                         false=pur["false"], duplicate=pur["duplicate"], unphysical_map=bad_map,
                         unphysical_hypotheses=bad_hyp, **(on_scan(k, tracker, EX, TX) if on_scan else {})))
        final = k == len(scans) - 1
        need = [(t, p, last_label[t]) for t, p in ends_at.get(k, []) if t in last_label]
        if final:  # every catalogued object: its last assigned track, else (a known object) its own label
            need += [(int(t), -1, last_label.get(int(t), int(t))) for t in objects["norad"]
                     if int(t) in last_label or int(t) in known]
        if need:
            held = _held_moments(tracker, [lb for _, _, lb in need])
            for t, p, lb in need:
                if lb in held:
                    x, P, t_x = held[lb]
                    ends.append(dict(target=int(t), pass_no=int(p), time=float(t_k), label=lb, x=x, P=P, t_x=t_x))
    return ScoredRun(name, pd.DataFrame(rows), pd.concat(ret_rows, ignore_index=True) if ret_rows else pd.DataFrame(),
                     pd.concat(assign, ignore_index=True) if assign else pd.DataFrame(), ends,
                     pd.concat(marg, ignore_index=True) if marg else None)

"""Radar and fence fused: the catalogue's trackers on two sensors, scored against the radar alone (config ``fusion``).

Scenario: the catalogue experiment's population and radar (:func:`.run.build_scenario`, the evaluated seed and window)
plus the fence (:func:`hypotrack.scenarios.catalogue.fence.space_fence`: Kwajalein, every azimuth at elevations 20°–23°,
S-band SNR detection; its measurement model — range, azimuth, elevation, range-rate and their σ — the radar's, its
``p_D`` and clutter rate from ``fusion.fence``). Both sensors scan every 10 s at the same instants. The radar's returns
are the same in both scenarios (one random stream per sensor, :func:`~hypotrack.scenarios.catalogue.simulate_catalogue`).

Two runs per tracker on the same seeds: **radar** (the radar's scans alone) and **radar + fence** (at each instant the
radar's scan, then the fence's at a zero interval: the sequential update of
:mod:`hypotrack.hypotheses.factored.multisensor`, which cites it). Both run through the multi-sensor trackers
(:class:`~hypotrack.hypotheses.factored.multisensor.MultiSensorFactored`,
:class:`~hypotrack.trackers.multisensor.MultiSensorSHT`) so that they differ in the fence's scans alone; each sensor has
its own tracking problem (:func:`.run.make_problem`: its sensor-frame model, SNR ``p_D``, clutter, field of view,
admissible-region births of its own returns), the sensors joined in one :class:`~hypotrack.registry.MultiSensorProblem`
from which the registry builds the fused tracker. The scorecard (:mod:`.scorecard`) is the operator's of the radar:
the radar's returns correlated, GOSPA and custody in the radar's view, re-acquisition at the radar's next pass, time
to orbit from an object's first *radar* return — so a difference is what the fence's returns between and during the
radar's passes did to the catalogue (an object the fence saw first is credited from the radar's first return).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...registry import MultiSensorProblem, build
from ...scenarios.catalogue import simulate_catalogue
from ...scenarios.catalogue.fence import space_fence
from ...scenarios.catalogue.snr import SizeModel, attach_snr_detection
from .physics import attach_tracker_snr, object_sizes
from .run import build_scenario, initial_tracks, make_motion, make_problem, tracker_sensor, tracker_spec
from .scorecard import COLUMNS, _catalogue_columns, run_scored, scorecard_row, unknown_time_to_orbit  # ssa_breakup's

__all__ = ["SENSOR_SETS", "TABLE_COLUMNS", "make_fence", "build_fused", "fused_problem", "fused_tracker", "run_fused",
           "fused_table",
           "fusion_claims", "fusion_macros", "plot_fusion"]

#: The runs compared: the radar alone, the radar and the fence.
SENSOR_SETS = ("radar", "radar+fence")


def make_fence(cfg):
    """The fence of ``cfg["fusion"]["fence"]`` (``p_D``, ``clutter_rate``, ``snr``: S-band SNR detection or the
    constant ``p_D``) with the radar block's measurement model and revisit (one scans table has one kind)."""
    r, f = cfg["radar"], cfg["fusion"]["fence"]
    if r.get("measurement", "enu") != "rae_rate":
        raise ValueError("fusion needs the documented radar (ssa_catalogue.radar.measurement: rae_rate): the fence "
                         "reports range, azimuth, elevation and range-rate")
    ang = float(r.get("sigma_angle_deg", 0.05))
    return space_fence(snr=bool(f.get("snr", True)), revisit_s=r["revisit_s"], p_D=f["p_D"],
                       clutter_rate=f["clutter_rate"], measurement="rae_rate",
                       sigma_range_km=float(r.get("sigma_range_km", 0.03)), sigma_az_deg=ang, sigma_el_deg=ang,
                       sigma_range_rate_km_s=float(r.get("sigma_range_rate_km_s", 0.01)),
                       range_rate_span_km_s=float(r.get("range_rate_span_km_s", 8.0)))


def build_fused(cfg, n: int, seed: int):
    """``(scenario, fused)``: the radar's scenario tuple (:func:`.run.build_scenario`) and the radar + fence scenario
    of the same objects, start, sizes and simulation seed (whose radar returns are the radar scenario's: checked)."""
    scenario = build_scenario(cfg, n, seed)
    objects, _, sc, _ = scenario
    ss = np.random.SeedSequence([int(seed), int(n)])
    sim_seed = int(ss.spawn(3)[1].generate_state(1)[0])  # build_scenario's simulation seed
    fused = simulate_catalogue(objects, (sc.sensors[0], make_fence(cfg)), n_scans=cfg["n_scans"], seed=sim_seed,
                               start=sc.start, sizes=object_sizes(cfg, objects))
    a, b = sc.scans, fused.scans[fused.scans["sensor"] == 0].reset_index(drop=True)
    if not (len(a) == len(b) and np.array_equal(a.filter(like="z_").to_numpy(), b.filter(like="z_").to_numpy())):
        raise RuntimeError("the radar's returns differ between the radar and the fused scenario")
    return scenario, fused


def _tracker_sensors(cfg, fused, sensors: str):
    """The trackers' sensors of ``sensors`` (:data:`SENSOR_SETS`): the radar's (its SNR p_D) and the fence's (S-band
    SNR p_D over the same size model when the fence has an SNR model)."""
    if sensors not in SENSOR_SETS:
        raise ValueError(f"sensors must be one of {SENSOR_SETS}, got {sensors!r}")
    out = [attach_tracker_snr(cfg, tracker_sensor(fused.sensors[0]))]
    if sensors == "radar+fence":
        fence = fused.sensors[1]
        t = tracker_sensor(fence)
        if fence.snr is not None:
            t = attach_snr_detection(t, fence.snr, SizeModel(debris_share=float(cfg.get("debris_share", 1.0))))
        out.append(t)
    return out


def fused_problem(cfg, scenario, tsensors) -> MultiSensorProblem:
    """The catalogue over the sensors ``tsensors``: each sensor's problem (:func:`.run.make_problem`: its model,
    field of view, admissible-region or one-point births of its own returns) on one motion model and the known
    objects at scan 0."""
    objects, unknown, sc, init_seed = scenario
    motion = make_motion(cfg)
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    return MultiSensorProblem.from_problems([make_problem(cfg, t, motion, means, covs, labels) for t in tsensors])


def fused_tracker(name: str, cfg, scenario, tsensors, seed: int):
    """Tracker ``name`` (``ssa_catalogue.trackers``) over the sensors ``tsensors`` (:func:`fused_problem`), built by
    the registry (:func:`hypotrack.registry.build`: the factored engine's multi-sensor filter for an engine with
    ``factored`` options, the multi-sensor GNN/JPDA for GNN/JPDA)."""
    return build(tracker_spec(cfg, name), fused_problem(cfg, scenario, tsensors), seed=int(seed))


def run_fused(name: str, cfg, n: int, seed: int, scenario, fused, sensors: str):
    """One scorecard row of tracker ``name`` on ``sensors`` (module docstring), with ``sensors``, the fence's returns
    used (``fence_returns``) and the run's CPU seconds (``cpu_s``)."""
    tsensors = _tracker_sensors(cfg, fused, sensors)
    tracker = fused_tracker(name, cfg, scenario, tsensors, seed)
    fence_scans = fused.scan_list(1) if len(tsensors) > 1 else None
    theta = scenario[2].theta

    def step(k, t_k, Z):
        tsensors[0].at(theta[k])
        tracker.step(Z, t_k, sensor=0)
        if fence_scans is not None:  # the fence's scan at the same instant: an update without prediction
            tsensors[1].at(theta[k])
            tracker.step(tsensors[1].returns(fence_scans[k][1]), t_k, sensor=1)

    run = run_scored(name, cfg, scenario, int(seed), on_scan=_catalogue_columns(cfg), tracker=tracker, step=step)
    motion = make_motion(cfg)
    card = scorecard_row(run, scenario, cfg, motion)
    m = cfg["metrics"]
    card.update(unknown_time_to_orbit(run, scenario, motion, m["next_pass_horizon_s"], m["completeness_km"]))
    n_fence = int((fused.scans["sensor"] == 1).sum()) if fence_scans is not None else 0
    return {**{c: card[c] for c in COLUMNS}, "sensors": sensors, "fence_returns": n_fence, "cpu_s": card["cpu_s"]}


#: The fusion table's columns: the scorecard's with the sensors and the fence's returns (no CPU times: deterministic).
TABLE_COLUMNS = ["tracker", "sensors", "fence_returns", *COLUMNS[1:]]


def fused_table(rows) -> pd.DataFrame:
    """The fusion table: per tracker, the radar-alone row then the fused one."""
    t = pd.DataFrame(list(rows))
    order = {s: i for i, s in enumerate(SENSOR_SETS)}
    t = t.assign(_s=t["sensors"].map(order)).sort_values(["_s"], kind="stable")
    trackers = list(dict.fromkeys(t["tracker"]))
    t = t.assign(_t=t["tracker"].map({x: i for i, x in enumerate(trackers)})).sort_values(["_t", "_s"], kind="stable")
    return t[TABLE_COLUMNS].reset_index(drop=True)


EXPERIMENT = "ssa_catalogue"
SOURCE = "extension (SSA at catalogue scale: radar and fence fused)"
_NAMES = {"glmb": "δ-GLMB", "homht_kbest": "HOMHT k-best", "rfisst": "R-FISST", "gnn": "GNN", "jpda": "JPDA"}


def _fmt(x, digits=3):
    return "n/a" if not np.isfinite(x) else f"{x:.{digits}g}"


def fusion_claims(table: pd.DataFrame) -> list:
    """Extension rows per tracker: completeness at the next radar pass, covariance realism at re-acquisition and
    GOSPA per object in the radar's view of the fused run, each with the radar-alone run's value in the note."""
    from ...reporting.ledger import Claim

    out = []
    for name, g in table.groupby("tracker", sort=False):
        r = g.set_index("sensors")
        if not set(SENSOR_SETS) <= set(r.index):
            continue
        a, f = r.loc["radar"], r.loc["radar+fence"]
        lab, n = _NAMES.get(name, name), int(f["n_objects"])
        common = f"radar and fence fused, N = {n}, {int(f['n_scans'])} scans, {int(f['fence_returns'])} fence returns"
        out.append(Claim(EXPERIMENT, f"fusion: completeness at the next radar pass, {lab}, N = {n}", SOURCE, "--",
                         _fmt(f["completeness"]), "--", "extension",
                         f"{common}; radar alone {_fmt(a['completeness'])} (share of all catalogued objects whose "
                         "track predicted to the next radar pass after the run is within 5 km)",
                         "measurement", key=f"fusion_completeness_{name}"))
        out.append(Claim(EXPERIMENT, f"fusion: covariance realism at re-acquisition, {lab}, N = {n}", SOURCE, "--",
                         _fmt(f["realism_95"]), "--", "extension",
                         f"{common}; goal 0.95; {int(f['reacquisitions'])} re-acquisitions, within 5 km "
                         f"{_fmt(f['reacq_within_km'])}; radar alone {_fmt(a['realism_95'])} over "
                         f"{int(a['reacquisitions'])}, within 5 km {_fmt(a['reacq_within_km'])}",
                         "measurement", key=f"fusion_realism_{name}"))
        out.append(Claim(EXPERIMENT, f"fusion: GOSPA per object in the radar's view (km), {lab}, N = {n}", SOURCE,
                         "--", _fmt(f["gospa_per_object_km"]), "--", "extension",
                         f"{common}; radar alone {_fmt(a['gospa_per_object_km'])}; cross-tags per 10^4 radar "
                         f"returns {_fmt(f['cross_tags_per_1e4'])} (radar alone {_fmt(a['cross_tags_per_1e4'])})",
                         "measurement", key=f"fusion_gospa_{name}"))
    return out


def fusion_macros(table: pd.DataFrame) -> dict:
    """Macros ``Fusion<Field><Tracker><Radar|Fused>`` of the table's compared fields, and the fence's returns."""
    fields = {"Completeness": "completeness", "Realism": "realism_95", "Reacq": "reacquisitions",
              "ReacqWithin": "reacq_within_km", "Gospa": "gospa_per_object_km", "CrossTags": "cross_tags_per_1e4",
              "TimeToOrbit": "time_to_orbit_unknown_s", "UnknownOrbit": "unknown_with_orbit"}
    v = {"FusionN": int(table["n_objects"].iloc[0]), "FusionScans": int(table["n_scans"].iloc[0]),
         "FusionFenceReturns": int(table["fence_returns"].max())}
    for r in table.itertuples(index=False):
        side = "Fused" if r.sensors == "radar+fence" else "Radar"
        for f, col in fields.items():
            x = float(getattr(r, col))
            v[f"Fusion{f}{r.tracker.replace('_', '')}{side}"] = int(x) if f in ("Reacq", "UnknownOrbit") else _fmt(x)
    return v


def plot_fusion(table: pd.DataFrame, pdf, png):
    """Radar alone against radar and fence, one pair of bars per tracker: completeness at the next radar pass, radar
    returns of real objects no track in view explained (per 10⁴), GOSPA per object in the radar's view."""
    from .figures import _SHORT, _fs, _plt, _save

    _plt()
    names = list(dict.fromkeys(table["tracker"]))
    fig, ax = _fs().subplots(1, 3, height=2.8)
    panels = [("completeness", "completeness (share)"), ("uncorrelated_per_1e4", "uncorrelated per 10$^4$ returns"),
              ("gospa_per_object_km", "GOSPA per object in view (km)")]
    x = np.arange(len(names))
    for a, (col, label) in zip(ax, panels):
        for i, (s, c) in enumerate(zip(SENSOR_SETS, ("tab:gray", "tab:blue"))):
            t = table[table["sensors"] == s].set_index("tracker").reindex(names)
            v = t[col].to_numpy(float)
            a.bar(x + (i - 0.5) * 0.38, np.where(np.isfinite(v), v, 0.0), 0.38, color=c, label=s.replace("+", " + "))
        a.set_xticks(x, [_SHORT.get(n, n) for n in names], rotation=45, ha="right", rotation_mode="anchor")
        a.set_ylabel(label)
        a.grid(alpha=0.3, axis="y")
    _fs().legend_below(fig, *ax[0].get_legend_handles_labels(), ncol=2, frameon=False)
    _save(fig, pdf, png)

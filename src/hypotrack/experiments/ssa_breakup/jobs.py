"""The pipeline jobs of the ``ssa_breakup`` experiment as library calls (the Snakemake scripts only read and write).

* :func:`score_tracker` — one tracker on every (scenario, seed): the scorecard rows (:mod:`.scorecard`);
  :func:`score_tracker_outputs` adds, for a factored filter, the rows of its ambiguity output (:mod:`.identities`,
  tracker ``<name>_amb``, at ``ambiguity.p_min`` in ``ambiguity.mode``) scored from the same run, and the sweep of
  both modes and ``p_min`` over ``ambiguity.p_min_sweep`` (:func:`.scorecard.identity_row` per value);
* :func:`density` — per (scenario, seed) the nearest-neighbour density rows and distances (:mod:`.summary`).

Seeds: ``seeds`` of the section; scenario ``s`` of seed ``k`` is built from ``k`` alone (:func:`.run.build`), so
every tracker job sees the same scans, and each tracker draws (Gibbs, MCMC) from the same ``k``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.stats import chi2

from ...scenarios.catalogue.breakup import gate_radius_km
from ..ssa_catalogue.run import make_motion
from .identities import MODES
from .run import build, control_radar, run_scored
from .scorecard import catalogued_ids, identity_row, scorecard_row
from .summary import density_rows
from .tuning import output_p_mins

__all__ = ["score_tracker", "score_tracker_outputs", "SWEEP_COLUMNS", "density", "smallest_gate_km"]


def _section(cfg, scenario: str, cfg_catalogue):
    """The section a scenario's trackers read: this experiment's (the control uses its own radar — site, field of
    view, clutter — and metrics but this experiment's measurement model (:func:`.run.control_radar`), trackers, model
    and initial errors, so both scenarios differ only in the scene)."""
    if scenario == "breakup":
        return cfg
    return {**cfg, "radar": control_radar(cfg, cfg_catalogue)}


def smallest_gate_km(cfg) -> float:
    """The smallest gate of the section's radar and gate probability: the ENU stand-in's isotropic one
    (:func:`gate_radius_km`), or the documented radar's across the beam at its nearest range,
    ``sqrt(χ²₄(P_G)) σ_angle r_min`` (the range gate is narrower, but two objects at one range and angle apart are
    told apart only across the beam; the track's own uncertainty neglected, so a real gate is larger)."""
    radar, p_gate = cfg["radar"], cfg["model"]["gate_probability"]
    if radar.get("measurement") == "rae_rate":
        return float(np.sqrt(chi2.ppf(p_gate, 4)) * np.radians(radar["sigma_angle_deg"]) * radar["r_min_km"])
    return gate_radius_km(radar["sigma_km"], p_gate)


def score_tracker(name: str, cfg, cfg_catalogue) -> pd.DataFrame:
    """Scorecard rows of tracker ``name`` on every scenario of ``cfg['scenarios']`` and seed of ``cfg['seeds']``
    (with an ``ambiguity`` block, a factored filter's ambiguity output rows after each run's own:
    :func:`score_tracker_outputs`)."""
    return score_tracker_outputs(name, cfg, cfg_catalogue)[0]


SWEEP_COLUMNS = ["scenario", "seed", "mode", "p_min", "tracker", "object_returns", "cross_tags", "cross_tags_per_1e4",
                 "catalogue_cross_tags_per_1e4", "id_switches", "id_switches_per_1e4", "uncorrelated_per_1e4"]


def score_tracker_outputs(name: str, cfg, cfg_catalogue) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``(cards, sweep)``: the scorecard rows of :func:`score_tracker` — per (scenario, seed) the run's row and, for
    a factored filter with an ``ambiguity`` block in ``cfg``, its ambiguity output's rows (tracker ``<name>_amb``,
    one per ``p_min`` of :func:`.tuning.output_p_mins`, column ``p_min``; NaN on the plain rows) from the same run —
    and the sweep rows (:data:`SWEEP_COLUMNS`; none for GNN/JPDA)."""
    amb = cfg.get("ambiguity")
    rows, sweep = [], []
    for scen in cfg["scenarios"]:
        sec = _section(cfg, scen, cfg_catalogue)
        for seed in cfg["seeds"]:
            scenario = build(scen, cfg, cfg_catalogue, int(seed))
            run = run_scored(name, sec, scenario, int(seed))
            motion = make_motion(sec)
            rows.append(dict(scenario=scen, seed=int(seed), **scorecard_row(run, scenario, sec, motion)))
            if amb is None or run.marginals is None:
                continue
            mode = amb.get("mode", "fresh")
            for p in output_p_mins(amb):
                out = run.with_output(p, mode)
                rows.append(dict(scenario=scen, seed=int(seed), p_min=p, **scorecard_row(out, scenario, sec, motion)))
            for m in MODES:
                for p in amb.get("p_min_sweep", []):
                    sweep.append(dict(scenario=scen, seed=int(seed), mode=m, p_min=float(p),
                                      **identity_row(run.with_output(float(p), m), catalogued_ids(scenario))))
    return pd.DataFrame(rows), pd.DataFrame(sweep, columns=SWEEP_COLUMNS)


def density(cfg, cfg_catalogue) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``(rows, distances)``: density rows per (scenario, seed) and the long table of distances (scenario, seed,
    km) — each scenario's smallest gate from its own radar."""
    rows, dist = [], []
    for scen in cfg["scenarios"]:
        sec = _section(cfg, scen, cfg_catalogue)
        for seed in cfg["seeds"]:
            _, _, sc, _ = build(scen, cfg, cfg_catalogue, int(seed))
            r, nn = density_rows(sc.truth, scen, int(seed), smallest_gate_km(sec))
            rows.append(r)
            dist.append(pd.DataFrame(dict(scenario=scen, seed=int(seed), nn_km=nn)))
    return pd.DataFrame(rows), pd.concat(dist, ignore_index=True)

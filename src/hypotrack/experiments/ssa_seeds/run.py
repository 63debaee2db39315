"""SSA verdicts over scenario seeds: ssa50 and ssa15 (document 000 Sec. IV-A, V-A) as a Monte Carlo.

The ``ssa50`` and ``ssa15`` experiments judge one realisation each; a verdict such as "P(N = 50) at
the end is 1" or "R-FISST and HOMHT agree at every scan" may be that realisation's luck. This
experiment draws ``n_seeds`` independent realisations of both scenarios (objects, births, clutter,
initial hypothesis) and runs the same named trackers on each — R-FISST as the paper's chain alone
and with this project's completion step, and on ssa15 HOMHT and R-FISST with the number of objects
fixed like HOMHT's (the like-for-like pair without births and deaths), and HOMHT with document 000's
births and deaths (Eq. 30), the population R-FISST runs with (the like-for-like pair with births and
deaths; ``ssa_seeds.extra_trackers``, ``ssa_seeds.births_reference``) — one shard per seed. The blind tracker
(:func:`hypotrack.experiments.ssa.blind_run`: EKF prediction of the initial hypothesis, no
measurement used, no births) runs on every realisation as the negative control of each verdict.

Steps: :func:`seed_scenario` draws realisation ``i``; :func:`run_seed` runs every tracker on both
cases and reduces each run to one row of :data:`SEED_COLUMNS`; :func:`distribution_table` gives
the distribution over seeds (quantiles, min, max, mean and standard error).
:func:`.claims.ssa_seeds_claims` states each SSA verdict over seeds with the ledger's Monte Carlo rule
(:func:`hypotrack.reporting.ledger.monte_carlo_claim`); :func:`.figures.plot_distributions` draws them.

Seeds: realisation ``i`` of case ``c`` uses child ``i`` of ``experiment_seeds(seed, "ssa_seeds/c")``
and tracker ``t`` on it the stream ``"ssa_seeds/c/i/t"``: a seed's result does not depend on how
many seeds are run. A scenario seed thus varies the sky and the chain together; :mod:`.chains` varies the
chain alone, on the report's realisation (streams ``"ssa_seeds/c/chain/j/t"``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import pandas as pd

from ..._validation import check_int
from ...scenarios.ssa import SSAScenario, params_from_config, simulate_ssa
from ..seeds import experiment_seeds
from ..stepping import Clocks
from ..ssa import (BLIND, BLIND_LABEL, OSPASettings, TrackerSettings, birth_recognition, blind_run, evaluate_map,
                   make_tracker, map_agreement, run_tracker)

__all__ = ["CASES", "METRICS", "SEED_COLUMNS", "distribution_table", "run_case", "run_seed", "seed_scenario",
           "tracker_settings"]

CASES = ("ssa50", "ssa15")
SEED_COLUMNS = ["case", "seed_index", "tracker", "label", "n_scans", "n_catalogue_end", "expected_number_end",
                "expected_number_error", "p_n_end", "births", "births_tracked_end", "birth_latency_mean", "birth_latency_max", "reference",
                "map_agreement", "births_reference", "map_agreement_births", "ospa_in_view_mean", "ospa_catalogue_mean",
                "children_per_scan_mean"]
#: Per-seed metrics summarised over seeds, with their meaning (figure labels).
METRICS = {
    "p_n_end": "P(N = true number) at the end",
    "expected_number_error": "E[N] minus the true number at the end",
    "births_tracked_end": "births tracked at the end",
    "birth_latency_mean": "mean scans from first in view to a correct track",
    "map_agreement": "fraction of scans with the reference's MAP hypothesis",
    "map_agreement_births": "fraction of scans with the MAP hypothesis of the reference with births and deaths",
    "ospa_in_view_mean": "mean OSPA in view (km)",
}


def seed_scenario(config: Mapping, case: str, index: int) -> SSAScenario:
    """Realisation ``index`` of SSA ``case`` under the config's ``ssa`` section (its ``n_scans``
    overridden by ``ssa_seeds.n_scans`` when set)."""
    if case not in CASES:
        raise ValueError(f"case must be one of {CASES}, got {case!r}")
    index = check_int(index, "index", minimum=0)
    section = dict(config["ssa"])
    if config["ssa_seeds"].get("n_scans"):
        section["n_scans"] = config["ssa_seeds"]["n_scans"]
    params = params_from_config(section, case)
    return simulate_ssa(params, experiment_seeds(config["seed"], f"ssa_seeds/{case}", index + 1)[index])


def tracker_settings(config: Mapping, case: str) -> dict:
    """The trackers ``ssa_seeds.trackers[case]`` as configured in the ``case`` section (or, for
    those run over seeds only, in ``ssa_seeds.extra_trackers[case]``, with the case section's
    ``max_hypotheses``, gate and population), with the MCMC proposals per parent overridden by
    ``ssa_seeds.n_steps`` when set."""
    own = config["ssa_seeds"]
    section = dict(config[case])
    extra = (own.get("extra_trackers") or {}).get(case) or {}
    clash = set(extra) & set(section.get("trackers", {}))
    if clash:
        raise ValueError(f"ssa_seeds.extra_trackers.{case} must not redefine {case}.trackers, got {sorted(clash)}")
    section["trackers"] = {**section.get("trackers", {}), **extra}
    out = {}
    for name in own["trackers"][case]:
        s = TrackerSettings.from_config(section, name)
        if own.get("n_steps") and s.kind == "rfisst":
            s = s.with_options(n_steps=int(own["n_steps"]))
        out[name] = s
    return out


def _row(case, index, name, label, scenario, run, section, reference_map, reference, births_map=None,
         births_reference=""):
    metrics, matched = evaluate_map(run.map_estimates, scenario, ospa_settings=OSPASettings(**section["ospa"]),
                                    error_bound_probability=section["error_bound_probability"])
    births = birth_recognition(matched, scenario)
    last = int(run.summary["scan"].max())
    n_end = int(metrics["n_catalogue"].iloc[-1])
    card = run.cardinality[run.cardinality["scan"] == last]
    delays = births.loc[births["delay_scans"] >= 0, "delay_scans"]
    agreement = np.nan
    if reference_map is not None:
        agreement = float(map_agreement(run.map_estimates, reference_map, scenario.prior_ids)["agree"].mean())
    return {
        "case": case, "seed_index": index, "tracker": name, "label": label, "n_scans": last + 1,
        "n_catalogue_end": n_end, "expected_number_end": float(run.summary["expected_number"].iloc[-1]),
        "expected_number_error": float(run.summary["expected_number"].iloc[-1]) - n_end,
        "p_n_end": float(card.loc[card["n_objects"] == n_end, "probability"].sum()),
        "births": len(births), "births_tracked_end": int(births["tracked_at_end"].sum()),
        "birth_latency_mean": float(delays.mean()) if len(delays) else np.nan,
        "birth_latency_max": float(delays.max()) if len(delays) else np.nan,
        "reference": reference if reference_map is not None else "", "map_agreement": agreement,
        "births_reference": births_reference if births_map is not None else "",
        "map_agreement_births": (float(map_agreement(run.map_estimates, births_map, scenario.prior_ids)["agree"].mean())
                                 if births_map is not None else np.nan),
        "ospa_in_view_mean": float(np.nanmean(metrics["ospa_in_view"])),
        "ospa_catalogue_mean": float(metrics["ospa_catalogue"].mean()),
        "children_per_scan_mean": float(run.summary.loc[run.summary["scan"] > 0, "n_children"].mean()),
    }


def _reference(config, case, settings):
    """ssa15: the configured reference (HOMHT); ssa50: the paper's chain (the first tracker)."""
    ref = config["ssa_seeds"].get("reference", {}).get(case)
    return ref if ref in settings else next(iter(settings))


def _births_reference(config, case, settings):
    """The configured tracker with births and deaths (``ssa_seeds.births_reference[case]``) that the
    trackers with births and deaths are compared with too, or ``None``."""
    ref = (config["ssa_seeds"].get("births_reference") or {}).get(case)
    if ref is None:
        return None
    if ref not in settings:  # defined but not run (ssa_seeds.trackers names a subset): no such pair
        defined = {*config[case].get("trackers", {}), *((config["ssa_seeds"].get("extra_trackers") or {}).get(case) or {})}
        if ref in defined:
            return None
        raise ValueError(f"ssa_seeds.births_reference.{case} must be one of the case's trackers {sorted(defined)}, "
                         f"got {ref!r}")
    if not settings[ref].population:
        raise ValueError(f"ssa_seeds.births_reference.{case}: {ref!r} must run with births and deaths (population true)")
    return ref


def run_seed(config: Mapping, index: int, progress: Callable[[str], None] | None = print):
    """Every configured tracker on realisation ``index`` of both cases.

    Returns ``(rows, timing)``: one :data:`SEED_COLUMNS` row per case and tracker, and one for the
    blind tracker (:data:`~hypotrack.experiments.ssa.BLIND`, the negative control of every check:
    EKF prediction of the initial hypothesis, no measurements, no births), deterministic given the
    config; and ``case, seed_index, tracker, seconds, cpu_seconds``.

    Every tracker but the reference is compared with the reference's MAP hypothesis; every tracker
    with births and deaths (and the blind tracker, the control) also with the births reference's
    (``births_reference``, ``map_agreement_births``), which itself has no row against the reference.
    """
    rows, timing = [], []
    for case in config["ssa_seeds"]["trackers"]:
        r, t = run_case(config, case, seed_scenario(config, case, index), index,
                        lambda name, case=case: f"ssa_seeds/{case}/{index}/{name}", f"seed {index}", progress)
        rows += r
        timing += t
    return pd.DataFrame(rows, columns=SEED_COLUMNS), pd.DataFrame(timing)


def run_case(config: Mapping, case: str, scenario: SSAScenario, index: int, stream: Callable[[str], str],
             what: str, progress: Callable[[str], None] | None = print) -> tuple[list, list]:
    """Every configured tracker of ``case`` and the blind tracker on ``scenario``: the rows and timing
    records of :func:`run_seed` (``seed_index`` = ``index``); tracker ``name`` draws from the stream
    ``experiment_seeds(seed, stream(name), 1)[0]``, so the caller says which randomness varies."""
    rows, timing = [], []
    settings = tracker_settings(config, case)
    ref = _reference(config, case, settings)
    bref = _births_reference(config, case, settings)
    runs = {}
    for name in [ref, *[n for n in settings if n != ref]]:  # the reference first: the others compare
        s = settings[name]
        rng = np.random.default_rng(experiment_seeds(config["seed"], stream(name), 1)[0])
        with Clocks() as clocks:
            runs[name] = run_tracker(make_tracker(scenario, s, rng), scenario, name=f"ssa_seeds {what} "
                                     f"{case} {s.label}", progress=progress, n_progress=4)
        timing.append({"case": case, "seed_index": index, "tracker": name,
                       "seconds": clocks.wall, "cpu_seconds": clocks.cpu})
    runs[BLIND] = blind_run(scenario)  # the negative control of every check (no measurement ever used)
    labels = {**{name: s.label for name, s in settings.items()}, BLIND: BLIND_LABEL}
    for name, label in labels.items():
        ref_map = runs[ref].map_estimates if name not in (ref, bref) else None
        births = bref is not None and name != bref and (name == BLIND or settings[name].population)
        rows.append(_row(case, index, name, label, scenario, runs[name], config[case], ref_map, ref,
                         runs[bref].map_estimates if births else None, bref or ""))
    return rows, timing


def distribution_table(per_seed: pd.DataFrame) -> pd.DataFrame:
    """Per case, tracker and metric of :data:`METRICS` (and the birth latency maximum and OSPA
    over the catalogue): ``n, mean, se, sd, min, q10, q25, median, q75, q90, max`` over seeds."""
    metrics = [m for m in (*METRICS, "expected_number_end", "birth_latency_max", "ospa_catalogue_mean",
                           "children_per_scan_mean") if m in per_seed]  # (a table without the pair with births)
    rows = []
    for (case, tracker), g in per_seed.groupby(["case", "tracker"], sort=False):
        for m in metrics:
            x = g[m].to_numpy(dtype=float)
            x = x[np.isfinite(x)]
            if not len(x):
                continue
            q = np.quantile(x, [0.1, 0.25, 0.5, 0.75, 0.9])
            sd = float(x.std(ddof=1)) if len(x) > 1 else np.nan
            rows.append({"case": case, "tracker": tracker, "label": g["label"].iloc[0], "metric": m, "n": len(x),
                         "mean": float(x.mean()), "se": sd / np.sqrt(len(x)) if len(x) > 1 else np.nan, "sd": sd,
                         "min": float(x.min()), "q10": q[0], "q25": q[1], "median": q[2], "q75": q[3], "q90": q[4],
                         "max": float(x.max())})
    return pd.DataFrame(rows, columns=["case", "tracker", "label", "metric", "n", "mean", "se", "sd", "min", "q10",
                                       "q25", "median", "q75", "q90", "max"])  # (columns even when empty)



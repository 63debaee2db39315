"""Tables, ledger rows and macros of the ``ssa_breakup`` experiment.

* :func:`scorecard_summary` — the scorecard (:mod:`.scorecard`) per (scenario, tracker): mean and standard
  error over the seeds of every column;
* :func:`cross_tag_ratios` — per scenario, the cross-tags per 10⁴ returns of each factored tracker over GNN's,
  per seed, then mean ± standard error over the seeds (a seed where GNN has none gives no ratio), against
  the goal ``ratio ≤ goal`` (default ½); with ``column="id_switches_per_1e4"`` the same ratio of the
  standard crediting, CLEAR-MOT's identity switches (:mod:`hypotrack.metrics_scorecard`), column ``metric``
  says which;
* :func:`ambiguity_sweep` — per (scenario, factored tracker, mode, ``p_min``) the ambiguity output's cross-tags and
  identity switches (mean ± s.e.) and both ratios to the reference's (:func:`cross_tag_ratios`), against the goal;
* :func:`density_table` — per (scenario, seed): the nearest-neighbour distances of the objects in view (median)
  and the share inside the smallest gate (:func:`hypotrack.scenarios.catalogue.breakup.gate_radius_km`);
* :func:`breakup_claims`, :func:`breakup_macros` — ledger rows (status *extension*) and macros.

Timing (CPU seconds) is kept apart in ``summary_timing.csv`` (machine-dependent).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...metrics_scorecard import mean_se
from ...reporting.ledger import Claim
from ...scenarios.catalogue.breakup import nearest_neighbour_km

__all__ = ["EXPERIMENT", "TRACKER_NAMES", "RATIO_TRACKERS", "AMBIGUITY_TRACKERS", "SCENARIO_NAMES", "TIMING_COLUMNS", "scorecard_summary", "cross_tag_ratios",
           "ambiguity_sweep", "breakup_ratios", "merged_sweeps",
           "density_rows", "density_table", "breakup_claims", "breakup_macros"]

EXPERIMENT = "ssa_breakup"
SOURCE = "extension (a fresh breakup cloud)"
TRACKER_NAMES = {"glmb": "δ-GLMB (Gibbs)", "glmb_murty": "δ-GLMB (Murty)", "homht_kbest": "HOMHT k-best", "rfisst": "R-FISST",
                 "gnn": "GNN", "jpda": "JPDA", "glmb_amb": "δ-GLMB (Gibbs), ambiguity output",
                 "glmb_murty_amb": "δ-GLMB (Murty), ambiguity output", "homht_kbest_amb": "HOMHT k-best, ambiguity output",
                 "rfisst_amb": "R-FISST, ambiguity output"}
#: The trackers whose cross-tags are compared with the reference's (those of a run's ``trackers_run``).
RATIO_TRACKERS = ("glmb", "glmb_murty", "homht_kbest", "rfisst")
#: Their ambiguity outputs (:meth:`.run.ScoredRun.with_output`), compared with the reference too (rows after theirs).
AMBIGUITY_TRACKERS = ("glmb_amb", "glmb_murty_amb", "homht_kbest_amb", "rfisst_amb")
SCENARIO_NAMES = {"breakup": "breakup cloud", "catalogue": "sparse catalogue"}
TIMING_COLUMNS = ("cpu_s",)
_KEYS = ("scenario", "tracker")
#: The ratio metrics: ``column: (what the claim calls it, key prefix)`` — the operator's cross-tags (the goal's) and
#: the standard crediting's identity switches.
_RATIO_METRICS = {"cross_tags_per_1e4": ("cross-tags", ""), "id_switches_per_1e4": ("identity switches", "idsw_"),
                  "catalogue_cross_tags_per_1e4": ("catalogue cross-tags", "cat_")}


def scorecard_summary(cards: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame]:
    """``(accuracy, timing)``: per (scenario, tracker) the number of seeds and, per numeric column,
    ``<col>`` (mean) and ``<col>_se`` (standard error over seeds); timing holds :data:`TIMING_COLUMNS`."""
    num = [c for c in cards.columns if c not in (*_KEYS, "seed") and pd.api.types.is_numeric_dtype(cards[c])]
    rows = []
    for (scen, name), g in cards.groupby(list(_KEYS), sort=False):
        r = dict(scenario=scen, tracker=name, n_seeds=int(g["seed"].nunique()))
        for c in num:
            r[c], r[f"{c}_se"] = mean_se(g[c])
        rows.append(r)
    out = pd.DataFrame(rows)
    tcols = [c for c in out.columns if c.split("_se")[0] in TIMING_COLUMNS]
    return out.drop(columns=tcols), out[[*_KEYS, "n_seeds", *tcols]]


def cross_tag_ratios(cards: pd.DataFrame, reference: str = "gnn", trackers=("glmb", "homht_kbest"),
                     goal: float = 0.5, column: str = "cross_tags_per_1e4") -> pd.DataFrame:
    """Per (scenario, tracker): cross-tags per 10⁴ returns (or another ``column`` of the cards, named in
    ``metric``) over ``reference``'s, mean ± s.e. over the seeds with a nonzero reference (``n_ratio`` of them),
    and whether the mean meets ``ratio ≤ goal`` (the verdict's statistic). Beside it, how the per-seed ratios
    spread: their median, the seeds whose own ratio meets the goal (``n_at_goal``), and the ratio of the two
    trackers' means over the same seeds (``ratio_of_means``: a seed where the reference makes few weighs less)."""
    rows = []
    for scen, g in cards.groupby("scenario", sort=False):
        ref = g[g["tracker"] == reference].set_index("seed")[column]
        for name in trackers:
            own = g[g["tracker"] == name].set_index("seed")[column]
            seeds = own.index.intersection(ref.index[ref > 0])
            ratio = (own.loc[seeds] / ref.loc[seeds]).to_numpy(float)
            m, se = mean_se(ratio)
            pooled = float(own.loc[seeds].sum() / ref.loc[seeds].sum()) if len(seeds) else np.nan
            rows.append(dict(scenario=scen, tracker=name, reference=reference, n_ratio=len(seeds), ratio=m, ratio_se=se,
                             goal=goal, meets_goal=bool(np.isfinite(m) and m <= goal), metric=column,
                             ratio_median=float(np.median(ratio)) if len(ratio) else np.nan,
                             n_at_goal=int(np.sum(ratio <= goal)), ratio_of_means=pooled))
    return pd.DataFrame(rows, columns=["scenario", "tracker", "reference", "n_ratio", "ratio", "ratio_se", "goal",
                                       "meets_goal", "metric", "ratio_median", "n_at_goal", "ratio_of_means"])


def breakup_ratios(cards: pd.DataFrame, trackers_run, reference: str = "gnn", goal: float = 0.5) -> pd.DataFrame:
    """The ratios table: :func:`cross_tag_ratios` of the cross-tags, of the identity switches and of the catalogue
    cross-tags (:mod:`.scorecard`) for the
    :data:`RATIO_TRACKERS` in ``trackers_run``, then the same for the :data:`AMBIGUITY_TRACKERS` outputs ``cards``
    holds (scored from the same runs), after every row of the plain outputs."""
    metrics = tuple(c for c in _RATIO_METRICS if c in cards)  # cards of an earlier run lack the catalogue's
    compared = tuple(t for t in RATIO_TRACKERS if t in trackers_run)
    amb = tuple(t for t in AMBIGUITY_TRACKERS if t in set(cards["tracker"]))
    parts = [cross_tag_ratios(cards, reference, names, goal=goal, column=c)
             for names in (compared, amb) if names for c in metrics]
    return pd.concat(parts, ignore_index=True)


def merged_sweeps(sweeps) -> pd.DataFrame:
    """The per-tracker sweep tables of :func:`.jobs.score_tracker_outputs` as one (GNN's and JPDA's are empty)."""
    filled = [t for t in sweeps if len(t)]
    return pd.concat(filled, ignore_index=True) if filled else sweeps[0]


def ambiguity_sweep(sweep: pd.DataFrame, cards: pd.DataFrame, reference: str = "gnn",
                    goal: float = 0.5) -> pd.DataFrame:
    """Per (scenario, tracker, mode, ``p_min``) of the sweep rows (:func:`.jobs.score_tracker_outputs`): the number of
    seeds, cross-tags and uncorrelated returns per 10⁴ returns and identity switches per 10⁴ object-scans (mean,
    s.e.), and the cross-tags' and identity switches' ratios to ``reference``'s in ``cards`` (:func:`cross_tag_ratios`: ``xtag_ratio``, ``idsw_ratio`` with s.e. and verdict)."""
    cols = ["scenario", "tracker", "mode", "p_min", "n_seeds", "cross_tags_per_1e4", "cross_tags_per_1e4_se",
            "id_switches_per_1e4", "id_switches_per_1e4_se", "uncorrelated_per_1e4", "uncorrelated_per_1e4_se",
            "xtag_ratio", "xtag_ratio_se", "xtag_meets_goal",
            "idsw_ratio", "idsw_ratio_se", "idsw_meets_goal", "goal"]
    if sweep.empty:
        return pd.DataFrame(columns=cols)
    ref = cards[cards["tracker"] == reference]
    rows = []
    for (scen, name, mode, p), g in sweep.groupby(["scenario", "tracker", "mode", "p_min"], sort=False):
        both = pd.concat([g, ref[ref["scenario"] == scen]], ignore_index=True)
        r = dict(scenario=scen, tracker=name, mode=mode, p_min=float(p), n_seeds=int(g["seed"].nunique()))
        for c in ("cross_tags_per_1e4", "id_switches_per_1e4", "uncorrelated_per_1e4"):
            r[c], r[f"{c}_se"] = mean_se(g[c])
        for pre, c in (("xtag", "cross_tags_per_1e4"), ("idsw", "id_switches_per_1e4")):
            q = cross_tag_ratios(both, reference, (name,), goal, c).iloc[0]
            r[f"{pre}_ratio"], r[f"{pre}_ratio_se"], r[f"{pre}_meets_goal"] = q["ratio"], q["ratio_se"], q["meets_goal"]
        rows.append(dict(r, goal=goal))
    return pd.DataFrame(rows, columns=cols)


def density_rows(truth: pd.DataFrame, scenario: str, seed: int, gate_km: float) -> tuple[dict, np.ndarray]:
    """One density row of a scenario's truth (median nearest-neighbour distance of the objects in view, share
    inside ``gate_km`` and inside 5 ``gate_km``) and the finite distances (for the figure)."""
    nn = nearest_neighbour_km(truth)
    nn = nn[np.isfinite(nn)]
    return (dict(scenario=scenario, seed=int(seed), n_pairs=len(nn), nn_median_km=float(np.median(nn)) if len(nn)
                 else float("nan"), gate_km=gate_km, share_in_gate=float(np.mean(nn <= gate_km)) if len(nn) else
                 float("nan"), share_in_5_gates=float(np.mean(nn <= 5 * gate_km)) if len(nn) else float("nan")), nn)


def density_table(rows) -> pd.DataFrame:
    """Density rows per seed, then a mean ± s.e. row per scenario (``seed = -1``)."""
    df = pd.DataFrame(rows)
    out = [df]
    for scen, g in df.groupby("scenario", sort=False):
        r = dict(scenario=scen, seed=-1, n_pairs=int(g["n_pairs"].sum()), gate_km=float(g["gate_km"].iloc[0]))
        for c in ("nn_median_km", "share_in_gate", "share_in_5_gates"):
            r[c], r[f"{c}_se"] = mean_se(g[c])
        out.append(pd.DataFrame([r]))
    return pd.concat(out, ignore_index=True)


def _f(x, d=3):
    return "--" if not np.isfinite(x) else f"{x:.{d}g}"


def _seeds(n) -> str:
    """``1 seed``, ``2 seeds`` (the report's garbled-text check refuses ``1 seeds``)."""
    return f"{int(n)} seed{'' if int(n) == 1 else 's'}"


def _withheld_note(summary: pd.DataFrame, r) -> str:
    """For an ambiguity output's row: its uncorrelated returns per 10⁴ against its plain output's (the difference is
    what it withheld while ambiguous); empty otherwise."""
    if r.tracker not in AMBIGUITY_TRACKERS or "uncorrelated_per_1e4" not in summary:
        return ""
    base = summary[(summary["scenario"] == r.scenario) & (summary["tracker"] == r.tracker.removesuffix("_amb"))]
    plain = f" against {_f(base['uncorrelated_per_1e4'].iloc[0])} for the plain output" if len(base) else ""
    return f"; uncorrelated {_f(r.uncorrelated_per_1e4)} per 10^4 returns{plain} (withheld while ambiguous)"


def breakup_claims(summary: pd.DataFrame, ratios: pd.DataFrame, density: pd.DataFrame, reference: str = "gnn") -> list:
    """Ledger rows (status *extension*): per scenario, each tracker's cross-tags per 10⁴ returns; the ratios to
    GNN against the goal; the share of ``reference``'s re-acquisitions with another object inside the gate; the
    share of nearest-neighbour distances inside the smallest gate."""
    out = []
    for r in summary.itertuples(index=False):
        out.append(Claim(EXPERIMENT, f"cross-tags per 10^4 returns, {TRACKER_NAMES[r.tracker]}, "
                         f"{SCENARIO_NAMES[r.scenario]}", SOURCE, "--",
                         f"{_f(r.cross_tags_per_1e4)} ± {_f(r.cross_tags_per_1e4_se, 2)}", "--", "extension",
                         f"mean ± s.e. over {_seeds(r.n_seeds)}; completeness {_f(r.completeness)}, duplicates "
                         f"{_f(r.duplicate_per_1000)} and false {_f(r.false_per_1000)} per 1,000 estimates"
                         # the price of an output that withholds ambiguous correlations
                         + _withheld_note(summary, r),
                         "measurement", key=f"crosstags_{r.scenario}_{r.tracker}"))
    for r in ratios.itertuples(index=False):
        what, pre = _RATIO_METRICS[getattr(r, "metric", "cross_tags_per_1e4")]
        out.append(Claim(EXPERIMENT, f"{what} of {TRACKER_NAMES[r.tracker]} over GNN's, "
                         f"{SCENARIO_NAMES[r.scenario]}", SOURCE, f"goal ≤ {r.goal:g}",
                         f"{_f(r.ratio)} ± {_f(r.ratio_se, 2)}", "--", "extension",
                         f"per-seed ratios over {_seeds(r.n_ratio)} with GNN {what}; "
                         f"{'meets' if r.meets_goal else 'misses'} the goal", "measurement",
                         key=f"{pre}ratio_{r.scenario}_{r.tracker}"))
    for r in summary[summary["tracker"] == reference].itertuples(index=False):
        out.append(Claim(EXPERIMENT, f"re-acquisitions with another object inside the track's gate, "
                         f"{TRACKER_NAMES[r.tracker]}, {SCENARIO_NAMES[r.scenario]}", SOURCE, "--",
                         f"{_f(r.nn_in_gate_share)} ± {_f(r.nn_in_gate_share_se, 2)}", "--", "extension",
                         f"the nearest other object in view inside the 99.9 % gate of the track predicted to the "
                         f"object's next pass; {_f(r.reacquisitions)} re-acquisitions per seed, {_seeds(r.n_seeds)}",
                         "measurement", key=f"reacq_gate_{r.scenario}"))
    for r in density[density["seed"] < 0].itertuples(index=False):
        out.append(Claim(EXPERIMENT, f"nearest-neighbour distances inside the smallest gate, "
                         f"{SCENARIO_NAMES[r.scenario]}", SOURCE, "--", f"{_f(r.share_in_gate)}", "--", "extension",
                         f"gate {r.gate_km:.2f} km; median distance {_f(r.nn_median_km)} km; "
                         f"{int(r.n_pairs)} (scan, object in view) pairs", "measurement",
                         key=f"nn_in_gate_{r.scenario}"))
    return out


def breakup_macros(summary: pd.DataFrame, ratios: pd.DataFrame, density: pd.DataFrame) -> dict:
    """Macros: per (scenario, tracker) cross-tags per 10⁴ returns (and s.e.), duplicates per 1,000 estimates,
    uncorrelated returns per 10⁴,
    completeness and covariance realism, identity switches per 10⁴ object-scans, the shares of first returns to
    the object's own label and of re-acquisitions that kept the label; the ratios with their s.e. and the verdict (``met``/``not met``); the density shares; the seeds and objects. A tracker of :data:`TRACKER_NAMES` (or
    ratio of :data:`RATIO_TRACKERS`) the cards do not hold gets NaN (written ``--``) under each of its names."""
    vals = {}
    for r in summary.itertuples(index=False):
        vals[f"crosstags_{r.scenario}_{r.tracker}"] = r.cross_tags_per_1e4
        vals[f"crosstags_se_{r.scenario}_{r.tracker}"] = r.cross_tags_per_1e4_se
        vals[f"duplicates_{r.scenario}_{r.tracker}"] = r.duplicate_per_1000
        vals[f"uncorrelated_{r.scenario}_{r.tracker}"] = getattr(r, "uncorrelated_per_1e4", float("nan"))
        vals[f"completeness_{r.scenario}_{r.tracker}"] = r.completeness
        vals[f"realism_{r.scenario}_{r.tracker}"] = r.realism_95
        # the standard crediting and where labels change objects (:mod:`.custody`)
        vals[f"idsw_{r.scenario}_{r.tracker}"] = getattr(r, "id_switches_per_1e4", float("nan"))
        vals[f"catxtags_{r.scenario}_{r.tracker}"] = getattr(r, "catalogue_cross_tags_per_1e4", float("nan"))
        vals[f"firstown_{r.scenario}_{r.tracker}"] = getattr(r, "first_return_own", float("nan"))
        vals[f"reacqkept_{r.scenario}_{r.tracker}"] = getattr(r, "reacquired_same_label", float("nan"))
        vals[f"n_seeds_{r.scenario}"] = int(r.n_seeds)
        vals[f"n_objects_{r.scenario}"] = int(round(r.n_objects))
    for r in ratios.itertuples(index=False):
        pre = _RATIO_METRICS[getattr(r, "metric", "cross_tags_per_1e4")][1]
        vals[f"{pre}ratio_{r.scenario}_{r.tracker}"] = r.ratio
        vals[f"{pre}ratio_se_{r.scenario}_{r.tracker}"] = r.ratio_se
        # the verdict as words, only where a ratio was measured
        vals[f"{pre}goal_{r.scenario}_{r.tracker}"] = (("met" if r.meets_goal else "not met") if np.isfinite(r.ratio)
                                                       else float("nan"))
    for r in density[density["seed"] < 0].itertuples(index=False):
        vals[f"nn_share_{r.scenario}"] = r.share_in_gate
        vals[f"nn_median_{r.scenario}"] = r.nn_median_km
    # a tracker a configuration does not run (the Gibbs delta-GLMB and R-FISST run in full.yaml) gets "--", so the
    # paper can leave its sentence out (\htifvalue) instead of failing on an undefined macro
    for scen in summary["scenario"].unique():
        for name in TRACKER_NAMES:
            for key in ("crosstags", "crosstags_se", "duplicates", "uncorrelated", "completeness", "realism", "idsw",
                        "catxtags", "firstown", "reacqkept"):
                vals.setdefault(f"{key}_{scen}_{name}", float("nan"))
        for name in (*RATIO_TRACKERS, *AMBIGUITY_TRACKERS):
            for pre in ("", "idsw_", "cat_"):
                vals.setdefault(f"{pre}ratio_{scen}_{name}", float("nan"))
                vals.setdefault(f"{pre}ratio_se_{scen}_{name}", float("nan"))
                vals.setdefault(f"{pre}goal_{scen}_{name}", float("nan"))
    return vals

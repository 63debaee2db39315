"""The committed breakup record — the evaluated seeds' verdict with a tuned ``p_min`` — and the only step that
writes it.

The record run is ``ssa_breakup`` under ``workflows/config/full.yaml`` overlaid with
``workflows/config/breakup_record.yaml`` (ten evaluated seeds, the ambiguity output's tuning protocol on seeds of its
own: :mod:`.tuning`), longer than the default budget. After it::

    python -m hypotrack.experiments.ssa_breakup.record results   # -> paper/record/ssa_breakup_*

writes ``ssa_breakup_record.csv`` (:func:`record_table`: per tracker of the breakup cloud its cross-tags, untagged
returns and identity switches, mean ± s.e. over the evaluated seeds, and its ratios to GNN's against the goal, the
ambiguity outputs at the tuned ``p_min``), copies the tuning table (``ssa_breakup_tuning.csv``) and writes the
configuration section it checked the tables against (``ssa_breakup_record_config.json``), renders the README's
block (``ssa_breakup_record.md``, :func:`record_markdown`) and regenerates the README. It refuses tables whose
evaluated or tuning seeds, or trackers, are not the record configuration's (``--force`` records them anyway).

The default pipeline's table job reads the committed record back (:func:`record_claims`, :func:`record_macros`):
the ledger's record rows and the paper's ``record_*`` macros come from it, so the paper quotes the ten-seed verdict
without the default run paying for it.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim
from ...reporting.readme import BREAKUP_RECORD
from ...reporting.record import RECORD, ROOT, overlaid_config, rewrite_readme, run_step
from .summary import EXPERIMENT, TRACKER_NAMES
from .tuning import chosen_p_min

__all__ = ["TABLE", "TUNING", "CONFIG", "BLOCK", "record_config", "record_table", "record_markdown",
           "update_breakup_record", "record_claims", "record_macros"]

TABLE = "ssa_breakup_record.csv"
TUNING = "ssa_breakup_tuning.csv"
CONFIG = "ssa_breakup_record_config.json"
BLOCK = BREAKUP_RECORD  # ssa_breakup_record.md, read by the README's generation
OVERLAYS = ("default.yaml", "full.yaml", "breakup_record.yaml")
_STATS = ("cross_tags_per_1e4", "uncorrelated_per_1e4", "id_switches_per_1e4", "completeness",
          "catalogue_cross_tags_per_1e4")
#: The ratios recorded: prefix -> metric (the operator's cross-tags, the goal's; identity switches; catalogue
#: cross-tags, each catalogued fragment's own number owned by it: :mod:`.scorecard`).
_RATIOS = (("", "cross_tags_per_1e4"), ("idsw_", "id_switches_per_1e4"), ("cat_", "catalogue_cross_tags_per_1e4"))


def record_config(workflow_dir=ROOT / "workflows") -> dict:
    """The ``ssa_breakup`` section of ``default.yaml`` overlaid with ``full.yaml`` then ``breakup_record.yaml``
    (:func:`~hypotrack.reporting.record.overlaid_config`)."""
    return overlaid_config(OVERLAYS, workflow_dir)["ssa_breakup"]


def record_table(summary: pd.DataFrame, ratios: pd.DataFrame, p_min: float, tuning_seeds, untagged_weight: float,
                 seeds) -> pd.DataFrame:
    """One row per tracker of the breakup cloud in ``summary`` (the table job's, ambiguity outputs at ``p_min``):
    :data:`_STATS` mean and s.e. over the seeds, and from ``ratios`` the cross-tag ratio to the reference
    (``ratio``, ``ratio_se``, ``n_ratio``, ``goal``, ``meets_goal``) and the identity-switch ratio (``idsw_*``);
    ``p_min``, the tuning seeds, λ and the evaluated seeds on every row."""
    s = summary[summary["scenario"] == "breakup"]
    r = ratios[ratios["scenario"] == "breakup"]
    rows = []
    for t in s.itertuples(index=False):
        row = dict(tracker=t.tracker, n_seeds=int(t.n_seeds))
        for c in _STATS:
            row[c], row[f"{c}_se"] = getattr(t, c, np.nan), getattr(t, f"{c}_se", np.nan)
        for pre, metric in _RATIOS:
            q = r[(r["tracker"] == t.tracker) & (r["metric"] == metric)]
            row[f"{pre}ratio"] = float(q["ratio"].iloc[0]) if len(q) else np.nan
            row[f"{pre}ratio_se"] = float(q["ratio_se"].iloc[0]) if len(q) else np.nan
            row[f"{pre}meets_goal"] = bool(q["meets_goal"].iloc[0]) if len(q) else False
            if pre != "idsw_":
                row[f"{pre}n_ratio"] = int(q["n_ratio"].iloc[0]) if len(q) else 0
                if not pre:
                    row["goal"] = float(q["goal"].iloc[0]) if len(q) else np.nan
                for c in ("ratio_median", "n_at_goal", "ratio_of_means"):
                    row[f"{pre}{c}"] = float(q[c].iloc[0]) if len(q) and c in q else np.nan
        rows.append(dict(row, p_min=float(p_min), tuning_seeds=" ".join(str(int(k)) for k in tuning_seeds),
                         untagged_weight=float(untagged_weight), seeds=" ".join(str(int(k)) for k in seeds)))
    return pd.DataFrame(rows)


def _check(sec: dict, scorecard: pd.DataFrame, tuning: pd.DataFrame) -> list[str]:
    """Where the results' tables are not the record configuration's run (empty: they are)."""
    out = []
    b = scorecard[scorecard["scenario"] == "breakup"]
    if sorted(set(b["seed"].astype(int))) != sorted(int(k) for k in sec["seeds"]):
        out.append(f"evaluated seeds {sorted(set(b['seed'].astype(int)))} for {sorted(sec['seeds'])}")
    want = set(sec["trackers_run"])
    if not want <= set(b["tracker"]):
        out.append(f"trackers {sorted(set(b['tracker']))} lack {sorted(want - set(b['tracker']))}")
    tun = sorted(set(tuning.loc[tuning["seed"] >= 0, "seed"].astype(int)))
    if tun != sorted(int(k) for k in sec["ambiguity"]["tuning"]["seeds"]):
        out.append(f"tuning seeds {tun} for {sorted(sec['ambiguity']['tuning']['seeds'])}")
    lam = set(tuning["untagged_weight"].astype(float))
    if lam != {float(sec["ambiguity"]["tuning"]["untagged_weight"])}:
        out.append(f"untagged_weight {sorted(lam)}")
    return out


def _pm(x, se=None, d=3) -> str:
    if not np.isfinite(x):
        return "--"
    return f"{x:.{d}g}" if se is None or not np.isfinite(se) else f"{x:.{d}g} ± {se:.2g}"


def record_markdown(table: pd.DataFrame, tuning: pd.DataFrame) -> str:
    """The README's block: the protocol in one sentence, the tuning table's means over the tuning seeds (every
    tracker) per ``p_min``, and the evaluated seeds' verdict per tracker."""
    first = table.iloc[0]
    seeds = first["seeds"].split()
    names = [TRACKER_NAMES.get(t.removesuffix("_amb"), t.removesuffix("_amb")) for t in dict.fromkeys(tuning["tracker"])
             if t != "all"]
    names = names[0] if len(names) == 1 else f"{', '.join(names[:-1])} and {names[-1]}"
    lines = [f"Record (`paper/record/{TABLE}`, `{TUNING}`; `full.yaml` with `breakup_record.yaml`): the "
             f"ambiguity output's `p_min` = {first['p_min']:g}, chosen on tuning seeds "
             f"{_seed_words(first['tuning_seeds'])} as the least mean cross-tags + {first['untagged_weight']:g} × "
             f"untagged returns (per 10⁴) of the ambiguity outputs of {names}, then evaluated on seeds "
             f"{_seed_words(first['seeds'])} ({len(seeds)} seeds). Tuning (mean over the tuning seeds and both "
             f"trackers):",
             "", "| p_min | cross-tags /10⁴ | untagged /10⁴ | cost | chosen |", "|---|---|---|---|---|"]
    allp = tuning[(tuning["tracker"] == "all") & (tuning["seed"] < 0)].sort_values("p_min")
    for r in allp.itertuples(index=False):
        lines.append(f"| {r.p_min:g} | {_pm(r.cross_tags_per_1e4)} | {_pm(r.uncorrelated_per_1e4)} | {_pm(r.score)} "
                     f"| {'yes' if r.chosen else ''} |")
    lines += ["", "Evaluated seeds (mean ± s.e.; ratios per seed to GNN's, over the seeds where GNN cross-tags; the "
              "verdict on their mean, the statistic stated before the runs; beside it their median, the seeds whose "
              "own ratio meets the goal, and the ratio of the mean cross-tags over those seeds):", "",
              "| tracker | seeds | cross-tags /10⁴ | ratio to GNN | goal ≤ 0.5 | median ratio | seeds at goal | "
              "ratio of means | untagged /10⁴ | id-switch ratio |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    for r in table.itertuples(index=False):
        has = np.isfinite(r.ratio)
        goal = ("met" if r.meets_goal else "not met") if has else ""
        spread = (f"{_pm(getattr(r, 'ratio_median', np.nan))} | {int(r.n_at_goal)} of {int(r.n_ratio)} | "
                  f"{_pm(getattr(r, 'ratio_of_means', np.nan))}" if has and np.isfinite(getattr(r, "n_at_goal", np.nan))
                  else " |  | ")  # three empty cells
        lines.append(f"| {TRACKER_NAMES[r.tracker]} | {int(r.n_seeds)} | {_pm(r.cross_tags_per_1e4, r.cross_tags_per_1e4_se)} | "
                     f"{_pm(r.ratio, r.ratio_se) if has else ''} | {goal} | {spread} | "
                     f"{_pm(r.uncorrelated_per_1e4, r.uncorrelated_per_1e4_se)} | "
                     f"{_pm(r.idsw_ratio, r.idsw_ratio_se) if has else ''} |")
    if "cat_ratio" in table:
        lines += ["", "Catalogue cross-tags (each catalogued fragment's own number owned by it: a swap of two catalogued "
                  "fragments kept to the end is charged every later return), the same seeds and statistics:", "",
                  "| tracker | catalogue cross-tags /10⁴ | ratio to GNN | goal ≤ 0.5 | median ratio | seeds at goal | "
                  "ratio of means |", "|---|---|---|---|---|---|---|"]
        for r in table.itertuples(index=False):
            has = np.isfinite(r.cat_ratio)
            lines.append(f"| {TRACKER_NAMES[r.tracker]} | "
                         f"{_pm(r.catalogue_cross_tags_per_1e4, r.catalogue_cross_tags_per_1e4_se)} | "
                         + (f"{_pm(r.cat_ratio, r.cat_ratio_se)} | {'met' if r.cat_meets_goal else 'not met'} | "
                            f"{_pm(r.cat_ratio_median)} | {int(r.cat_n_at_goal)} of {int(r.cat_n_ratio)} | "
                            f"{_pm(r.cat_ratio_of_means)} |" if has else " |  |  |  |  |"))
    return "\n".join(lines) + "\n"


def update_breakup_record(results, record=RECORD, workflow_dir=ROOT / "workflows", force: bool = False,
                          readme=None) -> list[Path]:
    """``record/ssa_breakup_record.csv``, ``ssa_breakup_tuning.csv`` and ``ssa_breakup_record_config.json`` from a
    record run's ``<results>/ssa_breakup`` (module docstring). Raises ``FileNotFoundError`` when the run has not
    written its tables, ``ValueError`` when they are not the record configuration's (``force``: record anyway)."""
    source = Path(results) / EXPERIMENT
    need = ("summary.csv", "ratios.csv", "scorecard.csv", "tuning.csv")
    missing = [f for f in need if not (source / f).exists()]
    if missing:
        raise FileNotFoundError(f"results {source} lacks {', '.join(missing)}: run the ssa_breakup rules under "
                                f"full.yaml and breakup_record.yaml first")
    sec = record_config(workflow_dir)
    tuning = pd.read_csv(source / "tuning.csv")
    differ = _check(sec, pd.read_csv(source / "scorecard.csv"), tuning)
    if differ and not force:
        raise ValueError("the results are not the breakup record's run (" + "; ".join(differ) + ")")
    tun = sec["ambiguity"]["tuning"]
    cards = pd.read_csv(source / "scorecard.csv")
    ran = sorted(set(cards.loc[cards["scenario"] == "breakup", "seed"].astype(int)))  # the seeds the tables hold
    table = record_table(pd.read_csv(source / "summary.csv"), pd.read_csv(source / "ratios.csv"),
                         chosen_p_min(tuning), tun["seeds"], tun["untagged_weight"], ran)
    record = Path(record)
    record.mkdir(parents=True, exist_ok=True)
    table.to_csv(record / TABLE, index=False, float_format="%.6g")
    tuning.to_csv(record / TUNING, index=False, float_format="%.6g")
    (record / CONFIG).write_text(json.dumps(sec, indent=1, sort_keys=True) + "\n")
    (record / BLOCK).write_text(record_markdown(table, tuning))
    written = [record / TABLE, record / TUNING, record / CONFIG, record / BLOCK]
    return written + ([rewrite_readme(readme, record)] if readme is not None else [])


def _seed_words(seeds: str) -> str:
    k = seeds.split()
    return k[0] if len(k) == 1 else f"{', '.join(k[:-1])} and {k[-1]}"


def record_claims(table: pd.DataFrame, reference: str = "gnn") -> list:
    """Ledger rows (status *extension*) of the committed record: the tuned ``p_min``, then for every tracker with a
    ratio its cross-tags over the reference's (mean ± s.e. over the evaluated seeds) against the goal, an
    ambiguity output's note giving its untagged returns against its MAP output's and the reference's; then the
    same for the catalogue cross-tags, where the record has them."""
    if table.empty:
        return []
    first = table.iloc[0]
    on = f"tuning seeds {_seed_words(first['tuning_seeds'])}"
    out = [Claim(EXPERIMENT, "ambiguity output's p_min, tuned on seeds of its own (record)", "extension (a fresh "
                 "breakup cloud)", "--", f"{first['p_min']:g}", "--", "extension",
                 f"least mean X + {first['untagged_weight']:g} U over the {on} (X cross-tags, U untagged returns per "
                 f"10^4); evaluated seeds {_seed_words(first['seeds'])}", "measurement", key="record_pmin")]
    unc = table.set_index("tracker")["uncorrelated_per_1e4"]
    for r in table[np.isfinite(table["ratio"].astype(float))].itertuples(index=False):
        note = f"per-seed ratios over {int(r.n_ratio)} evaluated seeds; {'meets' if r.meets_goal else 'misses'} the goal"
        if r.tracker.endswith("_amb"):
            plain = unc.get(r.tracker.removesuffix("_amb"), np.nan)
            note += (f"; p_min {r.p_min:g} from the {on}; untagged {r.uncorrelated_per_1e4:.3g} per 10^4 returns "
                     f"against {plain:.3g} for the MAP output and {unc.get(reference, np.nan):.3g} for GNN")
        out.append(Claim(EXPERIMENT, f"cross-tags of {TRACKER_NAMES[r.tracker]} over GNN's, breakup cloud, "
                         f"{int(r.n_seeds)}-seed record", "extension (a fresh breakup cloud)", f"goal ≤ {r.goal:g}",
                         f"{r.ratio:.3g} ± {r.ratio_se:.2g}", "--", "extension", note, "measurement",
                         key=f"record_ratio_{r.tracker}"))
    if "cat_ratio" not in table:
        return out
    for r in table[np.isfinite(table["cat_ratio"].astype(float))].itertuples(index=False):
        out.append(Claim(EXPERIMENT, f"catalogue cross-tags of {TRACKER_NAMES[r.tracker]} over GNN's, breakup cloud, "
                         f"{int(r.n_seeds)}-seed record", "extension (a fresh breakup cloud)", f"goal ≤ {r.goal:g}",
                         f"{r.cat_ratio:.3g} ± {r.cat_ratio_se:.2g}", "--", "extension",
                         f"each catalogued fragment's own number owned by it; per-seed ratios over "
                         f"{int(r.cat_n_ratio)} evaluated seeds (median {r.cat_ratio_median:.3g}, ratio of means "
                         f"{r.cat_ratio_of_means:.3g}); {'meets' if r.cat_meets_goal else 'misses'} the goal",
                         "measurement", key=f"record_cat_ratio_{r.tracker}"))
    return out


def record_macros(table: pd.DataFrame) -> dict:
    """Macros of the committed record: ``record_pmin``, ``record_lambda``, ``record_tuning_seeds`` and
    ``record_seeds`` (words), ``record_n_seeds``, and per tracker ``record_{crosstags,uncorrelated,ratio,ratio_se,idsw_ratio}_<tracker>``
    and ``record_goal_<tracker>`` (``met``/``not met`` where a ratio was measured), with the per-seed ratios' spread
    ``record_{ratio_median,n_at_goal,ratio_of_means}_<tracker>``."""
    if table.empty:
        return {}
    first = table.iloc[0]
    vals = dict(record_pmin=float(first["p_min"]), record_lambda=float(first["untagged_weight"]),
                record_tuning_seeds=_seed_words(first["tuning_seeds"]), record_n_seeds=int(first["n_seeds"]),
                record_seeds=_seed_words(first["seeds"]))
    for r in table.itertuples(index=False):
        vals[f"record_crosstags_{r.tracker}"] = r.cross_tags_per_1e4
        vals[f"record_uncorrelated_{r.tracker}"] = r.uncorrelated_per_1e4
        vals[f"record_ratio_{r.tracker}"] = r.ratio
        vals[f"record_ratio_se_{r.tracker}"] = r.ratio_se
        vals[f"record_idsw_ratio_{r.tracker}"] = r.idsw_ratio
        vals[f"record_n_ratio_{r.tracker}"] = int(r.n_ratio)
        if "cat_ratio" in table:  # the catalogue cross-tags (a record written before them has none)
            vals[f"record_catxtags_{r.tracker}"] = r.catalogue_cross_tags_per_1e4
            vals[f"record_cat_ratio_{r.tracker}"] = r.cat_ratio
            vals[f"record_cat_ratio_se_{r.tracker}"] = r.cat_ratio_se
            if np.isfinite(r.cat_ratio):
                vals[f"record_cat_goal_{r.tracker}"] = "met" if r.cat_meets_goal else "not met"
                vals[f"record_cat_ratio_median_{r.tracker}"] = float(r.cat_ratio_median)
                vals[f"record_cat_n_at_goal_{r.tracker}"] = int(r.cat_n_at_goal)
                vals[f"record_cat_n_ratio_{r.tracker}"] = int(r.cat_n_ratio)
                vals[f"record_cat_ratio_of_means_{r.tracker}"] = float(r.cat_ratio_of_means)
        if np.isfinite(r.ratio):
            vals[f"record_goal_{r.tracker}"] = "met" if r.meets_goal else "not met"
            for c in ("ratio_median", "n_at_goal", "ratio_of_means"):  # the per-seed ratios' spread
                v = getattr(r, c, np.nan)
                if np.isfinite(v):
                    vals[f"record_{c}_{r.tracker}"] = int(v) if c == "n_at_goal" else float(v)
    return vals


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hypotrack.experiments.ssa_breakup.record",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("results", help="the record run's results folder")
    parser.add_argument("--force", action="store_true", help="record tables of another config")
    args = parser.parse_args(argv)
    return run_step(lambda: update_breakup_record(args.results, force=args.force, readme=ROOT / "README.md"))


if __name__ == "__main__":
    raise SystemExit(main())

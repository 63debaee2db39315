"""The ambiguity output's ``p_min`` chosen on tuning seeds by a stated rule, then used on the evaluated seeds.

The protocol (``ssa_breakup.ambiguity.tuning``), declared before any evaluated seed is looked at:

* **tuning seeds** — ``tuning.seeds``, disjoint from the section's ``seeds`` (the evaluated ones;
  :func:`tuning_section` refuses an overlap). The factored trackers and the reference (``tuning.trackers``) run on
  them with every other setting of the section (:func:`tuning_section`: the breakup scenario only — the control has
  no ambiguity to tune);
* **the rule** — for each ``p_min`` of ``ambiguity.p_min_sweep``, the operator's cost of the output (the
  withholding or fresh mode of ``ambiguity.mode``) on every tuning seed and factored tracker,

  .. math::  C(p) = X(p) + \\lambda\\, U(p),

  with ``X`` the cross-tags and ``U`` the untagged (uncorrelated) returns, both per 10⁴ object returns, and
  ``λ = tuning.untagged_weight``. The cost is averaged over the tuning seeds and the factored trackers, and the
  chosen ``p_min`` is the one of least mean cost (ties: the smallest ``p_min``, the one withholding least).
  :func:`tuning_table` writes every (tracker, seed, ``p_min``) score and the means; :func:`chosen_p_min` reads the
  choice off it;
* **the evaluated verdict** — the evaluated seeds' ambiguity output is scored at every ``p_min`` of the sweep from
  the same runs (:func:`output_p_mins`), and the table job keeps the rows at the chosen one
  (:func:`select_output`): the choice cannot see the evaluated seeds, and no tracker runs again.

Without a ``tuning`` block ``ambiguity.p_min`` is used as given (the default config, which cannot afford the
tuning runs: :func:`used_p_min`).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...metrics_scorecard import mean_se

__all__ = ["TUNING_COLUMNS", "tuning_section", "output_p_mins", "tuning_table", "chosen_p_min", "used_p_min",
           "select_output", "evaluated_cards"]

TUNING_COLUMNS = ["tracker", "seed", "mode", "p_min", "cross_tags_per_1e4", "uncorrelated_per_1e4",
                  "untagged_weight", "score", "xtag_ratio", "chosen"]


def _tuning(cfg) -> dict | None:
    amb = cfg.get("ambiguity") or {}
    tun = amb.get("tuning")
    return tun if tun and tun.get("seeds") else None


def tuning_section(cfg) -> dict:
    """The section the tuning runs read: ``cfg`` with ``seeds`` the tuning seeds and the breakup scenario alone.
    Raises ``ValueError`` when the section has no ``ambiguity.tuning.seeds`` or when a tuning seed is also
    evaluated (``seeds``)."""
    tun = _tuning(cfg)
    if tun is None:
        raise ValueError("ssa_breakup.ambiguity.tuning.seeds must name at least one tuning seed")
    seeds = [int(s) for s in tun["seeds"]]
    shared = sorted(set(seeds) & {int(s) for s in cfg["seeds"]})
    if shared:
        raise ValueError(f"ssa_breakup.ambiguity.tuning.seeds must be disjoint from ssa_breakup.seeds (the "
                         f"evaluated seeds); both hold {shared}")
    return {**cfg, "seeds": seeds, "scenarios": ["breakup"]}


def output_p_mins(amb) -> list[float]:
    """The ``p_min`` values at which a run's ambiguity output is scored in full (one card row each): with a
    ``tuning`` block every value of ``p_min_sweep`` (the choice is made later, on other seeds), else ``p_min``."""
    if amb.get("tuning") and amb["tuning"].get("seeds"):
        values = [float(p) for p in amb.get("p_min_sweep", [])]
        if not values:
            raise ValueError("ssa_breakup.ambiguity.p_min_sweep must hold the candidate p_min values when "
                             "ambiguity.tuning is set")
        return sorted(set(values))
    return [float(amb["p_min"])]


def tuning_table(sweep: pd.DataFrame, cards: pd.DataFrame, mode: str, untagged_weight: float,
                 reference: str = "gnn") -> pd.DataFrame:
    """The rule's scores (module docstring) from the tuning runs' sweep rows (:data:`.jobs.SWEEP_COLUMNS`) and
    cards (for the reference's cross-tags, reported as ``xtag_ratio``, not used by the rule).

    One row per (factored tracker, tuning seed, ``p_min``) of ``mode`` with ``score = X + λ U``, then per ``p_min``
    one row per tracker (``seed = -1``: mean over the seeds) and one over every tracker (``tracker = "all"``,
    ``seed = -1``), whose least score is the choice (``chosen`` True on the ``p_min``'s rows)."""
    lam = float(untagged_weight)
    if not np.isfinite(lam) or lam < 0:
        raise ValueError(f"ssa_breakup.ambiguity.tuning.untagged_weight must be finite and >= 0, got {untagged_weight}")
    rows = sweep[(sweep["scenario"] == "breakup") & (sweep["mode"] == mode)]
    if rows.empty:
        raise ValueError(f"no tuning sweep rows for mode {mode!r} in the breakup scenario")
    ref = cards[(cards["scenario"] == "breakup") & (cards["tracker"] == reference)].set_index("seed")
    ref = ref["cross_tags_per_1e4"]
    per = rows[["tracker", "seed", "mode", "p_min", "cross_tags_per_1e4", "uncorrelated_per_1e4"]].copy()
    per["seed"] = per["seed"].astype(np.int64)
    per["untagged_weight"] = lam
    per["score"] = per["cross_tags_per_1e4"] + lam * per["uncorrelated_per_1e4"]
    r = per["seed"].map(ref)
    per["xtag_ratio"] = np.where(r > 0, per["cross_tags_per_1e4"] / r, np.nan)
    per = per.sort_values(["tracker", "seed", "p_min"], kind="stable")
    means = []
    for (name, p), g in [*per.groupby(["tracker", "p_min"], sort=True),
                         *((("all", p), g) for p, g in per.groupby("p_min", sort=True))]:
        means.append(dict(tracker=name, seed=-1, mode=mode, p_min=float(p), untagged_weight=lam,
                          cross_tags_per_1e4=mean_se(g["cross_tags_per_1e4"])[0],
                          uncorrelated_per_1e4=mean_se(g["uncorrelated_per_1e4"])[0],
                          score=mean_se(g["score"])[0], xtag_ratio=float(np.nanmean(g["xtag_ratio"]))
                          if g["xtag_ratio"].notna().any() else float("nan")))
    out = pd.concat([per, pd.DataFrame(means)], ignore_index=True)
    overall = out[(out["tracker"] == "all") & (out["seed"] == -1)].sort_values("p_min", kind="stable")
    best = float(overall["p_min"].iloc[int(np.argmin(overall["score"].to_numpy()))])  # first minimum: smallest p_min
    out["chosen"] = np.isclose(out["p_min"].to_numpy(float), best, rtol=0, atol=1e-12)
    return out[TUNING_COLUMNS].reset_index(drop=True)


def chosen_p_min(table: pd.DataFrame) -> float:
    """The ``p_min`` :func:`tuning_table` chose (the one its rows mark ``chosen``)."""
    p = np.unique(table.loc[table["chosen"].astype(bool), "p_min"].to_numpy(float))
    if len(p) != 1:
        raise ValueError(f"a tuning table marks exactly one p_min as chosen, this one {p.tolist()}")
    return float(p[0])


def used_p_min(cfg, table: pd.DataFrame | None = None) -> float:
    """The ``p_min`` of the evaluated verdict: :func:`chosen_p_min` of the tuning ``table`` when the section tunes
    (``ambiguity.tuning``), else ``ambiguity.p_min``."""
    if _tuning(cfg) is None:
        return float(cfg["ambiguity"]["p_min"])
    if table is None:
        raise ValueError("ssa_breakup.ambiguity.tuning is set: the evaluated p_min comes from its tuning table")
    return chosen_p_min(table)


def select_output(cards: pd.DataFrame, p_min: float) -> pd.DataFrame:
    """The cards with the ambiguity outputs' rows at ``p_min`` alone and without the ``p_min`` column (the plain
    outputs' rows, ``p_min`` NaN, all kept). Raises ``ValueError`` when an ambiguity output has no row there."""
    if "p_min" not in cards:
        return cards
    p = cards["p_min"].to_numpy(float)
    amb = np.isfinite(p)
    keep = ~amb | np.isclose(p, float(p_min), rtol=0, atol=1e-12)
    missing = set(cards.loc[amb, "tracker"]) - set(cards.loc[amb & keep, "tracker"])
    if missing:
        raise ValueError(f"p_min {p_min} is not among the scored ambiguity outputs of {sorted(missing)}")
    return cards[keep].drop(columns="p_min").reset_index(drop=True)


def evaluated_cards(cards: pd.DataFrame, cfg, table: pd.DataFrame | None = None) -> tuple[pd.DataFrame, float | None]:
    """``(cards, p_min)``: the evaluated seeds' cards with the ambiguity outputs at the ``p_min`` of the verdict
    (:func:`used_p_min`: the tuning ``table``'s choice, or ``ambiguity.p_min`` without tuning;
    :func:`select_output`), and that ``p_min`` (None, cards unchanged, without an ``ambiguity`` block)."""
    if not cfg.get("ambiguity"):
        return cards, None
    p = used_p_min(cfg, table)
    return select_output(cards, p), p

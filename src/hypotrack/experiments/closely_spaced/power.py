"""Does the Table 6.1 MHT check have power? Every broken MHT of :mod:`.controls` through the row's check.

The MHT row of Table 6.1 (document 003) checks the MHT's MOSPA against the published 0.1376 with
the ledger's Monte Carlo rule (:func:`hypotrack.reporting.verdict.monte_carlo_verdict`). A check
has power when a tracker built to break what the row is about, the association hypothesis the MHT
keeps, *fails* it. This module puts each broken MHT through that same check and also measures,
paired on the same runs, how far each one moves the MOSPA from the MHT's:

* :func:`control_verdict` — the row's check applied to a control. The published number's own Monte
  Carlo error (``published_runs`` runs) is the spread of the *published method* over √published_runs,
  so it is estimated from the method's runs (not the control's): a noisier control does not make the
  published number less certain.
* :func:`paired_differences` — per control, the mean and standard error of the per-run difference
  control − method (same scenario realisations, so the scenario's variance cancels).
* :func:`mht_power_table` — one row per broken MHT and window (every scan, after the transient):
  value ± s.e., its distance from the published value, the paired difference from the MHT, and the
  verdict of the row's check (a control *fails* only when that verdict is "not reproduced").
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..._validation import check_int, check_nonnegative
from ...reporting.verdict import Verdict, monte_carlo_verdict
from .controls import CONTROLS, MHT_CONTROLS, misstated_noise_name
from .published import TABLE_6_1

__all__ = ["WINDOWS", "control_verdict", "paired_differences", "mht_power_table", "mht_power_macros"]

#: Window name -> per-run column of the shard tables.
WINDOWS = {"every scan": "mospa", "after the transient": "mospa_steady"}


def control_verdict(control: dict, method: dict, published: float, tolerance: float,
                    published_runs: int | None) -> Verdict:
    """The Monte Carlo verdict of a control under its method's row check.

    ``control`` and ``method`` hold ``n``, ``mean`` and ``se``. The interval is ``mean_c ± q·s`` with
    ``s = √(se_c² + sd_m²/published_runs)``, ``sd_m = se_m·√n_m`` the method's spread (the published
    number is the method's average over ``published_runs`` runs) and q the t quantile of
    ``n_c − 1`` d.o.f. at 99.73 %; without ``published_runs`` it is the plain rule on the control.
    """
    tolerance = check_nonnegative(tolerance, "tolerance")
    se = float(control["se"])
    if published_runs is not None:
        published_runs = check_int(published_runs, "published_runs", minimum=1)
        sd_method = float(method["se"]) * math.sqrt(int(method["n"]))
        se = math.hypot(se, sd_method / math.sqrt(published_runs))
    return monte_carlo_verdict(float(control["mean"]), se, float(published), tolerance, int(control["n"]))


def paired_differences(per_run: pd.DataFrame, method: str, controls, column: str) -> pd.DataFrame:
    """Per control: ``n``, mean and s.e. of ``control − method`` over the runs both have (paired by run).

    ``per_run`` has columns ``method, run, <column>`` (the shard tables of :func:`.run.shard_tables`).
    """
    wide = per_run.pivot_table(index="run", columns="method", values=column, aggfunc="first")
    if method not in wide:
        raise ValueError(f"method must be one of the per-run methods {sorted(wide.columns)}, got {method!r}")
    rows = []
    for c in controls:
        if c not in wide:
            raise ValueError(f"controls must be per-run methods {sorted(wide.columns)}, got {c!r}")
        d = (wide[c] - wide[method]).dropna().to_numpy()
        if d.size < 2:
            raise ValueError(f"{c!r} and {method!r} share {d.size} runs; the paired difference needs at least 2")
        rows.append({"control": c, "n": d.size, "diff": d.mean(), "diff_se": d.std(ddof=1) / math.sqrt(d.size)})
    return pd.DataFrame(rows)


def _what(name: str) -> str:
    if name in CONTROLS:
        return CONTROLS[name][1]
    factor = name.removeprefix("MHT[R × ").removesuffix("]")
    return f"the MHT assuming the measurement variance R × {factor} (a model defect, not an association one)"


def mht_power_table(per_run: pd.DataFrame, cfg, *, chosen: str = "MHT[random hypothesis]") -> pd.DataFrame:
    """Every broken MHT through the MHT row's check, over every scan and after the transient.

    Columns: ``window, control, what, hypothesis_broken`` (whether the control breaks the association
    hypothesis rather than the filter's model), ``n, mean, se, relative_to_published``,
    ``paired_diff, paired_diff_se, paired_z`` (control − MHT on the same runs), ``verdict`` (the row's
    check, :func:`control_verdict`), ``control_fails`` and ``chosen`` (the control wired into the
    ledger rows). The first rows of each window are the MHT itself (its own verdict).
    """
    tol = float(cfg["reconstruction_rel_tol"]) * TABLE_6_1["MHT"]
    runs = int(cfg["published_runs"])
    names = [*MHT_CONTROLS, *(misstated_noise_name(f) for f in cfg["mht_noise_factors"])]
    if chosen not in names:
        raise ValueError(f"chosen must be one of {names}, got {chosen!r}")
    rows = []
    for window, column in WINDOWS.items():
        g = per_run.groupby("method")[column]
        stats = pd.DataFrame({"n": g.count(), "mean": g.mean(), "se": g.std(ddof=1) / np.sqrt(g.count())})
        mht = stats.loc["MHT"]
        own = monte_carlo_verdict(float(mht["mean"]), float(mht["se"]), TABLE_6_1["MHT"], tol, int(mht["n"]), runs)
        rows.append({"window": window, "control": "MHT", "what": "the MHT (the row itself)",
                     "hypothesis_broken": False, "n": int(mht["n"]), "mean": mht["mean"], "se": mht["se"],
                     "paired_diff": 0.0, "paired_diff_se": 0.0, "paired_z": np.nan, "verdict": own.status,
                     "control_fails": np.nan, "chosen": False})
        paired = paired_differences(per_run, "MHT", names, column).set_index("control")
        for name in names:
            c = stats.loc[name]
            v = control_verdict(c, mht, TABLE_6_1["MHT"], tol, runs)
            p = paired.loc[name]
            rows.append({"window": window, "control": name, "what": _what(name),
                         "hypothesis_broken": name in MHT_CONTROLS, "n": int(c["n"]), "mean": c["mean"],
                         "se": c["se"], "paired_diff": p["diff"], "paired_diff_se": p["diff_se"],
                         "paired_z": p["diff"] / p["diff_se"] if p["diff_se"] > 0 else np.nan,
                         "verdict": v.status, "control_fails": v.status == "not reproduced",
                         "chosen": name == chosen})
    table = pd.DataFrame(rows)
    table.insert(table.columns.get_loc("se") + 1, "relative_to_published", table["mean"] / TABLE_6_1["MHT"] - 1)
    return table


def _signed(percent: float) -> str:
    """A rounded signed percentage without a negative zero: "+3", "−2", "+0"."""
    v = round(percent)
    return f"{'+' if v >= 0 else '−'}{abs(v):d}"


def _key(name: str) -> str:
    return {"MHT[swapped labels]": "Swapped", "MHT[random hypothesis]": "Random",
            "MHT[no joint hypothesis]": "NoJoint"}[name]


def mht_power_macros(table: pd.DataFrame) -> dict:
    """Numbers the paper quotes from :func:`mht_power_table` (stable names, no config value in them).

    Per window (``Every``/``Steady``) the MHT's own ``PowerMht<Window>Rel``; per hypothesis-breaking control
    and window: ``Power<Control><Window>Mean``,
    ``…Rel`` (percent from the published value), ``…Diff`` and ``…DiffZ`` (paired, against the MHT) and
    ``…Verdict``; the misstated-noise controls as the range ``PowerNoiseRelMin/Max`` (percent, every scan)
    and ``PowerNoiseFails`` (how many fail, both windows); ``PowerHypothesisFails`` counts the
    hypothesis-breaking controls that fail the check, of ``PowerHypothesisControls``.
    """
    out = {}
    for window, tag in (("every scan", "Every"), ("after the transient", "Steady")):
        w = table[table["window"] == window]
        out[f"PowerMht{tag}Rel"] = _signed(100 * w[w["control"] == "MHT"]["relative_to_published"].iloc[0])
        for r in w[w["hypothesis_broken"]].itertuples():
            k = f"Power{_key(r.control)}{tag}"
            out[f"{k}Mean"] = f"{r.mean:.4g}"
            out[f"{k}Rel"] = _signed(100 * r.relative_to_published)
            out[f"{k}Diff"] = f"{r.paired_diff:+.3g}"
            out[f"{k}DiffZ"] = f"{r.paired_z:.3g}"
            out[f"{k}Verdict"] = r.verdict
    noise = table[(table["control"] != "MHT") & ~table["hypothesis_broken"].astype(bool)]
    every = noise[noise["window"] == "every scan"]
    if len(every):
        out["PowerNoiseRelMin"] = _signed(100 * every["relative_to_published"].min())
        out["PowerNoiseRelMax"] = _signed(100 * every["relative_to_published"].max())
    out["PowerNoiseFails"] = str(int(noise["control_fails"].astype(bool).sum()))
    out["PowerNoiseCells"] = str(len(noise))
    hyp = table[table["hypothesis_broken"].astype(bool)]
    out["PowerHypothesisFails"] = str(int(hyp["control_fails"].astype(bool).sum()))
    out["PowerHypothesisCells"] = str(len(hyp))
    return out

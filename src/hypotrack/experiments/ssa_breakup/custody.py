"""Where a scored run's labels change objects: the custody measures of the ``ssa_breakup`` scorecard.

A cross-tag (:func:`hypotrack.metrics_scorecard.return_tallies`) is charged over the whole run, so it says how
many returns a label change cost, not where it happened. These measures locate the changes, from the same
tables (:class:`.run.ScoredRun`: the returns with the label each correlates to, the per-scan assignment):

* :func:`first_return_own` — **acquisition**: the share of catalogued objects whose first correlated return
  of the run goes to their own catalogued label (the known objects start with their id as label,
  :func:`.run.run_scored`). A catalogued object whose first return goes to another object's label has been
  swapped by the first update that could see it;
* :func:`reacquired_same_label` — **re-acquisition**: per (object, pass ≥ 1) with assigned scans in both that
  pass and the one before (:func:`.run.pass_ends`), whether the label the object holds most often in that pass
  is the label it held last in the pass before; the share of such passes that kept it.

Both are shares in [0, 1], NaN when nothing qualifies.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["first_return_own", "reacquired_same_label"]


def first_return_own(returns: pd.DataFrame, catalogued) -> float:
    """Share of the catalogued objects with a correlated return whose first one (lowest scan, then table
    order) is correlated to their own label (``returns``: ``scan``, ``origin``, ``label``; module docstring)."""
    cat = np.asarray(catalogued, dtype=np.int64).reshape(-1)
    r = returns[(returns["label"] >= 0) & returns["origin"].isin(cat)]
    if len(r) == 0:
        return float("nan")
    first = r.sort_values("scan", kind="stable").groupby("origin", sort=True)["label"].first()
    return float(np.mean(first.to_numpy() == first.index.to_numpy()))


def reacquired_same_label(assign: pd.DataFrame, passes: pd.DataFrame) -> float:
    """Share of re-acquisitions that kept the label (module docstring). ``assign``: ``scan``, ``target``,
    ``label`` (−1 none); ``passes``: :func:`.run.pass_ends` rows (``target``, ``pass_no``, ``first_scan``,
    ``last_scan``). A tie for the most frequent label goes to the smallest label."""
    a = assign[assign["label"] >= 0]
    by_target = {t: g.sort_values("scan", kind="stable") for t, g in a.groupby("target", sort=False)}
    kept = []
    for t, ps in passes.sort_values(["target", "pass_no"]).groupby("target", sort=True):
        g = by_target.get(t)
        if g is None:
            continue
        s, lab = g["scan"].to_numpy(), g["label"].to_numpy()
        rows = list(ps.itertuples(index=False))
        for prev, cur in zip(rows[:-1], rows[1:]):
            before = lab[(s >= prev.first_scan) & (s <= prev.last_scan)]
            now = lab[(s >= cur.first_scan) & (s <= cur.last_scan)]
            if len(before) and len(now):
                values, counts = np.unique(now, return_counts=True)
                kept.append(values[np.argmax(counts)] == before[-1])
    return float(np.mean(kept)) if kept else float("nan")

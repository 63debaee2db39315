"""SSA experiments, step 3: MAP estimates against the truth, and two trackers against each other.

:func:`evaluate_map` scores the MAP estimates (OSPA in view and over the catalogue, and the
paper's "green circle / red star" verdict of every estimate, document 000 Fig. 7);
:func:`birth_recognition` times when each birth is tracked; :func:`map_agreement` compares two
trackers' MAP hypotheses scan by scan.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment
from scipy.stats import chi2

from ..._validation import check_positive, check_probability
from ...metrics import ospa
from ...scenarios.ssa import SSAScenario
from .run import POS_COV
from .scenario import catalogue_mask, truth_arrays

__all__ = [
    "AGREEMENT_TOLERANCE_KM",
    "OSPASettings",
    "birth_recognition",
    "evaluate_configured",
    "evaluate_map",
    "map_agreement",
]

# Two filters that made the same association decisions at every scan run the same EKF on the
# same returns: their estimates agree to rounding — and to the 1e-5 km resolution of positions of
# up to 3e4 km written with 10 significant digits. One different decision moves an estimate by
# a sizeable fraction of a measurement's error (σ = 1 km), so 1 m separates the two cases.
AGREEMENT_TOLERANCE_KM = 1e-3


@dataclass(frozen=True)
class OSPASettings:
    """OSPA parameters (Schuhmacher, Vo & Vo 2008) of the SSA experiments.

    ``c_in_view`` (km) scores the objects in the field of view, where estimates are about as
    good as a measurement; ``c_catalogue`` (km) scores every object the filter should know,
    whose along-track errors grow while out of view. ``p`` is the order.
    """

    p: float = 2.0
    c_in_view: float = 10.0
    c_catalogue: float = 100.0

    def __post_init__(self):
        for name in ("p", "c_in_view", "c_catalogue"):
            check_positive(getattr(self, name), name)
        if self.p < 1:
            raise ValueError(f"p must be >= 1, got {self.p}")


def _mahalanobis2(diff, cov_entries):
    """d² of (n, 2) differences under (n, 3) packed symmetric 2×2 covariances."""
    a, b, c = cov_entries[:, 0], cov_entries[:, 1], cov_entries[:, 2]
    det = a * c - b * b
    x, y = diff[:, 0], diff[:, 1]
    return (c * x * x - 2 * b * x * y + a * y * y) / det


def _match_scan(labels, pos, cov, X, catalogue, known, gate):
    """Truth id matched to each estimate (−1: none) and its d² (see the module docstring)."""
    n = len(labels)
    truth_of = np.full(n, -1, dtype=np.int64)
    d2 = np.full(n, np.inf)
    is_known = np.isin(labels, known)
    if is_known.any():
        ids = labels[is_known]
        truth_of[is_known] = ids
        d2[is_known] = _mahalanobis2(X[ids, :2] - pos[is_known], cov[is_known])
    born = np.flatnonzero(~is_known)
    cand = np.setdiff1d(np.flatnonzero(catalogue), known)
    if len(born) and len(cand):
        cost = np.stack([_mahalanobis2(X[cand, :2] - pos[i], np.repeat(cov[i][None], len(cand), 0))
                         for i in born])
        rows, cols = linear_sum_assignment(np.minimum(cost, 1e12))
        ok = cost[rows, cols] <= gate
        truth_of[born[rows[ok]]] = cand[cols[ok]]
        d2[born[rows[ok]]] = cost[rows[ok], cols[ok]]
    return truth_of, d2


def evaluate_map(map_estimates: pd.DataFrame, scenario: SSAScenario, *, ospa_settings=OSPASettings(),
                 error_bound_probability: float = 0.9999):
    """Compare a run's MAP estimates with the truth, scan by scan.

    Parameters
    ----------
    map_estimates : DataFrame
        :attr:`TrackingRun.map_estimates`.
    scenario : SSAScenario
    ospa_settings : OSPASettings
    error_bound_probability : float
        An estimate is correct when the true position lies inside this probability's
        position ellipse of the estimate (the paper's "error bound", Fig. 7).

    Returns
    -------
    metrics : DataFrame
        Per scan: ``scan, n_in_view, n_catalogue, n_map_in_view, ospa_in_view,
        ospa_catalogue, n_correct, n_incorrect, n_false, n_missed``. In-view OSPA compares the
        estimates whose position is in the FOV with the objects in view; catalogue OSPA all
        estimates with every catalogue object; ``ospa_in_view`` is NaN at scans where neither
        the truth nor the estimates have an object in view.
    matched : DataFrame
        One row per estimate (``role = "estimate"``: ``label``, matched ``truth_id`` or −1,
        ``d2``, ``status`` correct / incorrect / false) and per true object (``role =
        "truth"``: ``status`` tracked / missed, or unseen for a birth not yet in view), with
        positions ``x, y`` (km) and the ``scan``.
    """
    p = check_probability(error_bound_probability, "error_bound_probability", low_open=True, high_open=True)
    gate = float(chi2.ppf(p, 2))
    X_all, in_view = truth_arrays(scenario)
    cat = catalogue_mask(scenario)
    K, N = in_view.shape
    known = np.asarray(scenario.prior_ids, dtype=np.int64)
    fov = scenario.fov
    groups = {k: g for k, g in map_estimates.groupby("scan", sort=True)}
    metric_rows, parts = [], []
    empty = map_estimates.iloc[:0]
    for k in range(K):
        g = groups.get(k, empty)
        labels = g["label"].to_numpy(dtype=np.int64)
        pos = g[["state_0", "state_1"]].to_numpy(dtype=float).reshape(-1, 2)
        cov = g[POS_COV].to_numpy(dtype=float).reshape(-1, 3)
        X = X_all[k]
        truth_of, d2 = _match_scan(labels, pos, cov, X, cat[k], known, gate)
        correct = (truth_of >= 0) & (d2 <= gate)
        status = np.where(correct, "correct", np.where(truth_of >= 0, "incorrect", "false"))
        tracked = np.zeros(N, dtype=bool)
        tracked[truth_of[correct]] = True
        t_status = np.where(tracked, "tracked", np.where(cat[k], "missed", "unseen"))
        est_in_view = fov.contains(pos) if len(pos) else np.zeros(0, dtype=bool)
        metric_rows.append({
            "scan": k, "n_in_view": int(in_view[k].sum()), "n_catalogue": int(cat[k].sum()),
            "n_map_in_view": int(est_in_view.sum()),
            # Nothing in view on either side is no evidence, not a perfect score.
            "ospa_in_view": (
                ospa(pos[est_in_view], X[in_view[k], :2], ospa_settings.c_in_view, ospa_settings.p)
                if est_in_view.any() or in_view[k].any() else np.nan
            ),
            "ospa_catalogue": ospa(pos, X[cat[k], :2], ospa_settings.c_catalogue, ospa_settings.p),
            "n_correct": int(correct.sum()), "n_incorrect": int(np.sum(status == "incorrect")),
            "n_false": int(np.sum(status == "false")), "n_missed": int(np.sum(t_status == "missed")),
        })
        parts.append(pd.DataFrame({"scan": k, "role": "estimate", "id": labels, "truth_id": truth_of,
                                   "x": pos[:, 0], "y": pos[:, 1], "d2": d2, "in_view": est_in_view,
                                   "status": status}))
        parts.append(pd.DataFrame({"scan": k, "role": "truth", "id": np.arange(N), "truth_id": np.arange(N),
                                   "x": X[:, 0], "y": X[:, 1], "d2": np.nan, "in_view": in_view[k],
                                   "status": t_status}))
    matched = pd.concat(parts, ignore_index=True)
    matched["d2"] = matched["d2"].replace(np.inf, np.nan)
    return pd.DataFrame(metric_rows), matched


def evaluate_configured(section: Mapping, scenario: SSAScenario, summary: pd.DataFrame,
                        map_estimates: pd.DataFrame):
    """:func:`evaluate_map` with an experiment config section's ``ospa`` and
    ``error_bound_probability``; the metrics are merged with the run's ``summary``."""
    truth_metrics, matched = evaluate_map(
        map_estimates, scenario, ospa_settings=OSPASettings(**section["ospa"]),
        error_bound_probability=section["error_bound_probability"],
    )
    return summary.merge(truth_metrics, on="scan", validate="one_to_one"), matched


def birth_recognition(matched: pd.DataFrame, scenario: SSAScenario) -> pd.DataFrame:
    """When the MAP hypothesis first holds a correct track of each birth.

    Returns ``birth_id, first_in_view_scan, first_tracked_scan`` (−1: never),
    ``delay_scans`` and ``tracked_at_end``.
    """
    truth = matched[(matched["role"] == "truth") & (matched["status"] == "tracked")]
    last = int(matched["scan"].max()) if len(matched) else 0
    rows = []
    for b in scenario.birth_ids:
        scans_tracked = truth.loc[truth["id"] == b, "scan"].to_numpy()
        first_seen = int(scenario.first_in_view_scan[b])
        first = int(scans_tracked.min()) if len(scans_tracked) else -1
        rows.append({"birth_id": int(b), "first_in_view_scan": first_seen, "first_tracked_scan": first,
                     "delay_scans": first - first_seen if first >= 0 and first_seen >= 0 else -1,
                     "tracked_at_end": bool(len(scans_tracked) and scans_tracked.max() == last)})
    return pd.DataFrame(rows, columns=["birth_id", "first_in_view_scan", "first_tracked_scan", "delay_scans",
                                       "tracked_at_end"])


def map_agreement(map_a: pd.DataFrame, map_b: pd.DataFrame, known_labels, *, c: float = 10.0, p: float = 2.0,
                  tolerance: float = AGREEMENT_TOLERANCE_KM) -> pd.DataFrame:
    """Per scan, whether two trackers' MAP hypotheses are the same hypothesis.

    Two MAP hypotheses agree when they hold the same objects and every object's estimated
    position differs by at most ``tolerance`` km: both trackers run the same EKF on the same
    returns, so equal estimates mean equal association histories. Objects of the initial
    hypothesis are paired by label (``known_labels``); tracks born in the filters carry labels
    that depend on each filter's bookkeeping, so they are paired by an optimal assignment on
    their positions.

    Returns ``scan, n_objects_a, n_objects_b, same_objects, max_difference_km, agree,
    ospa_between`` (OSPA with cut-off ``c`` and order ``p`` between the two sets of positions).
    """
    check_positive(tolerance, "tolerance")
    known = np.asarray(known_labels, dtype=np.int64)
    ga = {k: g for k, g in map_a.groupby("scan", sort=True)}
    gb = {k: g for k, g in map_b.groupby("scan", sort=True)}
    if set(ga) != set(gb):
        raise ValueError("the two MAP tables must cover the same scans")
    rows = []
    for k in sorted(ga):
        a, b = ga[k], gb[k]
        pa = a[["state_0", "state_1"]].to_numpy(dtype=float)
        pb = b[["state_0", "state_1"]].to_numpy(dtype=float)
        ka, kb = np.isin(a["label"].to_numpy(), known), np.isin(b["label"].to_numpy(), known)
        la, lb = a["label"].to_numpy()[ka], b["label"].to_numpy()[kb]
        same = np.array_equal(np.sort(la), np.sort(lb)) and (~ka).sum() == (~kb).sum()
        diff = np.nan
        if same:
            d_known = pa[ka][np.argsort(la)] - pb[kb][np.argsort(lb)]
            diff = float(np.max(np.abs(d_known), initial=0.0))
            if (~ka).any():
                dist = np.max(np.abs(pa[~ka][:, None, :] - pb[~kb][None, :, :]), axis=2)
                r, cidx = linear_sum_assignment(dist)
                diff = max(diff, float(dist[r, cidx].max()))
        rows.append({"scan": k, "n_objects_a": len(a), "n_objects_b": len(b), "same_objects": bool(same),
                     "max_difference_km": diff, "agree": bool(same and diff <= tolerance),
                     "ospa_between": ospa(pa, pb, c, p)})
    return pd.DataFrame(rows)

"""The operator's scorecard of a space-surveillance tracker: the pieces, each on plain arrays.

A catalogue operator asks of a tracker (Vallado & Griesbach-style catalogue-maintenance measures):

* **return correlation** — each return from a real object is *correlated* to the track nearest to it after
  the scan (:func:`correlate_returns`: the track whose posterior position lies within ``gate_km`` of the
  return, nearest first; none: *uncorrelated*). Each track label is *owned* by the true object it was
  assigned to most often over the run (:func:`label_owners`, the track-purity convention); a return
  correlated to a track owned by another object is a **cross-tag** (:func:`return_tallies`). Clutter
  returns are left out of these counts. Rates are per 10⁴ object returns (:func:`per`).
* **purity** — per scan, the estimates in view optimally assigned to the truths in view with cut-off
  ``c`` (as GOSPA); an unassigned estimate within ``c`` of some truth is a **duplicate** (a second track on
  an object already held), any other unassigned one is **false** (:func:`purity_counts`). Per 1,000
  estimates.
* **accuracy at re-acquisition** — the error of a track predicted across an object's gap out of view, in
  the radial / in-track / cross-track frame of the true state (:func:`ric_error`: R along ``r``, C along
  ``r × v``, I = C × R), and the **covariance realism** — the share of squared Mahalanobis distances
  ``e^T P^-1 e`` (3-D position) inside the 95 % bound ``χ²₃(0.95) = 7.815`` (:func:`mahalanobis2`,
  :func:`chi2_share`; a realistic covariance puts 95 % inside).
* **completeness** — the share of catalogued objects whose predicted position at their next pass is within
  5 km of the truth (the caller predicts; :func:`within`).
* **time to orbit** — per object, the seconds from its first detection (its first return) to the end of
  the first pass, ending at or after that detection, whose track predicted to the object's next pass is
  within 5 km of the truth there (:func:`time_to_orbit`): how long an object born from the data waits for
  an orbit good enough to find it again.
* **GOSPA per object in view** — the sums over scans of GOSPA's localisation, missed and false parts
  (p = 1) divided by the number of (scan, object in view) pairs (:func:`gospa_parts_per_object`).

Counts are exact integers; averages over runs come with the standard error ``s / sqrt(n)`` (:func:`mean_se`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.stats import chi2

from ._validation import check_positive, check_probability

__all__ = ["correlate_returns", "label_owners", "catalogue_owners", "return_tallies", "id_switches", "cross_tag_causes",
           "CROSS_TAG_CAUSES", "purity_counts", "ric_frame", "ric_error",
           "mahalanobis2", "chi2_share", "within", "per", "mean_se", "gospa_parts_per_object", "time_to_orbit",
           "CHI2_95_3D"]

CHI2_95_3D = float(chi2.ppf(0.95, 3))
"""The 95 % bound of a 3-D squared Mahalanobis distance (7.8147)."""


def _pos(a, name):
    a = np.asarray(a, dtype=float).reshape(-1, 3)  # an empty input, of any shape, becomes (0, 3)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite positions (n, 3)")
    return a


def _ids(a, name):
    """Object ids or track labels as a flat int64 array: integers, or numbers of whole value (``3.0``, an
    object column of ints, an empty column of any dtype). A fractional or non-finite id is refused: the
    int64 cast would truncate 2.5 to another object's id 2."""
    a = np.asarray(a).reshape(-1)
    try:
        f = a.astype(float)  # integers pass the test below as they are
    except (TypeError, ValueError):
        f = None
    if a.dtype.kind == "b" or f is None or not np.all(np.isfinite(f) & (f == np.round(f))):
        raise ValueError(f"{name} must be integer ids, got {a.tolist()!r}")
    return a.astype(np.int64)  # from a itself: an object array's Python ints beyond 2^53 stay exact


def correlate_returns(returns, est_labels, est_pos, gate_km: float) -> np.ndarray:
    """The label of the estimate nearest to each return within ``gate_km`` (Euclidean), −1 when none.

    ``returns`` (m, 3), ``est_labels`` (n,), ``est_pos`` (n, 3). Several returns may correlate to one track.
    """
    g = check_positive(gate_km, "gate_km")
    Z, E = _pos(returns, "returns"), _pos(est_pos, "est_pos")
    lab = _ids(est_labels, "est_labels")
    if len(lab) != len(E):
        raise ValueError(f"est_labels must have one label per estimate ({len(E)}), got {len(lab)}")
    out = np.full(len(Z), -1, np.int64)
    if len(Z) == 0 or len(E) == 0:
        return out
    D = np.linalg.norm(Z[:, None] - E[None], axis=-1)
    j = np.argmin(D, axis=1)
    ok = D[np.arange(len(Z)), j] <= g
    out[ok] = lab[j[ok]]
    return out


def label_owners(targets, labels) -> dict:
    """``{label: target}``: the target each label was assigned to most often (ties: the smallest target id),
    from parallel arrays of (target, label) assignments; labels < 0 (unassigned) are ignored."""
    t, lab = _ids(targets, "targets"), _ids(labels, "labels")
    if len(t) != len(lab):
        raise ValueError(f"targets and labels must have the same length, got {len(t)} and {len(lab)}")
    keep = lab >= 0
    t, lab = t[keep], lab[keep]
    owners = {}
    if len(t) == 0:
        return owners
    pairs, counts = np.unique(np.stack([lab, t], axis=1), axis=0, return_counts=True)
    # sort by label, then count descending, then target ascending: the first row per label wins
    order = np.lexsort((pairs[:, 1], -counts, pairs[:, 0]))
    for i in order:
        owners.setdefault(int(pairs[i, 0]), int(pairs[i, 1]))
    return owners


def catalogue_owners(owners: dict, catalogued) -> dict:
    """``owners`` (:func:`label_owners`) with each catalogued object's own label owned by that object: a catalogue
    entry's identity is its number, whatever object the tracker later followed with it, so a return of object B
    correlated to entry A is a cross-tag even when the tracker swapped A and B for good (the track-purity owner,
    B, would call it correct). Other labels — newborn tracks, an output's fresh identities — keep their owner."""
    out = dict(owners)
    out.update({int(k): int(k) for k in _ids(catalogued, "catalogued")})
    return out


def return_tallies(origin, correlated, owners: dict) -> dict:
    """Counts over the returns of real objects (``origin >= 0``): ``n_returns``; ``correct`` (correlated to a
    track its origin owns); ``cross_tags`` (to a track another object owns); ``orphan`` (to a track no object
    owns: a false or duplicate track); ``uncorrelated`` (``correlated == −1``). They add up to ``n_returns``."""
    o, c = _ids(origin, "origin"), _ids(correlated, "correlated")
    if len(o) != len(c):
        raise ValueError(f"origin and correlated must have the same length, got {len(o)} and {len(c)}")
    real = o >= 0
    o, c = o[real], c[real]
    own = np.array([owners.get(int(x), -1) for x in c], dtype=np.int64)
    unc = c < 0
    return dict(n_returns=int(len(o)), correct=int((~unc & (own == o)).sum()),
                cross_tags=int((~unc & (own >= 0) & (own != o)).sum()), orphan=int((~unc & (own < 0)).sum()),
                uncorrelated=int(unc.sum()))


def id_switches(scans, targets, labels) -> int:
    """CLEAR-MOT identity switches (module docstring): from parallel arrays of per-scan assignments
    (scan, target, label; label < 0: the target had no estimate that scan, skipped), per target in scan order,
    the number of times its label differs from its previous assigned label. Exact integer."""
    s, t, lab = _ids(scans, "scans"), _ids(targets, "targets"), _ids(labels, "labels")
    if not len(s) == len(t) == len(lab):
        raise ValueError(f"scans, targets and labels must have the same length, got {len(s)}, {len(t)} and {len(lab)}")
    keep = lab >= 0
    s, t, lab = s[keep], t[keep], lab[keep]
    order = np.lexsort((s, t))
    t, lab = t[order], lab[order]
    return int(np.sum((t[1:] == t[:-1]) & (lab[1:] != lab[:-1])))


#: The causes of a cross-tag (:func:`cross_tag_causes`), in the order they are tested.
CROSS_TAG_CAUSES = ("newborn", "own_label", "carried_label", "elsewhere")


def cross_tag_causes(scan, origin, correlated, owners: dict, assign_scans, assign_targets, assign_labels,
                     catalogued) -> dict:
    """The cross-tags of :func:`return_tallies` by cause, the first that applies (counts add up to its
    ``cross_tags``):

    * ``newborn`` — the label is not a catalogued object's (a track born from the data);
    * ``own_label`` — the label is the return's origin's own catalogued label and the per-scan assignment puts it
      on the origin at that scan: a right association, charged because the label held another object longer
      (a swap elsewhere in the run);
    * ``carried_label`` — the per-scan assignment puts the label on the origin at that scan, but it is another
      catalogued object's: custody carried over from another object (a swap at acquisition or re-acquisition);
    * ``elsewhere`` — the label is on another object, or on none, at that scan: a single-scan misassociation
      or a duplicate track.

    ``scan, origin, correlated``: the returns (as :func:`return_tallies`, with their scan); ``assign_*``: the
    per-scan assignment (scan, target, label; label < 0 none); ``catalogued``: the catalogued labels.
    """
    sc, o, c = _ids(scan, "scan"), _ids(origin, "origin"), _ids(correlated, "correlated")
    if not len(sc) == len(o) == len(c):
        raise ValueError(f"scan, origin and correlated must have the same length, got {len(sc)}, {len(o)} and {len(c)}")
    own = np.array([owners.get(int(x), -1) for x in c], dtype=np.int64)
    x = (o >= 0) & (c >= 0) & (own >= 0) & (own != o)
    on = {(int(a), int(b)): int(t) for a, b, t in zip(_ids(assign_scans, "assign_scans"),
                                                     _ids(assign_labels, "assign_labels"),
                                                     _ids(assign_targets, "assign_targets")) if b >= 0}
    cat_set = set(_ids(catalogued, "catalogued").tolist())
    out = dict.fromkeys(CROSS_TAG_CAUSES, 0)
    for s_, o_, c_ in zip(sc[x], o[x], c[x]):
        if int(c_) not in cat_set:
            out["newborn"] += 1
        elif on.get((int(s_), int(c_))) == int(o_):
            out["own_label" if c_ == o_ else "carried_label"] += 1
        else:
            out["elsewhere"] += 1
    return out


def purity_counts(truth_pos, est_pos, cutoff_km: float) -> dict:
    """``n_estimates``, ``false`` and ``duplicate`` estimates of one scan (module docstring): the optimal
    assignment minimises ``Σ min(d, c)`` and keeps the pairs closer than ``c``."""
    c = check_positive(cutoff_km, "cutoff_km")
    T, E = _pos(truth_pos, "truth_pos"), _pos(est_pos, "est_pos")
    n = len(E)
    if n == 0:
        return dict(n_estimates=0, false=0, duplicate=0)
    if len(T) == 0:
        return dict(n_estimates=n, false=n, duplicate=0)
    D = np.linalg.norm(E[:, None] - T[None], axis=-1)
    r, k = linear_sum_assignment(np.minimum(D, c))
    assigned = np.zeros(n, bool)
    assigned[r[D[r, k] < c]] = True
    near = D.min(axis=1) < c
    return dict(n_estimates=n, false=int((~assigned & ~near).sum()), duplicate=int((~assigned & near).sum()))


def ric_frame(x_true) -> np.ndarray:
    """Rows R, I, C ``(n, 3, 3)`` of the radial / in-track / cross-track frame of TEME states ``(n, 6)``."""
    X = np.asarray(x_true, dtype=float).reshape(-1, 6)
    R = X[:, :3] / np.linalg.norm(X[:, :3], axis=1, keepdims=True)
    C = np.cross(X[:, :3], X[:, 3:])
    C /= np.linalg.norm(C, axis=1, keepdims=True)
    return np.stack([R, np.cross(C, R), C], axis=1)


def ric_error(x_true, x_est) -> np.ndarray:
    """Position error ``x_est − x_true`` ``(n, 3)`` in the RIC frame of the true states."""
    X = np.asarray(x_true, dtype=float).reshape(-1, 6)
    E = np.asarray(x_est, dtype=float).reshape(len(X), -1)[:, :3]
    return np.einsum("nij,nj->ni", ric_frame(X), E - X[:, :3])


def mahalanobis2(err, P) -> np.ndarray:
    """``e_i^T P_i^-1 e_i`` of errors ``(n, d)`` and covariances ``(n, d, d)`` (Cholesky solve)."""
    e = np.asarray(err, dtype=float)
    P = np.asarray(P, dtype=float)
    if e.ndim != 2 or P.shape != e.shape + e.shape[-1:]:
        raise ValueError(f"err (n, d) and P (n, d, d) must match, got {e.shape} and {P.shape}")
    if len(e) == 0:
        return np.zeros(0)
    L = np.linalg.cholesky(0.5 * (P + np.swapaxes(P, 1, 2)))
    y = np.linalg.solve(L, e[..., None])[..., 0]
    return np.sum(y * y, axis=1)


def chi2_share(d2, prob: float = 0.95, dim: int = 3) -> float:
    """Share of squared Mahalanobis distances ``d2`` inside ``χ²_dim(prob)`` (NaN for none)."""
    d2 = np.asarray(d2, dtype=float).reshape(-1)
    if len(d2) == 0:
        return float("nan")
    return float(np.mean(d2 <= chi2.ppf(check_probability(prob, "prob"), dim)))


def within(pred_pos, true_pos, radius_km: float = 5.0) -> np.ndarray:
    """Mask of predictions within ``radius_km`` of the truth (rows of ``(n, 3)``)."""
    r = check_positive(radius_km, "radius_km")
    return np.linalg.norm(_pos(pred_pos, "pred_pos") - _pos(true_pos, "true_pos"), axis=1) <= r


def per(count, total, scale: float) -> float:
    """``scale · count / total`` (NaN when ``total`` is 0): rates per 10⁴ returns, per 1,000 estimates."""
    return float(scale * count / total) if total else float("nan")


def mean_se(values) -> tuple[float, float]:
    """Mean and standard error ``s / sqrt(n)`` (sample s, ddof 1) of the finite values (NaN s.e. for n < 2)."""
    v = np.asarray(values, dtype=float).reshape(-1)
    v = v[np.isfinite(v)]
    if len(v) == 0:
        return float("nan"), float("nan")
    return float(v.mean()), float(v.std(ddof=1) / np.sqrt(len(v))) if len(v) > 1 else float("nan")


def gospa_parts_per_object(localisation, missed, false, n_in_view) -> dict:
    """GOSPA (p = 1) and its parts per (scan, object in view): sums over scans over ``Σ n_in_view``."""
    n = float(np.sum(n_in_view))
    parts = dict(localisation=float(np.sum(localisation)), missed=float(np.sum(missed)), false=float(np.sum(false)))
    out = {f"gospa_{k}_per_object_km": (v / n if n else float("nan")) for k, v in parts.items()}
    out["gospa_per_object_km"] = sum(parts.values()) / n if n else float("nan")
    return out


def time_to_orbit(det_target, det_time, pass_target, pass_end, pass_ok) -> tuple[np.ndarray, np.ndarray]:
    """Time to orbit (module docstring) of every detected object that has one.

    ``det_target``, ``det_time``: one row per detection (object id, time s; any order, repeats allowed);
    ``pass_target``, ``pass_end``, ``pass_ok``: one row per (object, pass) scored at re-acquisition — the
    time its pass ended and whether its track predicted from there re-acquires the object at its next pass.
    For object ``o`` with first detection ``t_o``: ``min{pass_end : pass_ok, pass_end >= t_o} − t_o``.

    Returns ``(objects, seconds)``, sorted by object id; objects never detected or without such a pass are
    left out (the caller counts them against the objects it asks about).
    """
    dt_ = _ids(det_target, "det_target")
    dtime = np.asarray(det_time, dtype=float).reshape(-1)
    pt = _ids(pass_target, "pass_target")
    pe = np.asarray(pass_end, dtype=float).reshape(-1)
    ok = np.asarray(pass_ok, dtype=bool).reshape(-1)
    if len(dt_) != len(dtime):
        raise ValueError(f"det_target and det_time must have the same length, got {len(dt_)} and {len(dtime)}")
    if not (len(pt) == len(pe) == len(ok)):
        raise ValueError(f"pass_target, pass_end and pass_ok must have the same length, got {len(pt)}, {len(pe)} "
                         f"and {len(ok)}")
    if not (np.all(np.isfinite(dtime)) and np.all(np.isfinite(pe))):
        raise ValueError("det_time and pass_end must be finite times (s)")
    first: dict = {}
    for o, t in zip(dt_.tolist(), dtime.tolist()):
        if t < first.get(o, np.inf):
            first[o] = t
    best: dict = {}
    for o, t, good in zip(pt.tolist(), pe.tolist(), ok.tolist()):
        if good and o in first and t >= first[o] and t < best.get(o, np.inf):
            best[o] = t
    objs = np.array(sorted(best), dtype=np.int64)
    return objs, np.array([best[o] - first[o] for o in objs.tolist()], dtype=float)

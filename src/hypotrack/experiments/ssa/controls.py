"""SSA experiments: negative controls, so that a passing check means something.

A check of document 000's SSA figures is evidence only when something built to break what the
claim is about *fails* it (:func:`hypotrack.reporting.verdict.with_control`). The control here is
the **blind tracker**: the initial hypothesis predicted by the EKF (document 000 Sec. V-A: "an Extended
Kalman Filter ... to compute the underlying state and covariance updates") without ever using a
measurement and without births or deaths. It is what a hypothesis filter degenerates to when its
data association never assigns a return; it costs one EKF prediction per object per scan.

:func:`blind_run` gives its :class:`~.run.TrackingRun` (same tables as a real tracker, so the
same evaluation and the same claim code score it); :func:`attach_controls` runs a claim list's
checks on the blind tracker's tables and fills each row's ``control`` column — a *reproduced* or
*qualitative* row whose control also passes becomes *uninformative*; :func:`every_scan_verdict`
is the "no red stars" check over every scan (document 000 Sec. V-A: "each method maintained the
correct hypothesis throughout the simulation"), which the blind tracker fails where it fails the
start / middle / end snapshots only by luck.

Where the blind tracker is not the right control — "E[N] stays at the initial hypothesis's size
until the first birth" is about not turning clutter into objects, which a tracker that uses no
return cannot do — the control is the **engine with a defect**: :func:`clutter_ignoring` makes
the clutter density 10⁶ times too small, and :func:`clutter_control_run` runs the tracker on it
up to the first birth.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from ..._validation import check_finite_array, check_probability
from ...reporting.verdict import with_control
from ...scenarios.ssa import SSAScenario
from ...scenarios.tables import state_columns
from .run import POS_COV, TrackingRun

__all__ = ["BLIND", "BLIND_LABEL", "CLUTTER_DEFECT", "CLUTTER_DEFECT_LABEL", "attach_controls", "blind_predictions",
           "blind_run", "clutter_control_run", "clutter_ignoring", "evaluate_blind",
           "every_scan_verdict", "scan_errors", "single_return_error_km"]

#: The blind tracker's name in tables (``tracker`` column) and in the ledger's ``control`` column.
BLIND = "blind"
BLIND_LABEL = "blind tracker (EKF prediction of the initial hypothesis, no measurements, no births)"


def blind_predictions(motion, means, covs, dts):
    """EKF predictions of ``n`` objects over scans without any update (document 000 Sec. V-A's EKF).

    ``x_k = f(x_{k−1}, Δt_k)``, ``P_k = Φ_k P_{k−1} Φ_kᵀ + Q(Δt_k)`` with ``Φ_k`` the motion
    model's state-transition matrix at ``x_{k−1}`` (``motion.transition``). ``dts`` are the
    ``K − 1`` time steps after the first scan. Returns ``(K, n, d)`` means and ``(K, n, d, d)``
    covariances; scan 0 is the initial hypothesis itself.
    """
    x = np.array(check_finite_array(means, "means", ndim=2), dtype=float)
    P = np.array(check_finite_array(covs, "covs", ndim=3), dtype=float)
    if P.shape != (len(x), x.shape[1], x.shape[1]):
        raise ValueError(f"covs must have shape ({len(x)}, {x.shape[1]}, {x.shape[1]}), got {P.shape}")
    dts = check_finite_array(dts, "dts", ndim=1)
    if np.any(dts < 0):
        raise ValueError(f"dts must be >= 0, got min {dts.min()}")
    K = len(dts) + 1
    X, C = np.empty((K, *x.shape)), np.empty((K, *P.shape))
    X[0], C[0] = x, P
    for k, dt in enumerate(dts, start=1):
        if len(x):
            x, Phi = motion.transition(x, dt)
            P = Phi @ P @ np.swapaxes(Phi, 1, 2) + motion.Q(dt)
        X[k], C[k] = x, P
    return X, C


def blind_run(scenario: SSAScenario, *, snapshots: Sequence[int] = ()) -> TrackingRun:
    """The blind tracker over every scan of ``scenario``, as a :class:`TrackingRun`.

    One hypothesis (weight 1) holding the initial hypothesis's objects, their EKF predictions as
    the MAP estimates, and the cardinality fixed at the initial hypothesis's size: no return is
    ever used (``n_children`` is 0). ``snapshots`` as in :func:`~.run.run_tracker`.
    """
    times = np.asarray(scenario.times, dtype=float)
    X, C = blind_predictions(scenario.motion, scenario.prior_means, scenario.prior_covs, np.diff(times))
    K, n = len(times), len(scenario.prior_ids)
    labels = np.asarray(scenario.prior_ids, dtype=np.int64)
    n_returns = scenario.scans.groupby("scan").size().reindex(range(K), fill_value=0).to_numpy()
    summary = pd.DataFrame({"scan": np.arange(K), "time": times, "n_returns": n_returns,
                            "expected_number": float(n), "map_n_objects": n, "map_weight": 1.0,
                            "n_hypotheses": 1, "effective_hypotheses": 1.0, "n_children": 0,
                            "mass_retained": 1.0, "log10_possible_children": np.nan})
    cardinality = pd.DataFrame({"scan": np.arange(K), "n_objects": n, "probability": 1.0})
    est = pd.DataFrame(X.reshape(K * n, -1), columns=state_columns(X.shape[2]))
    est.insert(0, "label", np.tile(labels, K))
    est.insert(0, "scan", np.repeat(np.arange(K), n))
    for c, (i, j) in zip(POS_COV, [(0, 0), (0, 1), (1, 1)]):
        est[c] = C[:, :, i, j].ravel()
    snaps = sorted({int(k) for k in snapshots})
    weights = pd.DataFrame({"scan": snaps, "time": times[snaps] if snaps else [], "rank": 1, "weight": 1.0,
                            "n_objects": n}, columns=["scan", "time", "rank", "weight", "n_objects"])
    return TrackingRun(summary=summary, cardinality=cardinality, map_estimates=est, weights=weights,
                       seconds=np.zeros(K), cpu_seconds=np.zeros(K))


def scan_errors(matched: pd.DataFrame) -> pd.DataFrame:
    """Per scan of an :func:`~.evaluation.evaluate_map` ``matched`` table: ``red_stars`` (estimates
    outside their error bound, or matched to no object), ``missed`` (catalogue objects without a
    correct estimate) and ``clean`` (neither)."""
    est = matched[matched["role"] == "estimate"]
    tru = matched[matched["role"] == "truth"]
    scans = np.sort(matched["scan"].unique())
    red = est[est["status"] != "correct"].groupby("scan").size().reindex(scans, fill_value=0)
    missed = tru[tru["status"] == "missed"].groupby("scan").size().reindex(scans, fill_value=0)
    return pd.DataFrame({"scan": scans, "red_stars": red.to_numpy(), "missed": missed.to_numpy(),
                         "clean": (red.to_numpy() == 0) & (missed.to_numpy() == 0)})


def single_return_error_km(scenario: SSAScenario) -> float:
    """RMS position error of one raw return, ``σ√2`` km (``σ`` per axis, document 000 Sec. V-A's "zero-mean
    Gaussian measurement noise"): an estimate that uses the returns should be at least this accurate."""
    return float(scenario.params.sigma * np.sqrt(2.0))


def every_scan_verdict(matched: pd.DataFrame, metrics: pd.DataFrame, *, tolerance: float,
                       max_ospa_km: float | None = None) -> tuple[str, bool]:
    """The "no red stars" check over every processed scan (scan 0, the initial hypothesis, is left out).

    Passes when the fraction of scans with a red star or a missed object is at most ``tolerance``
    (in [0, 1]; the config states why: a consistent filter's ``error_bound_probability`` ellipse
    misses now and then by chance) and, when ``max_ospa_km`` is given, the mean in-view OSPA is at
    most that (:func:`single_return_error_km`: document 000 Sec. V-A shows the figures "to illustrate
    that the methods accurately track the objects"). Returns the measured text and whether it passes.
    """
    tol = check_probability(tolerance, "tolerance")
    if max_ospa_km is not None and not max_ospa_km > 0:
        raise ValueError(f"max_ospa_km must be > 0 (km), got {max_ospa_km!r}")
    e = scan_errors(matched)
    e = e[e["scan"] > 0]
    n_bad, n = int((~e["clean"]).sum()), len(e)
    frac = n_bad / n if n else 0.0
    ospa_mean = float(np.nanmean(metrics.loc[metrics["scan"] > 0, "ospa_in_view"])) if n else float("nan")
    text = f"{100 * frac:.1f} % of {n} scans ({n_bad}) with a red star or a missed object; in-view OSPA {ospa_mean:.3g} km"
    ok = frac <= tol and (max_ospa_km is None or ospa_mean <= max_ospa_km)
    return text, bool(ok)


_PASS = ("reproduced", "qualitative")


def attach_controls(claims: Sequence, control_claims: Sequence | Mapping, *, what: str = BLIND_LABEL,
                    keys: Sequence[str] | None = None) -> list:
    """Fill the ``control`` column of ``claims`` from the same checks run on a control.

    ``control_claims`` are the claims the same code gives on the control's tables (a list, or a
    mapping key -> claim); row ``key`` of ``claims`` gets the control row with the same key: its
    measured value, and whether it *passes* (its status is *reproduced* or *qualitative*).
    :func:`~hypotrack.reporting.verdict.with_control` demotes a passing row whose control also
    passes to *uninformative*. Rows without a key, or whose key the control lacks (or is not in
    ``keys`` when given), are returned unchanged.
    """
    by_key = dict(control_claims) if isinstance(control_claims, Mapping) else \
        {c.key: c for c in control_claims if c.key}
    out = []
    for c in claims:
        ctl = by_key.get(c.key) if c.key and (keys is None or c.key in keys) else None
        if ctl is None:
            out.append(c)
            continue
        out.append(with_control(c, what, ctl.reproduced.replace(" -> ", " → "), ctl.status in _PASS))
    return out


def evaluate_blind(section: Mapping, scenario: SSAScenario, *, snapshots: Sequence[int] = ()):
    """The blind tracker on ``scenario`` scored like a configured tracker (:func:`~.evaluation.evaluate_configured`
    with the experiment section's OSPA and error bound): ``(run, metrics, matched, births)``."""
    from .evaluation import birth_recognition, evaluate_configured

    run = blind_run(scenario, snapshots=snapshots)
    metrics, matched = evaluate_configured(section, scenario, run.summary, run.map_estimates)
    return run, metrics, matched, birth_recognition(matched, scenario)


#: How much too small the clutter-ignoring engine takes the clutter density g(z) = 1/V (document 000 Sec. II-B).
CLUTTER_DEFECT = 1e6
CLUTTER_DEFECT_LABEL = "the same R-FISST with its clutter density 10⁶ times too small (clutter ignored)"


def clutter_ignoring(scenario: SSAScenario, factor: float = CLUTTER_DEFECT) -> SSAScenario:
    """``scenario`` as an engine that (almost) ignores clutter models it: the clutter region's area,
    hence ``1/g(z)``, ``factor`` times too large (range limit scaled by about √factor). A clutter
    return then costs ``log factor`` more as clutter than the truth says, so the engine explains it
    as a birth: the defect the claim "E[N] stays at the initial hypothesis's size until the first
    birth" (document 000 Fig. 11) is about. The data (truth, scans) are unchanged."""
    from dataclasses import replace

    from ...models.sensors import PoissonClutter

    if not factor > 1:
        raise ValueError(f"factor must be > 1, got {factor!r}")
    fov = scenario.params.fov
    r_max = float(np.sqrt(factor * (fov.r_max**2 - fov.r_min**2) + fov.r_min**2))
    sensor = replace(scenario.sensor, clutter=PoissonClutter(scenario.sensor.clutter.rate, replace(fov, r_max=r_max)))
    return replace(scenario, sensor=sensor)


def clutter_control_run(scenario: SSAScenario, settings, seed, *, progress=None) -> TrackingRun:
    """The tracker ``settings`` on :func:`clutter_ignoring` ``(scenario)`` over the scans before the
    first birth enters the field of view (what the "E[N] before the first birth" check reads)."""
    from .run import run_tracker
    from .trackers import make_tracker

    first = scenario.first_in_view_scan[scenario.birth_ids]
    first = first[first >= 0]
    n = int(first.min()) if len(first) else len(scenario.times)
    defect = clutter_ignoring(scenario)
    return run_tracker(make_tracker(defect, settings, seed), defect, name="clutter-ignoring control",
                       progress=progress, n_progress=4, n_scans=max(n, 1))

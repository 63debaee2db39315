"""Monte Carlo drivers for the cardinality-tracking example (document 003 §4, Fig. 4.2).

:func:`cardinality_run` simulates one counts-only realisation and runs the classical
track-oriented MHT (exact MAP of Eq. 4.1), the cardinality tracker (Tetris extraction, both
variants) and the exact equivalence-class MAP (count dynamic programme); :func:`cardinality_monte_carlo`
repeats it over seeded runs and tabulates the cardinality errors and the Tetris optimality gap;
:func:`realisation_tables` gives Fig. 4.2's tables. The figure is drawn in :mod:`.figures`, the
reproduction claims are stated in :mod:`.claims`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..._validation import check_int, check_positive
from ...scenarios.cardinality import simulate_cardinality
from ...trackers.cardinality import (
    CountModel,
    constant_count_estimate,
    exact_count_dp,
    per_scan_count_estimate,
    tetris_extract,
)

__all__ = [
    "CARDINALITY_METHODS",
    "cardinality_monte_carlo",
    "cardinality_run",
    "low_clutter_control",
    "monte_carlo_table",
    "realisation_tables",
    "summarise_cardinality",
]

#: Estimators compared in the cardinality experiment, in plotting order; the last two are the trivial
#: estimators run as negative controls (the constant λ_b/p_χ and the per-scan (r_k − λ_fa)/p_d).
CARDINALITY_METHODS = ("classical_mht", "cardinality_tracker", "tetris_group", "exact_class_map", "constant_prior",
                       "per_scan")


def cardinality_run(*, n_scans, p_chi, lambda_b, p_d, lambda_fa, start="steady_state", max_alive_factor=2.0, rng) -> dict:
    """One realisation: truth, counts and every estimator's number of targets per scan.

    Parameters
    ----------
    n_scans, p_chi, lambda_b, p_d, lambda_fa, start
        Scenario and model parameters (see :func:`~hypotrack.scenarios.cardinality.simulate_cardinality`);
        the trackers use the same ``p_d, p_χ, λ_b, λ_fa``.
    max_alive_factor : float
        The dynamic programmes search at most ``max_alive_factor · max_k r_k`` live targets.
    rng : numpy.random.Generator or int

    Returns
    -------
    dict
        ``n_true``, ``r`` and one ``(T,)`` estimate per name in :data:`CARDINALITY_METHODS`
        (``constant_prior`` and ``per_scan`` are the trivial estimators of
        :func:`~hypotrack.trackers.cardinality.constant_count_estimate` and
        :func:`~hypotrack.trackers.cardinality.per_scan_count_estimate`);
        ``J`` — class objective (Eq. 4.8) of each class estimator; ``tracks`` — the tracker's tracks;
        ``cap_reached`` — whether a dynamic programme touched its search cap.
    """
    factor = check_positive(max_alive_factor, "max_alive_factor")
    real = simulate_cardinality(n_scans=n_scans, p_chi=p_chi, lambda_b=lambda_b, p_d=p_d, lambda_fa=lambda_fa, rng=rng, start=start)
    model = CountModel(p_d, p_chi, lambda_b, lambda_fa)
    cap = max(1, int(np.ceil(factor * real.r.max(initial=0))))
    classical = exact_count_dp(real.r, model, equivalence_class=False, max_alive=cap)
    exact = exact_count_dp(real.r, model, equivalence_class=True, max_alive=cap)
    tetris = tetris_extract(real.r, model, variant="row_dp")
    group = tetris_extract(real.r, model, variant="group")
    return {
        "n_true": real.n_true,
        "r": real.r,
        "classical_mht": classical.n,
        "cardinality_tracker": tetris.n,
        "tetris_group": group.n,
        "exact_class_map": exact.n,
        "constant_prior": constant_count_estimate(len(real.r), model),
        "per_scan": per_scan_count_estimate(real.r, model),
        "J": {"cardinality_tracker": tetris.J, "tetris_group": group.J, "exact_class_map": exact.J},
        "tracks": tetris.tracks,
        "cap_reached": bool(classical.cap_reached or exact.cap_reached),
    }


def low_clutter_control(*, n_scans, p_chi, lambda_b, p_d, lambda_fa, start="steady_state", max_alive_factor=2.0,
                        rng) -> dict:
    """The classical track-oriented MHT (exact MAP of Eq. 4.1) on one realisation at the given, low,
    false-alarm rate: the negative control of "the classical MHT returns no tracks", whose cause in
    the document is a "sufficiently high false alarm rate". Returns ``n_true``, ``r`` and
    ``classical_mht`` (the MAP's number of targets per scan)."""
    factor = check_positive(max_alive_factor, "max_alive_factor")
    real = simulate_cardinality(n_scans=n_scans, p_chi=p_chi, lambda_b=lambda_b, p_d=p_d, lambda_fa=lambda_fa, rng=rng,
                                start=start)
    cap = max(1, int(np.ceil(factor * real.r.max(initial=0))))
    classical = exact_count_dp(real.r, CountModel(p_d, p_chi, lambda_b, lambda_fa), equivalence_class=False,
                               max_alive=cap)
    return {"n_true": real.n_true, "r": real.r, "classical_mht": classical.n}


def cardinality_monte_carlo(*, n_runs, seed, progress: bool = False, **params) -> dict:
    """Repeat :func:`cardinality_run` over ``n_runs`` seeded realisations.

    Parameters
    ----------
    n_runs : int
    seed : int or numpy.random.SeedSequence
        Each run gets its own child sequence.
    progress : bool
        Print one line per finished run.
    **params
        Passed to :func:`cardinality_run`.

    Returns
    -------
    dict of (n_runs,) arrays
        ``mean_abs_error[<method>]`` — mean over scans of ``|n̂_k − n_k|``; ``mean_n_true``;
        ``mean_n[<method>]``; ``J_gap_row_dp`` and ``J_gap_group`` — exact optimum minus the
        Tetris objective (>= 0); ``J_opt`` — the exact optimum of Eq. 4.8 (the scale of the gaps);
        ``cap_reached``.
    """
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    children = (np.random.SeedSequence(seed) if isinstance(seed, int) else seed).spawn(n_runs)
    err = {m: np.empty(n_runs) for m in CARDINALITY_METHODS}
    mean_n = {m: np.empty(n_runs) for m in CARDINALITY_METHODS}
    out = {k: np.empty(n_runs) for k in ("mean_n_true", "J_gap_row_dp", "J_gap_group", "J_opt")}
    out["cap_reached"] = np.zeros(n_runs, dtype=bool)
    for i, child in enumerate(children):
        res = cardinality_run(rng=np.random.default_rng(child), **params)
        for m in CARDINALITY_METHODS:
            err[m][i] = np.abs(res[m] - res["n_true"]).mean()
            mean_n[m][i] = res[m].mean()
        out["mean_n_true"][i] = res["n_true"].mean()
        out["J_gap_row_dp"][i] = res["J"]["exact_class_map"] - res["J"]["cardinality_tracker"]
        out["J_gap_group"][i] = res["J"]["exact_class_map"] - res["J"]["tetris_group"]
        out["J_opt"][i] = res["J"]["exact_class_map"]
        out["cap_reached"][i] = res["cap_reached"]
        if progress:
            print(f"  run {i + 1}/{n_runs}: mean |n-hat - n| = {err['cardinality_tracker'][i]:.2f} (tracker), "
                  f"{err['classical_mht'][i]:.2f} (classical MHT)", flush=True)
    out["mean_abs_error"] = err
    out["mean_n"] = mean_n
    return out


def monte_carlo_table(result: dict, first_run: int = 0) -> pd.DataFrame:
    """Long per-run table (``run, method, mean_abs_error, mean_n, mean_n_true, J_gap, J_opt, cap_reached``)."""
    n = len(result["mean_n_true"])
    gaps = {"cardinality_tracker": result["J_gap_row_dp"], "tetris_group": result["J_gap_group"]}
    frames = [
        pd.DataFrame({
            "run": first_run + np.arange(n), "method": m, "mean_abs_error": result["mean_abs_error"][m],
            "mean_n": result["mean_n"][m], "mean_n_true": result["mean_n_true"],
            "J_gap": gaps.get(m, np.full(n, np.nan)), "J_opt": result["J_opt"], "cap_reached": result["cap_reached"],
        })
        for m in CARDINALITY_METHODS
    ]
    return pd.concat(frames, ignore_index=True)


def summarise_cardinality(per_run: pd.DataFrame):
    """Pool per-run tables into the error table and the Tetris optimality table.

    Returns
    -------
    errors : pandas.DataFrame
        Per method: ``mean_abs_error`` (mean over runs and scans of ``|n̂_k − n_k|``), its
        ``std_error`` over runs, ``mean_n``, ``mean_n_true``, ``n_runs``; ``bias`` (mean of
        ``n̂ − n``) and ``bias_se``; ``excess_error`` and ``excess_error_se``: the method's error
        minus the cardinality tracker's, paired run by run (positive: the tracker is better).
    optimality : pandas.DataFrame
        Per Tetris variant: share of runs reaching the exact class optimum (gap < 1e-6),
        mean and worst gap in log-probability, the worst gap relative to that run's optimum
        (``worst_relative_gap``) and the mean optimum ``mean_J_opt``.
    """
    per_run = per_run.assign(bias=per_run["mean_n"] - per_run["mean_n_true"])
    tracker = per_run[per_run["method"] == "cardinality_tracker"].set_index("run")["mean_abs_error"]
    per_run = per_run.assign(excess=per_run["mean_abs_error"].to_numpy() - tracker.reindex(per_run["run"]).to_numpy())
    g = per_run.groupby("method", sort=False)
    root_n = np.sqrt(g.size())
    errors = pd.DataFrame({
        "mean_abs_error": g["mean_abs_error"].mean(),
        "std_error": g["mean_abs_error"].std(ddof=1) / root_n,
        "mean_n": g["mean_n"].mean(), "mean_n_true": g["mean_n_true"].mean(), "n_runs": g.size(),
        "bias": g["bias"].mean(), "bias_se": g["bias"].std(ddof=1) / root_n,
        "excess_error": g["excess"].mean(), "excess_error_se": g["excess"].std(ddof=1) / root_n,
    }).reset_index()
    tet = per_run[per_run["J_gap"].notna()].assign(rel=lambda t: t["J_gap"] / t["J_opt"].abs())
    gt = tet.groupby("method", sort=False)
    optimality = pd.DataFrame({
        "fraction_at_optimum": gt["J_gap"].apply(lambda x: float(np.mean(x < 1e-6))),
        "mean_gap": gt["J_gap"].mean(), "worst_gap": gt["J_gap"].max(), "worst_relative_gap": gt["rel"].max(),
        "mean_J_opt": gt["J_opt"].mean(), "n_runs": gt.size(),
    }).reset_index().rename(columns={"method": "variant"})
    return errors, optimality


def realisation_tables(result: dict):
    """Fig. 4.2's tables from one :func:`cardinality_run`: per-scan counts of every method
    (``scan, n_true, r`` and one column per :data:`CARDINALITY_METHODS` entry) and the
    cardinality tracker's tracks (``row, start, end, n_meas, log_score``)."""
    counts = pd.DataFrame({"scan": np.arange(len(result["n_true"])), "n_true": result["n_true"], "r": result["r"]})
    for m in CARDINALITY_METHODS:
        counts[m] = result[m]
    tracks = pd.DataFrame([{"row": t.row, "start": t.start, "end": t.end, "n_meas": len(t.scans),
                            "log_score": t.log_score} for t in result["tracks"]],
                          columns=["row", "start", "end", "n_meas", "log_score"])
    return counts, tracks



"""Monte Carlo drivers for document 003 §5–6: the swap experiment and Table 6.1.

Everything here is vectorised over Monte Carlo runs and driven by explicit seeds, so the
Snakemake scripts only read a config section, call one function per shard and write tables.

* :func:`swap_shard` / :func:`summarise_swaps` — Figs 5.1–5.3: RMS error of the equivalent
  measurement and the average single-hypothesis / hypothesis-class log-probability (Eq. 5.22)
  against the number of random swaps, for two static targets seen by N sensors, and the swap
  rate ``i*/N`` minimising that RMS (or maximising the class probability) against distance.
* :func:`swap_curve` — one distance's curve of the summary.

The ledger rows are stated in :mod:`.claims`, the figures drawn in :mod:`.figures`. Table 6.1 and
Figs 6.1–6.2 (the closely spaced targets) live in :mod:`hypotrack.experiments.closely_spaced`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.special import gammaln

from ..._validation import check_finite_array, check_int, check_positive
from ...scenarios.closely_spaced import static_pair_scans

__all__ = [
    "swap_shard",
    "summarise_swaps",
    "swap_curve",
]


def _swap_statistics(Z_lower, Z_upper, truth, sigma, rng):
    """Per-run squared errors and log-probabilities for ``i = 0..N`` random swaps."""
    n_runs, N = Z_lower.shape
    order = np.argsort(rng.random((n_runs, N)), axis=1)
    Z1 = np.take_along_axis(Z_lower, order, axis=1)
    Z2 = np.take_along_axis(Z_upper, order, axis=1)
    zeros = np.zeros((n_runs, 1))
    moved = np.concatenate([zeros, np.cumsum(Z2 - Z1, axis=1)], axis=1)  # swapping the first i
    zbar_1 = (Z1.sum(axis=1, keepdims=True) + moved) / N  # Eq. 6.6 with the first i swapped
    zbar_2 = (Z2.sum(axis=1, keepdims=True) - moved) / N  # Eq. 6.7
    sq_err = 0.5 * ((zbar_1 - truth[0]) ** 2 + (zbar_2 - truth[1]) ** 2)
    # Per-sensor posterior of "no swap" vs "swap" with equal priors (reconstruction §4.6).
    ll_keep = -((Z1 - truth[0]) ** 2 + (Z2 - truth[1]) ** 2) / (2 * sigma**2)
    ll_swap = -((Z2 - truth[0]) ** 2 + (Z1 - truth[1]) ** 2) / (2 * sigma**2)
    norm = np.logaddexp(ll_keep, ll_swap)
    lp_keep, lp_swap = ll_keep - norm, ll_swap - norm
    swapped_first = np.concatenate([zeros, np.cumsum(lp_swap, axis=1)], axis=1)
    kept_rest = np.concatenate([np.cumsum(lp_keep[:, ::-1], axis=1)[:, ::-1], zeros], axis=1)
    log_single = swapped_first + kept_rest
    return sq_err, log_single


def _log_binom(N):
    i = np.arange(N + 1)
    return gammaln(N + 1) - gammaln(i + 1) - gammaln(N - i + 1)


def swap_shard(distances, *, n_sensors: int, sigma: float, n_runs: int, seed) -> pd.DataFrame:
    """Figs 5.1–5.3 raw sums for one shard of runs: merging N sensors' returns with ``i`` random swaps.

    Two static targets at 0 and each ``distance``; each sensor reports both with N(0, σ²) noise,
    sorted. For every ``i = 0..N`` a uniformly random set of ``i`` sensors has its returns
    swapped before the two N-sensor averages are formed (``i = 0`` is the GNNF paradigm).

    Parameters
    ----------
    distances : sequence of float
        Target separations (m), >= 0; each gets its own child stream of ``seed``.
    n_sensors, n_runs : int
    sigma : float
        Measurement-noise standard deviation (m).
    seed : int or numpy.random.SeedSequence

    Returns
    -------
    pandas.DataFrame
        One row per (distance, swaps): ``n_runs``, ``sum_sq_err`` (summed over runs of the
        squared error averaged over the two targets) and ``sum_log_prob_single`` (summed
        log-posterior of the one swapped hypothesis drawn) and ``sum_sq_err_labelled``: the same
        statistic when each sensor's returns are labelled by their true target instead of sorted (the
        negative control: without the sorting bias, swaps only add error). The control's draws come from
        a second set of child streams, so the main columns do not depend on it. Pool shards with
        :func:`summarise_swaps`.
    """
    distances = check_finite_array(distances, "distances", ndim=1)
    n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    sigma = check_positive(sigma, "sigma")
    sequence = np.random.SeedSequence(seed) if isinstance(seed, int) else seed
    children = sequence.spawn(len(distances))
    control_children = sequence.spawn(len(distances))
    frames = []
    for dist, child, control_child in zip(distances, children, control_children):
        rng = np.random.default_rng(child)
        truth, Z_lower, Z_upper = static_pair_scans(float(dist), n_runs=n_runs, n_sensors=n_sensors, sigma=sigma, rng=rng)
        sq_err, log_single = _swap_statistics(Z_lower, Z_upper, truth, sigma, rng)
        crng = np.random.default_rng(control_child)
        Z = truth + sigma * crng.standard_normal((n_runs, n_sensors, 2))  # labelled by the true target, not sorted
        sq_err_labelled, _ = _swap_statistics(Z[..., 0], Z[..., 1], truth, sigma, crng)
        frames.append(pd.DataFrame({
            "distance": float(dist), "swaps": np.arange(n_sensors + 1), "n_runs": n_runs,
            "sum_sq_err": sq_err.sum(axis=0), "sum_log_prob_single": log_single.sum(axis=0),
            "sum_sq_err_labelled": sq_err_labelled.sum(axis=0),
        }))
    return pd.concat(frames, ignore_index=True)


def summarise_swaps(shards: pd.DataFrame):
    """Pool :func:`swap_shard` tables into the curves of Figs 5.1–5.2 and the rates of Fig. 5.3.

    Returns
    -------
    curves : pandas.DataFrame
        Per (distance, swaps): ``rms`` (m) of the equivalent measurement over targets and runs,
        ``log_prob_single`` (mean log-posterior of one hypothesis with that many swaps) and
        ``log_prob_class`` (plus ``ln C(N, i)``, Eq. 5.22), ``rms_labelled`` (the control of
        :func:`swap_shard`, when the shards have it).
    rates : pandas.DataFrame
        Per distance: ``rms_optimal_swaps`` / ``rms_optimal_rate`` (the ``i`` minimising the RMS,
        and ``i/N``), ``class_optimal_swaps`` / ``class_optimal_rate`` (maximising the class
        log-probability), ``rms_at_optimum`` and ``rms_no_swaps`` (m).
    """
    sums = ["n_runs", "sum_sq_err", "sum_log_prob_single"] + (["sum_sq_err_labelled"]
                                                              if "sum_sq_err_labelled" in shards else [])
    pooled = shards.groupby(["distance", "swaps"], as_index=False)[sums].sum()
    n_sensors = int(pooled["swaps"].max())
    curves = pooled[["distance", "swaps"]].copy()
    curves["rms"] = np.sqrt(pooled["sum_sq_err"] / pooled["n_runs"])
    curves["log_prob_single"] = pooled["sum_log_prob_single"] / pooled["n_runs"]
    curves["log_prob_class"] = curves["log_prob_single"] + _log_binom(n_sensors)[curves["swaps"].to_numpy()]
    curves["n_runs"] = pooled["n_runs"]
    if "sum_sq_err_labelled" in pooled:
        curves["rms_labelled"] = np.sqrt(pooled["sum_sq_err_labelled"] / pooled["n_runs"])
    rows = []
    for dist, c in curves.groupby("distance", sort=True):
        i_rms = int(c["swaps"].to_numpy()[np.argmin(c["rms"].to_numpy())])
        i_cls = int(c["swaps"].to_numpy()[np.argmax(c["log_prob_class"].to_numpy())])
        rows.append({
            "distance": dist, "rms_optimal_swaps": i_rms, "rms_optimal_rate": i_rms / n_sensors,
            "class_optimal_swaps": i_cls, "class_optimal_rate": i_cls / n_sensors,
            "rms_at_optimum": float(c["rms"].min()), "rms_no_swaps": float(c.loc[c["swaps"] == 0, "rms"].iloc[0]),
        })
    return curves, pd.DataFrame(rows)


def swap_curve(curves: pd.DataFrame, distance: float) -> pd.DataFrame:
    """The rows of :func:`summarise_swaps`'s curves at ``distance``, by number of swaps (Figs 5.1–5.2)."""
    return curves[np.isclose(curves["distance"], distance)].sort_values("swaps")

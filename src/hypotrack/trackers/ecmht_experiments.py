"""Monte Carlo drivers for seed 003 §5–6: the swap experiment and Table 6.1.

Everything here is vectorised over Monte Carlo runs and driven by explicit seeds, so the
Snakemake scripts only read a config section, call one function per shard and write tables.

* :func:`swap_curves` — Figs 5.1–5.2: RMS error of the equivalent measurement and the average
  single-hypothesis / hypothesis-class log-probability (Eq. 5.22) against the number of
  random swaps, for two static targets seen by N sensors.
* :func:`optimal_swap_rates` — Fig. 5.3: the swap rate ``i*/N`` minimising that RMS (and the one
  maximising the class probability) against the distance between the targets.
* :func:`closely_spaced_monte_carlo` — Table 6.1: MOSPA of the ideal filter, PDAF, MHT and
  ECMHT on the two-target OU problem, scored on the one-step prediction ``X(k|k−1)``.
* :func:`closely_spaced_realisation` — one realisation's tracks (Figs 6.1–6.2).
"""

from __future__ import annotations

import zlib

import numpy as np
from scipy.special import gammaln

from .._validation import check_finite_array, check_int, check_nonnegative, check_positive
from ..models.motion import OrnsteinUhlenbeck
from ..scenarios.closely_spaced import simulate_closely_spaced, static_pair_scans
from .ecmht import PDAF_VARIANTS, ECMHTFilter, GNNFilter, IdealFilter, PDAFilter, mospa_two_targets

__all__ = [
    "TABLE_6_1",
    "experiment_seeds",
    "swap_curves",
    "optimal_swap_rates",
    "closely_spaced_monte_carlo",
    "closely_spaced_realisation",
]

#: Published MOSPA (m², see reconstruction §5.4) of Table 6.1.
TABLE_6_1 = {"ideal": 0.0363, "PDAF": 0.8518, "MHT": 0.1376, "ECMHT": 0.0586}


def experiment_seeds(seed: int, experiment: str, n: int) -> list:
    """``n`` independent child seed sequences of the master ``seed`` for one experiment.

    The experiment name is folded into the entropy so that experiments sharing the master seed
    draw independent streams; child ``i`` (one per shard or per grid point) is stable whatever
    the other children are used for.
    """
    seed = check_int(seed, "seed", minimum=0)
    n = check_int(n, "n", minimum=1)
    return np.random.SeedSequence([seed, zlib.crc32(experiment.encode())]).spawn(n)


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


def swap_curves(distance: float, *, n_sensors: int, sigma: float, n_runs: int, rng) -> dict:
    """Figs 5.1–5.2: statistics of merging N sensors' returns with ``i`` random swaps.

    Two static targets at 0 and ``distance``; each sensor reports both with N(0, σ²) noise,
    sorted. For every ``i = 0..N`` a uniformly random set of ``i`` sensors has its returns
    swapped before the two N-sensor averages are formed (``i = 0`` is the GNNF).

    Parameters
    ----------
    distance : float
        Target separation (m), >= 0.
    n_sensors, n_runs : int
    sigma : float
        Measurement-noise standard deviation (m).
    rng : numpy.random.Generator or int

    Returns
    -------
    dict with arrays over ``i = 0..N``:
        ``swaps``; ``rms`` — RMS error of the equivalent measurement over targets and runs (m);
        ``log_prob_single`` — mean log-posterior of the one swapped hypothesis drawn;
        ``log_prob_class`` — the same plus ``ln C(N, i)`` (Eq. 5.22); ``sum_sq_err`` — summed
        squared error (for pooling shards).
    """
    distance = check_nonnegative(distance, "distance")
    rng = np.random.default_rng(rng)
    truth, Z_lower, Z_upper = static_pair_scans(distance, n_runs=n_runs, n_sensors=n_sensors, sigma=sigma, rng=rng)
    sq_err, log_single = _swap_statistics(Z_lower, Z_upper, truth, sigma, rng)
    mean_single = log_single.mean(axis=0)
    return {
        "swaps": np.arange(n_sensors + 1),
        "rms": np.sqrt(sq_err.mean(axis=0)),
        "sum_sq_err": sq_err.sum(axis=0),
        "log_prob_single": mean_single,
        "log_prob_class": mean_single + _log_binom(n_sensors),
    }


def optimal_swap_rates(distances, *, n_sensors: int, sigma: float, n_runs: int, seeds) -> dict:
    """Fig. 5.3: swap rate ``i*/N`` against target separation.

    For each distance (with its own seed), ``rms_optimal`` is the ``i`` minimising the RMS
    error of :func:`swap_curves` and ``class_optimal`` the ``i`` maximising the average class
    log-probability; both are divided by N.

    Returns
    -------
    dict of arrays over distances: ``distance``, ``rms_optimal_rate``, ``class_optimal_rate``,
    ``rms_at_optimum``, ``rms_no_swaps``.
    """
    distances = check_finite_array(distances, "distances", ndim=1)
    if len(seeds) != len(distances):
        raise ValueError(f"need one seed per distance: {len(seeds)} seeds for {len(distances)} distances")
    out = {k: np.empty(len(distances)) for k in ("rms_optimal_rate", "class_optimal_rate", "rms_at_optimum", "rms_no_swaps")}
    for n, (dist, seed) in enumerate(zip(distances, seeds)):
        c = swap_curves(float(dist), n_sensors=n_sensors, sigma=sigma, n_runs=n_runs, rng=np.random.default_rng(seed))
        i_rms = int(np.argmin(c["rms"]))
        out["rms_optimal_rate"][n] = i_rms / n_sensors
        out["class_optimal_rate"][n] = int(np.argmax(c["log_prob_class"])) / n_sensors
        out["rms_at_optimum"][n] = c["rms"][i_rms]
        out["rms_no_swaps"][n] = c["rms"][0]
    out["distance"] = distances
    return out


def _filters(model, R, n_sensors, dt, ecmht_rng, pdaf_variant):
    return {
        "ideal": IdealFilter(model, R, n_sensors, dt),
        "PDAF": PDAFilter(model, R, n_sensors, dt, variant=pdaf_variant),
        "MHT": GNNFilter(model, R, n_sensors, dt),
        "ECMHT": ECMHTFilter(model, R, n_sensors, dt, rng=ecmht_rng),
    }


def _scenario_and_filters(sigma2, gamma, n_runs, n_scans, n_sensors, R, dt, initial_variance, pdaf_variant, seed):
    """Simulate the scenario and build the four filters from two independent child streams."""
    model = OrnsteinUhlenbeck(sigma2, gamma)
    scen_seed, ecmht_seed = (np.random.SeedSequence(seed) if isinstance(seed, int) else seed).spawn(2)
    real = simulate_closely_spaced(
        model, n_runs=n_runs, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
        initial_variance=initial_variance, rng=np.random.default_rng(scen_seed),
    )
    return model, real, _filters(model, R, n_sensors, dt, np.random.default_rng(ecmht_seed), pdaf_variant)


def closely_spaced_monte_carlo(
    *,
    sigma2: float,
    gamma: float,
    n_runs: int,
    n_scans: int,
    n_sensors: int,
    R: float,
    dt: float = 1.0,
    initial_variance: float = 0.01,
    pdaf_variant: str = "sequential",
    extra_pdaf_variants=(),
    seed,
) -> dict:
    """Table 6.1: MOSPA of the ideal filter, PDAF, MHT and ECMHT over ``n_runs`` realisations.

    Each scan ``k ≥ 2`` is scored with :func:`~hypotrack.trackers.ecmht.mospa_two_targets` of
    the one-step predictions ``X(k|k−1)`` against the truth ``x_k`` (reconstruction §6.4).

    Parameters
    ----------
    sigma2, gamma : float
        OU intensity σ_q² (m²/s) and mean-reversion rate γ (1/s).
    n_runs, n_scans, n_sensors : int
    R : float
        Per-sensor measurement variance (m²).
    dt : float
        Scan interval (s).
    initial_variance : float
        Variance of each target's initial position (m²).
    pdaf_variant : str
        Multi-sensor PDAF form reported as "PDAF" (see :data:`~hypotrack.trackers.ecmht.PDAF_VARIANTS`).
    extra_pdaf_variants : sequence of str
        Further PDAF forms scored as ``"PDAF[<variant>]"``.
    seed : int or numpy.random.SeedSequence
        Seeds the scenario and the ECMHT's sensor orders (two independent streams).

    Returns
    -------
    dict
        ``per_run`` — method → (n_runs,) mean MOSPA of each run; ``per_scan`` — method →
        (n_scans − 1,) MOSPA averaged over runs for scans 2..n_scans; ``mean_swaps`` — the
        ECMHT's mean ``i*`` per scan.
    """
    for v in (pdaf_variant, *extra_pdaf_variants):
        if v not in PDAF_VARIANTS:
            raise ValueError(f"PDAF variant must be one of {PDAF_VARIANTS}, got {v!r}")
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    model, real, filters = _scenario_and_filters(sigma2, gamma, n_runs, n_scans, n_sensors, R, dt, initial_variance,
                                                 pdaf_variant, seed)
    for v in extra_pdaf_variants:
        filters[f"PDAF[{v}]"] = PDAFilter(model, R, n_sensors, dt, variant=v)
    scores = {name: np.empty((real.truth.shape[0], n_scans - 1)) for name in filters}
    swaps = np.empty(n_scans - 1)
    for k in range(n_scans):
        for name, f in filters.items():
            f.step(real.scans[:, k])
            if k > 0:
                scores[name][:, k - 1] = mospa_two_targets(f.predictions(), real.truth[:, k])
        if k > 0:
            swaps[k - 1] = filters["ECMHT"].last_swaps.mean()
    return {
        "per_run": {name: s.mean(axis=1) for name, s in scores.items()},
        "per_scan": {name: s.mean(axis=0) for name, s in scores.items()},
        "mean_swaps": swaps,
    }


def closely_spaced_realisation(
    *, sigma2, gamma, n_scans, n_sensors, R, dt=1.0, initial_variance=0.01, pdaf_variant="sequential", seed
) -> dict:
    """One realisation's truth and filtered tracks ``X(k|k)`` of every method (Figs 6.1–6.2).

    Returns
    -------
    dict
        ``time`` (n_scans,), ``truth`` (n_scans, 2), and method → (n_scans, 2) estimates.
    """
    _, real, filters = _scenario_and_filters(sigma2, gamma, 1, n_scans, n_sensors, R, dt, initial_variance,
                                             pdaf_variant, seed)
    out = {"time": real.times, "truth": real.truth[0]}
    for name, f in filters.items():
        out[name] = np.stack([f.step(real.scans[:, k])[0].copy() for k in range(n_scans)])
    return out

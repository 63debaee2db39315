"""Monte Carlo drivers for seed 003 §5–6: the swap experiment and Table 6.1.

Everything here is vectorised over Monte Carlo runs and driven by explicit seeds, so the
Snakemake scripts only read a config section, call one function per shard and write tables.

* :func:`swap_shard` / :func:`summarise_swaps` — Figs 5.1–5.3: RMS error of the equivalent
  measurement and the average single-hypothesis / hypothesis-class log-probability (Eq. 5.22)
  against the number of random swaps, for two static targets seen by N sensors, and the swap
  rate ``i*/N`` minimising that RMS (or maximising the class probability) against distance.
* :func:`closely_spaced_monte_carlo` — Table 6.1: MOSPA of the ideal filter, PDAF, MHT and
  ECMHT on the two-target OU problem, scored on the one-step prediction ``X(k|k−1)``.
* :func:`summarise_closely_spaced` — pool shards into Table 6.1 with standard errors.
* :func:`closely_spaced_realisation` — one realisation's tracks (Figs 6.1–6.2).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.special import gammaln

from .seeds import experiment_seeds
from .._validation import check_finite_array, check_int, check_nonnegative, check_positive
from ..models.motion import OrnsteinUhlenbeck
from ..report import Claim
from ..scenarios.closely_spaced import simulate_closely_spaced, static_pair_scans
from ..trackers.ecmht import PDAF_VARIANTS, ECMHTFilter, GNNFilter, IdealFilter, PDAFilter, mospa_two_targets

__all__ = [
    "TABLE_6_1",
    "swap_shard",
    "summarise_swaps",
    "shard_runs",
    "summarise_closely_spaced",
    "pool_per_scan",
    "closely_spaced_monte_carlo",
    "closely_spaced_realisation",
    "swap_claims",
    "plot_swap_figures",
]

#: Published MOSPA (m², see reconstruction §5.4) of Table 6.1.
TABLE_6_1 = {"ideal": 0.0363, "PDAF": 0.8518, "MHT": 0.1376, "ECMHT": 0.0586}


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
        log-posterior of the one swapped hypothesis drawn). Pool shards with :func:`summarise_swaps`.
    """
    distances = check_finite_array(distances, "distances", ndim=1)
    n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    sigma = check_positive(sigma, "sigma")
    children = (np.random.SeedSequence(seed) if isinstance(seed, int) else seed).spawn(len(distances))
    frames = []
    for dist, child in zip(distances, children):
        rng = np.random.default_rng(child)
        truth, Z_lower, Z_upper = static_pair_scans(float(dist), n_runs=n_runs, n_sensors=n_sensors, sigma=sigma, rng=rng)
        sq_err, log_single = _swap_statistics(Z_lower, Z_upper, truth, sigma, rng)
        frames.append(pd.DataFrame({
            "distance": float(dist), "swaps": np.arange(n_sensors + 1), "n_runs": n_runs,
            "sum_sq_err": sq_err.sum(axis=0), "sum_log_prob_single": log_single.sum(axis=0),
        }))
    return pd.concat(frames, ignore_index=True)


def summarise_swaps(shards: pd.DataFrame):
    """Pool :func:`swap_shard` tables into the curves of Figs 5.1–5.2 and the rates of Fig. 5.3.

    Returns
    -------
    curves : pandas.DataFrame
        Per (distance, swaps): ``rms`` (m) of the equivalent measurement over targets and runs,
        ``log_prob_single`` (mean log-posterior of one hypothesis with that many swaps) and
        ``log_prob_class`` (plus ``ln C(N, i)``, Eq. 5.22).
    rates : pandas.DataFrame
        Per distance: ``rms_optimal_swaps`` / ``rms_optimal_rate`` (the ``i`` minimising the RMS,
        and ``i/N``), ``class_optimal_swaps`` / ``class_optimal_rate`` (maximising the class
        log-probability), ``rms_at_optimum`` and ``rms_no_swaps`` (m).
    """
    pooled = shards.groupby(["distance", "swaps"], as_index=False)[["n_runs", "sum_sq_err", "sum_log_prob_single"]].sum()
    n_sensors = int(pooled["swaps"].max())
    curves = pooled[["distance", "swaps"]].copy()
    curves["rms"] = np.sqrt(pooled["sum_sq_err"] / pooled["n_runs"])
    curves["log_prob_single"] = pooled["sum_log_prob_single"] / pooled["n_runs"]
    curves["log_prob_class"] = curves["log_prob_single"] + _log_binom(n_sensors)[curves["swaps"].to_numpy()]
    curves["n_runs"] = pooled["n_runs"]
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


def shard_runs(n_runs: int, n_shards: int, shard: int) -> int:
    """Number of Monte Carlo runs of shard ``shard`` when ``n_runs`` are split over ``n_shards``."""
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    n_shards = check_int(n_shards, "n_shards", minimum=1, maximum=n_runs)
    shard = check_int(shard, "shard", minimum=0, maximum=n_shards - 1)
    return n_runs // n_shards + (1 if shard < n_runs % n_shards else 0)


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


def summarise_closely_spaced(per_run: pd.DataFrame, pdaf_variant: str) -> pd.DataFrame:
    """Pool per-run MOSPA (columns ``method, run, mospa``) into Table 6.1.

    Returns one row per method with ``published_mospa`` (NaN for methods the paper does not
    list), ``reproduced_mospa`` (mean over runs and scans, m²), ``std_error`` (standard error
    over runs), ``relative_difference`` and ``n_runs``; the row ``PDAF`` is the PDAF form
    ``pdaf_variant``, the other forms follow as ``PDAF[<variant>]``.
    """
    g = per_run.groupby("method", sort=False)["mospa"]
    table = pd.DataFrame({"reproduced_mospa": g.mean(), "std_error": g.std(ddof=1) / np.sqrt(g.count()), "n_runs": g.count()})
    order = [m for m in TABLE_6_1] + sorted(m for m in table.index if m not in TABLE_6_1)
    table = table.loc[[m for m in order if m in table.index]].reset_index()
    table.insert(1, "published_mospa", table["method"].map(TABLE_6_1).astype(float))
    table["relative_difference"] = table["reproduced_mospa"] / table["published_mospa"] - 1
    table["pdaf_variant"] = np.where(table["method"] == "PDAF", pdaf_variant,
                                     table["method"].str.extract(r"PDAF\[(\w+)\]", expand=False).fillna(""))
    return table


def pool_per_scan(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Pool per-shard per-scan MOSPA means (``method, scan, time, mospa, n_runs``), weighting by runs."""
    df = per_scan.assign(weighted=per_scan["mospa"] * per_scan["n_runs"])
    g = df.groupby(["method", "scan", "time"], sort=False, as_index=False)[["weighted", "n_runs"]].sum()
    g["mospa"] = g["weighted"] / g["n_runs"]
    return g[["method", "scan", "time", "mospa", "n_runs"]]


# ---------------------------------------------------------------- swaps: ledger and figures
def _swap_curve(curves: pd.DataFrame, distance: float) -> pd.DataFrame:
    return curves[np.isclose(curves["distance"], distance)].sort_values("swaps")


def swap_claims(curves: pd.DataFrame, rates: pd.DataFrame, *, distance: float, n_sensors: int) -> list:
    """Ledger rows of Figs 5.1–5.3: the RMS minimum near 4 swaps (3–5), the class-posterior peak
    within 3 swaps of it, the optimal swap rate 0.5 (± 1/N) at zero distance and 0 for the
    farthest distance simulated."""
    c = _swap_curve(curves, distance)
    i_min = int(c["swaps"].to_numpy()[np.argmin(c["rms"].to_numpy())])
    i_cls = int(c["swaps"].to_numpy()[np.argmax(c["log_prob_class"].to_numpy())])
    r = rates.set_index("distance").sort_index()
    near, far = r["rms_optimal_rate"].iloc[0], r.index.max()
    ev = "published number"
    return [
        Claim("swaps", "Fig 5.1 RMS minimum at about 4 swaps", "003 Sec. 5, Fig 5.1", "about 4", str(i_min),
              "3-5 swaps", "reproduced" if 3 <= i_min <= 5 else "not reproduced",
              f"RMS {c['rms'].iloc[0]:.3g} m with no swaps, {c['rms'].min():.3g} m at the minimum", ev,
              key="rms_minimum"),
        Claim("swaps", "Fig 5.2 class posterior peak consistent with Fig 5.1", "003 Sec. 5, Fig 5.2",
              "consistent with about 4", str(i_cls), "within 3 of the RMS minimum",
              "reproduced" if abs(i_cls - i_min) <= 3 else "not reproduced",
              "the single-hypothesis curve peaks at 0 swaps (the MAP hypothesis has none)", ev, key="class_peak"),
        Claim("swaps", "Fig 5.3 optimal swap rate at zero distance", "003 Sec. 5, Fig 5.3", "0.5", f"{near:.3g}",
              f"+/- 1/{n_sensors}", "reproduced" if abs(near - 0.5) <= 1 / n_sensors + 1e-12 else "not reproduced",
              "", ev, key="rate_zero_distance"),
        Claim("swaps", "Fig 5.3 optimal swap rate for distant targets", "003 Sec. 5, Fig 5.3", "0",
              f"{r.loc[far, 'rms_optimal_rate']:.3g} at {far:g} m", "exact",
              "reproduced" if r.loc[far, "rms_optimal_rate"] == 0 else "not reproduced",
              f"first zero at {r.index[r['rms_optimal_rate'] == 0].min():g} m", ev, key="rate_far"),
    ]


def plot_swap_figures(curves: pd.DataFrame, rates: pd.DataFrame, *, distance: float, n_sensors: int,
                      sigma: float, paths: dict) -> None:
    """Figs 5.1, 5.2 and 5.3; ``paths`` maps ``fig51/fig52/fig53`` to ``(pdf, png)``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = _swap_curve(curves, distance)
    n = int(c["n_runs"].iloc[0])
    setting = f"{distance:g} m apart, {n_sensors} sensors, sigma = {sigma:g} m, {n} runs"

    def figure(key, draw, xlabel, ylabel, title):
        fig, ax = plt.subplots(figsize=(6.5, 4.2))
        draw(ax)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.legend()
        fig.tight_layout()
        for path, kw in zip(paths[key], ({}, {"dpi": 150})):
            fig.savefig(path, **kw)
        plt.close(fig)

    i_min = int(c["swaps"].to_numpy()[np.argmin(c["rms"].to_numpy())])

    def fig51(ax):
        ax.plot(c["swaps"], c["rms"], "o-", ms=3)
        ax.axvline(i_min, color="gray", ls=":", label=f"minimum at {i_min} swaps")

    def fig52(ax):
        ax.plot(c["swaps"], c["log_prob_single"], "o-", ms=3, label="unique hypothesis")
        ax.plot(c["swaps"], c["log_prob_class"], "s-", ms=3, label="hypothesis class (Eq. 5.22)")

    def fig53(ax):
        ax.plot(rates["distance"], rates["rms_optimal_rate"], "o-", ms=3, label="minimum RMS error (Fig 5.1 criterion)")
        ax.plot(rates["distance"], rates["class_optimal_rate"], "s--", ms=3, label="maximum class posterior (Eq. 5.22)")
        ax.set_ylim(-0.02, 0.55)

    figure("fig51", fig51, "number of random measurement swaps i", "RMS error of the equivalent measurement (m)",
           f"Fig 5.1: equivalent-measurement error vs swaps\n({setting})")
    figure("fig52", fig52, "number of swaps i", "average log posterior probability",
           f"Fig 5.2: single-hypothesis vs class posterior\n({setting})")
    figure("fig53", fig53, "distance between targets (m)", "optimal swap rate i*/N",
           f"Fig 5.3: optimal swap rate vs target separation\n({n_sensors} sensors, sigma = {sigma:g} m, "
           f"{n} runs per distance)")

"""Document 003 Table 6.1 and Figs 6.1–6.2: two closely spaced OU targets seen by N sensors.

* :func:`closely_spaced_monte_carlo` — one shard of Table 6.1: MOSPA of the ideal filter,
  PDAF, MHT and ECMHT, scored on the one-step prediction ``X(k|k−1)`` (reconstruction §6.4),
  per run over every scored scan and over the scans after the filters' transient.
* :func:`summarise_closely_spaced` — pool shards into Table 6.1: n, mean, standard error,
  published value, z and the ledger's one Monte Carlo verdict
  (:func:`hypotrack.reporting.verdict.monte_carlo_verdict`).
* :func:`closely_spaced_realisation` — one realisation's tracks (Figs 6.1–6.2).

The ideal filter's MOSPA has a closed form (:mod:`.oracle`); the ledger rows and
figures built from these tables are in :mod:`.claims` and
:mod:`.figures`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..._validation import check_int, check_nonnegative, check_positive
from ...models.motion import OrnsteinUhlenbeck
from ...reporting.verdict import monte_carlo_verdict
from ...scenarios.closely_spaced import simulate_closely_spaced
from ...trackers.ecmht import PDAF_VARIANTS, ECMHTFilter, GNNFilter, IdealFilter, PDAFilter, mospa_two_targets
from .power import control_verdict
from .published import TABLE_6_1
from .controls import (CONTROLS, IndependentOrderECMHTFilter, NonExclusiveNNFilter, PredictionOnlyFilter,
                       RandomHypothesisGNNFilter, SwappedLabelGNNFilter, controlled_method, misstated_noise_name)

__all__ = [
    "LABELLED_IDEAL",
    "realisation_table",
    "shard_tables",
    "TABLE_6_1",
    "closely_spaced_monte_carlo",
    "closely_spaced_realisation",
    "pool_per_scan",
    "summarise_closely_spaced",
]


#: The ideal filter scored against its own targets (known association, no best pairing per scan).
LABELLED_IDEAL = "ideal[labelled]"


def _filters(model, R, n_sensors, dt, ecmht_rng, pdaf_variant):
    return {
        "ideal": IdealFilter(model, R, n_sensors, dt),
        "PDAF": PDAFilter(model, R, n_sensors, dt, variant=pdaf_variant),
        "MHT": GNNFilter(model, R, n_sensors, dt),
        "ECMHT": ECMHTFilter(model, R, n_sensors, dt, rng=ecmht_rng),
    }


def _scenario_and_filters(sigma2, gamma, n_runs, n_scans, n_sensors, R, dt, initial_variance, pdaf_variant, seed,
                          controls=False, noise_factors=()):
    """Simulate the scenario and build the four filters from independent child streams of ``seed``
    (scenario, ECMHT orders; with ``controls``, the negative controls of :mod:`.controls` too, the
    ECMHT control from a third stream and the random-hypothesis MHT from a child of that stream, so
    the other streams are unchanged; ``noise_factors``: the MHT with R × factor for each)."""
    model = OrnsteinUhlenbeck(sigma2, gamma)
    scen_seed, ecmht_seed, control_seed = (np.random.SeedSequence(seed) if isinstance(seed, int) else seed).spawn(3)
    real = simulate_closely_spaced(
        model, n_runs=n_runs, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
        initial_variance=initial_variance, rng=np.random.default_rng(scen_seed),
    )
    filters = _filters(model, R, n_sensors, dt, np.random.default_rng(ecmht_seed), pdaf_variant)
    if controls:
        filters["ideal[blind]"] = PredictionOnlyFilter(model, R, n_sensors, dt)
        filters["MHT[swapped labels]"] = SwappedLabelGNNFilter(model, R, n_sensors, dt)
        filters["ECMHT[independent orders]"] = IndependentOrderECMHTFilter(
            model, R, n_sensors, dt, rng=np.random.default_rng(control_seed))
        (coin_seed,) = control_seed.spawn(1)  # a child: the ECMHT control's stream above is unchanged
        filters["MHT[random hypothesis]"] = RandomHypothesisGNNFilter(model, R, n_sensors, dt,
                                                                      rng=np.random.default_rng(coin_seed))
        filters["MHT[no joint hypothesis]"] = NonExclusiveNNFilter(model, R, n_sensors, dt)
        for factor in noise_factors:
            filters[misstated_noise_name(factor)] = GNNFilter(model, R * factor, n_sensors, dt)
    return model, real, filters


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
    transient_scans: int = 0,
    controls: bool = False,
    noise_factors=(),
    seed,
) -> dict:
    """Table 6.1: MOSPA of the ideal filter, PDAF, MHT and ECMHT over ``n_runs`` realisations.

    Each scan ``k ≥ 2`` is scored with :func:`~hypotrack.trackers.ecmht.mospa_two_targets` of
    the one-step predictions ``X(k|k−1)`` against the truth ``x_k`` (reconstruction §6.4): the
    better of the two track–truth pairings, chosen per scan. The ideal filter is also scored
    against its own targets (:data:`LABELLED_IDEAL`), the error its Riccati variance describes.

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
    transient_scans : int
        Scored scans (from scan 2 on) left out of the ``per_run_steady`` means, 0 .. n_scans − 2.
    controls : bool
        Also run the negative controls of :mod:`.controls` (:data:`~.controls.CONTROLS`), scored the
        same way; the blind control is also scored against its own targets (``ideal[blind, labelled]``).
    noise_factors : sequence of float
        With ``controls``: also the MHT whose filter assumes the measurement variance ``R × factor``
        (each factor > 0 and ≠ 1), scored as ``MHT[R × <factor>]``.
    seed : int or numpy.random.SeedSequence
        Seeds the scenario and the ECMHT's sensor orders (two independent streams).

    Returns
    -------
    dict
        ``per_run`` — method → (n_runs,) mean MOSPA of each run over scans 2..n_scans;
        ``per_run_steady`` — the same over the scans after the first ``transient_scans`` scored
        ones; ``per_scan`` — method → (n_scans − 1,) MOSPA averaged over runs for scans
        2..n_scans; ``mean_swaps`` — the ECMHT's mean ``i*`` per scan.
    """
    for v in (pdaf_variant, *extra_pdaf_variants):
        if v not in PDAF_VARIANTS:
            raise ValueError(f"PDAF variant must be one of {PDAF_VARIANTS}, got {v!r}")
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    noise_factors = [check_positive(f, "noise_factors") for f in noise_factors]
    if any(f == 1 for f in noise_factors) or len(set(noise_factors)) != len(noise_factors):
        raise ValueError(f"noise_factors must be distinct and differ from 1 (1 is the MHT itself), got {noise_factors}")
    transient_scans = check_int(transient_scans, "transient_scans", minimum=0, maximum=n_scans - 2)
    model, real, filters = _scenario_and_filters(sigma2, gamma, n_runs, n_scans, n_sensors, R, dt, initial_variance,
                                                 pdaf_variant, seed, controls, noise_factors)
    for v in extra_pdaf_variants:
        filters[f"PDAF[{v}]"] = PDAFilter(model, R, n_sensors, dt, variant=v)
    labelled = {LABELLED_IDEAL: "ideal", **({"ideal[blind, labelled]": "ideal[blind]"} if controls else {})}
    names = [*filters, *labelled]
    scores = {name: np.empty((real.truth.shape[0], n_scans - 1)) for name in names}
    swaps = np.empty(n_scans - 1)
    for k in range(n_scans):
        for name, f in filters.items():
            f.step(real.scans[:, k])
            if k > 0:
                scores[name][:, k - 1] = mospa_two_targets(f.predictions(), real.truth[:, k])
        if k > 0:
            for name, source in labelled.items():
                err = filters[source].predictions() - real.truth[:, k]
                scores[name][:, k - 1] = 0.5 * (err**2).sum(axis=1)
            swaps[k - 1] = filters["ECMHT"].last_swaps.mean()
    return {
        "per_run": {name: s.mean(axis=1) for name, s in scores.items()},
        "per_run_steady": {name: s[:, transient_scans:].mean(axis=1) for name, s in scores.items()},
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


def realisation_table(res: dict) -> pd.DataFrame:
    """The tracks of :func:`closely_spaced_realisation` as a table (``time, truth_0, truth_1, ...``)."""
    table = pd.DataFrame({"time": res["time"]})
    for name in ("truth", "ideal", "PDAF", "MHT", "ECMHT"):
        for j in range(2):
            table[f"{name}_{j}"] = res[name][:, j]
    return table


def shard_tables(res: dict, *, first_run: int, dt: float) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per-run (``method, run, mospa, mospa_steady``) and per-scan tables of one shard."""
    per_run = pd.concat([
        pd.DataFrame({"method": m, "run": first_run + np.arange(len(v)), "mospa": v,
                      "mospa_steady": res["per_run_steady"][m]})
        for m, v in res["per_run"].items()
    ])
    n_runs = len(next(iter(res["per_run"].values())))
    per_scan = pd.concat([
        pd.DataFrame({"method": m, "scan": np.arange(1, len(v) + 1), "time": np.arange(1, len(v) + 1) * dt,
                      "mospa": v, "n_runs": n_runs})
        for m, v in res["per_scan"].items()
    ])
    return per_run, per_scan


def summarise_closely_spaced(per_run: pd.DataFrame, pdaf_variant: str, *, rel_tol: float,
                             column: str = "mospa", published_runs: int | None = None) -> pd.DataFrame:
    """Pool per-run MOSPA (columns ``method, run, <column>``) into Table 6.1.

    One row per method: ``n`` (runs), ``mean`` (MOSPA over runs and scans, m²), ``se`` (standard
    error over runs), ``published`` (NaN for rows the paper does not list), ``relative_difference``,
    ``z = (mean − published)/se`` and ``verdict`` by the ledger's Monte Carlo rule with the
    reconstruction tolerance ``rel_tol × published`` (``published_runs``: the runs behind the
    published numbers, whose own Monte Carlo error widens the interval); the row ``PDAF`` is the PDAF
    form ``pdaf_variant``, the other forms follow as ``PDAF[<variant>]``. The labelled ideal is
    compared with the ideal's published value, and each negative control of :data:`~.controls.CONTROLS`
    (and each misstated-noise MHT) with the published value of the method it controls, the published
    number's own error taken from that method's spread (:func:`~.power.control_verdict`; a control's
    verdict should be "not reproduced").
    """
    rel_tol = check_nonnegative(rel_tol, "rel_tol")
    if published_runs is not None:
        published_runs = check_int(published_runs, "published_runs", minimum=1)
    g = per_run.groupby("method", sort=False)[column]
    table = pd.DataFrame({"n": g.count(), "mean": g.mean(), "se": g.std(ddof=1) / np.sqrt(g.count())})
    order = [*TABLE_6_1, LABELLED_IDEAL, *CONTROLS]
    order += sorted(m for m in table.index if m not in order)
    table = table.loc[[m for m in order if m in table.index]].reset_index()
    published = {**TABLE_6_1, LABELLED_IDEAL: TABLE_6_1["ideal"]}
    published.update({name: published[of] for name, (of, _) in CONTROLS.items()})
    published.update({m: published[controlled_method(m)] for m in table["method"] if controlled_method(m)})
    table["published"] = table["method"].map(published).astype(float)
    table["relative_difference"] = table["mean"] / table["published"] - 1
    rows = table.set_index("method")
    z, verdict = [], []
    for r in table.itertuples():
        if np.isnan(r.published):
            z.append(np.nan)
            verdict.append("")
            continue
        of = controlled_method(r.method)
        if of in rows.index and published_runs is not None:  # the published error from the method's spread
            v = control_verdict(rows.loc[r.method], rows.loc[of], r.published, rel_tol * r.published, published_runs)
        else:
            v = monte_carlo_verdict(r.mean, r.se, r.published, rel_tol * r.published, int(r.n), published_runs)
        z.append(v.z)
        verdict.append(v.status)
    table["z"] = z
    table["verdict"] = verdict
    table["pdaf_variant"] = np.where(table["method"] == "PDAF", pdaf_variant,
                                     table["method"].str.extract(r"PDAF\[(\w+)\]", expand=False).fillna(""))
    return table


def pool_per_scan(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Pool per-shard per-scan MOSPA means (``method, scan, time, mospa, n_runs``), weighting by runs."""
    df = per_scan.assign(weighted=per_scan["mospa"] * per_scan["n_runs"])
    g = df.groupby(["method", "scan", "time"], sort=False, as_index=False)[["weighted", "n_runs"]].sum()
    g["mospa"] = g["weighted"] / g["n_runs"]
    return g[["method", "scan", "time", "mospa", "n_runs"]]

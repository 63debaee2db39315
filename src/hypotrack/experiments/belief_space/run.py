"""Document 001's numeric claims, from the formulas and from the hypothesis engine's own weights.

Three claims of Chakravorty, Faber, Hussein & Mishra (document 001):

* **Eq. 39** — a hypothesis with one undetected birth weighs ``(1 − p_D) α`` times its twin
  without it. Engine: the children of :meth:`hypotrack.hypotheses.HypothesisFilter.expand`
  of kind ``UNDETECTED_BIRTH`` against their association twins, for document 001's binomial birth
  (in the Poisson limit of Eq. 33, and exact) and document 000's single-event model.
* **Eq. 43** — one scan later, the child ``γ`` that assigns a return ``z*`` to the undetected
  birth weighs less than ``(1 − p_D)`` times the child ``γ'`` that explains ``z*`` as a new birth.
  Formula: ``ω^γ/ω^γ' = (1 − p_D) V̄ ∫ p(z*|x) p_b⁻(x) dx`` (Eq. 42), evaluated for the paper's
  uniform pixel birth and for the Gaussian birth pdf the engine carries for an undetected birth
  (a moment match of the pixel); engine: the same two children in a two-scan run.
* **Sec. V-A** — for a fixed number of targets FISST with Poisson clutter (Eq. 18) and Reid's
  HOMHT (Eq. 30) give identical posteriors; H-FISST (document 000 Eq. 8) does not.

This module runs the checks and returns their tables; the figures drawn from them are in
:mod:`.figures`, the checks table and the ledger rows in :mod:`.claims`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.special import logsumexp
from scipy.stats import norm

from ...gaussian import innovation, log_likelihood, predict_with
from ...hypotheses import (ChildSet, ExhaustiveGenerator, FISSTPoissonWeights, HFISSTWeights,
                                  HypothesisFilter, ReidWeights)
from ...hypotheses.population_events import BinomialPopulation, SingleEventPopulation, birth_prior_gaussian
from ...models import ConstantVelocity
from ...models.population import SingleEventBirthDeath, UniformBirthDensity
from ...models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from ...scenarios.cluttered import simulate_cv_targets

__all__ = [
    "ratio_table",
    "eq43_offsets_table",
    "eq43_noise_table",
    "equivalence_table",
]

# ---------------------------------------------------------------------------------------------
# Eq. 39: undetected-birth weight ratio


def _pixel_row(n_pixels: int, size: float):
    """``n_pixels`` square pixels of side ``size`` in a row, and the box that holds them."""
    pixels = [Box([i * size, 0.0], [(i + 1) * size, size]) for i in range(n_pixels)]
    return pixels, Box([0.0, 0.0], [n_pixels * size, size])


def _sensor(p_D, region, measurement_var, clutter_rate):
    return Sensor(LinearPositionSensor(np.eye(2) * measurement_var, 4), DetectionModel(p_D, region),
                  PoissonClutter(clutter_rate, region))


def twin_log_ratios(children: ChildSet) -> np.ndarray:
    """``log(w_v / w_v')`` for every undetected-birth child ``v`` and its association twin ``v'``
    (same parent, same association event)."""
    twin = {(p, ev.tobytes()): w for p, ev, k, w in
            zip(children.parent, children.events, children.kind, children.log_weights) if k == ChildSet.ASSOCIATION}
    return np.array([w - twin[(p, ev.tobytes())] for p, ev, k, w in
                     zip(children.parent, children.events, children.kind, children.log_weights)
                     if k == ChildSet.UNDETECTED_BIRTH])


def _ratio_scene(cfg):
    """Two targets in a row of pixels and four returns: two near the targets, two elsewhere
    (candidate births), so that twins with 0, 1 and 2 detected births all occur."""
    size = float(cfg["pixel_size"])
    pixels, region = _pixel_row(int(cfg["n_pixels"]), size)
    width = region.high[0]
    means = np.array([[0.15 * width, 0.2 * size, 1.0, 0.0], [0.85 * width, 0.8 * size, 0.0, -1.0]])
    covs = np.repeat(np.eye(4)[None], 2, axis=0)
    Z = np.array([[0.15 * width + 1.2, 0.2 * size + 1.1], [0.85 * width - 0.2, 0.8 * size - 1.0],
                  [0.4 * width, 0.9 * size], [0.6 * width, 0.1 * size]])
    return pixels, region, means, covs, Z


def engine_twin_ratios(p_D: float, alpha: float, model: str, cfg) -> np.ndarray:
    """The engine's ``w_v / w_v'`` for every undetected-birth twin pair (one scan, exhaustive).

    ``model``: ``"poisson_limit"`` / ``"binomial"`` (document 001 birth, FISST weights) or
    ``"single_event"`` (document 000 Eq. 30, H-FISST weights).
    """
    pixels, region, means, covs, Z = _ratio_scene(cfg)
    densities = [UniformBirthDensity(px, np.eye(2) * float(cfg["velocity_std"]) ** 2) for px in pixels]
    if model == "single_event":
        population = SingleEventPopulation(SingleEventBirthDeath(alpha, float(cfg["beta"]), len(pixels)),
                                           birth_densities=densities)
        weights = HFISSTWeights()
    elif model in ("poisson_limit", "binomial"):
        population = BinomialPopulation(densities, alpha=alpha, poisson_limit=model == "poisson_limit")
        weights = FISSTPoissonWeights()
    else:
        raise ValueError(f"model must be poisson_limit, binomial or single_event, got {model!r}")
    sensor = _sensor(p_D, region, float(cfg["measurement_var"]), float(cfg["clutter_rate"]))
    filt = HypothesisFilter(ConstantVelocity(float(cfg["q"])), sensor, weights, ExhaustiveGenerator(),
                            population=population, max_hypotheses=10**6, means=means, covs=covs)
    return np.exp(twin_log_ratios(filt.expand(Z)))


def ratio_table(cfg) -> pd.DataFrame:
    """Eq. 39 over the grid ``cfg["p_D"] × cfg["alpha"]``: formulas and the engine, side by side.

    Columns: ``eq39`` = (1 − p_D) α; ``exact_binomial`` = (1 − p_D) α / (1 − α) (Eq. 31 without
    Eq. 33); ``single_event`` = (1 − p_D) α / (1 − M_b α − M_d β) (document 000 Eq. 30, both targets in
    view); ``engine_<model>`` the engine's mean ratio and ``engine_<model>_spread`` its largest
    relative deviation over all twin pairs of the scan.
    """
    rows = []
    n_pixels, beta = int(cfg["n_pixels"]), float(cfg["beta"])
    for p_D in cfg["p_D"]:
        for alpha in cfg["alpha"]:
            row = {"p_D": p_D, "alpha": alpha, "eq39": (1 - p_D) * alpha,
                   "exact_binomial": (1 - p_D) * alpha / (1 - alpha),
                   "single_event": (1 - p_D) * alpha / (1 - n_pixels * alpha - 2 * beta)}
            for model in ("poisson_limit", "binomial", "single_event"):
                r = engine_twin_ratios(p_D, alpha, model, cfg)
                row[f"engine_{model}"] = float(np.mean(r))
                row[f"engine_{model}_spread"] = float(np.max(np.abs(r / np.mean(r) - 1)))
                row[f"engine_{model}_pairs"] = len(r)
            rows.append(row)
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------------------
# Eq. 42-43: one scan after an undetected birth


def _eq43_filter(cfg, measurement_std: float):
    if not 0 <= int(cfg["pixel"]) < int(cfg["n_pixels"]):
        raise ValueError(f"belief_space.eq43.pixel must lie in [0, n_pixels - 1], got {cfg['pixel']}")
    size = float(cfg["pixel_size"])
    pixels, region = _pixel_row(int(cfg["n_pixels"]), size)
    vel_cov = np.eye(2) * float(cfg["velocity_std"]) ** 2
    densities = [UniformBirthDensity(px, vel_cov) for px in pixels]
    population = BinomialPopulation(densities, alpha=float(cfg["alpha"]), poisson_limit=True)
    sensor = _sensor(float(cfg["p_D"]), region, measurement_std**2, float(cfg["clutter_rate"]))
    filt = HypothesisFilter(ConstantVelocity(float(cfg["q"])), sensor, FISSTPoissonWeights(), ExhaustiveGenerator(),
                            population=population, dt=float(cfg["dt"]), max_hypotheses=10**6)
    return filt, densities, pixels


def engine_gamma_ratio(cfg, measurement_std: float, offsets) -> np.ndarray:
    """The engine's ``ω^γ / ω^γ'`` for a return ``z*`` at each ``offset`` (pixel widths, along x)
    from the centre of pixel ``cfg["pixel"]``, one scan after a scan with no returns.

    Scan 1 is empty: the engine keeps ``v'`` (no birth) and, per pixel, ``v`` (one undetected
    birth, weight ratio ``(1 − p_D) α``). Scan 2 holds only ``z*``: ``γ`` is the child of ``v``
    that assigns ``z*`` to its undetected birth, ``γ'`` the child of ``v'`` that assigns it to a
    new birth in the same pixel.
    """
    r_star = int(cfg["pixel"])
    size = float(cfg["pixel_size"])
    out = []
    for offset in np.atleast_1d(offsets):
        filt, _, pixels = _eq43_filter(cfg, measurement_std)
        filt.step(np.zeros((0, 2)))
        kept = filt.last_kept
        v = int(np.flatnonzero((kept.kind == ChildSet.UNDETECTED_BIRTH) & (kept.arg == r_star))[0])
        v_prime = int(np.flatnonzero(kept.kind == ChildSet.ASSOCIATION)[0])
        centre = (pixels[r_star].low + pixels[r_star].high) / 2
        z_star = centre + np.array([offset * size, 0.0])
        children = filt.expand(z_star[None, :])
        assoc = children.kind == ChildSet.ASSOCIATION
        # v holds one object (code 0); v' holds none, so birth column r* has code 0 + r*.
        gamma = assoc & (children.parent == v) & (children.events[:, 0] == 0)
        gamma_p = assoc & (children.parent == v_prime) & (children.events[:, 0] == r_star)
        if gamma.sum() != 1 or gamma_p.sum() != 1:
            raise RuntimeError("could not identify the children gamma and gamma' in the engine's expansion")
        out.append(float(np.exp(children.log_weights[gamma][0] - children.log_weights[gamma_p][0])))
    return np.array(out)


def gaussian_formula_ratio(cfg, measurement_std: float, offsets) -> np.ndarray:
    """Eq. 42 with the engine's Gaussian undetected-birth pdf: ``(1 − p_D) V̄ N(z*; H x̂⁻, S⁻)``.

    The pdf is :func:`birth_prior_gaussian` of the pixel (a moment match) predicted by the same
    constant-velocity model — evaluated with :mod:`hypotrack.gaussian`, not by the engine.
    """
    r_star, size, dt = int(cfg["pixel"]), float(cfg["pixel_size"]), float(cfg["dt"])
    _, densities, pixels = _eq43_filter(cfg, measurement_std)
    mean, cov = birth_prior_gaussian(densities[r_star])
    x_pred, P_pred = predict_with(ConstantVelocity(float(cfg["q"])), mean, cov, dt)
    H = np.hstack([np.eye(2), np.zeros((2, 2))])
    z_pred, S, _ = innovation(x_pred, P_pred, H, np.eye(2) * measurement_std**2)
    centre = (pixels[r_star].low + pixels[r_star].high) / 2
    z = centre[None, :] + np.outer(np.atleast_1d(offsets) * size, [1.0, 0.0])
    loglik = np.array([log_likelihood(zi, z_pred, S) for zi in z])
    return (1 - float(cfg["p_D"])) * pixels[r_star].area * np.exp(loglik)


def _position_spread_var(cfg, measurement_std: float) -> float:
    """Per-axis variance added to a birth position in one scan: velocity, process noise, sensor."""
    dt = float(cfg["dt"])
    return dt**2 * float(cfg["velocity_std"]) ** 2 + float(cfg["q"]) * dt**3 / 3 + measurement_std**2


def uniform_formula_ratio(cfg, measurement_std: float, offsets) -> np.ndarray:
    """Eq. 42 for the paper's uniform pixel birth (document 001 Eq. 31), exactly.

    The predicted position is uniform on the square pixel plus Gaussian spread ``s²`` per axis,
    so ``V̄ ∫ p(z*|x) p_b⁻(x) dx = Π_axes [Φ((d + L/2)/s) − Φ((d − L/2)/s)] ≤ 1``.
    """
    L = float(cfg["pixel_size"])
    s = np.sqrt(_position_spread_var(cfg, measurement_std))
    d = np.atleast_1d(offsets) * L
    along = norm.cdf((d + L / 2) / s) - norm.cdf((d - L / 2) / s)
    across = norm.cdf(L / 2 / s) - norm.cdf(-L / 2 / s)
    return (1 - float(cfg["p_D"])) * along * across


def uniform_centre_deficit(cfg, measurement_std: float) -> float:
    """``1 − ratio / (1 − p_D)`` at the pixel centre for the uniform birth, without cancellation:
    ``1 − (1 − 2 Φ(−L/2s))² = 4 Φ(−L/2s) (1 − Φ(−L/2s))`` (strictly positive: Eq. 43 is strict)."""
    tail = norm.sf(float(cfg["pixel_size"]) / 2 / np.sqrt(_position_spread_var(cfg, measurement_std)))
    return float(4 * tail * (1 - tail))


def variance_matched_centre_ratio(cfg, measurement_std) -> np.ndarray:
    """Analytic Eq. 42 at the pixel centre for a Gaussian matched to the pixel's variance L²/12:
    ``(1 − p_D) (6/π) L² / (L² + 12 e)``, ``e`` the per-axis spread; above ``1 − p_D`` while
    ``e < (6/π − 1) L² / 12``."""
    L = float(cfg["pixel_size"])
    e = np.array([_position_spread_var(cfg, s) for s in np.atleast_1d(measurement_std)])
    return (1 - float(cfg["p_D"])) * (6 / np.pi) * L**2 / (L**2 + 12 * e)


def eq43_offsets_table(cfg) -> pd.DataFrame:
    """Eq. 43 across the pixel at ``cfg["measurement_std"]``: ratio / (1 − p_D) per offset."""
    offsets = np.linspace(-0.5, 0.5, int(cfg["n_offsets"]))
    s = float(cfg["measurement_std"])
    scale = 1 - float(cfg["p_D"])
    return pd.DataFrame({
        "offset_pixels": offsets,
        "uniform_formula": uniform_formula_ratio(cfg, s, offsets) / scale,
        "gaussian_formula": gaussian_formula_ratio(cfg, s, offsets) / scale,
        "engine": engine_gamma_ratio(cfg, s, offsets) / scale,
    })


def eq43_noise_table(cfg) -> pd.DataFrame:
    """Eq. 43 at the pixel centre against the measurement noise: where does the bound start to hold?"""
    rows = []
    scale = 1 - float(cfg["p_D"])
    for s in cfg["noise_sweep"]:
        rows.append({
            "measurement_std": s,
            "spread_over_pixel_area": _position_spread_var(cfg, s) / float(cfg["pixel_size"]) ** 2,
            "uniform_formula": float(uniform_formula_ratio(cfg, s, 0.0)[0]) / scale,
            "uniform_deficit_at_centre": uniform_centre_deficit(cfg, s),
            "gaussian_formula": float(gaussian_formula_ratio(cfg, s, 0.0)[0]) / scale,
            "variance_matched_analytic": float(variance_matched_centre_ratio(cfg, s)[0]) / scale,
            "engine": float(engine_gamma_ratio(cfg, s, 0.0)[0]) / scale,
        })
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------------------
# Sec. V-A: FISST = HOMHT for a fixed number of targets


def _by_lineage(filt):
    store = filt.store
    return {key: (lw, store.means[t]) for key, lw, t in zip(filt.lineage_keys, filt.log_weights, filt.track_lists)}


def _tv(a: dict, b: dict) -> float:
    """Total-variation distance of two posteriors keyed by lineage (absent = weight 0)."""
    weight = lambda d, k: float(np.exp(d[k][0])) if k in d else 0.0  # noqa: E731
    return 0.5 * sum(abs(weight(a, k) - weight(b, k)) for k in set(a) | set(b))


def equivalence_table(cfg, seed: int) -> pd.DataFrame:
    """FISST-Poisson, Reid and H-FISST filters on seeded cluttered scenarios, compared by lineage.

    Per run and scan: the largest |Δ log w| and |Δ mean| between FISST and Reid over their common
    hypotheses (identical sets are required), and the total-variation distance between the
    H-FISST and Reid posteriors.
    """
    n_targets = int(cfg["n_targets"])
    seeds = np.random.SeedSequence(seed).spawn(int(cfg["n_runs"]))
    rows = []
    for run, ss in enumerate(seeds):
        rng = np.random.default_rng(ss)
        X0 = np.column_stack([rng.uniform(0, 10, (n_targets, 2)), rng.normal(0, 0.7, (n_targets, 2))])
        P0 = np.repeat(np.diag([1.0, 1.0, 0.1, 0.1])[None], n_targets, axis=0)
        scen = simulate_cv_targets(X0, n_scans=int(cfg["n_scans"]) + 1, dt=1.0, q_truth=0.05,
                                   R=np.eye(2) * float(cfg["measurement_var"]), p_D=float(cfg["p_D"]),
                                   clutter_rate=float(cfg["clutter_rate"]), region=Box([-15.0, -15.0], [25.0, 25.0]),
                                   rng=rng)
        filters = {name: HypothesisFilter(scen.motion, scen.sensor, w, ExhaustiveGenerator(), dt=1.0,
                                          max_hypotheses=int(cfg["max_hypotheses"]), means=X0, covs=P0, seed=0)
                   for name, w in (("fisst", FISSTPoissonWeights()), ("reid", ReidWeights()),
                                   ("hfisst", HFISSTWeights()))}
        for scan, (_, Z) in enumerate(scen.scan_list()[1:], start=1):
            for f in filters.values():
                f.step(Z)
            a, b, h = (_by_lineage(filters[k]) for k in ("fisst", "reid", "hfisst"))
            same = a.keys() == b.keys()
            rows.append({
                "run": run, "scan": scan, "n_returns": len(Z), "n_hypotheses": len(a),
                "same_hypotheses": same,
                "max_abs_dlogw_fisst_reid": max(abs(a[k][0] - b[k][0]) for k in a) if same else np.inf,
                "max_abs_dmean_fisst_reid": max(float(np.max(np.abs(a[k][1] - b[k][1]), initial=0.0)) for k in a)
                if same else np.inf,
                "tv_hfisst_reid": _tv(h, b),
                "effective_hypotheses_reid": float(np.exp(-logsumexp(2 * np.array([v[0] for v in b.values()])))),
            })
    return pd.DataFrame(rows)

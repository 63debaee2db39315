"""The linear-Gaussian benchmark of the GLMB papers, run by the engine's trackers.

Scenario (Vo & Vo 2013 Sec. V; Vo, Vo & Hoang 2017 Sec. V): 2-D constant velocity with
discrete white-noise acceleration (``T = 1 s``, ``σ_v = 5 m/s²``), ``p_S = 0.99``, four
labeled-Bernoulli birth terms (``r_B = 0.03``, standard deviation 10 in every state component),
position returns with ``σ = 10 m``, ``p_D = 0.98``, Poisson clutter (rate 30) on
``[−1000, 1000]²``, 100 scans. The truth (birth and death times, initial states, noiseless
constant-velocity motion) is the public demo's, given as data in the config.

Trackers (named in the config): ``glmb`` (Gibbs), ``glmb_murty``, ``rfisst`` (the chain alone,
``completion_rounds = 0``, or with the neighbour completion) and ``homht_kbest``; R-FISST and
HOMHT run with the same labeled multi-Bernoulli birth terms expressed as their own population
models (see :func:`make_tracker`); ``gmphd`` is Stone Soup's GM-PHD filter with the same models,
the peer baseline (:mod:`.glmb_benchmark_gmphd`). Estimates are the MAP hypothesis's means (the
GM-PHD's: its components with weight > 0.5). Metrics: OSPA (``c = 100 m``, ``p = 1``) on
positions with its localisation and cardinality parts, the estimated number of objects, and the
run time per scan.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..._validation import check_int, check_positive
from ...hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation, glmb, glmb_murty
from ...hypotheses.filter import HypothesisFilter
from ...hypotheses.generators import MCMCGenerator, MurtyGenerator
from ...hypotheses.population_events import BinomialPopulation
from ...hypotheses.weights import FISSTPoissonWeights, HFISSTWeights
from ...metrics import ospa
from ...models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

__all__ = ["KINDS", "PEER_KINDS", "DiscreteWhiteNoiseAcceleration", "BenchmarkModel", "benchmark_model", "truth_states",
           "simulate_scans", "make_tracker", "implementation_labels", "legend_labels", "run_tracker", "ospa_parts"]

KINDS = ("glmb", "glmb_murty", "rfisst", "homht_kbest", "gmphd")
PEER_KINDS = {"gmphd": "Stone Soup GM-PHD, peer implementation"}


@dataclass(frozen=True)
class DiscreteWhiteNoiseAcceleration:
    """2-D CV with piecewise-constant acceleration ``N(0, σ_v²)`` per scan (state ``[x, y, vx, vy]``):
    ``Q = σ_v² G Gᵀ``, ``G = [T²/2 I; T I]`` (the GLMB demos' model)."""

    sigma_v: float

    def F(self, dt):
        F = np.eye(4)
        F[0, 2] = F[1, 3] = dt
        return F

    def Q(self, dt):
        G = np.vstack([dt**2 / 2 * np.eye(2), dt * np.eye(2)])
        return self.sigma_v**2 * G @ G.T

    def transition(self, x, dt):
        F = self.F(dt)
        x = np.asarray(x, dtype=float)
        return x @ F.T, np.broadcast_to(F, x.shape[:-1] + (4, 4))


@dataclass(frozen=True)
class BenchmarkModel:
    motion: DiscreteWhiteNoiseAcceleration
    sensor: Sensor
    p_survive: float
    r_birth: float
    birth_means: np.ndarray
    birth_cov: np.ndarray
    n_scans: int


def benchmark_model(cfg) -> BenchmarkModel:
    """The scenario's models from the config section (names as in the module docstring)."""
    R = np.eye(2) * check_positive(cfg["sigma_r"], "sigma_r") ** 2
    half = check_positive(cfg["half_width"], "half_width")
    region = Box([-half, -half], [half, half])
    sensor = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)),
                    DetectionModel(cfg["p_D"]), PoissonClutter(cfg["clutter_rate"], region))
    return BenchmarkModel(
        motion=DiscreteWhiteNoiseAcceleration(check_positive(cfg["sigma_v"], "sigma_v")), sensor=sensor,
        p_survive=cfg["p_S"], r_birth=cfg["r_birth"],
        birth_means=np.asarray(cfg["birth_means"], dtype=float),
        birth_cov=np.eye(4) * check_positive(cfg["birth_std"], "birth_std") ** 2,
        n_scans=check_int(cfg["n_scans"], "n_scans", minimum=1),
    )


def truth_states(truth_rows, n_scans: int, dt: float = 1.0):
    """Per scan ``k = 1 .. n_scans`` the true states ``(n_k, 4)`` and identities, from rows
    ``[t_birth, t_death, x, y, vx, vy]`` (present for ``t_birth <= k < t_death``; noiseless CV)."""
    rows = np.asarray(truth_rows, dtype=float).reshape(-1, 6)
    out = []
    for k in range(1, n_scans + 1):
        alive = (rows[:, 0] <= k) & (k < rows[:, 1])
        age = k - rows[alive, 0]
        x = rows[alive, 2:6].copy()
        x[:, :2] += age[:, None] * dt * x[:, 2:]
        out.append((x, np.flatnonzero(alive)))
    return out


def simulate_scans(model: BenchmarkModel, truth, rng):
    """Returns per scan: detections of the true positions (``p_D``, ``σ_r``) plus Poisson clutter."""
    scans = []
    R = model.sensor.measurement.R
    for x, _ in truth:
        det = rng.uniform(size=len(x)) < model.sensor.detection.p_D
        z = x[det, :2] + rng.multivariate_normal(np.zeros(2), R, size=int(det.sum())).reshape(-1, 2)
        clutter = model.sensor.clutter.sample(rng)
        Z = np.vstack([z, clutter]).reshape(-1, 2)
        scans.append(Z[rng.permutation(len(Z))])
    return scans


def _birth_terms(model):
    H, R = model.sensor.measurement.H, model.sensor.measurement.R
    return [GaussianBirthTerm(m, model.birth_cov, H, R) for m in model.birth_means]


def make_tracker(kind: str, model: BenchmarkModel, options: dict, seed):
    """A named tracker with the scenario's models.

    ``gmphd``: Stone Soup's GM-PHD filter, the peer implementation
    (:mod:`.glmb_benchmark_gmphd`; deterministic, ``seed`` unused).

    ``glmb`` / ``glmb_murty``: the δ-GLMB presets with the labeled multi-Bernoulli population.
    ``rfisst`` and ``homht_kbest``: H-FISST weights with the chain, and FISST weights with Poisson
    clutter with Murty, both under seed 001's binomial population with the *same* birth terms
    (``α = r_B``) and survival — the nesting of :mod:`hypotrack.hypotheses.population_lmb`: at
    most one death or undetected birth per child.
    """
    if kind == "gmphd":
        from .gmphd import make_gmphd

        return make_gmphd(model, options)
    if kind not in KINDS:
        raise ValueError(f"tracker kind must be one of {', '.join(KINDS)}, got {kind!r}")
    if "max_hypotheses" not in options:
        raise ValueError(f"tracker kind {kind} needs max_hypotheses (H_inf, an integer >= 1)")
    common = {"max_hypotheses": options["max_hypotheses"], "gate_probability": options.get("gate_probability"),
              "seed": seed}
    lmb = LabeledMultiBernoulliPopulation(_birth_terms(model), r_birth=model.r_birth, p_survive=model.p_survive)
    if kind == "glmb":
        return glmb(model.motion, model.sensor, population=lmb, n_sweeps=options["n_sweeps"], **common)
    if kind == "glmb_murty":
        return glmb_murty(model.motion, model.sensor, population=lmb, **common)
    binom = BinomialPopulation(_birth_terms(model), alpha=model.r_birth, p_survive=model.p_survive)
    if kind == "rfisst":
        gen = MCMCGenerator(n_steps=options["n_steps"], completion_rounds=options.get("completion_rounds", 2))
        return HypothesisFilter(model.motion, model.sensor, HFISSTWeights(), gen, population=binom, **common)
    if kind == "homht_kbest":
        gen = MurtyGenerator(k=options["max_hypotheses"])
        return HypothesisFilter(model.motion, model.sensor, FISSTPoissonWeights(), gen, population=binom, **common)
    raise ValueError(f"tracker kind must be one of {', '.join(KINDS)}, got {kind!r}")


def implementation_labels(trackers: dict) -> dict:
    """Per named tracker: ``"hypotrack engine"`` or the peer's name (tables and figure legends)."""
    return {name: PEER_KINDS.get(spec["kind"], "hypotrack engine") for name, spec in trackers.items()}


def legend_labels(trackers: dict) -> dict:
    """Per named tracker: its name and what it is, for figure legends."""
    what = {"glmb": "δ-GLMB, Gibbs", "glmb_murty": "δ-GLMB, Murty", "homht_kbest": "HOMHT, Murty k-best"}
    out = {}
    for name, spec in trackers.items():
        kind = spec["kind"]
        if kind == "rfisst":
            desc = "R-FISST + completion" if spec.get("completion_rounds", 2) else "R-FISST, chain alone"
        else:
            desc = PEER_KINDS.get(kind) or what.get(kind, kind)
        out[name] = f"{name} ({desc})"
    return out


def ospa_parts(X, Y, c: float):
    """OSPA (p = 1) and its localisation and cardinality parts (Schuhmacher et al. 2008, Eq. 3)."""
    n, m = len(X), len(Y)
    if max(n, m) == 0:
        return 0.0, 0.0, 0.0
    total = ospa(X, Y, c=c, p=1.0)
    card = c * abs(n - m) / max(n, m)
    return total, total - card, card


def run_tracker(tracker: HypothesisFilter, scans, truth, c: float) -> pd.DataFrame:
    """Per scan: OSPA, its parts, true and estimated number of objects, run time (s)."""
    rows = []
    for k, (Z, (x, _)) in enumerate(zip(scans, truth), start=1):
        t0 = time.perf_counter()
        post = tracker.step(Z)
        est = post.map_estimate.means[:, :2] if post.map_estimate is not None else np.zeros((0, 2))
        dt = time.perf_counter() - t0
        o, loc, card = ospa_parts(est, x[:, :2], c)
        rows.append({"scan": k, "ospa": o, "ospa_loc": loc, "ospa_card": card, "n_true": len(x),
                     "n_est": len(est), "expected_number": float(post.expected_number), "time_s": dt})
    return pd.DataFrame(rows)


def benchmark_shard(cfg, seed_seq, first_run: int, n_runs: int) -> pd.DataFrame:
    """Per scan metrics of every named tracker on ``n_runs`` Monte Carlo realisations.

    Each run draws one scan sequence from its own seed (``seed_seq`` spawned per run); every
    tracker sees the same scans and its own seeded random stream. The run times go in
    ``time_s`` (keep them out of deterministic tables)."""
    model = benchmark_model(cfg)
    truth = truth_states(cfg["truth"], model.n_scans)
    parts = []
    for r, child in enumerate(seed_seq.spawn(n_runs)):
        scan_seed, *tracker_seeds = child.spawn(1 + len(cfg["trackers"]))
        scans = simulate_scans(model, truth, np.random.default_rng(scan_seed))
        for (name, spec), ts in zip(cfg["trackers"].items(), tracker_seeds):
            print(f"glmb_benchmark run {first_run + r}: {name}", flush=True)
            tracker = make_tracker(spec["kind"], model, spec, np.random.default_rng(ts))
            df = run_tracker(tracker, scans, truth, float(cfg["ospa_c"]))
            df.insert(0, "tracker", name)
            df.insert(0, "run", first_run + r)
            parts.append(df)
    return pd.concat(parts, ignore_index=True)

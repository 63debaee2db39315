"""The Williams-2015 scenario as the PMBM paper uses it (García-Fernández, Williams, Granström & Svensson 2018).

Williams ("Marginal multi-Bernoulli filters: RFS derivation of MHT, JIPDA and association-based
MeMBer", IEEE TAES 51(3), 2015, Sec. VI) builds trajectories that meet: four objects whose states at
the mid-point of the run (step ``(N + 1)/2``) are drawn close together,
``x ~ N([150, 0, 150, 0], 0.1 I)`` in the paper's ``[x, vx, y, vy]`` order, then propagated forward
(``x_{k+1} = F x_k + w``) and backward (``x_{k−1} = F⁻¹(x_k + w)``) with the nearly-constant-velocity
noise ``w ~ N(0, Q)``, ``Q = q [[T³/3, T²/2], [T²/2, T]]`` per axis, ``q = 0.02``, ``T = 1 s``. The
PMBM paper's Sec. VI takes the variant in which all four are present from the first step and the
first dies at the mid-point (present at steps ``1 .. (N − 1)/2``), 81 steps, position returns with
``R = I``, ``p_D = 0.9``, ``p_S = 0.99``, Poisson clutter with 10 returns per scan uniform on
``[0, 300]²``, a Poisson birth intensity ``0.005 N([100, 0, 100, 0], diag(150², 1, 150², 1))`` and
GOSPA with ``c = 10``, ``p = 2``, ``α = 2`` on positions.

As in the paper's code the truth is drawn once (from its own seed) and the Monte Carlo runs redraw
the returns only. States here are in this project's ``[x, y, vx, vy]`` order.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_int, check_positive, check_probability
from ...hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation
from ...models.motion import ConstantVelocity
from ...models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from ...registry import TrackingProblem

__all__ = ["Williams2015", "scenario", "draw_truth", "simulate_scans", "make_problem", "truth_at"]


@dataclass(frozen=True)
class Williams2015:
    """The scenario's models and settings (names as in the module docstring)."""

    motion: ConstantVelocity
    sensor: Sensor
    n_steps: int
    n_objects: int
    p_survive: float
    mid_mean: np.ndarray
    mid_cov: np.ndarray
    birth_weight: float
    birth_mean: np.ndarray
    birth_cov: np.ndarray
    n_birth_terms: int

    @property
    def midpoint(self) -> int:
        return (self.n_steps + 1) // 2


def scenario(cfg) -> Williams2015:
    """The scenario from a config section (keys as in ``williams2015.schema.yaml``)."""
    n_steps = check_int(cfg["n_steps"], "n_steps", minimum=3)
    if n_steps % 2 == 0:
        raise ValueError(f"n_steps must be odd (the trajectories are drawn at the mid-point), got {n_steps}")
    side = check_positive(cfg["side"], "side")
    R = np.eye(2) * check_positive(cfg["sigma_r"], "sigma_r") ** 2
    sensor = Sensor(LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)),
                    DetectionModel(check_probability(cfg["p_D"], "p_D", low_open=True)),
                    PoissonClutter(check_positive(cfg["clutter_rate"], "clutter_rate"), Box([0.0, 0.0], [side, side])))
    birth = cfg["birth"]
    return Williams2015(
        motion=ConstantVelocity(check_positive(cfg["q"], "q")), sensor=sensor, n_steps=n_steps,
        n_objects=check_int(cfg["n_objects"], "n_objects", minimum=1),
        p_survive=check_probability(cfg["p_S"], "p_S", low_open=True),
        mid_mean=np.array([side / 2, side / 2, 0.0, 0.0]),
        mid_cov=np.eye(4) * check_positive(cfg["mid_variance"], "mid_variance"),
        birth_weight=check_probability(birth["weight"], "birth.weight", low_open=True, high_open=True),
        birth_mean=np.asarray(birth["mean"], dtype=float),
        birth_cov=np.diag(np.asarray(birth["std"], dtype=float) ** 2),
        n_birth_terms=check_int(birth.get("n_terms", 1), "birth.n_terms", minimum=1),
    )


def draw_truth(model: Williams2015, rng) -> np.ndarray:
    """The true states ``(n_objects, n_steps, 4)``, NaN where an object is absent.

    Drawn at the mid-point and propagated forward and backward (Williams 2015 Sec. VI; the module
    docstring); object 0 is present at steps ``1 .. midpoint − 1`` only, the others throughout."""
    n, T, mid = model.n_objects, model.n_steps, model.midpoint
    F, Q = model.motion.F(1.0), model.motion.Q(1.0)
    L = np.linalg.cholesky(Q)
    Finv = np.linalg.inv(F)
    X = np.full((n, T, 4), np.nan)
    x0 = model.mid_mean + rng.standard_normal((n, 4)) @ np.linalg.cholesky(model.mid_cov).T
    X[:, mid - 1] = x0
    xf, xb = x0.copy(), x0.copy()
    for t in range(1, mid):
        # the forward and backward draws alternate as in Williams' generator (one stream, forward first)
        xf = xf @ F.T + rng.standard_normal((n, 4)) @ L.T
        xb = (xb + rng.standard_normal((n, 4)) @ L.T) @ Finv.T
        X[:, mid - 1 + t] = xf
        X[:, mid - 1 - t] = xb
    X[0, mid - 1:] = np.nan  # the first object dies at the mid-point
    return X


def truth_at(truth: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """States ``(n_k, 4)`` and object indices of the objects present at step ``k`` (0-based)."""
    present = np.flatnonzero(~np.isnan(truth[:, k, 0]))
    return truth[present, k], present


def simulate_scans(model: Williams2015, truth: np.ndarray, rng) -> list[np.ndarray]:
    """Per step the returns ``(m_k, 2)``: each present object detected with ``p_D`` (position plus
    ``N(0, R)``), then ``Poisson(λ)`` clutter returns uniform on the square, in that order (as the
    paper's ``CreateMeasurement``)."""
    R = model.sensor.measurement.R
    L = np.linalg.cholesky(R)
    scans = []
    for k in range(model.n_steps):
        x, _ = truth_at(truth, k)
        det = rng.uniform(size=len(x)) < model.sensor.detection.p_D
        z = x[det, :2] + rng.standard_normal((int(det.sum()), 2)) @ L.T
        scans.append(np.vstack([z, model.sensor.clutter.sample(rng)]).reshape(-1, 2))
    return scans


def make_problem(model: Williams2015) -> TrackingProblem:
    """The scenario as a :class:`~hypotrack.registry.TrackingProblem`: no known objects; the Poisson birth
    intensity ``w_B N(m_B, P_B)`` as ``n_terms`` labeled-Bernoulli terms of existence ``w_B / n_terms``
    each (for small ``w_B`` a Poisson and a multi-Bernoulli of the same mean differ by ``O(w_B²)``; more
    terms let more objects be born at one scan) and survival ``p_S``."""
    H, R = model.sensor.measurement.H, model.sensor.measurement.R
    terms = [GaussianBirthTerm(model.birth_mean, model.birth_cov, H, R) for _ in range(model.n_birth_terms)]
    lmb = LabeledMultiBernoulliPopulation(terms, r_birth=model.birth_weight / model.n_birth_terms,
                                          p_survive=model.p_survive)
    return TrackingProblem(model.motion, model.sensor, births=lmb, dt=1.0)

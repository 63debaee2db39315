"""2-D constant-velocity targets in Poisson clutter: crossing and closely spaced formations.

The setting of the lecture notes on single-hypothesis tracking (paper 004): a few targets
observed by one position sensor with detection probability ``P_D`` and uniform Poisson
clutter over the surveillance region ``V_S`` (lecture 004, "Standard settings":
``P_FA(m) = Poisson(β_FA V_S)``, ``p_FA(y) = 1/V_S``). Two layouts matter for GNN vs JPDA:

* :func:`crossing_targets` — targets on straight lines that all pass through one point halfway
  through the run, at a small crossing angle; this is where JPDA's track coalescence
  (Fitzgerald 1986, shown in the lecture) appears;
* :func:`closely_spaced_targets` — a formation of parallel targets a small distance apart, so
  that gates overlap and the association clusters are large (the cross-check and the
  performance benchmark).

Both return a :class:`ClutteredScenario` holding tidy truth and scans tables
(:mod:`hypotrack.scenarios.tables`), the models, and the true initial states (for trackers
started on known tracks, as in the lecture's "all the past is summarized by a 3 track
hypothesis"). Everything is a deterministic function of the parameters and the seed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from .._validation import (
    check_finite_array,
    check_int,
    check_nonnegative,
    check_positive,
    check_probability,
    check_seed,
)
from ..models.motion import ConstantVelocity
from ..models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from .tables import scans_table, scans_to_list, truth_table, truth_to_list

__all__ = ["ClutteredScenario", "simulate_cv_targets", "crossing_targets", "closely_spaced_targets"]


@dataclass(frozen=True, eq=False)
class ClutteredScenario:
    """Truth and scans of 2-D constant-velocity targets seen by one sensor in clutter.

    Attributes
    ----------
    truth : pandas.DataFrame
        Truth table (state ``[x, y, vx, vy]`` in m and m/s).
    scans : pandas.DataFrame
        Scans table (``z_0, z_1`` = measured x, y in m; ``origin`` target id or −1).
    times : (K,) ndarray
        Scan times (s).
    initial_states : (n, 4) ndarray
        True target states at the first scan, in target-id order.
    motion : ConstantVelocity
    sensor : Sensor
        Measurement (``H``, ``R``), detection (``p_D``) and clutter (rate, region) models.
    """

    truth: pd.DataFrame
    scans: pd.DataFrame
    times: np.ndarray
    initial_states: np.ndarray
    motion: ConstantVelocity
    sensor: Sensor

    @property
    def region(self) -> Box:
        """The surveillance region ``V_S`` (clutter and detection region)."""
        return self.sensor.clutter.region

    @property
    def clutter_density(self) -> float:
        """Clutter spatial intensity ``β_FA`` = expected returns per unit area per scan."""
        return self.sensor.clutter.intensity

    def scan_list(self, *, with_origin: bool = False) -> list:
        """One ``(time, Z)`` pair per scan (``Z`` of shape (m, 2), possibly empty)."""
        return scans_to_list(self.scans, times=self.times, with_origin=with_origin)

    def truth_list(self) -> list:
        """One ``(time, ids, X)`` triple per scan."""
        return truth_to_list(self.truth, times=self.times)


def _sensor(R, p_D, clutter_rate, region) -> Sensor:
    return Sensor(
        LinearPositionSensor(R, ndim_state=4, position_indices=(0, 1)),
        DetectionModel(p_D, fov=region),
        PoissonClutter(clutter_rate, region),
    )


def simulate_cv_targets(initial_states, *, n_scans, dt, q_truth, R, p_D, clutter_rate, region, rng):
    """Simulate targets from given initial states and one sensor's scans.

    Random draws, in order, per scan ``k ≥ 1``: the process noise of every target; then per
    scan ``k ≥ 0`` the sensor's detections, noise, clutter and shuffle
    (:meth:`hypotrack.models.sensors.Sensor.observe`). Targets exist for the whole run.

    Parameters
    ----------
    initial_states : (n, 4) array_like
        ``[x, y, vx, vy]`` of each target at scan 0 (m, m/s); ``n = 0`` is allowed.
    n_scans : int
        Number of scans ``K`` ≥ 1.
    dt : float
        Scan interval (s), > 0.
    q_truth : float
        Acceleration noise intensity of the truth (m²/s³), ≥ 0 (0: straight lines).
    R : (2, 2) array_like
        Measurement-noise covariance (m²).
    p_D : float
        Detection probability in (0, 1].
    clutter_rate : float
        Expected clutter returns per scan over ``region``, ≥ 0.
    region : Box
        Surveillance region (clutter is uniform over it; targets outside it are not detected).
    rng : numpy.random.Generator or int

    Returns
    -------
    ClutteredScenario
    """
    X0 = np.asarray(initial_states, dtype=float)
    X0 = np.zeros((0, 4)) if X0.size == 0 else check_finite_array(X0, "initial_states", shape=(None, 4))
    n_scans = check_int(n_scans, "n_scans", minimum=1)
    dt = check_positive(dt, "dt")
    motion = ConstantVelocity(check_nonnegative(q_truth, "q_truth"))
    sensor = _sensor(R, p_D, clutter_rate, region)
    rng = np.random.default_rng(check_seed(rng, "rng"))
    n = len(X0)
    F = motion.F(dt)
    chol_Q = np.linalg.cholesky(motion.Q(dt)) if motion.q > 0 else np.zeros((4, 4))
    times = dt * np.arange(n_scans)
    X = X0.copy()
    t_rows, s_rows, Z_rows, o_rows = [], [], [], []
    truth_parts = []
    for k in range(n_scans):
        if k > 0:
            X = X @ F.T + rng.standard_normal((n, 4)) @ chol_Q.T
        truth_parts.append(X.copy())
        Z, origin = sensor.observe(X, rng)
        s_rows.append(np.full(len(Z), k))
        t_rows.append(np.full(len(Z), times[k]))
        Z_rows.append(Z)
        o_rows.append(origin)
    states = np.concatenate(truth_parts) if n else np.zeros((0, 4))
    scan_idx = np.repeat(np.arange(n_scans), n)
    truth = truth_table(
        scan=scan_idx,
        time=times[scan_idx],
        target=np.tile(np.arange(n), n_scans),
        states=states,
        in_view=sensor.in_view(states) if n else np.zeros(0, bool),
    )
    scans = scans_table(
        scan=np.concatenate(s_rows),
        time=np.concatenate(t_rows),
        sensor=np.zeros(sum(len(z) for z in Z_rows), dtype=np.int64),
        Z=np.concatenate(Z_rows),
        origin=np.concatenate(o_rows),
        p=2,
    )
    return ClutteredScenario(truth, scans, times, X0, ConstantVelocity(motion.q), sensor)


def _simulate_in_box(X0_of, *, n_scans, dt, q_truth, sigma, p_D, clutter_rate, margin, rng):
    """Validate the shared arguments, build the paths' surveillance box and simulate.

    ``X0_of(n_scans, dt)`` returns the initial states, which depend on the timing.
    """
    n_scans = check_int(n_scans, "n_scans", minimum=1)
    dt = check_positive(dt, "dt")
    sigma = check_positive(sigma, "sigma")
    check_probability(p_D, "p_D", low_open=True)
    margin = check_positive(margin, "margin")
    X0 = X0_of(n_scans, dt)
    # The box holds every target's noise-free path, plus the margin on each side.
    anchor = X0 if len(X0) else np.zeros((1, 4))
    ends = np.vstack([anchor[:, :2], anchor[:, :2] + dt * (n_scans - 1) * anchor[:, 2:]])
    region = Box(ends.min(axis=0) - margin, ends.max(axis=0) + margin)
    return simulate_cv_targets(
        X0, n_scans=n_scans, dt=dt, q_truth=q_truth, R=sigma**2 * np.eye(2), p_D=p_D,
        clutter_rate=clutter_rate, region=region, rng=rng,
    )


def crossing_targets(
    n_targets: int = 2,
    *,
    speed: float = 10.0,
    crossing_angle_deg: float = 10.0,
    n_scans: int = 60,
    dt: float = 1.0,
    q_truth: float = 0.0,
    sigma: float = 5.0,
    p_D: float = 0.9,
    clutter_rate: float = 10.0,
    margin: float = 100.0,
    rng=0,
) -> ClutteredScenario:
    """Targets whose straight paths all cross at the origin at the middle scan.

    Target ``i`` moves at ``speed`` with heading spread evenly over ``±crossing_angle/2``
    around the +x axis and passes through ``(0, 0)`` at scan ``(n_scans − 1) / 2``; with
    ``q_truth > 0`` the paths wander around those lines. For two targets the heading
    difference is the crossing angle.

    Parameters
    ----------
    n_targets : int
        Number of crossing targets ≥ 1.
    speed : float
        Target speed (m/s), > 0.
    crossing_angle_deg : float
        Angle between the outermost headings (deg), in [0, 180).
    n_scans, dt, q_truth, p_D, clutter_rate, rng
        As in :func:`simulate_cv_targets`.
    sigma : float
        Measurement noise standard deviation per axis (m), ``R = σ² I``.
    margin : float
        Distance from the paths' bounding box to the edge of the surveillance region (m).
    """
    n_targets = check_int(n_targets, "n_targets", minimum=1)
    speed = check_positive(speed, "speed")
    angle = check_nonnegative(crossing_angle_deg, "crossing_angle_deg")
    if angle >= 180:
        raise ValueError(f"crossing_angle_deg must lie in [0, 180), got {crossing_angle_deg!r}")
    headings = np.deg2rad(np.linspace(-angle / 2, angle / 2, n_targets)) if n_targets > 1 else np.zeros(1)
    v = speed * np.column_stack([np.cos(headings), np.sin(headings)])

    def initial_states(n_scans, dt):
        t_cross = dt * (n_scans - 1) / 2
        return np.column_stack([-t_cross * v, v])

    return _simulate_in_box(
        initial_states, n_scans=n_scans, dt=dt, q_truth=q_truth, sigma=sigma, p_D=p_D,
        clutter_rate=clutter_rate, margin=margin, rng=rng,
    )


def closely_spaced_targets(
    n_targets: int = 4,
    *,
    spacing: float = 20.0,
    speed: float = 10.0,
    n_scans: int = 25,
    dt: float = 1.0,
    q_truth: float = 0.05,
    sigma: float = 5.0,
    p_D: float = 0.9,
    clutter_rate: float = 10.0,
    margin: float = 100.0,
    rng=0,
) -> ClutteredScenario:
    """A formation of parallel targets ``spacing`` apart, moving along +x together.

    Targets start on the segment ``x = 0``, ``y = 0, spacing, 2·spacing, …``; with a spacing of
    a few measurement standard deviations their gates overlap and they form one or a few large
    association clusters (the case where exact JPDA is expensive).

    Parameters
    ----------
    n_targets : int
        Number of targets ≥ 0.
    spacing : float
        Distance between neighbours (m), > 0.
    speed : float
        Common speed along +x (m/s), ≥ 0.
    n_scans, dt, q_truth, p_D, clutter_rate, rng
        As in :func:`simulate_cv_targets`.
    sigma, margin
        As in :func:`crossing_targets`.
    """
    n_targets = check_int(n_targets, "n_targets", minimum=0)
    spacing = check_positive(spacing, "spacing")
    speed = check_nonnegative(speed, "speed")

    def initial_states(n_scans, dt):
        X0 = np.zeros((n_targets, 4))
        X0[:, 1] = spacing * np.arange(n_targets)
        X0[:, 2] = speed
        return X0

    return _simulate_in_box(
        initial_states, n_scans=n_scans, dt=dt, q_truth=q_truth, sigma=sigma, p_D=p_D,
        clutter_rate=clutter_rate, margin=margin, rng=rng,
    )

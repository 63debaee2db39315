"""Two closely spaced targets on a line, seen by N synchronous sensors (document 003, §5–6).

Ground truth follows the exactly discretised Ornstein–Uhlenbeck process (Eqs. 5.1–5.3); every
sensor reports both targets with independent Gaussian noise of variance R, no missed detections
and no false alarms (Eq. 5.4). Arrays carry a leading Monte Carlo run axis so that thousands of
realisations are generated (and later filtered) at once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int, check_nonnegative, check_positive, check_seed
from ..models.motion import OrnsteinUhlenbeck

__all__ = ["CloselySpacedRealisation", "simulate_closely_spaced", "static_pair_scans"]


@dataclass(frozen=True)
class CloselySpacedRealisation:
    """Truth and scans of ``n_runs`` independent realisations.

    Attributes
    ----------
    truth : (n_runs, n_scans, 2)
        Target positions ``x_k`` (m), target order fixed by label.
    scans : (n_runs, n_scans, n_sensors, 2)
        ``scans[r, k, n, j]`` is sensor ``n``'s return from target ``j`` (labelled). Trackers
        that do not know the origin sort the last axis themselves; the ideal filter uses labels.
    times : (n_scans,)
        Scan times (s), starting at 0.
    """

    truth: np.ndarray
    scans: np.ndarray
    times: np.ndarray

    @property
    def sorted_scans(self) -> np.ndarray:
        """Each sensor's returns in increasing order (what a sensor without labels reports)."""
        return np.sort(self.scans, axis=-1)


def simulate_closely_spaced(
    model: OrnsteinUhlenbeck,
    *,
    n_runs: int,
    n_scans: int,
    n_sensors: int,
    R: float,
    dt: float = 1.0,
    initial_variance: float = 0.01,
    rng,
) -> CloselySpacedRealisation:
    """Simulate two independent OU targets and N-sensor scans (Eqs. 5.1–5.4).

    Parameters
    ----------
    model : OrnsteinUhlenbeck
        Target motion, ``σ_q² = 0.01 m²/s``, ``γ = 0.005 s⁻¹`` in Table 6.1.
    n_runs, n_scans, n_sensors : int
        Monte Carlo runs, scans per run, sensors (1000, 100, 10 in Table 6.1).
    R : float
        Per-sensor measurement-noise variance (m²), 1 in Table 6.1.
    dt : float
        Scan interval (s).
    initial_variance : float
        Variance of each target's initial position ``X₀ ~ N(0, initial_variance)``, drawn
        independently per target. The tokens of Eq. 5.1 give ``N(0, σ_q²)``, numerically
        0.01 m² (reconstruction §6.5); 0 puts both targets at the origin.
    rng : numpy.random.Generator or int

    Returns
    -------
    CloselySpacedRealisation
    """
    if not isinstance(model, OrnsteinUhlenbeck):
        raise TypeError(f"model must be an OrnsteinUhlenbeck, got {type(model).__name__}")
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    n_scans = check_int(n_scans, "n_scans", minimum=1)
    n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    R = check_positive(R, "R")
    dt = check_positive(dt, "dt")
    initial_variance = check_nonnegative(initial_variance, "initial_variance")
    rng = np.random.default_rng(check_seed(rng, "rng"))
    A = float(model.F(dt)[0, 0])
    Q = float(model.Q(dt)[0, 0])
    truth = np.empty((n_runs, n_scans, 2))
    truth[:, 0] = np.sqrt(initial_variance) * rng.standard_normal((n_runs, 2))
    w = np.sqrt(Q) * rng.standard_normal((n_runs, n_scans - 1, 2))
    for k in range(1, n_scans):
        truth[:, k] = A * truth[:, k - 1] + w[:, k - 1]
    noise = np.sqrt(R) * rng.standard_normal((n_runs, n_scans, n_sensors, 2))
    scans = truth[:, :, None, :] + noise
    return CloselySpacedRealisation(truth=truth, scans=scans, times=dt * np.arange(n_scans))


def static_pair_scans(distance, *, n_runs: int, n_sensors: int, sigma: float, rng):
    """One synchronous scan of two static targets at 0 and ``distance`` (the swap experiment, §5).

    Returns
    -------
    truth : (2,) array ``[0, distance]``
    Z_lower, Z_upper : (n_runs, n_sensors) arrays
        Each sensor's smaller and larger return.
    """
    distance = check_nonnegative(distance, "distance")
    n_runs = check_int(n_runs, "n_runs", minimum=1)
    n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
    sigma = check_positive(sigma, "sigma")
    rng = np.random.default_rng(check_seed(rng, "rng"))
    truth = np.array([0.0, distance])
    Z = truth + sigma * rng.standard_normal((n_runs, n_sensors, 2))
    Z.sort(axis=-1)
    return truth, Z[..., 0], Z[..., 1]

"""Linear motion models: transition matrix ``F(dt)`` and process noise ``Q(dt)``.

Every motion model (linear here, nonlinear in :mod:`hypotrack.models.orbit`) follows one
protocol, so the same trackers run a Kalman filter or an EKF:

* ``ndim`` — state dimension;
* ``transition(x, dt) -> (x_pred, F)`` — propagated means ``(n, d)`` and the transition
  matrices / Jacobians (state-transition matrices) ``(n, d, d)``, batched over rows of ``x``;
* ``Q(dt)`` — process-noise covariance ``(d, d)``;
* ``propagate(x, dt)`` — means only.

:func:`hypotrack.gaussian.predict_with` turns that into the (extended) Kalman prediction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_nonnegative, check_positive

__all__ = ["ConstantVelocity", "OrnsteinUhlenbeck"]


def _check_dt(dt) -> float:
    return check_nonnegative(dt, "dt")


def _linear_transition(model, x, dt):
    x = np.atleast_2d(np.asarray(x, dtype=float))
    F = model.F(dt)
    return x @ F.T, np.broadcast_to(F, (x.shape[0], *F.shape))


@dataclass(frozen=True)
class ConstantVelocity:
    """Nearly-constant-velocity model in ``n_spatial`` dimensions (white-noise acceleration).

    State order ``[x, y, vx, vy]`` for the 2-D case (positions first, then velocities).
    ``Q(dt) = q [[dt³/3 I, dt²/2 I], [dt²/2 I, dt I]]`` with ``q`` the acceleration
    power spectral density (Bar-Shalom et al. 2001, §6.2.2).
    """

    q: float
    n_spatial: int = 2

    def __post_init__(self):
        object.__setattr__(self, "q", check_nonnegative(self.q, "q"))
        if self.n_spatial not in (1, 2, 3):
            raise ValueError(f"n_spatial must be 1, 2 or 3, got {self.n_spatial!r}")

    @property
    def ndim(self) -> int:
        return 2 * self.n_spatial

    def F(self, dt) -> np.ndarray:
        dt = _check_dt(dt)
        k = self.n_spatial
        F = np.eye(2 * k)
        F[:k, k:] = dt * np.eye(k)
        return F

    def Q(self, dt) -> np.ndarray:
        dt = _check_dt(dt)
        k = self.n_spatial
        i = np.arange(k)
        # Filled by index rather than np.block: Q is built every scan of every tracker.
        Q = np.zeros((2 * k, 2 * k))
        Q[i, i] = dt**3 / 3
        Q[i, i + k] = Q[i + k, i] = dt**2 / 2
        Q[i + k, i + k] = dt
        return self.q * Q

    def propagate(self, x, dt) -> np.ndarray:
        return np.asarray(x, dtype=float) @ self.F(dt).T

    def transition(self, x, dt):
        return _linear_transition(self, x, dt)


@dataclass(frozen=True)
class OrnsteinUhlenbeck:
    """1-D Ornstein–Uhlenbeck position process ``dX = −γ X dt + σ dW``, discretised exactly.

    ``F(dt) = e^{−γ dt}``, ``Q(dt) = σ²/(2γ) (1 − e^{−2γ dt})`` (Coraluppi & Carthel §6; the
    stationary variance is σ²/(2γ)).

    Parameters
    ----------
    sigma2 : float
        Diffusion intensity σ² (m²/s), > 0.
    gamma : float
        Mean-reversion rate γ (1/s), > 0.
    """

    sigma2: float
    gamma: float

    def __post_init__(self):
        object.__setattr__(self, "sigma2", check_positive(self.sigma2, "sigma2"))
        object.__setattr__(self, "gamma", check_positive(self.gamma, "gamma"))

    ndim = 1

    def F(self, dt) -> np.ndarray:
        return np.array([[np.exp(-self.gamma * _check_dt(dt))]])

    def Q(self, dt) -> np.ndarray:
        dt = _check_dt(dt)
        return np.array([[self.sigma2 / (2 * self.gamma) * -np.expm1(-2 * self.gamma * dt)]])

    @property
    def stationary_variance(self) -> float:
        return self.sigma2 / (2 * self.gamma)

    def propagate(self, x, dt) -> np.ndarray:
        return np.asarray(x, dtype=float) * np.exp(-self.gamma * _check_dt(dt))

    def transition(self, x, dt):
        return _linear_transition(self, x, dt)

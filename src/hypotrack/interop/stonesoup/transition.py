"""hypotrack's nonlinear motion models as Stone Soup transition models, for Stone Soup's extended
Kalman predictor: the peer side of the catalogue timings runs the trackers' own orbit dynamics.

:func:`orbit_transition_model` wraps a motion model of the protocol of :mod:`hypotrack.models.motion`
(``ndim``, ``transition(x, dt)`` → propagated states and state-transition matrices, ``Q(dt)``), e.g.
:class:`hypotrack.models.orbit3d.J2Orbit3D` or :class:`~hypotrack.models.orbit3d.TwoBodyOrbit3D`.
For a state ``x`` and interval ``Δt`` Stone Soup's EKF asks for

* ``function(x, Δt)`` — the propagated mean, ``motion.transition(x, Δt)``'s state (for the orbit
  models the real part of the complex-step run, bit-identical to ``motion.propagate``);
* ``jacobian(x, Δt)`` — ``Φ = ∂x(t + Δt)/∂x(t)``, the same call's matrix;
* ``covar(Δt)`` — the process noise ``motion.Q(Δt)``.

The predictor asks for the mean and the Jacobian of the same state one after the other, so the model
keeps the last ``(state, Δt)`` and its result: one integration per track and scan, not two. The state
is in hypotrack's order (no permutation). Stone Soup is imported when a model is built, so hypotrack
works without it.
"""

from __future__ import annotations

import numpy as np

from ._common import require_stonesoup

__all__ = ["orbit_transition_model"]

_CLASS = None


def _model_class():
    """The Stone Soup ``TransitionModel`` subclass, built once on first use."""
    global _CLASS
    if _CLASS is not None:
        return _CLASS
    require_stonesoup()
    from stonesoup.base import Property
    from stonesoup.models.base import GaussianModel, TimeVariantModel
    from stonesoup.models.transition.base import TransitionModel
    from stonesoup.types.array import CovarianceMatrix, StateVector

    class HypotrackOrbit(TransitionModel, GaussianModel, TimeVariantModel):
        """hypotrack's EKF dynamics (the motion model's transition and Q) as a Stone Soup model."""

        motion: object = Property(doc="hypotrack motion model with transition(x, dt) and Q(dt), e.g. J2Orbit3D")

        @property
        def ndim_state(self):
            return self.motion.ndim

        def _transition(self, state, time_interval):
            x = np.asarray(state.state_vector, float).reshape(1, self.motion.ndim)
            dt = time_interval.total_seconds()
            key = (x.tobytes(), dt)
            if getattr(self, "_key", None) != key:  # function and jacobian of one state: integrate once
                xp, F = self.motion.transition(x, dt)
                self._key, self._val = key, (xp[0], F[0])
            return self._val

        def function(self, state, noise=False, time_interval=None, **kwargs):
            return StateVector(self._transition(state, time_interval)[0])

        def jacobian(self, state, time_interval=None, **kwargs):
            return self._transition(state, time_interval)[1]

        def covar(self, time_interval=None, **kwargs):
            return CovarianceMatrix(self.motion.Q(time_interval.total_seconds()))

    _CLASS = HypotrackOrbit
    return _CLASS


def orbit_transition_model(motion):
    """``motion`` (a hypotrack motion model: ``ndim``, ``transition``, ``Q``) as a Stone Soup
    transition model for ``ExtendedKalmanPredictor`` (module docstring)."""
    return _model_class()(motion=motion)

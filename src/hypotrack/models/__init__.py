"""Motion, sensor and population models."""

from .motion import ConstantVelocity, OrnsteinUhlenbeck

__all__ = ["ConstantVelocity", "OrnsteinUhlenbeck"]

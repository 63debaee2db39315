"""Motion, sensor and population models."""

from .motion import ConstantVelocity, OrnsteinUhlenbeck
from .orbit import TwoBodyOrbit
from .orbit3d import J2Orbit3D, TwoBodyOrbit3D
from .plausibility import plausible_orbits
from .population import (
    BinomialBirth,
    BinomialSurvival,
    SingleEventBirthDeath,
    UniformBirthDensity,
    continuous_birth_death,
)
from .sensors import (
    Box,
    DetectionModel,
    FieldOfView,
    LinearPositionSensor,
    PoissonClutter,
    Sensor,
    SensorArray,
)

__all__ = [
    "ConstantVelocity",
    "OrnsteinUhlenbeck",
    "TwoBodyOrbit",
    "TwoBodyOrbit3D",
    "J2Orbit3D",
    "plausible_orbits",
    "LinearPositionSensor",
    "FieldOfView",
    "Box",
    "PoissonClutter",
    "DetectionModel",
    "Sensor",
    "SensorArray",
    "SingleEventBirthDeath",
    "UniformBirthDensity",
    "BinomialBirth",
    "BinomialSurvival",
    "continuous_birth_death",
]

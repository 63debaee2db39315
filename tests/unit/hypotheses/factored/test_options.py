"""The factored filter's options: one object, one default each, every bad value named."""

import dataclasses

import numpy as np
import pytest

from hypotrack.hypotheses import ExhaustiveGenerator, FactoredFilter, ReidWeights, homht
from hypotrack.hypotheses.factored import AdaptiveBirth, FactoredOptions
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

REGION = Box([-20.0, -20.0], [20.0, 20.0])
SENSOR = Sensor(LinearPositionSensor(np.eye(2) * 0.5, ndim_state=4, position_indices=(0, 1)),
                DetectionModel(0.8, REGION), PoissonClutter(1.0, REGION))
MOTION = ConstantVelocity(q=0.05)


def test_defaults_are_stated_once():
    o = FactoredOptions()
    assert (o.split, o.births, o.factor_tol, o.min_weight, o.adaptive_birth, o.workers, o.parallel,
            o.measure_transfer, o.lazy, o.gate_out_of_view) == (
        "marginal", "coupled", 1e-10, 0.0, None, 1, "process", False, False, True)
    ff = FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator())
    assert ff.options == o
    f = homht(MOTION, SENSOR)
    assert FactoredFilter.from_filter(f).options == o
    assert FactoredFilter.from_filter(f, lazy=True).options == dataclasses.replace(o, lazy=True)
    assert FactoredFilter.from_filter(f, FactoredOptions(lazy=True), workers=2).options.workers == 2


@pytest.mark.parametrize("name, value, error, match", [
    ("split", "always", ValueError, r"^split must be one of \('marginal', 'exact', 'never'\), got 'always'$"),
    ("births", "none", ValueError, r"^births must be one of \('coupled', 'free'\), got 'none'$"),
    ("factor_tol", 0.0, ValueError, r"^factor_tol must be a finite number > 0, got 0.0$"),
    ("factor_tol", np.nan, ValueError, r"^factor_tol must be a finite number > 0, got nan$"),
    ("factor_tol", "tiny", ValueError, r"^factor_tol must be a finite number > 0, got 'tiny'$"),
    ("min_weight", 1.0, ValueError, r"^min_weight must lie in \[0, 1\), got 1.0$"),
    ("min_weight", -0.1, ValueError, r"^min_weight must lie in \[0, 1\), got -0.1$"),
    ("adaptive_birth", "yes", TypeError, r"^adaptive_birth must be an AdaptiveBirth or None, got str$"),
    ("workers", 0, ValueError, r"^workers must be an integer in \[1, inf\], got 0$"),
    ("workers", 1.5, TypeError, r"^workers must be an integer, got float$"),
    ("parallel", "mpi", ValueError, r"^parallel must be one of \('process', 'thread'\), got 'mpi'$"),
    ("measure_transfer", "yes", TypeError, r"^measure_transfer must be True or False, got 'yes'$"),
    ("lazy", None, TypeError, r"^lazy must be True or False, got None$"),
    ("gate_out_of_view", 1, TypeError, r"^gate_out_of_view must be True or False, got 1$"),
])
def test_each_bad_option_is_named(name, value, error, match):
    with pytest.raises(error, match=match):
        FactoredOptions(**{name: value})
    with pytest.raises(error, match=match):  # the same check through the filter's keywords
        FactoredFilter.from_filter(homht(MOTION, SENSOR), **{name: value})


def test_unknown_options_and_late_changes():
    with pytest.raises(ValueError, match=r"unknown options \['cap'\]; allowed: split, births"):
        FactoredOptions.from_keywords(cap="top")
    with pytest.raises(ValueError, match=r"unknown options \['lazzy'\]"):
        FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), lazzy=True)
    with pytest.raises(TypeError, match="options must be a FactoredOptions"):
        FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), options={"lazy": True})
    ff = FactoredFilter(MOTION, SENSOR, ReidWeights(), ExhaustiveGenerator(), lazy=True)
    ff.workers, ff.parallel, ff.measure_transfer = 3, "thread", True  # between scans: validated, kept
    assert (ff.options.workers, ff.options.parallel, ff.options.measure_transfer, ff.options.lazy) == (3, "thread", True, True)
    with pytest.raises(ValueError, match=r"^workers must be an integer in \[1, inf\], got 0$"):
        ff.workers = 0
    with pytest.raises(ValueError, match="only workers, parallel and measure_transfer"):
        ff.set_options(lazy=False)
    assert ff.options.workers == 3
    with pytest.raises(dataclasses.FrozenInstanceError):
        ff.options.lazy = False
    assert FactoredOptions(adaptive_birth=AdaptiveBirth()).adaptive_birth == AdaptiveBirth()

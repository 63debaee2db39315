"""Tracker specifications: one vocabulary, defaults stated once, every bad option named."""

from __future__ import annotations

import inspect

import pytest

from hypotrack.hypotheses import presets
from hypotrack.hypotheses.factored import FactoredOptions
from hypotrack.hypotheses.generators import MCMCGenerator
from hypotrack.registry import FAMILIES, SpecError, TrackerSpec, kinds, preset, register, unregister
from hypotrack.trackers import MOfNInitiator, SingleHypothesisTracker


def test_defaults_fill_every_option_and_kind_overrides_the_family():
    s = TrackerSpec.from_config({"kind": "rfisst", "n_steps": 500})
    assert dict(s.options) == {"n_steps": 500, "mcmc_variant": "paper", "completion_rounds": 2, "burn_in": None,
                               "init": "random", "max_hypotheses": 100, "gate_probability": None, "cap": "top",
                               "merge_duplicates": True, "population": True, "factored": None}
    assert TrackerSpec.from_config({"kind": "homht"}).options["population"] is False  # Reid without a population
    assert TrackerSpec.from_config({"kind": "hfisst"}).options["population"] is True
    f = TrackerSpec.from_config({"kind": "glmb", "factored": {"lazy": True}}).options["factored"]
    assert f == {"lazy": True, "split": "marginal", "births": "coupled", "factor_tol": 1e-10, "min_weight": 0.0,
                 "gate_out_of_view": True, "workers": 1, "parallel": "process", "measure_transfer": False,
                 "fast_path": False, "replay": False, "bernoulli_lane": False}


@pytest.mark.parametrize("mapping, where", [
    ({"kind": "rfisst", "n_step": 5}, "x.n_step"),                       # misspelled option
    ({"kind": "rfisst", "n_steps": 0}, "x.n_steps"),                     # out of range
    ({"kind": "rfisst", "mcmc_variant": "fast"}, "x.mcmc_variant"),      # not in the enum
    ({"kind": "glmb", "factored": {"lazzy": True}}, "x.factored"),       # misspelled nested option
    ({"kind": "gnn", "m_of_n": [2]}, "x.m_of_n"),                        # wrong length
    ({"kind": "gnn", "n_sweeps": 3}, "x.n_sweeps"),                      # another family's option
    ({"kind": "gmm"}, "x.kind"),                                         # unknown kind
    ({"n_steps": 3}, "x"),                                               # no kind
    ({"kind": "hfisst", "gate_probability": 1.0}, "x.gate_probability"),
])
def test_bad_specification_names_the_field(mapping, where):
    with pytest.raises(SpecError, match=f"'{where}'"):
        TrackerSpec.from_config(mapping, "x")


def _default(fn, name):
    return inspect.signature(fn).parameters[name].default


def test_schema_defaults_equal_the_python_defaults_they_reach():
    """Defaults are stated once, in presets.yaml; the Python API's own defaults must agree with them."""
    opts = lambda kind: TrackerSpec.from_config({"kind": kind}).options
    for name in ("n_steps", "completion_rounds", "burn_in", "init", "mcmc_variant"):
        assert opts("rfisst")[name] == _default(presets.rfisst, name), name
    assert opts("hfisst")["max_events"] == _default(presets.hfisst, "max_events")
    assert opts("homht")["max_events"] == _default(presets.homht, "max_events")
    assert opts("glmb")["n_sweeps"] == _default(presets.glmb, "n_sweeps")
    for kind in ("homht_kbest", "fisst_kbest", "glmb_murty"):
        assert opts(kind)["k"] == _default(getattr(presets, kind), "k")
    from hypotrack.hypotheses import HypothesisFilter
    for name in ("max_hypotheses", "gate_probability", "cap", "merge_duplicates"):
        assert opts("hfisst")[name] == _default(HypothesisFilter, name), name
    factored = FAMILIES["engine"]["factored"]["properties"]
    fields = FactoredOptions.__dataclass_fields__
    assert set(factored) == set(fields) - {"adaptive_birth"}  # the birth terms come from the problem
    for name, schema in factored.items():
        assert schema["default"] == fields[name].default, name
    sht = opts("gnn")
    for name in ("max_misses", "gnn_score"):
        assert sht[name] == _default(SingleHypothesisTracker, name), name
    assert sht["initial_velocity_std"] == _default(MOfNInitiator, "initial_velocity_std")
    assert MCMCGenerator.__dataclass_fields__["variant"].default == opts("rfisst")["mcmc_variant"]


def test_register_refuses_clashes_and_bad_schemas():
    with pytest.raises(ValueError, match="already registered"):
        register("rfisst", lambda problem, **kw: None, family="engine")
    with pytest.raises(ValueError, match="already options of the engine family"):
        register("x_test", lambda problem, **kw: None, family="engine", options={"max_hypotheses": {"default": 1}})
    with pytest.raises(ValueError, match="needs a schema with a default"):
        register("x_test", lambda problem, **kw: None, family="engine", options={"depth": {"type": "integer"}})
    with pytest.raises(ValueError, match="family"):
        register("x_test", lambda problem, **kw: None, family="pmbm")
    assert "x_test" not in kinds()
    with pytest.raises(KeyError):
        unregister("x_test")


def test_builtin_kinds_and_families():
    assert kinds() == ("hfisst", "rfisst", "homht", "homht_kbest", "fisst_kbest", "glmb", "glmb_murty",
                       "gnn", "jpda", "pdaf", "pmbm_murty", "pmbm_gibbs", "pmb_lbp")
    assert kinds("single") == ("gnn", "jpda", "pdaf")
    assert preset("glmb").family == "engine"


def test_problem_validity_reaches_every_engine_preset_and_jpda_marginals_the_single_trackers():
    import numpy as np

    from hypotrack.models import ConstantVelocity
    from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    from hypotrack.registry import TrackingProblem, build

    sensor = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4, position_indices=(0, 1)), DetectionModel(0.9),
                    PoissonClutter(1.0, Box([-50, -50], [50, 50])))
    slow = lambda means: np.abs(means[:, 2]) < 5.0  # noqa: E731  (a stand-in physics test)
    problem = TrackingProblem(ConstantVelocity(0.1), sensor, [[0.0, 0, 1, 0]], [np.eye(4)], validity=slow)
    for kind in ("hfisst", "rfisst", "homht", "homht_kbest", "fisst_kbest"):
        assert build({"kind": kind}, problem, seed=0).validity is slow, kind
    assert build({"kind": "jpda", "jpda_marginals": "lbp"}, problem).jpda_marginals == "lbp"
    assert build({"kind": "hfisst"}, TrackingProblem(ConstantVelocity(0.1), sensor)).validity is None
    with pytest.raises(TypeError, match="validity must be callable"):
        TrackingProblem(ConstantVelocity(0.1), sensor, validity=3)

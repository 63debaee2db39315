"""One registry of tracker presets: every experiment and the Stone Soup adapter build trackers here.

A tracker is named by a **specification** — a registered ``kind`` and its options, e.g.
``{kind: rfisst, n_steps: 10000, completion_rounds: 0}`` — validated against one schema whose
defaults are stated once (``presets.yaml``; a misspelled option is an error naming it), and built
on a :class:`TrackingProblem` (the motion and sensor models, the known objects, the birth model)
by :func:`build`. The result follows :class:`hypotrack.protocol.Tracker`.

Adding a tracker is one call, after which every experiment's config and the Stone Soup adapter
accept its kind:

>>> from hypotrack.hypotheses import presets
>>> from hypotrack.registry import engine_options, register, unregister
>>> def greedy_rfisst(problem, *, seed, population, chain_length, **common):
...     return presets.rfisst(problem.motion, problem.sensor, n_steps=chain_length, init="best",
...                           population=problem.event_population() if population else None,
...                           **engine_options(problem, seed, common))
>>> _ = register("greedy_rfisst", greedy_rfisst, family="engine",
...              options={"chain_length": {"type": "integer", "minimum": 1, "default": 1000}})
>>> TrackerSpec.from_config({"kind": "greedy_rfisst"}).options["chain_length"]
1000
>>> unregister("greedy_rfisst")
"""

from . import builtin  # noqa: F401  (registers hypotrack's own kinds)
from .build import build, build_fused
from .builtin import engine_options
from .problem import MeasurementBirths, MultiSensorProblem, SensorEntry, TrackingProblem
from .spec import FAMILIES, Preset, SpecError, TrackerSpec, kinds, preset, register, unregister

__all__ = ["FAMILIES", "MeasurementBirths", "MultiSensorProblem", "Preset", "SensorEntry", "SpecError", "TrackerSpec",
           "TrackingProblem", "build", "build_fused", "engine_options", "kinds", "preset", "register", "unregister"]

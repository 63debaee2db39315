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

Several sensors
---------------
On a :class:`MultiSensorProblem` — the shared motion model and known objects, and one :class:`SensorEntry` per
sensor: its measurement model and frame, field of view (``in_view``, required), ``p_D`` (``detection.p_D``, or
``detection.p_D_of`` of the state), clutter and births — :func:`build` returns the **fused** tracker: the preset
builds one tracker per sensor (on :meth:`MultiSensorProblem.problem` ``(s)``, a :class:`TrackingProblem`) and its
family joins them — the ``engine`` kinds on the factored engine
(:class:`~hypotrack.hypotheses.factored.multisensor.MultiSensorFactored`; ``factored`` options required), the
``single`` kinds as :class:`~hypotrack.trackers.multisensor.MultiSensorSHT`. Its ``step(Z, time, sensor=s)`` takes
a scan of sensor ``s``; scans at one instant are processed one after the other (the sequential, iterated-corrector
update). ``hfisst`` (its preset's ``no_fusion`` says why) and the ``poisson_mb`` kinds have no fused form: an error
naming the kind. A :class:`TrackingProblem` builds the single-sensor tracker, as ever.

>>> import numpy as np
>>> from hypotrack.models import ConstantVelocity
>>> from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
>>> def entry(r, box):
...     s = Sensor(LinearPositionSensor(np.eye(2) * r, ndim_state=4), DetectionModel(0.9, box),
...                PoissonClutter(1.0, box))
...     return SensorEntry(s, in_view=lambda x: box.contains(x[:, :2]))
>>> left, right = Box([-50, -50], [10, 50]), Box([-10, -50], [50, 50])
>>> problem = MultiSensorProblem(ConstantVelocity(0.1), [entry(1.0, left), entry(0.1, right)],
...                              means=[[-20, 0, 1, 0], [20, 0, -1, 0]], covs=np.stack([np.eye(4)] * 2), labels=[7, 9])
>>> tracker = build({"kind": "gnn"}, problem)
>>> _ = tracker.step(np.array([[-19.0, 0.1]]), 1.0, sensor=0)  # the left sensor sees object 7 only
>>> _ = tracker.step(np.array([[19.0, -0.1]]), 1.0, sensor=1)  # the right one, at the same instant, 9
>>> est = tracker.estimates()
>>> est.labels.tolist(), np.round(est.x[:, 0], 1).tolist()
([7, 9], [-19.0, 19.0])
>>> build({"kind": "pmbm_murty"}, problem)
Traceback (most recent call last):
...
ValueError: pmbm_murty: kind 'pmbm_murty' (family poisson_mb) has no multi-sensor form; the kinds of the engine and single families fuse (MultiSensorFactored, MultiSensorSHT)
"""

from . import builtin  # noqa: F401  (registers hypotrack's own kinds)
from .build import build, build_fused
from .builtin import engine_options
from .problem import MeasurementBirths, MultiSensorProblem, SensorEntry, TrackingProblem
from .spec import FAMILIES, Preset, SpecError, TrackerSpec, kinds, preset, register, unregister

__all__ = ["FAMILIES", "MeasurementBirths", "MultiSensorProblem", "Preset", "SensorEntry", "SpecError", "TrackerSpec",
           "TrackingProblem", "build", "build_fused", "engine_options", "kinds", "preset", "register", "unregister"]

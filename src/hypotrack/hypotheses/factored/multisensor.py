"""Several sensors fused in one factored filter: scans merged in time, each updated with its own sensor.

A scan of sensor ``s`` at time ``t`` is a :class:`SensorScan`; :func:`merge_scans` merges the sensors' sequences in
time (ties in sensor order). :class:`MultiSensorFactored` steps the factored filter (:class:`~.engine.FactoredFilter`)
through them, each scan with **its sensor's engine**: a :class:`~..filter.HypothesisFilter` per sensor, built for that
sensor (its measurement model and frame, ``p_D`` — constant or a ``detection.p_D_of`` of the state —, clutter rate and
volume, field of view through ``detection.in_view``, HOMHT's seeded births at its own returns), all sharing the
filter's posterior, random generator and motion model. What a scan touches is that sensor's: the tracks in its view
are the ones predicted and scored (``lazy``), missed (``p_D`` of its view), updated (its EKF).

Sequential update (the iterated corrector)
------------------------------------------
Scans at the same instant from two sensors are processed one after the other: a scan at a zero interval is an update
without prediction (the second sensor's corrector applied to the first one's posterior). For independent sensors
whose returns are conditionally independent given the objects this is the multi-sensor Bayes filter's corrector
written as a product of single-sensor correctors — exact for the full multi-object filter, and the standard
approximation once each corrector is truncated or capped (Mahler, *Statistical Multisource-Multitarget Information
Fusion*, Artech House 2007: the "iterated-corrector" multi-sensor filter, whose approximate forms depend on the order
of the sensors; for the δ-GLMB filter Vo, Vo & Beard, "Multi-sensor multi-object tracking with the generalized
labeled multi-Bernoulli filter", IEEE TSP 67(23), 2019, who contrast it with the joint multi-sensor update). The
population's per-scan events (a birth term, a per-scan survival) count once per sensor scan, as a second scan of a
single sensor at the same time would (:meth:`~..filter.HypothesisFilter.step`).

Birth terms built for the scan they belong to
---------------------------------------------
The single-sensor filter builds the next scan's measurement-driven birth terms (:class:`~..population_adaptive.
AdaptiveBirth`) at the end of a scan, predicted over *that* scan's interval and observed by *its* sensor — right for
evenly spaced scans of one sensor. Here the unexplained returns' states are made at the end of their scan, by their
own sensor (its one-point initiation or admissible-region mixture, at its site and time), and held; when the next
scan arrives they are predicted over the real interval to it — zero between two sensors at one instant — and become
birth terms gated and scored by the next scan's sensor (:meth:`AdaptiveBirth.observed
<..population_adaptive.AdaptiveBirth.observed>`). A state held from another sensor's scan at the same instant that
lies outside this sensor's field of view waits for the next later scan: the engine gives a birth term one detection
probability (the sensor's ``p_D``), so offered here it would be "born undetected" with weight ``r_B (1 − p_D)`` where
the sensor could not have seen it; waiting is the same as a ``p_D`` of 0 there when objects survive with
``p_S = 1`` (the catalogue's population). With one sensor and evenly spaced scans this is the single-sensor filter's
birth model, except at the first scan (whose own interval, often zero, the single-sensor filter reuses).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..._validation import check_finite_float, check_int
from ...gaussian import predict_with_unchecked
from ..filter import HypothesisFilter
from ..population_adaptive import AdaptiveBirth
from ..state import scan_interval
from .engine import FactoredFilter

__all__ = ["SensorScan", "merge_scans", "MultiSensorFactored"]


@dataclass(frozen=True, eq=False)
class SensorScan:
    """One scan: its time, its returns ``Z`` ``(m, p)`` in its sensor's frame, and its sensor's index."""

    time: float
    Z: np.ndarray
    sensor: int


def merge_scans(sequences: Sequence) -> list[SensorScan]:
    """The scans of several sensors in time order: ``sequences[s]`` is sensor ``s``'s ``[(t, Z), ...]`` (times not
    decreasing). Scans at one time keep the sensors' order (sensor 0 first), so a merge is deterministic."""
    out = []
    for s, seq in enumerate(sequences):
        last = -np.inf
        for t, Z in seq:
            t = check_finite_float(t, f"sequences[{s}] time")
            if t < last:
                raise ValueError(f"sequences[{s}]: scan times must not decrease, got {t} after {last}")
            last = t
            out.append(SensorScan(t, np.asarray(Z, dtype=float), s))
    order = sorted(range(len(out)), key=lambda i: (out[i].time, out[i].sensor, i))
    return [out[i] for i in order]


@dataclass(frozen=True, eq=False)
class _Pending:
    """Unexplained returns' states at their scans (``times``), waiting for a scan that may detect them; ``weights`` of
    the mixture components (1 for one-point states)."""

    x: np.ndarray
    P: np.ndarray
    weights: np.ndarray
    times: np.ndarray

    def take(self, rows) -> "_Pending":
        return _Pending(self.x[rows], self.P[rows], self.weights[rows], self.times[rows])

    def then(self, other: "_Pending") -> "_Pending":
        return _Pending(*(np.concatenate([getattr(self, f), getattr(other, f)]) for f in ("x", "P", "weights", "times")))


class MultiSensorFactored(FactoredFilter):
    """The factored filter over the scans of several sensors (module docstring).

    Made with :meth:`from_filters`: one configured :class:`~..filter.HypothesisFilter` per sensor (the same motion
    model, state dimension, weight model kind and caps; each with its sensor, and HOMHT's seeded-birth density of its
    sensor) and, for measurement-driven births, one :class:`~..population_adaptive.AdaptiveBirth` per sensor (the same
    ``r_birth``; a mixture such as the admissible region is of its own sensor's returns). The first filter's hypotheses
    are the initial posterior; :meth:`step` takes ``sensor=`` (default 0). With one sensor it is the single-sensor
    filter but for the birth terms' interval (module docstring).
    """

    def _configure(self, engine, options, changes):
        super()._configure(engine, options, changes)
        self._engines = [engine]
        self._births = [self._options.adaptive_birth]
        self._templates = [self._born_templates]
        self._sensor = 0
        self._pending = None

    @classmethod
    def from_filters(cls, filters: Sequence, births: Sequence | None = None, options=None, /, **option_changes):
        """The fused filter of ``filters`` (one :class:`~..filter.HypothesisFilter` per sensor, the first one's
        posterior) with ``births`` (one :class:`AdaptiveBirth` or ``None`` per sensor; ``None``: no adaptive births).
        ``options``/``option_changes``: as :meth:`FactoredFilter.from_filter` (``adaptive_birth`` is ``births[0]``).
        The first three are positional only: the factored option ``births`` (coupled or free) is an option change."""
        filters = list(filters)
        if not filters:
            raise ValueError("filters must hold one HypothesisFilter per sensor, got none")
        for i, f in enumerate(filters):
            if not isinstance(f, HypothesisFilter):
                raise TypeError(f"filters[{i}] must be a HypothesisFilter, got {type(f).__name__}")
        births = [None] * len(filters) if births is None else list(births)
        if len(births) != len(filters):
            raise ValueError(f"births must hold one AdaptiveBirth (or None) per sensor: {len(filters)} filters, "
                             f"{len(births)} births")
        if "adaptive_birth" in option_changes:
            raise ValueError("give the sensors' adaptive births as births, not adaptive_birth")
        for i, b in enumerate(births):
            if b is not None and not isinstance(b, AdaptiveBirth):
                raise TypeError(f"births[{i}] must be an AdaptiveBirth or None, got {type(b).__name__}")
            if b is not None and b.r_birth != births[0].r_birth:
                raise ValueError(f"births[{i}].r_birth = {b.r_birth} must equal births[0].r_birth = {births[0].r_birth}")
        obj = cls.from_filter(filters[0], options, adaptive_birth=births[0], **option_changes)
        for f, b in zip(filters[1:], births[1:]):
            obj.add_sensor(f, b)
        return obj

    def add_sensor(self, f: HypothesisFilter, birth: AdaptiveBirth | None = None) -> int:
        """Add a sensor: ``f`` configured for it (its hypotheses are not used) and its adaptive ``birth`` (``None``
        exactly when the filter has none). Returns the sensor's index."""
        E, i = self._engines[0], len(self._engines)
        if not isinstance(f, HypothesisFilter):
            raise TypeError(f"f must be a HypothesisFilter, got {type(f).__name__}")
        if f.state_dim != E.state_dim or type(f.weights) is not type(E.weights) or f.motion is not E.motion:
            raise ValueError(f"filters[{i}] must share filters[0]'s motion model (the same object), state "
                             f"dimension and weight model kind")
        if f.weights.seeded_births != E.weights.seeded_births:
            raise ValueError(f"filters[{i}]: seeded births on one sensor need them on every sensor")
        if (birth is None) != (self._births[0] is None):
            raise ValueError("births must be an AdaptiveBirth for every sensor or None for every sensor")
        if birth is not None and getattr(f.population, "n_birth_regions", 1):
            raise ValueError(f"filters[{i}]: adaptive births set the population's birth terms each scan: give a "
                             f"population with no birth terms")
        # the sensor's engine; one random generator for all, so a run is one seeded stream
        self._engines.append(HypothesisFilter(**f.configuration(), seed=self.rng))
        self._templates.append({})
        self._births.append(birth)
        return i

    @property
    def n_sensors(self) -> int:
        return len(self._engines)

    @property
    def sensor(self) -> int:
        """The sensor of the last scan (of the next one until :meth:`step`)."""
        return self._sensor

    def _use(self, sensor: int) -> None:
        """Step the next scan with sensor ``sensor``'s engine (its models, its population — whose measurement-driven
        birth terms :meth:`_step` sets — and its lone-birth templates)."""
        self._sensor = sensor
        self._engine, self._born_templates = self._engines[sensor], self._templates[sensor]

    def step(self, Z, time=None, *, dt=None, sensor: int = 0):
        """One scan of sensor ``sensor`` (index into :meth:`from_filters`' ``filters``): returns ``Z`` in its frame
        at ``time`` (``dt`` as :meth:`FactoredFilter.step`; a zero interval is the sequential update of the module
        docstring). All-or-nothing: if it raises, the filter is as before, sensor and held birth states included."""
        sensor = check_int(sensor, "sensor", minimum=0, maximum=self.n_sensors - 1)
        saved = (self._sensor, self._pending)
        try:
            self._use(sensor)
            return super().step(Z, time, dt=dt)  # restores this engine's population if it raises
        except BaseException:
            self._use(saved[0])
            self._pending = saved[1]
            raise

    def step_scan(self, scan: SensorScan):
        """:meth:`step` of one :class:`SensorScan`."""
        return self.step(scan.Z, scan.time, sensor=scan.sensor)

    def _step(self, Z, time, dt):
        if self._options.adaptive_birth is not None:
            _, now = scan_interval(self.time, time, dt, self._engine.dt)
            self._set_birth_terms(self._held_terms(now))
        return super()._step(Z, time, dt)

    def _held_terms(self, now: float) -> list:
        """This scan's birth terms from the held states (module docstring): those of an earlier scan all, predicted
        over the real interval; those of this instant (another sensor's scan) at a zero interval — no motion, no
        process noise — if in this sensor's view, the others held for the next scan. Observed by this scan's sensor."""
        p = self._pending
        if p is None or len(p.x) == 0:
            self._pending = None
            return []
        same = p.times == now
        if same.any():
            wait = np.flatnonzero(same)[~self._advance_view(p.x[same], 0)[1]]
            use = np.setdiff1d(np.arange(len(p.x)), wait)
            self._pending, p = (p.take(wait) if len(wait) else None), p.take(use)
        else:
            self._pending = None
        gap = now - p.times
        x, P = p.x.copy(), p.P.copy()
        for g in np.unique(gap[gap > 0]):
            sel = gap == g
            x[sel], P[sel] = predict_with_unchecked(self._engine.motion, p.x[sel], p.P[sel], float(g))
        E = self._engine
        return self._births[self._sensor].observed(x, P, p.weights, E.H, E.R, measurement=E.measurement)

    def _births_after(self, Z, interval) -> int:
        """Hold the states of this scan's unexplained returns (made by this scan's sensor, at this scan's time) for the
        next scan; this scan's terms are used. Returns the number of states held (these and those still waiting)."""
        E = self._engine
        if len(Z):
            x, P, w = self._births[self._sensor].components(Z, E.H, E.R, measurement=E.measurement)
            new = _Pending(x, P, np.ones(len(x)) if w is None else w, np.full(len(x), self.time))
            self._pending = new if self._pending is None else self._pending.then(new)
        self._set_birth_terms([])
        return 0 if self._pending is None else len(self._pending.x)

    def _reset(self, time: float = 0.0):
        super()._reset(time)
        self._pending = None

"""The one surface every tracker of hypotrack offers: :class:`Tracker` and :class:`TrackEstimates`.

A tracker is started from known objects and then fed one scan at a time, each with its time:

>>> tracker.initialise(means, covs, labels, time=0.0)   # doctest: +SKIP
>>> for t, Z in scans:                                  # doctest: +SKIP
...     tracker.step(Z, t)
...     est = tracker.estimates()                       # labels, means, covariances

* ``step(Z, time)``: the returns ``Z`` (``(m, dz)``, ``m = 0`` is a normal empty scan) observed at the
  absolute ``time``; the tracker predicts over ``time − tracker.time`` and updates. A zero interval
  is an update without prediction (a second sensor's scan at the same time, or the first scan at
  the priors' epoch); a negative one is refused. ``time=None`` steps by the tracker's own default
  interval where it has one (the hypothesis filters' ``dt``).
* ``estimates()``: the tracker's current :class:`TrackEstimates` (for the hypothesis filters, the
  maximum a posteriori hypothesis's tracks).
* ``posterior()`` (:class:`HypothesisTracker` only): the hypothesis filters' posterior over
  hypotheses.

The experiments, the Stone Soup adapter and :mod:`hypotrack.registry` use only this surface, so a
tracker registered as a preset reaches every one of them. Who implements it: the hypothesis engine
(:class:`~hypotrack.hypotheses.HypothesisFilter` and every preset), the factored engine
(:class:`~hypotrack.hypotheses.factored.FactoredFilter`) and the single-hypothesis trackers
(:class:`~hypotrack.trackers.SingleHypothesisTracker`: GNN, JPDA, PDAF). Document 003's filters
(:mod:`hypotrack.trackers.ecmht`: the ideal filter, MHT, ECMHT, PDAF on two closely spaced targets;
:mod:`hypotrack.trackers.cardinality`) do not: they step a batch of Monte Carlo runs of synchronous
multi-sensor scans at once and hold unlabelled positions (or only counts), a different shape of problem.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

__all__ = ["TrackEstimates", "Tracker", "HypothesisTracker"]


@dataclass(frozen=True, eq=False)
class TrackEstimates:
    """A tracker's tracks at one time, each with its label.

    Attributes
    ----------
    time : float
        Time of the last scan (or of :meth:`Tracker.initialise`).
    labels : (n,) int64
        One stable label per track: the label given to :meth:`Tracker.initialise` for a known object,
        a new one for a track born from the data.
    x : (n, d)
        Means.
    P : (n, d, d) or None
        Covariances; ``None`` where the tracker does not predict them to ``time`` (the factored
        filter's lazy lane, whose objects are out of view).

    Examples
    --------
    >>> import numpy as np
    >>> est = TrackEstimates(2.0, np.array([7, 9]), np.zeros((2, 4)), None)
    >>> len(est), est.labels.tolist()
    (2, [7, 9])
    """

    time: float
    labels: np.ndarray
    x: np.ndarray
    P: np.ndarray | None = None

    @property
    def ids(self) -> np.ndarray:
        """The labels (the single-hypothesis trackers' name for them)."""
        return self.labels

    def __len__(self) -> int:
        return len(self.labels)


@runtime_checkable
class Tracker(Protocol):
    """What every tracker of hypotrack implements (see the module docstring)."""

    time: float | None

    def initialise(self, means, covs, labels=None, *, time: float = 0.0):
        """Known objects: means ``(n, d)``, covariances ``(n, d, d)``, optional integer labels ``(n,)``
        (default ``0 .. n − 1``), valid at ``time``."""

    def step(self, Z, time: float | None = None):
        """One scan: returns ``Z`` ``(m, dz)`` observed at ``time`` (see the module docstring)."""

    def estimates(self) -> TrackEstimates:
        """The current tracks."""


@runtime_checkable
class HypothesisTracker(Tracker, Protocol):
    """A :class:`Tracker` that keeps a posterior over hypotheses (the engine's presets)."""

    def posterior(self, n_top: int = 1):
        """The posterior: weights, cardinality distribution, the ``n_top`` heaviest hypotheses."""

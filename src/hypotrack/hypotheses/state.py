"""The engine's state, apart from its configuration: :class:`FilterState` and :class:`StepResult`.

A :class:`~.filter.HypothesisFilter` is a configuration (models, weight model, generator,
population, cap) and a state: the hypotheses over a shared track store (document 001 Sec. III-C:
a hypothesis holds indices into one store of Gaussian tracks). :meth:`~.filter.HypothesisFilter.advance`
maps a state, the scan's predicted tracks and its :class:`~.scan_context.ScanContext` to the next
state (document 000 Eq. 11, 19); ``step`` is that map on the filter's own state, and the factored
filter (:mod:`.factored`) applies it group by group, a group's hypotheses being a state of their own.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._validation import check_finite_float
from .tracks import TrackStore

__all__ = ["FilterState", "StepResult", "scan_interval"]


@dataclass(frozen=True, eq=False)
class FilterState:
    """Hypotheses over one track store.

    Attributes
    ----------
    store : TrackStore
        The tracks every hypothesis indexes.
    log_w : (H,) float
        Normalised log-weights (log-sum-exp 0).
    tracks : list of (n_h,) int64
        Per hypothesis, the indices of its tracks in ``store``.
    keys : list
        Per hypothesis, a hashable key of its lineage (the population and association events of
        every scan), equal across filters that generated the same hypothesis.
    next_label : int
        The label the next newborn track gets. A group of the factored filter holds 0 here: the
        factored filter numbers newborn objects itself and passes its next label to each step.

    The arrays are shared, never written in place: a new state is a new object.

    Examples
    --------
    >>> s = FilterState.initial(np.zeros((2, 4)), np.repeat(np.eye(4)[None], 2, axis=0))
    >>> len(s), s.tracks[0].tolist(), s.next_label
    (1, [0, 1], 2)
    """

    store: TrackStore
    log_w: np.ndarray
    tracks: list
    keys: list
    next_label: int = 0

    @classmethod
    def initial(cls, means, covs=None, labels=None, *, ndim: int | None = None) -> "FilterState":
        """One hypothesis of weight 1 holding ``n`` objects (``n = 0`` allowed: give ``ndim``).

        ``labels`` default to ``0 .. n − 1``; the next label is one past the largest."""
        means = np.asarray(means, dtype=float)
        if means.size == 0:
            if ndim is None:
                ndim = means.shape[-1] if means.ndim == 2 else None
            store = TrackStore.from_arrays(np.zeros((0, ndim or 0)), None, ndim=ndim)
        else:
            if covs is None:
                raise ValueError("covs are required with means")
            store = TrackStore.from_arrays(means, covs, labels)
        nxt = int(store.labels.max()) + 1 if len(store) else 0
        return cls(store, np.zeros(1), [np.arange(len(store), dtype=np.int64)], [()], nxt)

    def __len__(self) -> int:
        """The number of hypotheses."""
        return len(self.log_w)

    @property
    def labels(self) -> np.ndarray:
        """The object labels held by some hypothesis (sorted, distinct)."""
        return np.unique(self.store.labels) if len(self.store) else np.zeros(0, dtype=np.int64)

    def with_next_label(self, next_label: int) -> "FilterState":
        """The same hypotheses, newborn tracks labelled from ``next_label``."""
        return replace(self, next_label=int(next_label))

    def with_store(self, store: TrackStore) -> "FilterState":
        """The same hypotheses over ``store`` (the same entries, e.g. predicted)."""
        return replace(self, store=store)

    def same_as(self, other: "FilterState") -> bool:
        """Bit-for-bit the same hypotheses: weights, track moments, labels, track lists and next label
        (the lineage keys are not compared: they name how a hypothesis was reached, not what it is)."""
        a, b = self.store, other.store
        return (self.next_label == other.next_label and len(self.tracks) == len(other.tracks)
                and np.array_equal(self.log_w, other.log_w) and np.array_equal(a.labels, b.labels)
                and np.array_equal(a.means, b.means) and np.array_equal(a.covs, b.covs)
                and all(np.array_equal(x, y) for x, y in zip(self.tracks, other.tracks)))


@dataclass(frozen=True, eq=False)
class StepResult:
    """What :meth:`~.filter.HypothesisFilter.advance` returns.

    Attributes
    ----------
    state : FilterState
        The hypotheses after the scan.
    sources : (N, 2) int64
        Per entry of the new store, ``(source, return)``: ``source >= 0`` the predicted track it
        was updated from, ``−1 − r`` birth term ``r``, ``−1 − B − c`` a seeded birth in component ``c``
        of its birth density (``B`` birth terms; :mod:`.seeded`); ``return`` the return it took, ``−1`` none.
    kept : ChildSet
        The kept children (parent, events, kind, argument, weight), in the new state's order.
    stats : dict
        The scan's counts and timings (``HypothesisFilter.last_stats``).
    n_new_labels : int
        Labels given to newborn tracks (``state.next_label`` minus the input state's).
    """

    state: FilterState
    sources: np.ndarray
    kept: object
    stats: dict
    n_new_labels: int = 0


def scan_interval(now: float, time=None, dt=None, default: float = 1.0) -> tuple[float, float]:
    """``(interval, time)`` of the next scan of a filter at time ``now``.

    Exactly one of ``time`` (the scan's absolute time; the interval is ``time − now``) and ``dt``
    (the interval itself) may be given; neither steps by ``default``. A zero interval is an update
    without prediction; a negative one raises ``ValueError`` naming the argument given.

    >>> scan_interval(2.0, time=2.5)
    (0.5, 2.5)
    >>> scan_interval(2.0, dt=0.0)
    (0.0, 2.0)
    """
    if time is not None and dt is not None:
        raise ValueError(f"give the scan's time or its interval dt, not both (time={time!r}, dt={dt!r})")
    if time is not None:
        t = check_finite_float(time, "time")
        if t < now:
            raise ValueError(f"time must be >= the filter's time {now!r} (scans in order), got {time!r}")
        return t - now, t
    if dt is None:
        return float(default), now + float(default)
    d = check_finite_float(dt, "dt")
    if d < 0:
        raise ValueError(f"dt must be a finite number >= 0, got {dt!r}")
    return d, now + d

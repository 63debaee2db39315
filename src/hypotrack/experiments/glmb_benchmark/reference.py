"""The GLMB papers' reference settings: their state extraction, their truncation, and a blind control.

State extraction (two rules, both reported):

* ``heaviest``: the means of the single heaviest hypothesis (this project's MAP hypothesis);
* ``map_cardinality``: the published demo's rule (Vo & Vo 2013 Sec. IV-C; Vo, Vo & Phung 2014
  Sec. V-C): first the MAP cardinality ``N̂ = argmax_n ρ(n)`` with ``ρ(n) = Σ_{I: |I| = n} w^{(I,ξ)}``
  (the cardinality distribution, Vo & Vo 2013 Eq. 14), then the heaviest hypothesis *of that
  cardinality*. The two differ when the heaviest hypothesis holds a cardinality whose total mass is
  not the largest.

Truncation (Vo, Vo & Hoang 2017 Sec. IV-C, the demo's ``H_upd = H_max = 1000``): parent ``h`` of
normalised weight ``w_h`` draws ``round(H_upd √w_h / Σ_j √w_j)`` Gibbs samples (the start, every
object missed, counts as the first), the distinct children are kept with exact weights, identical
children of different parents merged, and the ``H_max`` heaviest kept (:class:`SqrtAllocationFilter`).

Negative control: :class:`BlindTracker` runs a tracker on empty scans (prediction only), so it can
follow no birth; scored the same way it must fail any check that a tracker follows the truth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_int
from ...hypotheses.filter import HypothesisFilter
from ...hypotheses.gibbs import GibbsGenerator

__all__ = ["EXTRACTIONS", "heaviest_index", "map_cardinality_index", "extract", "sqrt_allocation",
           "AllocatedGibbsGenerator", "SqrtAllocationFilter", "BlindTracker"]

EXTRACTIONS = ("heaviest", "map_cardinality")


def _check(log_weights, n_objects):
    lw = np.asarray(log_weights, dtype=float).ravel()
    n = np.asarray(n_objects, dtype=np.int64).ravel()
    if len(lw) == 0 or len(lw) != len(n):
        raise ValueError(f"log_weights and n_objects must be non-empty and of one length, got {len(lw)} and {len(n)}")
    if np.any(n < 0):
        raise ValueError("n_objects must be >= 0")
    return lw, n


def heaviest_index(log_weights, n_objects) -> int:
    """Index of the heaviest hypothesis (the first of equal weights)."""
    lw, _ = _check(log_weights, n_objects)
    return int(np.argmax(lw))


def map_cardinality_index(log_weights, n_objects) -> int:
    """Index of the heaviest hypothesis among those holding the MAP cardinality (module docstring;
    ties: the smaller cardinality, then the first hypothesis)."""
    lw, n = _check(log_weights, n_objects)
    w = np.exp(lw - lw.max())
    N = int(np.argmax(np.bincount(n, weights=w)))
    cand = np.flatnonzero(n == N)
    return int(cand[np.argmax(lw[cand])])


def extract(tracker, post, rule: str) -> np.ndarray:
    """Position-and-velocity estimates ``(n, d)`` of ``tracker`` after a step by extraction ``rule``.

    A tracker without hypotheses (the GM-PHD peer) has one estimate set: both rules return it."""
    if rule not in EXTRACTIONS:
        raise ValueError(f"extraction rule must be one of {', '.join(EXTRACTIONS)}, got {rule!r}")
    tracker = tracker.tracker if isinstance(tracker, BlindTracker) else tracker
    if rule == "heaviest" or not isinstance(tracker, HypothesisFilter):
        return post.map_estimate.means if post.map_estimate is not None else np.zeros((0, 4))
    lists = tracker.state.tracks
    h = map_cardinality_index(tracker.log_weights, [len(t) for t in lists])
    return tracker.store.means[lists[h]]


def sqrt_allocation(log_weights, total: int) -> np.ndarray:
    """Samples per parent: ``round(total √w_h / Σ_j √w_j)`` (round half away from zero, as MATLAB)."""
    total = check_int(total, "total_samples", minimum=1)
    lw = np.asarray(log_weights, dtype=float)
    s = np.exp(0.5 * (lw - lw.max()))
    share = total * s / s.sum()
    return np.floor(share + 0.5).astype(np.int64)


@dataclass(frozen=True)
class AllocatedGibbsGenerator(GibbsGenerator):
    """The Gibbs generator whose number of sweeps :class:`SqrtAllocationFilter` sets per parent:
    ``n_sweeps = 0`` is allowed here (a parent allotted one sample keeps only its all-missed start),
    unlike :class:`GibbsGenerator`, where it would mean never using a measurement."""

    n_sweeps: int = 0

    def __post_init__(self):
        check_int(self.n_sweeps, "n_sweeps", minimum=0)


class SqrtAllocationFilter(HypothesisFilter):
    """The δ-GLMB filter with the demo's truncation (module docstring): the Gibbs generator's
    number of samples is set per parent from its weight; ``total_samples`` is ``H_upd``.

    It uses the engine's extension point :meth:`~hypotrack.hypotheses.filter.HypothesisFilter.parent_generators`:
    one generator per parent, each with its own number of sweeps."""

    def __init__(self, *args, total_samples: int, **kwargs):
        super().__init__(*args, **kwargs)
        if not isinstance(self.generator, GibbsGenerator):
            raise TypeError(f"SqrtAllocationFilter needs a GibbsGenerator, got {type(self.generator).__name__}")
        self.total_samples = check_int(total_samples, "total_samples", minimum=1)

    def parent_generators(self, state):
        # n samples = the start plus n - 1 sweeps (a parent allotted none still yields its start)
        allocation = sqrt_allocation(state.log_w, self.total_samples)
        return [AllocatedGibbsGenerator(n_sweeps=max(int(n) - 1, 0)) for n in allocation]


class BlindTracker:
    """A tracker fed empty scans whatever it is given: prediction only (the negative control)."""

    def __init__(self, tracker):
        self.tracker = tracker

    def step(self, Z):
        Z = np.asarray(Z, dtype=float).reshape(-1, 2)
        return self.tracker.step(Z[:0])

"""The association problem of one parent hypothesis: every child weight as a gather-sum.

DESIGN.md §4.2: for each weight model the log-weight of a child is a sum of entries of the
parent's *data association matrix* (document 000 Fig. 4) plus a term in the counts. Here that
matrix is split by how its columns may be used:

* ``target_scores`` (m, C) — *exclusive* columns, at most one return each: the parent's
  ``n_objects`` objects first, then birth regions (document 000 Eq. 30: a return may be the one
  detection of a newly born object);
* ``option_scores`` (m, T) — *row options* any number of returns may take: option 0 is
  clutter, option 1 (HOMHT only) "a new target seeded at this return" (document 001 Eq. 35);
* ``count_term`` (n_objects + 1, C − n_objects + 1) — ``φ[k, b]`` for ``k`` returns on objects
  and ``b`` on birth columns (H-FISST's ``−log(C(m, k) k!)`` of Eq. 8, FISST's Poisson-clutter
  factor of document 001 Eq. 6–7, the population-event probability of Eq. 30 …; ``-inf`` forbids a
  count, e.g. two births under the single-event model);
* ``constant`` — everything common to all children (parent log-weight, ``Σ log(1 − p_D)``).

An *event* is an int vector over the returns: ``a_i >= 0`` an exclusive column, ``a_i = -1``
clutter, ``a_i = -2`` a seeded birth (generally ``-1 - t`` for option ``t``). This extends the
project-wide convention of :mod:`hypotrack.association` by the extra columns.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..association.samplers import check_problem, checked_event_log_weights

__all__ = ["AssociationProblem", "CLUTTER", "SEEDED_BIRTH"]

CLUTTER = -1
SEEDED_BIRTH = -2


@dataclass(frozen=True, eq=False)
class AssociationProblem:
    """Scores of all children of one parent (see the module docstring).

    Attributes
    ----------
    target_scores : (m, C) float array
    option_scores : (m, T) float array, ``T >= 1`` (column 0 clutter, finite)
    n_objects : int
    count_term : (n_objects + 1, C - n_objects + 1) float array
    constant : float
    """

    target_scores: np.ndarray
    option_scores: np.ndarray
    n_objects: int
    count_term: np.ndarray
    constant: float = 0.0

    def __post_init__(self):
        ts = np.asarray(self.target_scores, dtype=float)
        os_ = np.asarray(self.option_scores, dtype=float)
        if ts.ndim != 2 or os_.ndim != 2 or ts.shape[0] != os_.shape[0] or os_.shape[1] < 1:
            raise ValueError(
                f"target_scores (m, C) and option_scores (m, T>=1) must share m, got {ts.shape} and {os_.shape}"
            )
        if not 0 <= self.n_objects <= ts.shape[1]:
            raise ValueError(f"n_objects must lie in [0, {ts.shape[1]}], got {self.n_objects}")
        ct = np.asarray(self.count_term, dtype=float)
        want = (self.n_objects + 1, ts.shape[1] - self.n_objects + 1)
        if ct.shape != want:
            raise ValueError(f"count_term must have shape {want}, got {ct.shape}")
        object.__setattr__(self, "target_scores", ts)
        object.__setattr__(self, "option_scores", os_)
        object.__setattr__(self, "count_term", ct)
        object.__setattr__(self, "constant", float(self.constant))

    @property
    def n_returns(self) -> int:
        return self.target_scores.shape[0]

    @property
    def n_exclusive(self) -> int:
        return self.target_scores.shape[1]

    @property
    def n_birth_columns(self) -> int:
        return self.n_exclusive - self.n_objects

    @property
    def n_options(self) -> int:
        return self.option_scores.shape[1]

    @cached_property
    def score(self) -> np.ndarray:
        """The full (m, C + T) data association matrix ``[target_scores | option_scores]``
        (built once: the chain, its starting event and the children's weights all read it)."""
        return np.hstack([self.target_scores, self.option_scores])

    @property
    def allowed(self) -> np.ndarray:
        """(m, C) bool: which return may take which exclusive column (finite score)."""
        return np.isfinite(self.target_scores)

    @property
    def count_term_is_constant(self) -> bool:
        """True when ``φ`` is the same for every count, i.e. the weight is a pure row sum
        (then k-best assignment ranks children exactly)."""
        ct = self.count_term
        return bool(np.all(ct == ct.flat[0]))

    @cached_property
    def checked(self) -> tuple:
        """``(score, n_objects, n_exclusive, count_term)`` validated once
        (:func:`hypotrack.association.samplers.check_problem`) for the searches and weights of this problem."""
        return check_problem(self.score, self.n_objects, self.n_exclusive, self.count_term)

    def log_weights(self, events) -> np.ndarray:
        """Exact child log-weights ``constant + Σ_i score[i, a_i] + φ[k, b]`` of events (E, m)."""
        events = np.asarray(events)
        if events.ndim != 2 or events.shape[1] != self.n_returns:
            raise ValueError(f"events must have shape (E, {self.n_returns}), got {events.shape}")
        return self.constant + checked_event_log_weights(*self.checked, events)

    def counts(self, events) -> tuple[np.ndarray, np.ndarray]:
        """``(k, b)`` per event: returns on object columns and on birth columns."""
        ev = np.asarray(events)
        k = np.sum((ev >= 0) & (ev < self.n_objects), axis=1)
        b = np.sum(ev >= self.n_objects, axis=1)
        return k, b

    def detected(self, events) -> np.ndarray:
        """(E, n_objects) bool: which parent objects each event assigns a return to."""
        ev = np.asarray(events)
        det = np.zeros((ev.shape[0], self.n_objects), dtype=bool)
        rows, cols = np.nonzero((ev >= 0) & (ev < self.n_objects))
        det[rows, ev[rows, cols]] = True
        return det

"""A hypothesis: a log-weight and references to shared tracks (document 000 Eq. 1–2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Hypothesis", "ChildSet"]


@dataclass(frozen=True)
class Hypothesis:
    """One multi-object hypothesis: ``log_weight`` and the indices of its tracks in the store.

    The multi-object pdf under the hypothesis is the product of its tracks' pdfs (document 000
    Eq. 2; the FISST pdf is its symmetrisation, document 000 Eq. 3 and 34).
    """

    log_weight: float
    tracks: tuple

    @property
    def n_objects(self) -> int:
        return len(self.tracks)


@dataclass(frozen=True, eq=False)
class ChildSet:
    """Children of all parents for one scan, before capping.

    Attributes
    ----------
    parent : (E,) int — index of the parent hypothesis.
    events : (E, m) int — the association event (codes of :mod:`.association_problem`).
    kind : (E,) int — 0 association child, 1 plus an undetected birth, 2 plus a death, 3 plus a
        set of silent events (labeled multi-Bernoulli population).
    arg : (E,) int — the birth region (kind 1), the parent-local index of the dead object
        (kind 2) or a bit mask (kind 3: bit ``j < M`` object ``j`` died, bit ``M + r`` birth
        term ``r`` born undetected); −1 otherwise.
    log_weights : (E,) float — unnormalised log-weights (parent weight included).
    """

    parent: np.ndarray
    events: np.ndarray
    kind: np.ndarray
    arg: np.ndarray
    log_weights: np.ndarray

    ASSOCIATION = 0
    UNDETECTED_BIRTH = 1
    DEATH = 2
    POPULATION_SET = 3

    def silent_events(self, c: int, n_objects: int) -> tuple[list, list]:
        """(dead parent-local objects, birth terms born undetected) of child ``c``."""
        kind, arg = int(self.kind[c]), int(self.arg[c])
        if kind == ChildSet.DEATH:
            return [arg], []
        if kind == ChildSet.UNDETECTED_BIRTH:
            return [], [arg]
        if kind == ChildSet.POPULATION_SET:
            bits = [j for j in range(arg.bit_length()) if arg >> j & 1]
            return [j for j in bits if j < n_objects], [j - n_objects for j in bits if j >= n_objects]
        return [], []

    def __len__(self) -> int:
        return len(self.log_weights)

    def take(self, idx) -> "ChildSet":
        idx = np.asarray(idx, dtype=np.int64)
        return ChildSet(self.parent[idx], self.events[idx], self.kind[idx], self.arg[idx], self.log_weights[idx])

    @staticmethod
    def concatenate(parts, n_returns: int) -> "ChildSet":
        parts = [p for p in parts if len(p)]
        if not parts:
            z = np.zeros(0, dtype=np.int64)
            return ChildSet(z, np.zeros((0, n_returns), dtype=np.int32), z, z, np.zeros(0))
        return ChildSet(*(np.concatenate([getattr(p, f) for p in parts])
                          for f in ("parent", "events", "kind", "arg", "log_weights")))

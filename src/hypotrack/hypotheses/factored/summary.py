"""The factored posterior as a summary: :class:`FactoredPosterior`, :func:`cardinality_total_variation`."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ..posterior import HypothesisEstimate, summarise
from ..tracks import TrackStore

__all__ = ["FactoredPosterior", "cardinality_total_variation"]


class FactoredPosterior:
    """The product posterior as a summary (each part computed when first read).

    Attributes
    ----------
    groups : per group, its :class:`~.posterior.Posterior` (the multi-hypothesis groups first,
        then the singletons in lane order).
    n_groups : the number of groups.
    cardinality : ``P(n objects)``, the convolution of the groups' cardinality distributions
        (a singleton shifts it by one).
    expected_number : the sum of the groups' expected numbers.
    map_estimate : the union of the groups' MAP hypotheses — the MAP of a product of
        independent distributions — with weight the product of theirs.
    """

    def __init__(self, states, singles, n_singles: int, n_top: int = 1, n_states: int | None = None):
        # states, singles: the groups and the lane's TrackStore, or functions giving them (lazy
        # groups and singletons are predicted to the scan only when a summary that needs them is read)
        self._get_states, self._get_singles, self._n_singles, self._n_top = states, singles, n_singles, n_top
        self._n_states = len(states) if n_states is None else n_states

    @cached_property
    def _states(self) -> tuple:
        return tuple(self._get_states() if callable(self._get_states) else self._get_states)

    @cached_property
    def _singles(self) -> TrackStore:
        return self._get_singles() if callable(self._get_singles) else self._get_singles

    @cached_property
    def _posts(self) -> tuple:
        return tuple(summarise(s.log_w, s.tracks, s.store, n_top=self._n_top) for s in self._states)

    @cached_property
    def groups(self) -> tuple:
        one, single = np.zeros(1), [np.zeros(1, dtype=np.int64)]
        L = self._singles
        return self._posts + tuple(
            summarise(one, single, TrackStore(L.means[[j]], L.covs[[j]], L.labels[[j]]), n_top=1) for j in range(len(L)))

    @property
    def n_groups(self) -> int:
        return self._n_states + self._n_singles

    @cached_property
    def cardinality(self) -> np.ndarray:
        card = np.zeros(self._n_singles + 1)
        card[-1] = 1.0
        for p in self._posts:
            card = np.convolve(card, p.cardinality)
        return card

    @cached_property
    def expected_number(self) -> float:
        return float(sum(p.expected_number for p in self._posts) + self._n_singles)

    @cached_property
    def map_estimate(self) -> HypothesisEstimate:
        maps = [p.map_estimate for p in self._posts]
        L = self._singles
        lw = float(sum(e.log_weight for e in maps))
        return HypothesisEstimate(
            float(np.exp(lw)), lw,
            np.concatenate([e.labels for e in maps] + [L.labels]),
            np.concatenate([e.means for e in maps] + [L.means]),
            np.concatenate([e.covs for e in maps] + [L.covs]),
        )


def cardinality_total_variation(p, q) -> float:
    """``½ Σ_n |p(n) − q(n)|`` between two cardinality distributions (zero-padded)."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    n = max(len(p), len(q))
    return 0.5 * float(np.abs(np.pad(p, (0, n - len(p))) - np.pad(q, (0, n - len(q)))).sum())

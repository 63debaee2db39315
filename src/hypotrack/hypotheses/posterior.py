"""Posterior summaries of a hypothesis filter (document 000 Figs 6, 8–11)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["HypothesisEstimate", "Posterior", "summarise"]


@dataclass(frozen=True, eq=False)
class HypothesisEstimate:
    """One hypothesis with its weight and the Gaussian estimates of its objects."""

    weight: float
    log_weight: float
    labels: np.ndarray
    means: np.ndarray
    covs: np.ndarray

    @property
    def n_objects(self) -> int:
        return len(self.labels)


@dataclass(frozen=True, eq=False)
class Posterior:
    """The discrete posterior over hypotheses and what a reader wants from it.

    Attributes
    ----------
    log_weights : (H,) normalised log-weights (log-sum-exp = 0), best first.
    n_objects : (H,) number of objects in each hypothesis.
    cardinality : (N_max + 1,) ``P(n objects)``, summing the weights of all hypotheses with
        ``n`` objects (document 000 Fig. 11).
    expected_number : ``Σ_n n P(n)``.
    top : the best hypotheses with their estimates, best first.
    """

    log_weights: np.ndarray
    n_objects: np.ndarray
    cardinality: np.ndarray
    expected_number: float
    top: tuple

    @property
    def weights(self) -> np.ndarray:
        return np.exp(self.log_weights)

    @property
    def map_estimate(self) -> HypothesisEstimate:
        return self.top[0]


def summarise(log_weights, track_lists, store, n_top: int = 10) -> Posterior:
    """Build a :class:`Posterior` from normalised log-weights and per-hypothesis track indices."""
    lw = np.asarray(log_weights, dtype=float)
    order = np.argsort(-lw, kind="stable")
    lw = lw[order]
    lists = [np.asarray(track_lists[i], dtype=np.int64) for i in order]
    n_obj = np.array([len(t) for t in lists], dtype=np.int64)
    w = np.exp(lw)
    card = np.bincount(n_obj, weights=w, minlength=1) if len(n_obj) else np.ones(1)
    top = tuple(
        HypothesisEstimate(float(w[h]), float(lw[h]), store.labels[t], store.means[t], store.covs[t])
        for h, t in enumerate(lists[:n_top])
    )
    return Posterior(lw, n_obj, card, float(np.dot(np.arange(len(card)), card)), top)

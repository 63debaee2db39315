"""The track store shared by all hypotheses (document 001 Sec. III-C: tracks are beliefs).

A hypothesis does not own Gaussian pdfs; it holds indices into one :class:`TrackStore`. Each
scan the whole store is predicted once (batched), and after the children have been chosen a
new store is built from the distinct ``(source, return)`` pairs the surviving children use,
so a track is updated once per pair however many hypotheses hold it (the TOMHT-style track
tree of document 001 Theorem 1, kept one generation deep).

Each track carries a ``label`` (the identity of the object it follows: inherited through
updates, fresh for every birth), which is what the posterior summaries report.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_covariance, check_finite_array
from ..gaussian import predict_with_unchecked, update_unchecked

__all__ = ["TrackStore", "update_pairs"]


@dataclass(frozen=True, eq=False)
class TrackStore:
    """Gaussian tracks ``N(means[j], covs[j])`` with persistent object ``labels[j]``."""

    means: np.ndarray
    covs: np.ndarray
    labels: np.ndarray

    @classmethod
    def from_arrays(cls, means, covs, labels=None, ndim=None) -> "TrackStore":
        """Validated store; ``means`` (n, d), ``covs`` (n, d, d); n = 0 needs ``ndim``."""
        means = np.asarray(means, dtype=float)
        if means.size == 0:
            if ndim is None:
                raise ValueError("an empty track store needs ndim")
            return cls(np.zeros((0, ndim)), np.zeros((0, ndim, ndim)), np.zeros(0, dtype=np.int64))
        means = check_finite_array(means, "means", ndim=2)
        n, d = means.shape
        covs = check_covariance(covs, "covs", dim=d, batched=True)
        if covs.shape[0] != n:
            raise ValueError(f"covs must have shape ({n}, {d}, {d}), got {covs.shape}")
        labels = np.arange(n, dtype=np.int64) if labels is None else np.asarray(labels, dtype=np.int64)
        if labels.shape != (n,):
            raise ValueError(f"labels must have shape ({n},), got {labels.shape}")
        return cls(means, covs, labels)

    def __len__(self) -> int:
        return self.means.shape[0]

    @property
    def ndim(self) -> int:
        return self.means.shape[1]

    def predict(self, motion, dt) -> "TrackStore":
        """Every track predicted once (batched (E)KF prediction through ``motion``)."""
        if len(self) == 0:
            return self
        x, P = predict_with_unchecked(motion, self.means, self.covs, dt)
        return TrackStore(x, P, self.labels)


def update_pairs(predicted: TrackStore, Z, H, R, sources, returns):
    """Kalman-update predicted tracks, once per distinct ``(source, return)`` pair.

    Parameters
    ----------
    predicted : TrackStore
    Z : (m, p) returns of the scan.
    H, R : measurement matrix and noise covariance; or ``H`` a measurement model
        (:mod:`hypotrack.models.measurement`: its :meth:`update`, e.g. the radar's EKF in the sensor
        frame) and ``R`` ``None``.
    sources, returns : (P,) int arrays
        Distinct pairs: track index in ``predicted`` and return index (``-1`` = missed, the
        predicted track is kept).

    Returns
    -------
    means (P, d), covs (P, d, d)
        Joseph-form updates (:func:`hypotrack.gaussian.update`), batched over pairs.
    """
    sources = np.asarray(sources, dtype=np.int64)
    returns = np.asarray(returns, dtype=np.int64)
    means = predicted.means[sources].copy()
    covs = predicted.covs[sources].copy()
    hit = returns >= 0
    if np.any(hit):
        Zh = np.asarray(Z)[returns[hit]]
        if R is None and hasattr(H, "update"):
            x, P = H.update(means[hit], covs[hit], Zh)
        else:
            x, P = update_unchecked(means[hit], covs[hit], Zh, H, R)
        means[hit], covs[hit] = x, P
    return means, covs

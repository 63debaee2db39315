"""Negative controls of Table 6.1 (document 003): the filters with a known defect.

A *reproduced* row is evidence only when the same check fails on something built to break what the
row is about (:mod:`hypotrack.reporting.verdict`). Each control here is the tested filter with one
defect, scored exactly as the filter it controls:

* :class:`PredictionOnlyFilter` — the ideal filter without its measurement update (Eqs. 5.10–5.11
  never applied after the first scan): a blind tracker that only predicts (Eqs. 5.8–5.9);
* :class:`SwappedLabelGNNFilter` — the MHT/GNN of Eqs. 6.1–6.4 with the association reversed:
  each sensor's smaller return goes to the *upper* track (the wrong one of the two assignments);
* :class:`IndependentOrderECMHTFilter` — the ECMHT of Eqs. 6.5–6.7 scoring the swap count on one
  random sensor order and merging on another, independent one (reconstruction §5.2: the defect
  raises the MOSPA from about 0.06 to about 0.096).

The controls of the ordering row and of the closed-form rows need no filter of their own (the ECMHT
with its swaps disabled, ``i* = 0``, *is* the MHT, :class:`~hypotrack.trackers.ecmht.GNNFilter`;
the closed-form rows' control scores the ideal filter on ``X(k|k)``), see :mod:`.claims`.
"""

from __future__ import annotations

import numpy as np

from ...trackers.ecmht import ECMHTFilter, GNNFilter, IdealFilter, _lower_upper, ecmht_swap_count, swap_merge

__all__ = ["PredictionOnlyFilter", "SwappedLabelGNNFilter", "IndependentOrderECMHTFilter", "CONTROLS"]


class PredictionOnlyFilter(IdealFilter):
    """The ideal filter with its measurement update removed: ``X(k|k) = X(k|k−1)`` after the first scan.

    Initialised like the ideal filter (each target's labelled sensor average, Eqs. 6.1–6.3), then
    only the prediction of Eqs. 5.8–5.9 runs.
    """

    def _update(self, Z: np.ndarray) -> None:
        self.x, self.P = self.x_pred, self.P_pred


class SwappedLabelGNNFilter(GNNFilter):
    """The GNN/MHT with the wrong assignment: the average of the larger returns feeds the lower track.

    Everything else (sorting, Eq. 6.4 innovation variance, Kalman update of Eqs. 6.10–6.11) is the
    :class:`~hypotrack.trackers.ecmht.GNNFilter`'s.
    """

    def _update(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        lower_is_0, _, _ = _lower_upper(self.x_pred)
        self._kalman(Zs[:, :, 1].mean(axis=1), Zs[:, :, 0].mean(axis=1), lower_is_0)


class IndependentOrderECMHTFilter(ECMHTFilter):
    """The ECMHT with the defect of reconstruction §5.2: the swap count ``i*`` of Eq. 6.5 is chosen on
    one random sensor order and the first ``i*`` sensors of a second, independent order are swapped
    and merged (Eqs. 6.6–6.7)."""

    def _update(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        score_order = np.argsort(self.rng.random(Zs.shape[:2]), axis=1)
        merge_order = np.argsort(self.rng.random(Zs.shape[:2]), axis=1)
        scored = np.take_along_axis(Zs, score_order[:, :, None], axis=1)
        merged = np.take_along_axis(Zs, merge_order[:, :, None], axis=1)
        lower_is_0, x_l, x_u = _lower_upper(self.x_pred)
        S1 = self.P_pred[:, 0] + self.R
        n_swaps = ecmht_swap_count(scored[:, :, 0], scored[:, :, 1], x_l, x_u, S1)
        z_l, z_u = swap_merge(merged[:, :, 0], merged[:, :, 1], n_swaps)
        self.last_swaps = n_swaps
        self._kalman(z_l, z_u, lower_is_0)


#: Control name -> (the method it controls, what it is, in the ledger's words).
CONTROLS = {
    "ideal[blind]": ("ideal", "the ideal filter without measurement updates (prediction only)"),
    "ideal[blind, labelled]": ("ideal[labelled]", "the ideal filter without measurement updates (prediction "
                               "only), scored against its own targets"),
    "MHT[swapped labels]": ("MHT", "the MHT with each sensor's smaller return given to the upper track"),
    "ECMHT[independent orders]": ("ECMHT", "the ECMHT choosing i* on one sensor order and merging on another, "
                                  "independent one"),
}

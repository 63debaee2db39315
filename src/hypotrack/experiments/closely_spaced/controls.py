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

The MHT row is about the *association hypothesis* the MHT keeps. For this problem (no clutter,
p_D = 1, 1-D, equal covariances) the best joint hypothesis is the order-preserving one and the MHT
of any tree depth equals the GNNF (document 003 §5; reconstruction §4.4), so "the MHT keeping a
single hypothesis" *is* the MHT and cannot be a control. The controls that break the hypothesis are:

* :class:`RandomHypothesisGNNFilter` — the MHT keeping a *random* feasible joint hypothesis: each
  sensor's two returns go to the two tracks by a fair coin (one return per track, Eqs. 6.6–6.7 with a
  random swapped set instead of the best one of Eq. 6.5);
* :class:`NonExclusiveNNFilter` — the joint hypothesis dropped: each track takes each sensor's return
  nearest its own prediction (Eqs. 5.18–5.19 per track), so both tracks may take the same return;
* :class:`SwappedLabelGNNFilter` (above) — the worst joint hypothesis, which MOSPA's best pairing
  partly forgives;
* the MHT with a misstated measurement variance (a model defect, not an association one):
  :class:`~hypotrack.trackers.ecmht.GNNFilter` built with ``R × factor``.

The controls of the ordering row and of the closed-form rows need no filter of their own (the ECMHT
with its swaps disabled, ``i* = 0``, *is* the MHT, :class:`~hypotrack.trackers.ecmht.GNNFilter`;
the closed-form rows' control scores the ideal filter on ``X(k|k)``), see :mod:`.claims`.
"""

from __future__ import annotations

import numpy as np

from ...trackers.ecmht import ECMHTFilter, GNNFilter, IdealFilter, lower_upper, ecmht_swap_count, swap_merge

__all__ = ["PredictionOnlyFilter", "SwappedLabelGNNFilter", "IndependentOrderECMHTFilter", "RandomHypothesisGNNFilter",
           "NonExclusiveNNFilter", "CONTROLS", "MHT_CONTROLS", "controlled_method",
           "misstated_noise_name"]


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
        lower_is_0, _, _ = lower_upper(self.x_pred)
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
        lower_is_0, x_l, x_u = lower_upper(self.x_pred)
        S1 = self.P_pred[:, 0] + self.R
        n_swaps = ecmht_swap_count(scored[:, :, 0], scored[:, :, 1], x_l, x_u, S1)
        z_l, z_u = swap_merge(merged[:, :, 0], merged[:, :, 1], n_swaps)
        self.last_swaps = n_swaps
        self._kalman(z_l, z_u, lower_is_0)


class RandomHypothesisGNNFilter(GNNFilter):
    """The MHT keeping a random feasible joint hypothesis instead of the best one.

    Per run and sensor a fair coin decides whether the sensor's smaller return feeds the lower track
    (and the larger the upper one) or the reverse: Eqs. 6.6–6.7 with each sensor in the swapped set
    with probability ½, independently, in place of the ``i*`` of Eq. 6.5 (which for the MHT is 0).
    Each return still goes to exactly one track. Update as :class:`GNNFilter` (Eqs. 6.8–6.11).

    Parameters
    ----------
    model, R, n_sensors, dt
        As for :class:`~hypotrack.trackers.ecmht.GNNFilter`.
    rng : numpy.random.Generator or int
        Source of the coins.
    """

    def __init__(self, model, R, n_sensors, dt=1.0, *, rng=None):
        super().__init__(model, R, n_sensors, dt)
        if rng is None:
            raise ValueError("rng must be given (a numpy Generator or an int seed): the control draws its hypotheses")
        self.rng = np.random.default_rng(rng)

    def _update(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        swap = self.rng.random(Zs.shape[:2]) < 0.5
        lower_is_0, _, _ = lower_upper(self.x_pred)
        z_l = np.where(swap, Zs[:, :, 1], Zs[:, :, 0]).mean(axis=1)
        z_u = np.where(swap, Zs[:, :, 0], Zs[:, :, 1]).mean(axis=1)
        self._kalman(z_l, z_u, lower_is_0)


class NonExclusiveNNFilter(GNNFilter):
    """Nearest neighbour per track, without the joint hypothesis (a return may feed both tracks).

    Each track takes, from every sensor, the return nearest its own prediction ``X_j(k|k−1)``
    (Eqs. 5.18–5.19 track by track, ties to the sensor's first return) and averages them; the update
    is the :class:`GNNFilter`'s (Eqs. 6.4, 6.8–6.11, variance R/N).
    """

    def _update(self, Z: np.ndarray) -> None:
        nearest = []
        for j in range(2):
            pick = np.argmin(np.abs(Z - self.x_pred[:, j, None, None]), axis=2)  # (runs, sensors)
            nearest.append(np.take_along_axis(Z, pick[:, :, None], axis=2)[:, :, 0].mean(axis=1))
        self._kalman(nearest[0], nearest[1], np.ones(len(self.x_pred), dtype=bool))


def misstated_noise_name(factor: float) -> str:
    """Method name of the MHT run with the measurement variance ``R × factor`` (e.g. ``MHT[R × 4]``)."""
    return f"MHT[R × {factor:g}]"


#: Control name -> (the method it controls, what it is, in the ledger's words).
CONTROLS = {
    "ideal[blind]": ("ideal", "the ideal filter without measurement updates (prediction only)"),
    "ideal[blind, labelled]": ("ideal[labelled]", "the ideal filter without measurement updates (prediction "
                               "only), scored against its own targets"),
    "MHT[swapped labels]": ("MHT", "the MHT with each sensor's smaller return given to the upper track"),
    "ECMHT[independent orders]": ("ECMHT", "the ECMHT choosing i* on one sensor order and merging on another, "
                                  "independent one"),
    "MHT[random hypothesis]": ("MHT", "the MHT keeping a random joint hypothesis (each sensor's two returns given to "
                               "the two tracks by a fair coin)"),
    "MHT[no joint hypothesis]": ("MHT", "nearest neighbour per track without the joint hypothesis (each track takes "
                                 "each sensor's return nearest its own prediction, so both may take the same)"),
}



def controlled_method(name: str) -> str | None:
    """The method a control of Table 6.1 controls (``None`` for a method that is not a control)."""
    if name in CONTROLS:
        return CONTROLS[name][0]
    return "MHT" if name.startswith("MHT[R × ") else None


#: The broken MHTs measured for the MHT rows' power table (the misstated-noise ones are added per factor).
MHT_CONTROLS = ("MHT[swapped labels]", "MHT[random hypothesis]", "MHT[no joint hypothesis]")

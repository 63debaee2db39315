"""What GNN, JPDA and the initiator share: the scan model and prediction + gating of tracks.

Lecture notes 004 ("Single hypothesis tracking"): when a scan arrives, the confirmed tracks are
predicted, the returns are gated against them (the validation matrix), association runs on
the gated pairs, and unused returns go to the initiation logic.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

from .._validation import (
    check_covariance,
    check_finite_array,
    check_measurements,
    check_nonnegative,
    check_positive,
    check_probability,
)
from ..association import gate_threshold, validation_matrix
from ..gaussian import innovation_unchecked, mahalanobis2_unchecked, predict_with_unchecked, symmetrize
from ..models.motion import ConstantVelocity, OrnsteinUhlenbeck

__all__ = ["ScanModel", "GatedTracks", "predict_tracks", "gate_tracks", "with_track_p_D"]


@dataclass(frozen=True, eq=False)
class ScanModel:
    """What a single-hypothesis tracker assumes about every scan (lecture 004, "Standard settings").

    Parameters
    ----------
    H : (p, d) array_like
        Measurement matrix.
    R : (p, p) array_like
        Measurement-noise covariance (symmetric positive definite).
    p_D : float
        Detection probability ``P_D`` of every target, in (0, 1].
    p_gate : float
        Gate probability ``P_G`` in (0, 1): a target's return lies in its gate with this
        probability; the gate is ``d² ≤ χ²_p⁻¹(P_G)``.
    clutter_density : float
        False-alarm spatial density ``β_FA`` (expected false returns per unit volume per scan), > 0.
    new_target_density : float
        New-target density ``β_NT`` ≥ 0 (used by GNN, whose external sources have density
        ``β_EX = β_FA + β_NT``; JPDA has no new-target hypotheses).
    measurement : optional
        A nonlinear measurement model (:class:`hypotrack.models.measurement.ExtendedMeasurement`, e.g. the
        catalogue radar's ``(ρ, az, el, ρ̇)`` in the sensor frame) in place of ``H`` (give ``H = None``,
        ``R`` its ``R``): gating and updates are then the EKF's, per-track Jacobian and wrapped residuals.
    """

    H: np.ndarray
    R: np.ndarray
    p_D: float
    p_gate: float
    clutter_density: float
    new_target_density: float = 0.0
    measurement: object = None

    def __post_init__(self):
        if self.measurement is not None and not self.measurement.linear:
            R = check_covariance(np.atleast_2d(self.measurement.R), "measurement.R")
            object.__setattr__(self, "H", None)
            object.__setattr__(self, "R", R)
        else:
            object.__setattr__(self, "measurement", None)
            H = check_finite_array(np.atleast_2d(self.H), "H", ndim=2)
            object.__setattr__(self, "H", H)
            object.__setattr__(self, "R", check_covariance(np.atleast_2d(self.R), "R", dim=H.shape[0]))
        self._post_common()

    def _post_common(self):
        object.__setattr__(self, "p_D", check_probability(self.p_D, "p_D", low_open=True))
        object.__setattr__(self, "p_gate", check_probability(self.p_gate, "p_gate", low_open=True, high_open=True))
        object.__setattr__(self, "clutter_density", check_positive(self.clutter_density, "clutter_density"))
        object.__setattr__(self, "new_target_density", check_nonnegative(self.new_target_density, "new_target_density"))
        object.__setattr__(self, "gate", gate_threshold(self.p_gate, self.dim))

    @classmethod
    def from_sensor(
        cls, sensor, *, p_gate: float = 0.99, new_target_density: float = 0.0, clutter_density: float | None = None
    ) -> "ScanModel":
        """Take ``H``, ``R``, ``P_D`` and ``β_FA`` from a :class:`hypotrack.models.sensors.Sensor`.

        ``clutter_density`` overrides the sensor's clutter intensity (needed when the sensor has
        none: the scores require ``β_FA > 0``).
        """
        if clutter_density is None:
            if sensor.clutter is None or sensor.clutter.intensity <= 0:
                raise ValueError(
                    "sensor has no clutter (β_FA = 0): pass clutter_density > 0 for the JPDA/GNN scores"
                )
            clutter_density = sensor.clutter.intensity
        m = sensor.measurement
        if getattr(m, "linear", True) is False:
            return cls(None, m.R, sensor.detection.p_D, p_gate, clutter_density, new_target_density, measurement=m)
        return cls(
            sensor.measurement.H, sensor.measurement.R, sensor.detection.p_D, p_gate, clutter_density,
            new_target_density,
        )

    @property
    def dim(self) -> int:
        """Measurement dimension ``p``."""
        return self.R.shape[0]

    @property
    def ndim_state(self) -> int:
        return self.H.shape[1] if self.measurement is None else self.measurement.ndim_state

    def residual_rows(self, Z_rows, z_pred) -> np.ndarray:
        """``z_j − ẑ_j`` per row (angle components wrapped for a nonlinear measurement)."""
        return Z_rows - z_pred if self.measurement is None else self.measurement.residual_rows(Z_rows, z_pred)

    def H_of(self, gated: "GatedTracks", tracks):
        """The measurement matrix of ``tracks``: ``H``, or their Jacobians ``(k, p, d)``."""
        return self.H if self.measurement is None else gated.Hj[tracks]

    @property
    def log_missed(self) -> float:
        """``log(1 − P_D P_G)``: the weight of "target not detected in its gate" (per track ``(n,)`` for a
        model of :func:`with_track_p_D`)."""
        return np.log1p(-self.p_D * self.p_gate)

    @property
    def external_density(self) -> float:
        """``β_EX = β_FA + β_NT`` (lecture 004, "GNN Algorithm")."""
        return self.clutter_density + self.new_target_density


def with_track_p_D(model: ScanModel, p_D) -> ScanModel:
    """A copy of ``model`` whose ``p_D`` is one value per track ``(n,)`` in (0, 1] (a state-dependent
    detection probability, e.g. a radar's SNR p_D at each predicted range), for one scan's scores: the GNN
    gains and JPDA weights broadcast it over the tracks' columns (rows for JPDA)."""
    p = np.asarray(p_D, dtype=float)
    if p.ndim != 1 or not np.all((p > 0) & (p <= 1)):
        raise ValueError(f"p_D per track must be a 1-d array of values in (0, 1], got shape {p.shape}")
    out = copy.copy(model)
    object.__setattr__(out, "p_D", p)
    return out


@dataclass(frozen=True, eq=False)
class GatedTracks:
    """Predicted tracks and their gating against one scan.

    Attributes
    ----------
    x, P : (n, d), (n, d, d)
        Predicted means and covariances.
    z_pred, S, K : (n, p), (n, p, p), (n, d, p)
        Predicted measurements, innovation covariances and Kalman gains.
    Z : (m, p)
        The scan's returns.
    d2 : (m, n)
        Squared Mahalanobis distances ``(z_i − ẑ_j)ᵀ S_j⁻¹ (z_i − ẑ_j)``.
    logdet : (n,) or None
        ``log det S_j``; ``None`` when the tracker's criterion does not use it (the Mahalanobis
        GNN criterion), :meth:`log_likelihood` then computes it.
    valid : (m, n) bool
        The validation matrix (lecture 004, "Gating"): return i lies in track j's gate.
    Hj : (n, p, d) or None
        Each track's measurement Jacobian (a nonlinear measurement model), else ``None``.
    """

    x: np.ndarray
    P: np.ndarray
    z_pred: np.ndarray
    S: np.ndarray
    K: np.ndarray
    Z: np.ndarray
    d2: np.ndarray
    logdet: np.ndarray | None
    valid: np.ndarray
    Hj: np.ndarray | None = None

    @property
    def n_tracks(self) -> int:
        return self.x.shape[0]

    @property
    def n_meas(self) -> int:
        return self.Z.shape[0]

    def log_likelihood(self) -> np.ndarray:
        """``log N(z_i; ẑ_j, S_j)``, shape (m, n) (the predicted measurement density)."""
        p = self.Z.shape[1]
        logdet = np.linalg.slogdet(self.S)[1] if self.logdet is None else self.logdet
        return -0.5 * (self.d2 + logdet[None, :] + p * np.log(2.0 * np.pi))


def predict_tracks(motion, x, P, dt):
    """Kalman prediction of every track by ``dt`` (no-op for ``dt = 0`` or no tracks)."""
    x = np.asarray(x, dtype=float)
    if len(x) == 0 or dt == 0:
        return x, np.asarray(P, dtype=float)
    return predict_with_unchecked(motion, x, np.asarray(P, dtype=float), dt)


def gate_tracks(x, P, Z, model: ScanModel, *, gate: float | None = None) -> GatedTracks:
    """Predicted measurements, distances and the validation matrix of predicted tracks ``x, P``.

    Parameters
    ----------
    x, P : (n, d), (n, d, d)
        Predicted track means and covariances (``n = 0`` allowed).
    Z : (m, p) array_like
        Returns of the scan (``m = 0`` allowed); NaN or inf raise ``ValueError``.
    model : ScanModel
    gate : float, optional
        Squared-distance gate; default the model's ``χ²_p⁻¹(P_G)``.
    """
    Z = check_measurements(Z, "Z", model.dim)
    x = np.asarray(x, dtype=float).reshape(-1, model.ndim_state)
    P = np.asarray(P, dtype=float).reshape(-1, model.ndim_state, model.ndim_state)
    n, p = len(x), model.dim
    if model.measurement is not None:
        z_pred, S, K, Hj = model.measurement.innovation(x, P)
        d2, logdet = model.measurement.mahalanobis2(Z, z_pred, S)
        return GatedTracks(x, P, z_pred, S, K, Z, d2, logdet, validation_matrix(d2, model.gate if gate is None else gate),
                           Hj)
    if n:
        z_pred, S, K = innovation_unchecked(x, P, model.H, model.R)
    else:
        z_pred, S, K = np.zeros((0, p)), np.zeros((0, p, p)), np.zeros((0, model.ndim_state, p))
    d2, logdet = mahalanobis2_unchecked(Z, z_pred, S)
    valid = validation_matrix(d2, model.gate if gate is None else gate)
    return GatedTracks(x, P, z_pred, S, K, Z, d2, logdet, valid)


# Motion models whose prediction is ``F(dt) x`` with a constant ``F(dt)`` (their ``transition``).
_LINEAR_MOTION = (ConstantVelocity, OrnsteinUhlenbeck)


class _ScanPredictor:
    """The trackers' own per-scan prediction: a linear model's ``F(dt)`` and ``Q(dt)`` are kept while
    ``dt`` repeats (a fixed scan period builds them once), other models go through
    :func:`predict_tracks`. Same numbers as :func:`predict_tracks` (same products, same order)."""

    def __init__(self, motion):
        self.motion = motion
        self.linear = isinstance(motion, _LINEAR_MOTION)
        self._dt, self._F, self._FT, self._Q = None, None, None, None

    def __call__(self, x, P, dt):
        if len(x) == 0 or dt == 0:
            return x, P
        if not self.linear:
            return predict_tracks(self.motion, x, P, dt)
        if dt != self._dt:
            self._F = self.motion.F(dt)
            self._FT, self._Q, self._dt = self._F.T, self.motion.Q(dt), dt
        return x @ self._FT, symmetrize(self._F @ P @ self._FT + self._Q)

    def mean(self, x, dt):
        """The means of :meth:`__call__` alone (no transition matrix, no covariance): ``x Fᵀ`` for a
        linear model, the model's ``propagate`` otherwise."""
        if len(x) == 0 or dt == 0:
            return x
        if not self.linear:
            return self.motion.propagate(x, dt)
        if dt != self._dt:
            self._F = self.motion.F(dt)
            self._FT, self._Q, self._dt = self._F.T, self.motion.Q(dt), dt
        return x @ self._FT


def _gate_scan(x, P, Z, model: ScanModel, *, logdet: bool = True) -> GatedTracks:
    """Unchecked :func:`gate_tracks` for a tracker's own step (inputs checked at its boundary).

    One batched inverse of the innovation covariances serves the gains ``K = P Hᵀ S⁻¹``, the
    distances ``νᵀ S⁻¹ ν`` of all (return, track) pairs and ``log det S``: a few numpy calls per
    scan whatever the number of tracks. ``S`` is positive definite by construction (``P`` kept PSD
    by the Joseph form, ``R`` checked PD), so the plain inverse is safe here; the numbers equal
    :func:`gate_tracks`' up to rounding. Without ``logdet`` the result's ``logdet`` is ``None``.
    """
    if len(x) == 0 or model.measurement is not None:
        return gate_tracks(x, P, Z, model)
    H = model.H
    z_pred = x @ H.T
    PHt = P @ H.T
    # P is symmetric (symmetrised by the prediction), so S is symmetric up to rounding (exactly
    # for a selection H) and the distances below use only the symmetric part of S⁻¹.
    S = H @ PHt + model.R
    S_inv = np.linalg.inv(S)
    d2 = _quadratic_forms(Z, z_pred, S_inv)
    log_det = np.log(np.linalg.det(S)) if logdet else None
    return GatedTracks(x, P, z_pred, S, PHt @ S_inv, Z, d2, log_det, d2 <= model.gate)


def _quadratic_forms(Z, z_pred, S_inv):
    """``d²[i, j] = (z_i − ẑ_j)ᵀ S_j⁻¹ (z_i − ẑ_j)`` as ``Σ_a Σ_b S⁻¹_j[a, b] r_a r_b`` over (m, n) planes.

    Each innovation component ``r_a = z_{i,a} − ẑ_{j,a}`` is one (m, n) array, so every operation
    runs over all pairs at once with contiguous inner loops; an (m, n, p) array with its tiny last
    axis (or an ``einsum`` over it) costs several times more per pair.
    """
    p = Z.shape[1]
    r = [Z[:, a, None] - z_pred[:, a] for a in range(p)]
    d2 = None
    for a in range(p):
        w = S_inv[:, a, a] * r[a]
        for b in range(a + 1, p):
            w += (S_inv[:, a, b] + S_inv[:, b, a]) * r[b]
        w *= r[a]
        d2 = w if d2 is None else d2 + w
    # Rounding can take the distance of a return on the prediction a hair below 0.
    return np.maximum(d2, 0.0, out=d2)

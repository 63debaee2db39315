"""Track initiation: tentative tracks from unused returns, confirmed by an M-of-N rule.

Lecture notes 004 separate initiation from the main association logic: returns that GNN leaves
to external sources (or that lie in no confirmed target's gate, for JPDA) are sent to the
*initiator*, which keeps tentative tracks, associates the next scans' unused returns with them
and promotes a tentative track to a confirmed one when it has been detected in ``M`` of its first
``N`` scans (the usual M-of-N logic; Blackman & Popoli 1999, §6.3). A tentative track that can no
longer reach ``M`` hits within ``N`` scans is dropped.

A tentative track starts at a single return (one-point initiation): position from the return
(``x = H⁺ z``, ``P_pos = H⁺ R H⁺ᵀ``) and zero velocity with a broad standard deviation
``initial_velocity_std``, so the first gate is wide enough to catch the target's next return.
With a nonlinear measurement model (a radar's ``(ρ, az, el, ρ̇)`` in the sensor frame) a new tentative
track is the model's own ``one_point`` initiation instead (the return's position and range-rate, velocity
across the line of sight ``N(0, initial_velocity_std²)``). Tentative tracks are associated with returns by GNN with the lecture's scores
(:func:`hypotrack.trackers.gnn.gnn_gains`).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int, check_measurements, check_positive, check_state_dimension
from ._sht_common import ScanModel, gate_tracks, predict_tracks
from .gnn import gnn_associate, gnn_gains, gnn_update

__all__ = ["MOfNInitiator"]


class MOfNInitiator:
    """Tentative tracks with M-of-N confirmation.

    Parameters
    ----------
    motion : motion model
        E.g. :class:`hypotrack.models.ConstantVelocity`.
    model : ScanModel
        Measurement model, ``P_D``, gate and clutter density (used for the GNN scores).
    m, n : int
        Confirm after ``m`` detections within the first ``n`` scans of a tentative track
        (its creating return counts as the first), ``1 ≤ m ≤ n``.
    initial_velocity_std : float
        Standard deviation of each velocity component of a new tentative track (state units
        per second), > 0.

    Attributes
    ----------
    x, P : (k, d), (k, d, d)
        Tentative tracks' current means and covariances.
    hits, age : (k,) int
        Detections so far and scans since creation (creation scan included).
    P0 : (d, d)
        Covariance of a new tentative track: the return's noise on the measured components,
        ``initial_velocity_std²`` on the others (one-point initiation).
    """

    def __init__(self, motion, model: ScanModel, *, m: int = 2, n: int = 3, initial_velocity_std: float = 10.0):
        if not isinstance(model, ScanModel):
            raise TypeError(f"model must be a ScanModel, got {type(model).__name__}")
        check_state_dimension(motion, model.ndim_state, f"the scan model (H of shape {(model.dim, model.ndim_state)})")
        self.motion = motion
        self.model = model
        self.n = check_int(n, "n", minimum=1)
        self.m = check_int(m, "m", minimum=1, maximum=self.n)
        self.initial_velocity_std = check_positive(initial_velocity_std, "initial_velocity_std")
        d = model.ndim_state
        self.set_model(model)
        self.x = np.zeros((0, d))
        self.P = np.zeros((0, d, d))
        self.hits = np.zeros(0, dtype=np.int64)
        self.age = np.zeros(0, dtype=np.int64)
        self._time = None

    def set_model(self, model: ScanModel) -> None:
        """Use ``model`` (of the same state dimension) from the next scan on: the scan's sensor when several sensors
        are fused (:mod:`.multisensor`); the tentative tracks are kept."""
        if not isinstance(model, ScanModel):
            raise TypeError(f"model must be a ScanModel, got {type(model).__name__}")
        if model.ndim_state != self.model.ndim_state:
            raise ValueError(f"model must have state dimension {self.model.ndim_state}, got {model.ndim_state}")
        self.model, d = model, model.ndim_state
        if model.measurement is None:
            H_pinv = np.linalg.pinv(model.H)
            self._H_pinv = H_pinv
            # Position block from the return's noise; the unmeasured (velocity) block broad.
            self.P0 = H_pinv @ model.R @ H_pinv.T + self.initial_velocity_std**2 * (np.eye(d) - H_pinv @ model.H)
        else:  # a nonlinear (sensor-frame) measurement: its own one-point initiation per return
            self._H_pinv, self.P0 = None, None

    def __len__(self) -> int:
        return len(self.x)

    def step(self, time: float, Z):
        """Process the returns the confirmed tracks did not use; return the newly confirmed tracks.

        Parameters
        ----------
        time : float
            Scan time (s), not earlier than the previous scan's.
        Z : (m, p) array_like
            Unused returns of the scan (``m = 0`` allowed).

        Returns
        -------
        x, P : (c, d), (c, d, d)
            Means and covariances of the tentative tracks confirmed at this scan.
        """
        Z = check_measurements(Z, "Z", self.model.dim)
        time = float(time)
        dt = 0.0 if self._time is None else time - self._time
        if dt < 0:
            raise ValueError(f"time must not decrease: got {time} after {self._time}")
        d = self.model.ndim_state

        x, P = predict_tracks(self.motion, self.x, self.P, dt)
        gated = gate_tracks(x, P, Z, self.model)
        a = gnn_associate(gnn_gains(gated, self.model))
        x, P, detected = gnn_update(gated, a, self.model)
        hits = self.hits + detected
        age = self.age + 1

        confirmed = hits >= self.m
        alive = ~confirmed & (hits + (self.n - age) >= self.m)
        out_x, out_P = x[confirmed], P[confirmed]

        unused = Z[a < 0]
        k = len(unused)
        self._time = time  # nothing below can fail: the step is all-or-nothing
        if self.model.measurement is None:
            x_new, P_new = unused @ self._H_pinv.T, np.broadcast_to(self.P0, (k, d, d))
        else:
            x_new, P_new = self.model.measurement.one_point(unused, 0.0, self.initial_velocity_std) if k else (
                np.zeros((0, d)), np.zeros((0, d, d)))
        self.x = np.concatenate([x[alive], x_new])
        self.P = np.concatenate([P[alive], P_new])
        self.hits = np.concatenate([hits[alive], np.ones(k, dtype=np.int64)])
        self.age = np.concatenate([age[alive], np.ones(k, dtype=np.int64)])
        # With m = 1 a single return confirms a track at once.
        if self.m == 1 and k:
            now = self.hits >= 1
            now[: int(alive.sum())] = False
            out_x = np.concatenate([out_x, self.x[now]])
            out_P = np.concatenate([out_P, self.P[now]])
            keep = ~now
            self.x, self.P, self.hits, self.age = self.x[keep], self.P[keep], self.hits[keep], self.age[keep]
        return out_x, out_P

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

**Mixture initiation** (``mixture``, e.g. the admissible region of a radar return, DeMars & Jah 2013:
:class:`hypotrack.scenarios.catalogue.admissible.SeededAdmissibleBirth`): a return starts one tentative
track per component of ``mixture.components(z)`` (none for ``K = 0``: no admissible state gives ``z``), the
*family* of that return. The siblings compete for the next returns in the same GNN (one return each), so
a return chain feeds one of them; each tentative track carries the score ``log w_c + Σ gains`` of the
returns it took (the log-likelihood ratio of the track against "never detected", its component's prior
weight included). When a family's tracks confirm, the best-scored one is confirmed and the whole family
is dropped: **at most one confirmed track per return chain**. With ``mixture.admissible(states)`` (the
plausibility test of the region: bound, perigee above the floor) a tentative track whose mean leaves the
admissible set after an update is dropped, so no tentative or confirmed-at-birth track holds an unbound
or too-low orbit.
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
    mixture : object, optional
        ``components(z) -> (w (K,), means (K, d), covs (K, d, d))``: a tentative track per component
        (module docstring, mixture initiation), and optionally ``admissible(states) -> (n,) bool``.

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

    def __init__(self, motion, model: ScanModel, *, m: int = 2, n: int = 3, initial_velocity_std: float = 10.0,
                 mixture=None):
        if not isinstance(model, ScanModel):
            raise TypeError(f"model must be a ScanModel, got {type(model).__name__}")
        check_state_dimension(motion, model.ndim_state, f"the scan model (H of shape {(model.dim, model.ndim_state)})")
        self.motion = motion
        self.model = model
        self.n = check_int(n, "n", minimum=1)
        self.m = check_int(m, "m", minimum=1, maximum=self.n)
        self.initial_velocity_std = check_positive(initial_velocity_std, "initial_velocity_std")
        d = model.ndim_state
        self.set_model(model, mixture)
        self.x = np.zeros((0, d))
        self.P = np.zeros((0, d, d))
        self.hits = np.zeros(0, dtype=np.int64)
        self.age = np.zeros(0, dtype=np.int64)
        self.family = np.zeros(0, dtype=np.int64)  # the return each tentative track started from (mixture)
        self.score = np.zeros(0)  # log w_c + the gains of its returns (mixture)
        self._n_families = 0
        self._time = None

    def set_model(self, model: ScanModel, mixture=None) -> None:
        """Use ``model`` (of the same state dimension) and that sensor's ``mixture`` (the admissible region is the
        sensor's: its site and frame; ``None``: one-point starts, as that sensor has no mixture) from the next scan on:
        the scan's sensor when several sensors are fused (:mod:`.multisensor`); the tentative tracks are kept."""
        if mixture is not None and not callable(getattr(mixture, "components", None)):
            raise TypeError(f"mixture must have components(z) -> (weights, means, covs), got {type(mixture).__name__}")
        if not isinstance(model, ScanModel):
            raise TypeError(f"model must be a ScanModel, got {type(model).__name__}")
        if model.ndim_state != self.model.ndim_state:
            raise ValueError(f"model must have state dimension {self.model.ndim_state}, got {model.ndim_state}")
        self.model, self.mixture, d = model, mixture, model.ndim_state
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
        gain = gnn_gains(gated, self.model)
        a = gnn_associate(gain)
        x, P, detected = gnn_update(gated, a, self.model)
        hits = self.hits + detected
        age = self.age + 1
        score = self.score.copy()
        rows = np.flatnonzero(a >= 0)
        score[a[rows]] += gain[rows, a[rows]]

        confirmed = hits >= self.m
        alive = ~confirmed & (hits + (self.n - age) >= self.m)
        if self.mixture is not None:
            confirmed, alive = self._families(x, confirmed, alive, score)
        out_x, out_P = x[confirmed], P[confirmed]

        unused = Z[a < 0]
        self._time = time  # nothing below can fail: the step is all-or-nothing
        if self.mixture is not None:
            x_new, P_new, fam_new, score_new = self._mixture_tracks(unused)
        elif self.model.measurement is None:
            x_new, P_new = unused @ self._H_pinv.T, np.broadcast_to(self.P0, (len(unused), d, d))
        else:
            x_new, P_new = self.model.measurement.one_point(unused, 0.0, self.initial_velocity_std) if len(unused) else (
                np.zeros((0, d)), np.zeros((0, d, d)))
        k = len(x_new)
        if self.mixture is None:  # every tentative track a family of its own (another sensor's scans may have one)
            fam_new, score_new = np.arange(self._n_families, self._n_families + k, dtype=np.int64), np.zeros(k)
            self._n_families += k
        self.x = np.concatenate([x[alive], x_new])
        self.P = np.concatenate([P[alive], P_new])
        self.hits = np.concatenate([hits[alive], np.ones(k, dtype=np.int64)])
        self.age = np.concatenate([age[alive], np.ones(k, dtype=np.int64)])
        self.family = np.concatenate([self.family[alive], fam_new])
        self.score = np.concatenate([score[alive], score_new])
        # With m = 1 a single return confirms a track at once.
        if self.m == 1 and k:
            now = self.hits >= 1
            now[: int(alive.sum())] = False
            pick = np.flatnonzero(now)
            if self.mixture is not None:  # one per family (the best-scored component) confirms; the family goes
                pick = pick[_best_per_family(self.family[now], self.score[now])]
                now = now | np.isin(self.family, self.family[now])
            out_x = np.concatenate([out_x, self.x[pick]])
            out_P = np.concatenate([out_P, self.P[pick]])
            keep = ~now
            self.x, self.P, self.hits, self.age = self.x[keep], self.P[keep], self.hits[keep], self.age[keep]
            self.family, self.score = self.family[keep], self.score[keep]
        return out_x, out_P

    def _mixture_tracks(self, Z):
        """Tentative tracks of returns ``Z``: one per component of each return's mixture (module docstring)."""
        d = self.model.ndim_state
        xs, Ps, fams, scores = [np.zeros((0, d))], [np.zeros((0, d, d))], [np.zeros(0, np.int64)], [np.zeros(0)]
        for z in Z:
            w, means, covs = self.mixture.components(z)
            if len(w):
                xs.append(np.asarray(means, dtype=float).reshape(-1, d))
                Ps.append(np.asarray(covs, dtype=float).reshape(-1, d, d))
                fams.append(np.full(len(w), self._n_families, np.int64))
                scores.append(np.log(np.asarray(w, dtype=float)))
            self._n_families += 1
        return np.concatenate(xs), np.concatenate(Ps), np.concatenate(fams), np.concatenate(scores)

    def _families(self, x, confirmed, alive, score):
        """Mixture initiation's rules (module docstring): tentative tracks leaving the admissible set are
        dropped; of a family with confirmed tracks the best-scored confirmed one confirms, the family goes."""
        admissible = getattr(self.mixture, "admissible", None)
        if admissible is not None and len(x):
            ok = np.asarray(admissible(x), dtype=bool)
            confirmed, alive = confirmed & ok, alive & ok
        if confirmed.any():
            fam = self.family[confirmed]
            pick = np.flatnonzero(confirmed)[_best_per_family(fam, score[confirmed])]
            confirmed = np.zeros_like(confirmed)
            confirmed[pick] = True
            alive = alive & ~np.isin(self.family, fam)
        return confirmed, alive


def _best_per_family(family, score) -> np.ndarray:
    """Index of the best-scored entry of each family (ties: the first), in order of first appearance."""
    order = np.lexsort((np.arange(len(score)), -score, family))  # by family, best score first
    fam_sorted = family[order]
    first = np.r_[True, fam_sorted[1:] != fam_sorted[:-1]]
    return np.sort(order[first])

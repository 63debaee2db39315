"""Two closely spaced 1-D Ornstein–Uhlenbeck targets seen by N synchronous sensors.

The filters of Coraluppi & Carthel, *Cardinality Tracking and the Equivalence-Class MHT*
(document 003), Sections 5–6, written as scalar Kalman recursions vectorised over Monte Carlo runs:
every array has a leading run axis, so one call filters a thousand realisations at once.

* :class:`IdealFilter` — known measurement origin: a Kalman filter per target on the average of
  its N measurements (variance R/N); the "ideal" row of Table 6.1.
* :class:`GNNFilter` — global nearest neighbour, Eqs. 5.18–5.21 applied to the multi-sensor
  equivalent measurements: the N smaller returns are averaged for the lower track and the N
  larger ones for the upper track (Eqs. 6.1–6.4, 6.8–6.11 with no swaps). For this problem it is
  the MHT of any tree depth (paper §5), the "MHT" row of Table 6.1.
* :class:`ECMHTFilter` — the equivalence-class MHT, Eqs. 6.1–6.11: before merging, swap the
  returns of the first ``i*`` sensors of a fresh random sensor order, ``i*`` maximising the
  class score of Eq. 6.5 (``ln C(N, i)`` plus the single-hypothesis log-likelihood).
* :class:`PDAFilter` — the PDAF, Eqs. 5.12–5.17, in one of five multi-sensor forms (the paper
  does not say which it used; see :data:`PDAF_VARIANTS`).

Conventions (reconstruction §4–§5, ``coraluppi_carthel_reconstruction.md``): state and
measurement are scalars, ``C = 1``; ``A = exp(−γ Δt)``, ``Q = σ²/(2γ)(1 − e^{−2γΔt})``;
a scan is an array ``(n_runs, n_sensors, 2)`` holding each sensor's two returns in any order;
estimates are ``(n_runs, 2)``. MOSPA is scored on the one-step prediction ``X(k|k−1)``
(:func:`mospa_two_targets`), which is what reproduces the ideal 0.0363 (reconstruction §6.4).
"""

from __future__ import annotations

import numpy as np
from scipy.special import gammaln

from .._validation import check_finite_array, check_int, check_positive, check_seed
from ..models.motion import OrnsteinUhlenbeck

__all__ = [
    "IdealFilter",
    "GNNFilter",
    "ECMHTFilter",
    "PDAFilter",
    "PDAF_VARIANTS",
    "ecmht_swap_scores",
    "ecmht_swap_count",
    "swap_merge",
    "mospa_two_targets",
]

#: Multi-sensor forms of the PDAF (:class:`PDAFilter`); the first is the default.
PDAF_VARIANTS = ("sequential", "equivalent", "parallel", "all_at_once", "jpda")


def _check_scan(Z, n_sensors: int) -> np.ndarray:
    """Return a scan as ``(n_runs, n_sensors, 2)``; a single run ``(n_sensors, 2)`` gains a run axis."""
    Z = check_finite_array(Z, "Z")
    if Z.ndim == 2:
        Z = Z[None]
    if Z.ndim != 3 or Z.shape[1:] != (n_sensors, 2):
        raise ValueError(f"Z must have shape (n_runs, {n_sensors}, 2) or ({n_sensors}, 2), got {Z.shape}")
    return Z


def lower_upper(x: np.ndarray):
    """Boolean mask of the lower track per run and the (lower, upper) predicted positions."""
    lower_is_0 = x[:, 0] <= x[:, 1]
    x_l = np.where(lower_is_0, x[:, 0], x[:, 1])
    x_u = np.where(lower_is_0, x[:, 1], x[:, 0])
    return lower_is_0, x_l, x_u


def _to_track_order(lower_is_0, v_l, v_u) -> np.ndarray:
    """Place per-run (lower, upper) values back in track order (track 0, track 1)."""
    return np.stack([np.where(lower_is_0, v_l, v_u), np.where(lower_is_0, v_u, v_l)], axis=1)


class _TwoTargetOU:
    """Shared initialisation (Eqs. 5.5–5.7 / 6.1–6.3) and prediction (Eqs. 5.8–5.9).

    Parameters
    ----------
    model : OrnsteinUhlenbeck
        Target motion (the same for both targets).
    R : float
        Per-sensor measurement-noise variance (m²), > 0.
    n_sensors : int
        Number N of synchronous sensors, >= 1.
    dt : float
        Scan interval Δt (s), > 0.
    """

    def __init__(self, model: OrnsteinUhlenbeck, R: float, n_sensors: int, dt: float = 1.0):
        if not isinstance(model, OrnsteinUhlenbeck):
            raise TypeError(f"model must be an OrnsteinUhlenbeck, got {type(model).__name__}")
        self.model = model
        self.R = check_positive(R, "R")
        self.n_sensors = check_int(n_sensors, "n_sensors", minimum=1)
        self.dt = check_positive(dt, "dt")
        self.A = float(model.F(self.dt)[0, 0])
        self.Q = float(model.Q(self.dt)[0, 0])
        self.x = None  # X(k|k), (n_runs, 2)
        self.P = None  # P(k|k), (n_runs, 2)
        self.x_pred = None  # X(k|k-1) of the latest scan (NaN at the first scan)
        self.P_pred = None

    def _initialise(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        self.x = Zs.mean(axis=1)  # Eqs. 6.1–6.2
        self.P = np.full_like(self.x, self.R / self.n_sensors)  # Eq. 6.3
        self.x_pred = np.full_like(self.x, np.nan)
        self.P_pred = np.full_like(self.x, np.nan)

    def _predict(self) -> None:
        self.x_pred = self.A * self.x  # Eq. 5.8
        self.P_pred = self.A * self.P * self.A + self.Q  # Eq. 5.9

    def step(self, Z) -> np.ndarray:
        """Process one scan; the first call initialises. Returns the filtered estimates ``X(k|k)``."""
        Z = _check_scan(Z, self.n_sensors)
        if self.x is not None and Z.shape[0] != self.x.shape[0]:
            raise ValueError(f"Z has {Z.shape[0]} runs, the filter was initialised with {self.x.shape[0]}")
        saved = self._snapshot()
        try:
            if self.x is None:
                self._initialise(Z)
            else:
                self._predict()
                self._update(Z)
        except BaseException:
            self._restore(saved)  # all-or-nothing: a failed scan can be retried
            raise
        return self.x

    def _snapshot(self):
        """The state a step changes: attributes (arrays are replaced, never written in place)
        and the random generator's state."""
        rng = getattr(self, "rng", None)
        return dict(vars(self)), (None if rng is None else rng.bit_generator.state)

    def _restore(self, saved) -> None:
        attrs, rng_state = saved
        vars(self).clear()
        vars(self).update(attrs)
        if rng_state is not None:
            self.rng.bit_generator.state = rng_state

    def estimates(self) -> np.ndarray:
        """Filtered estimates ``X(k|k)`` of the latest scan, ``(n_runs, 2)``."""
        if self.x is None:
            raise RuntimeError("no scan processed yet")
        return self.x

    def predictions(self) -> np.ndarray:
        """One-step predictions ``X(k|k−1)`` used by the latest update (NaN after the first scan)."""
        if self.x_pred is None:
            raise RuntimeError("no scan processed yet")
        return self.x_pred

    def _update(self, Z: np.ndarray) -> None:  # pragma: no cover - abstract
        raise NotImplementedError


class _EquivalentMeasurementFilter(_TwoTargetOU):
    """Kalman update of each track with an N-sensor average (Eqs. 6.4, 6.8–6.11)."""

    def _kalman(self, z_l, z_u, lower_is_0) -> None:
        S = self.P_pred + self.R / self.n_sensors  # Eq. 6.4
        L = self.P_pred / S  # Eq. 5.11
        z = _to_track_order(lower_is_0, z_l, z_u)
        self.x = self.x_pred + L * (z - self.x_pred)  # Eq. 6.10
        # Joseph form; for the scalar optimal gain it equals (1 − L) P (Eq. 6.11).
        self.P = (1 - L) ** 2 * self.P_pred + L**2 * self.R / self.n_sensors


class IdealFilter(_EquivalentMeasurementFilter):
    """Kalman filter per target with known measurement origin (Table 6.1, "ideal").

    ``Z[:, n, j]`` must be sensor ``n``'s return from target ``j`` (labelled, not sorted).
    """

    def _initialise(self, Z: np.ndarray) -> None:
        self.x = Z.mean(axis=1)
        self.P = np.full_like(self.x, self.R / self.n_sensors)
        self.x_pred = np.full_like(self.x, np.nan)
        self.P_pred = np.full_like(self.x, np.nan)

    def _update(self, Z: np.ndarray) -> None:
        zbar = Z.mean(axis=1)
        self._kalman(zbar[:, 0], zbar[:, 1], np.ones(len(zbar), dtype=bool))


class GNNFilter(_EquivalentMeasurementFilter):
    """Multi-sensor GNNF / MHT: average the smaller and the larger returns separately.

    In 1-D with equal covariances the global nearest-neighbour assignment gives each sensor's
    smaller return to the lower predicted track (reconstruction §4.4), so the equivalent
    measurements are the two order-statistic averages (ECMHT with ``i* = 0``).
    """

    def _update(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        lower_is_0, _, _ = lower_upper(self.x_pred)
        self._kalman(Zs[:, :, 0].mean(axis=1), Zs[:, :, 1].mean(axis=1), lower_is_0)


def ecmht_swap_scores(Z_lower, Z_upper, x_l, x_u, S1) -> np.ndarray:
    """Class log-scores of Eq. 6.5 for ``i = 0..N`` swaps of the first ``i`` sensors.

    Parameters
    ----------
    Z_lower, Z_upper : (n_runs, N) arrays
        Each sensor's smaller and larger return, already in the (random) order in which
        sensors are swapped: swapping ``i`` sensors swaps columns ``0..i−1``.
    x_l, x_u : (n_runs,) arrays
        Predicted positions of the lower and upper track.
    S1 : (n_runs,) array or float
        Per-sensor innovation variance ``C P(k+1|k) C' + R`` (not ``+ R/N``: with ``R/N`` the
        ECMHT collapses to the GNN result; reconstruction §5.2).

    Returns
    -------
    (n_runs, N + 1) array
        ``ln C(N, i) − (1 / 2 S1) [Σ_{n<i} ((Z2 − x_l)² + (Z1 − x_u)²) + Σ_{n≥i} ((Z1 − x_l)² + (Z2 − x_u)²)]``.
    """
    Z_lower = np.asarray(Z_lower, dtype=float)
    Z_upper = np.asarray(Z_upper, dtype=float)
    n = Z_lower.shape[1]
    x_l = np.asarray(x_l, dtype=float)[:, None]
    x_u = np.asarray(x_u, dtype=float)[:, None]
    swapped = (Z_upper - x_l) ** 2 + (Z_lower - x_u) ** 2
    kept = (Z_lower - x_l) ** 2 + (Z_upper - x_u) ** 2
    zeros = np.zeros((Z_lower.shape[0], 1))
    # "Each summation is zero when the upper limit is below the lower limit": empty sums are 0.
    swapped_first_i = np.concatenate([zeros, np.cumsum(swapped, axis=1)], axis=1)
    kept_rest = np.concatenate([np.cumsum(kept[:, ::-1], axis=1)[:, ::-1], zeros], axis=1)
    i = np.arange(n + 1)
    log_binom = gammaln(n + 1) - gammaln(i + 1) - gammaln(n - i + 1)
    S1 = np.asarray(S1, dtype=float).reshape(-1, 1)
    return log_binom[None, :] - (swapped_first_i + kept_rest) / (2.0 * S1)


def ecmht_swap_count(Z_lower, Z_upper, x_l, x_u, S1) -> np.ndarray:
    """Number of swaps ``i*`` of Eq. 6.5 per run (the smallest maximiser on ties)."""
    return np.argmax(ecmht_swap_scores(Z_lower, Z_upper, x_l, x_u, S1), axis=1)


def swap_merge(Z_lower, Z_upper, n_swaps):
    """Equivalent measurements of Eqs. 6.6–6.7: swap the first ``n_swaps`` sensors, then average.

    Returns ``(Zbar_l, Zbar_u)``, each ``(n_runs,)``.
    """
    Z_lower = np.asarray(Z_lower, dtype=float)
    Z_upper = np.asarray(Z_upper, dtype=float)
    swap = np.arange(Z_lower.shape[1])[None, :] < np.asarray(n_swaps)[:, None]
    to_lower = np.where(swap, Z_upper, Z_lower)
    to_upper = np.where(swap, Z_lower, Z_upper)
    return to_lower.mean(axis=1), to_upper.mean(axis=1)


class ECMHTFilter(_EquivalentMeasurementFilter):
    """Equivalence-class MHT (Eqs. 6.1–6.11).

    Each scan draws a fresh random sensor order per run; the *same* order defines the swapped
    set that is scored (Eq. 6.5) and the one that is merged (Eqs. 6.6–6.7) — drawing two
    independent sets raises the MOSPA from ≈0.06 to ≈0.096 (reconstruction §5.2).

    Parameters
    ----------
    model, R, n_sensors, dt
        As for :class:`GNNFilter`.
    rng : numpy.random.Generator or int
        Source of the random sensor orders.
    """

    def __init__(self, model, R, n_sensors, dt=1.0, *, rng=None):
        super().__init__(model, R, n_sensors, dt)
        if rng is None:
            raise ValueError("rng must be given (a numpy Generator or an int seed): the ECMHT draws sensor orders")
        self.rng = np.random.default_rng(check_seed(rng, "rng"))
        self.last_swaps = None

    def _update(self, Z: np.ndarray) -> None:
        Zs = np.sort(Z, axis=-1)
        order = np.argsort(self.rng.random(Zs.shape[:2]), axis=1)
        Zs = np.take_along_axis(Zs, order[:, :, None], axis=1)
        lower_is_0, x_l, x_u = lower_upper(self.x_pred)
        S1 = self.P_pred[:, 0] + self.R
        n_swaps = ecmht_swap_count(Zs[:, :, 0], Zs[:, :, 1], x_l, x_u, S1)
        z_l, z_u = swap_merge(Zs[:, :, 0], Zs[:, :, 1], n_swaps)
        self.last_swaps = n_swaps
        self._kalman(z_l, z_u, lower_is_0)


def _pda_apply(x, P, nu, beta, R_eff):
    """The PDA state update of Eqs. 5.14–5.17 with given association probabilities.

    ``nu`` (n_runs, m) innovations, ``beta`` (n_runs, m) their probabilities (rows sum to 1, β₀ = 0).
    """
    L = P / (P + R_eff)  # Eqs. 5.10-5.11
    nu_c = np.sum(beta * nu, axis=1)  # Eq. 5.14
    spread = np.sum(beta * nu**2, axis=1) - nu_c**2  # bracket of Eq. 5.17
    return x + L * nu_c, (1 - L) * P + L**2 * spread  # Eqs. 5.15-5.17


def _pda_update(x, P, Zc, R_eff):
    """One PDA update (Eqs. 5.12–5.17, ``p_D = 1``, no clutter so ``β₀ = 0``).

    ``x, P`` : (n_runs,), ``Zc`` : (n_runs, m) candidate measurements, ``R_eff`` their variance.
    """
    S = P + R_eff  # Eq. 5.10
    nu = Zc - x[:, None]  # Eq. 5.13
    logw = -0.5 * nu**2 / S[:, None]  # Eq. 5.12 (the common normaliser of N(·; x, S) cancels)
    beta = np.exp(logw - logw.max(axis=1, keepdims=True))
    beta /= beta.sum(axis=1, keepdims=True)
    return _pda_apply(x, P, nu, beta, R_eff)


def _jpda_pair_update(x, P, Zn, R):
    """One sensor's JPDA update of both tracks (lecture 004 Eq. (1), ``p_D = 1``, no clutter).

    With two tracks and one sensor's two returns ``Zn`` (n_runs, 2) the joint events are the two
    assignments: straight (track 0 ← return 0, track 1 ← return 1) and crossed, weighing
    ``N(z_a; x₀, S₀) N(z_b; x₁, S₁)`` (the factors ``1/√(2π S_j)`` are common and cancel). Each
    track's marginal probabilities then enter its PDA update (Eqs. 5.14–5.17) with variance R.
    """
    S = P + R  # (n_runs, 2)
    nu = Zn[:, None, :] - x[:, :, None]  # (n_runs, track, return)
    d = nu**2 / (2 * S[:, :, None])
    straight = -(d[:, 0, 0] + d[:, 1, 1])
    crossed = -(d[:, 0, 1] + d[:, 1, 0])
    b_straight = 1.0 / (1.0 + np.exp(np.clip(crossed - straight, -700, 700)))
    beta = np.stack([np.stack([b_straight, 1 - b_straight], axis=1),
                     np.stack([1 - b_straight, b_straight], axis=1)], axis=1)  # (n_runs, track, return)
    out_x, out_P = np.empty_like(x), np.empty_like(P)
    for j in range(2):
        out_x[:, j], out_P[:, j] = _pda_apply(x[:, j], P[:, j], nu[:, j], beta[:, j], R)
    return out_x, out_P


class PDAFilter(_TwoTargetOU):
    """PDAF (Eqs. 5.12–5.17) for N sensors; each track runs its own PDAF, ignoring the other.

    The paper gives the single-sensor PDAF only. Variants (``variant=``):

    * ``"sequential"`` — the single-sensor PDAF applied sensor after sensor within a scan,
      each with that sensor's two returns and variance R (prediction once per scan);
    * ``"equivalent"`` — one PDAF update on the two order-statistic averages, variance R/N;
    * ``"parallel"`` — association probabilities per sensor (variance ``P + R``), the N
      combined innovations averaged and applied with the R/N gain; spread term accumulated
      as the variance of the average;
    * ``"all_at_once"`` — one single-sensor PDAF update per scan with all 2N returns of the scan
      as the candidates (variance R each): the PDAF's assumption of at most one target return
      per scan taken literally, so a scan carries one return's worth of information;
    * ``"jpda"`` — the two tracks coupled (JPDA, lecture 004 Eq. (1)): sensor after sensor, the
      joint association probabilities of the two assignments of that sensor's two returns, then
      each track's PDA update with its marginals (:func:`_jpda_pair_update`).

    The default, ``"sequential"``, is the form Table 6.1's "PDAF" row reports.
    """

    def __init__(self, model, R, n_sensors, dt=1.0, *, variant: str = "sequential"):
        super().__init__(model, R, n_sensors, dt)
        if variant not in PDAF_VARIANTS:
            raise ValueError(f"variant must be one of {PDAF_VARIANTS}, got {variant!r}")
        self.variant = variant

    def _update(self, Z: np.ndarray) -> None:
        x = self.x_pred.copy()
        P = self.P_pred.copy()
        if self.variant == "sequential":
            for n in range(self.n_sensors):
                for j in range(2):
                    x[:, j], P[:, j] = _pda_update(x[:, j], P[:, j], Z[:, n, :], self.R)
        elif self.variant == "equivalent":
            Zs = np.sort(Z, axis=-1).mean(axis=1)
            for j in range(2):
                x[:, j], P[:, j] = _pda_update(x[:, j], P[:, j], Zs, self.R / self.n_sensors)
        elif self.variant == "all_at_once":
            Zall = Z.reshape(Z.shape[0], -1)
            for j in range(2):
                x[:, j], P[:, j] = _pda_update(x[:, j], P[:, j], Zall, self.R)
        elif self.variant == "jpda":
            for n in range(self.n_sensors):
                x, P = _jpda_pair_update(x, P, Z[:, n, :], self.R)
        else:
            N = self.n_sensors
            for j in range(2):
                S1 = P[:, j] + self.R
                nu = Z - x[:, j, None, None]  # (runs, N, 2)
                logw = -0.5 * nu**2 / S1[:, None, None]
                beta = np.exp(logw - logw.max(axis=2, keepdims=True))
                beta /= beta.sum(axis=2, keepdims=True)
                nu_n = np.sum(beta * nu, axis=2)  # per-sensor combined innovation
                spread = np.sum(np.sum(beta * nu**2, axis=2) - nu_n**2, axis=1) / N**2
                L = P[:, j] / (P[:, j] + self.R / N)
                x[:, j] = x[:, j] + L * nu_n.mean(axis=1)
                P[:, j] = (1 - L) * P[:, j] + L**2 * spread
        self.x, self.P = x, P


def mospa_two_targets(estimates, truth) -> np.ndarray:
    """Per-scan squared OSPA (p = 2, no cut-off) of two estimates against two truths.

    ``d = min over the two pairings of ½ Σ_j (x̂_π(j) − x_j)²`` (reconstruction §5.4), i.e.
    ``ospa(X̂, X, c=∞, p=2)²``; the mean over scans and runs is the MOSPA of Table 6.1 (m²).

    Parameters
    ----------
    estimates, truth : array_like, shape (..., 2)

    Returns
    -------
    array of shape (...)
    """
    e = np.asarray(estimates, dtype=float)
    t = np.asarray(truth, dtype=float)
    if e.shape != t.shape or e.shape[-1] != 2:
        raise ValueError(f"estimates and truth must have equal shapes (..., 2), got {e.shape} and {t.shape}")
    straight = (e[..., 0] - t[..., 0]) ** 2 + (e[..., 1] - t[..., 1]) ** 2
    crossed = (e[..., 0] - t[..., 1]) ** 2 + (e[..., 1] - t[..., 0]) ** 2
    return 0.5 * np.minimum(straight, crossed)

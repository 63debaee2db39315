"""Cardinality tracking: counts-only data, classical MHT versus the equivalence-class MAP.

Coraluppi & Carthel, *Cardinality Tracking and the Equivalence-Class MHT* (document 003), §4, with
the equations restored in ``coraluppi_carthel_reconstruction.md`` §3. Each scan k reports only
its number of returns ``r_k``: ``d`` detections of surviving targets, ``b`` detected births and
``f = r − d − b`` false alarms. Both objectives depend on the counts alone, so every solution is
summarised by the per-scan counts ``(χ_k, d_k, b_k)`` with ``τ_{k+1} = τ_k − χ_k + b_k``,
``τ_1 = 0``:

``J = Σ_k [ w_k + (d_k + b_k) ln(p_d/λ_fa) + (τ_k − χ_k − d_k) ln(1 − p_d) + b_k ln μ_k
+ χ_k ln p_χ + (τ_k − χ_k) ln(1 − p_χ)]``

with ``μ_1 = λ_b/p_χ`` (tracks present at the start of the data are the steady-state
population), ``μ_k = λ_b`` after, and ``w_k = ln(r_k!/(b_k! f_k!))`` for the equivalence class
(Eq. 4.8) or ``w_k = 0`` for a single track-oriented hypothesis (Eq. 4.1).

* :func:`exact_count_dp` maximises either objective exactly by dynamic programming over the
  number of live targets. With ``equivalence_class=False`` it is the classical track-oriented
  MHT on counts, whose MAP at ``λ_fa = 10`` is the null solution (no tracks).
* :func:`tetris_extract` is the paper's row-by-row ("Tetris") extraction: the K rule
  (Eq. 4.10), the track score (Eq. 4.11), the row/scan measurement values and the birth
  coupling of the ``1/b!`` factor (reconstruction §3.4).
* :class:`CardinalityTracker` and :class:`ClassicalCountMHT` wrap them in the tracker surface
  (``step(r)`` per scan, ``estimates()`` → estimated number of targets per scan).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import gammaln

from .._validation import check_finite_array, check_int, check_positive, check_probability

__all__ = [
    "CountModel",
    "CountSolution",
    "Track",
    "TetrisResult",
    "check_counts",
    "count_objective",
    "exact_count_dp",
    "k_rule",
    "track_log_score",
    "tetris_extract",
    "counts_from_tracks",
    "alive_from_counts",
    "CardinalityTracker",
    "ClassicalCountMHT",
    "constant_count_estimate",
    "per_scan_count_estimate",
]


@dataclass(frozen=True)
class CountModel:
    """Parameters of the counts-only problem (Eqs. 2.1–2.2, 4.1).

    Parameters
    ----------
    p_d : float
        Detection probability, in (0, 1].
    p_chi : float
        Per-scan termination probability p_χ, in (0, 1).
    lambda_b : float
        Mean number of births per scan λ_b, > 0.
    lambda_fa : float
        Mean number of false alarms per scan λ_fa, > 0.
    """

    p_d: float
    p_chi: float
    lambda_b: float
    lambda_fa: float

    def __post_init__(self):
        object.__setattr__(self, "p_d", check_probability(self.p_d, "p_d", low_open=True))
        object.__setattr__(self, "p_chi", check_probability(self.p_chi, "p_chi", low_open=True, high_open=True))
        object.__setattr__(self, "lambda_b", check_positive(self.lambda_b, "lambda_b"))
        object.__setattr__(self, "lambda_fa", check_positive(self.lambda_fa, "lambda_fa"))

    @property
    def log_miss(self) -> float:
        """``ln(1 − p_d)``; ``−inf`` when ``p_d = 1`` (a miss is impossible)."""
        return math.log1p(-self.p_d) if self.p_d < 1 else -math.inf

    def log_birth_mean(self, k: int) -> float:
        """``ln μ_k``: the steady-state population ``λ_b/p_χ`` at the first scan, ``λ_b`` after."""
        return math.log(self.lambda_b / self.p_chi) if k == 0 else math.log(self.lambda_b)


def check_counts(r, name: str = "r") -> np.ndarray:
    """Return a 1-D array of non-negative integer counts (an empty sequence is allowed)."""
    arr = check_finite_array(r, name)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a 1-D sequence of counts, got shape {arr.shape}")
    if np.any(arr < 0) or np.any(arr != np.round(arr)):
        raise ValueError(f"{name} must hold non-negative integers")
    return arr.astype(np.int64)


def _times_log(n, log_value):
    """``n · log_value`` with ``0 · (−inf) = 0`` (an event that never happens costs nothing)."""
    n = np.asarray(n)
    if not np.isinf(log_value):
        return n * log_value
    with np.errstate(invalid="ignore"):
        return np.where(n == 0, 0.0, n * log_value)


def _scan_terms(model: CountModel, k, r, tau, chi, d, b, equivalence_class: bool):
    """Log-factor of one scan of the objective (broadcast over array arguments)."""
    f = r - d - b
    survivors = tau - chi
    val = (
        (d + b) * math.log(model.p_d / model.lambda_fa)
        + _times_log(survivors - d, model.log_miss)
        + b * model.log_birth_mean(k)
        + chi * math.log(model.p_chi)
        + survivors * math.log1p(-model.p_chi)
    )
    if equivalence_class:
        val = val + gammaln(r + 1) - gammaln(b + 1) - gammaln(f + 1)
    return val


def count_objective(r, chi, d, b, model: CountModel, *, equivalence_class: bool = True) -> float:
    """The batch log-objective J of a count sequence (Eq. 4.8 summed, or Eq. 4.1 summed).

    Parameters
    ----------
    r : (T,) measured counts.
    chi, d, b : (T,) terminations, detections of surviving targets and detected births per scan.
    model : CountModel
    equivalence_class : bool
        True: log-probability of the equivalence class (includes ``ln r!/(b! f!)``);
        False: log-probability of one track-oriented global hypothesis.

    Returns
    -------
    float
        J up to the data-only constant; the null solution (all false alarms) scores 0.
    """
    r = check_counts(r)
    chi, d, b = (check_counts(a, n) for a, n in ((chi, "chi"), (d, "d"), (b, "b")))
    if not (len(chi) == len(d) == len(b) == len(r)):
        raise ValueError("r, chi, d and b must have the same length")
    tau = 0
    total = 0.0
    for k in range(len(r)):
        if chi[k] > tau or d[k] > tau - chi[k] or d[k] + b[k] > r[k]:
            raise ValueError(f"infeasible counts at scan {k}: tau={tau}, chi={chi[k]}, d={d[k]}, b={b[k]}, r={r[k]}")
        total += float(_scan_terms(model, k, r[k], tau, chi[k], d[k], b[k], equivalence_class))
        tau = tau - chi[k] + b[k]
    return total


@dataclass(frozen=True)
class CountSolution:
    """A count sequence and its objective value.

    Attributes
    ----------
    J : float
        Objective (Eq. 4.8 or 4.1 summed over scans), 0 for the null solution.
    chi, d, b, f : (T,) int arrays
        Terminations, detections, detected births and false alarms per scan.
    n : (T,) int array
        Estimated number of targets at each scan, ``τ_k − χ_k + b_k``.
    cap_reached : bool
        Whether the optimal path touches the ``max_alive`` cap of the search (if it does, a
        larger cap might find a better solution).
    """

    J: float
    chi: np.ndarray
    d: np.ndarray
    b: np.ndarray
    f: np.ndarray
    n: np.ndarray
    cap_reached: bool = False


def alive_from_counts(chi, b) -> np.ndarray:
    """Number of targets at each scan, ``n_k = Σ_{j≤k} (b_j − χ_j)``."""
    return np.cumsum(np.asarray(b, dtype=np.int64) - np.asarray(chi, dtype=np.int64))


def _best_detections(model, r, s, b, equivalence_class):
    """Optimal number of detected survivors for ``s`` survivors and ``b`` births.

    The ``d``-dependent part of the scan term is ``−ln((r−b−d)!) + d c`` (class) or ``d c``
    (single hypothesis) with ``c = ln(p_d / (λ_fa (1 − p_d)))``: concave in ``d``, so the
    unconstrained maximiser clipped to ``[0, min(s, r − b)]`` is the constrained one.
    """
    upper = np.minimum(s, r - b)
    if model.p_d == 1:
        return upper
    c = math.log(model.p_d / (model.lambda_fa * (1 - model.p_d)))
    if equivalence_class:
        # increments ln(r − b − d) + c stay positive while r − b − d > e^{−c}
        unconstrained = np.ceil(r - b - math.exp(-c)) if c > -700 else np.zeros_like(upper)
        return np.clip(unconstrained, 0, upper).astype(np.int64)
    return upper if c > 0 else np.zeros_like(upper)


def exact_count_dp(r, model: CountModel, *, equivalence_class: bool = True, max_alive: int | None = None) -> CountSolution:
    """Exact maximiser of the count objective J by dynamic programming over the live count.

    Each scan is split into a termination stage (``τ → s = τ − χ``) and a
    detection-and-birth stage (``s → s + b`` with the best ``d`` for ``(s, b)``); the state
    is the number of live targets, so the cost is ``O(T · max_alive · max r)``.

    Parameters
    ----------
    r : (T,) measured counts.
    model : CountModel
    equivalence_class : bool
        True: the cardinality tracker's class objective (Eq. 4.8); False: the classical
        track-oriented MHT (Eq. 4.1), whose MAP is the null solution when ``λ_fa`` is large.
    max_alive : int, optional
        Largest number of live targets searched. Default ``Σ r`` (every target needs a
        detection at birth), which makes the search exact.

    Returns
    -------
    CountSolution
    """
    r = check_counts(r)
    T = len(r)
    total = int(r.sum())
    cap = total if max_alive is None else min(check_int(max_alive, "max_alive", minimum=0), total)
    if T == 0:
        z = np.zeros(0, dtype=np.int64)
        return CountSolution(0.0, z, z, z, z, z)
    log_pchi = math.log(model.p_chi)
    log_surv = math.log1p(-model.p_chi)
    V = np.full(cap + 1, -np.inf)
    V[0] = 0.0
    states = np.arange(cap + 1)
    back_tau, back_b, back_d = [], [], []
    for k in range(T):
        # Termination stage: V1[s] = max_{τ ≥ s} V[τ] + (τ − s) ln p_χ + s ln(1 − p_χ).
        W = V + states * log_pchi
        rev = W[::-1]
        run_max = np.maximum.accumulate(rev)
        # index of the (first) maximiser in each reversed prefix
        is_new = np.concatenate([[True], rev[1:] > run_max[:-1]])
        arg_rev = np.maximum.accumulate(np.where(is_new, np.arange(cap + 1), 0))
        tau_of_s = (cap - arg_rev)[::-1]
        V1 = run_max[::-1] - states * log_pchi + states * log_surv
        # Detection-and-birth stage over the grid (τ', b), s = τ' − b.
        rk = int(r[k])
        bb = np.arange(rk + 1)[None, :]
        s = states[:, None] - bb
        valid = s >= 0
        s_c = np.where(valid, s, 0)
        d = _best_detections(model, rk, s_c, bb, equivalence_class)
        f = rk - d - bb
        g = (
            (d + bb) * math.log(model.p_d / model.lambda_fa)
            + _times_log(s_c - d, model.log_miss)
            + bb * model.log_birth_mean(k)
        )
        if equivalence_class:
            g = g + gammaln(rk + 1) - gammaln(bb + 1) - gammaln(f + 1)
        val = np.where(valid & (f >= 0), V1[s_c] + g, -np.inf)
        b_best = np.argmax(val, axis=1)
        V = val[states, b_best]
        back_tau.append(tau_of_s)
        back_b.append(b_best)
        back_d.append(d[states, b_best])
    end = int(np.argmax(V))
    J = float(V[end])
    chi = np.zeros(T, dtype=np.int64)
    dd = np.zeros(T, dtype=np.int64)
    b = np.zeros(T, dtype=np.int64)
    peak = 0
    tau_next = end
    for k in range(T - 1, -1, -1):
        b[k] = back_b[k][tau_next]
        dd[k] = back_d[k][tau_next]
        s_k = tau_next - b[k]
        tau_k = int(back_tau[k][s_k])
        chi[k] = tau_k - s_k
        peak = max(peak, tau_next, tau_k)
        tau_next = tau_k
    f = r - dd - b
    return CountSolution(J, chi, dd, b, f, alive_from_counts(chi, b), cap_reached=bool(peak >= cap and cap < total))


def k_rule(p_d: float, p_chi: float, lambda_b: float) -> int:
    """Largest gap K of missed scans worth bridging within one Tetris row (Eq. 4.10).

    ``K = max{g ≥ 0 : (1 − p_d)^g (1 − p_χ)^{g+1} ≥ λ_b p_χ}``; ``K = 0`` if ``p_d = 1`` or no
    ``g`` qualifies. Independent of the data.
    """
    model = CountModel(p_d, p_chi, lambda_b, 1.0)
    if model.p_d == 1:
        return 0
    threshold = math.log(model.lambda_b * model.p_chi)
    g = 0
    while (g + 1) * model.log_miss + (g + 2) * math.log1p(-model.p_chi) >= threshold:
        g += 1
    return g


def track_log_score(n_scans: int, n_meas: int, model: CountModel, *, starts_at_data_start: bool, reaches_data_end: bool) -> float:
    """``ln L(N, M)`` of Eq. 4.11 for a track spanning N scans with M measurements.

    ``L = λ_b p_χ p_d^M (1 − p_d)^{N−M} (1 − p_χ)^{N−1}``, with ``λ_b → λ_b/p_χ`` for a track
    present at the start of the data and no ``p_χ`` for a track that reaches its end.
    """
    N = check_int(n_scans, "n_scans", minimum=1)
    M = check_int(n_meas, "n_meas", minimum=1, maximum=N)
    val = model.log_birth_mean(0 if starts_at_data_start else 1)
    val += M * math.log(model.p_d) + float(_times_log(N - M, model.log_miss)) + (N - 1) * math.log1p(-model.p_chi)
    if not reaches_data_end:
        val += math.log(model.p_chi)
    return val


@dataclass(frozen=True)
class Track:
    """An extracted cardinality track: its Tetris row, first and last scan, detection scans."""

    row: int
    start: int
    end: int
    scans: tuple
    log_score: float


@dataclass(frozen=True)
class TetrisResult:
    """Output of :func:`tetris_extract`.

    Attributes
    ----------
    tracks : list of Track
    n : (T,) estimated number of targets per scan.
    J : float
        Sum of the tracks' scores, which equals the class objective of their count sequence.
    K : int
        The gap rule of Eq. 4.10 used.
    """

    tracks: list
    n: np.ndarray
    J: float
    K: int


def _row_candidates(ks, lnv, B, model, T):
    """Log-scores ``ℓ(a, i)`` of the tracks spanning row measurements ``a..i`` of one group."""
    m = len(ks)
    cum = np.concatenate([[0.0], np.cumsum(lnv)])
    a = np.arange(m)[:, None]
    i = np.arange(m)[None, :]
    start = ks[a]
    end = ks[i]
    n_meas = i - a + 1
    n_scans = end - start + 1
    log_mu = np.where(start == 0, model.log_birth_mean(0), model.log_birth_mean(1))
    ell = (
        math.log(model.p_d) + log_mu
        - np.log1p(B[start])  # birth coupling 1/j from the 1/b! factor
        + (n_meas - 1) * math.log(model.p_d)
        + _times_log(n_scans - n_meas, model.log_miss)
        + (n_scans - 1) * math.log1p(-model.p_chi)
        + np.where(end < T - 1, math.log(model.p_chi), 0.0)
        + (cum[i + 1] - cum[a])
    )
    return np.where(i >= a, ell, -np.inf)


def _best_intervals(ell):
    """Disjoint intervals ``[a, i]`` maximising the summed score (weighted-interval DP)."""
    m = ell.shape[0]
    best = np.zeros(m + 1)
    choice = np.full(m, -1)
    for i in range(m):
        cand = best[: i + 1] + ell[: i + 1, i]
        a = int(np.argmax(cand))
        if cand[a] > best[i]:
            best[i + 1] = cand[a]
            choice[i] = a
        else:
            best[i + 1] = best[i]
    intervals = []
    i = m - 1
    while i >= 0:
        if choice[i] >= 0:
            intervals.append((int(choice[i]), i))
            i = int(choice[i]) - 1
        else:
            i -= 1
    return intervals[::-1]


def tetris_extract(r, model: CountModel, *, variant: str = "row_dp") -> TetrisResult:
    """Row-by-row optimal track extraction from the Tetris structure (paper §4, Fig. 4.1).

    Scan k's ``r_k`` returns are stacked from the bottom, so row z is present at scan k iff
    ``r_k ≥ z``. Rows are processed bottom-up; within a row, runs of measurements separated by
    more than K misses (Eq. 4.10) are never joined. A track in row z over scans ``[s, e]`` scores

    ``ℓ = ln L(N, M) − ln j + Σ_{k ∈ meas} ln v(z, k)``  (Eq. 4.11 and reconstruction §3.4),

    where ``v(z, k) = (r_k − D_{<z}(k)) / λ_fa`` is the value of explaining a return by a track
    rather than a false alarm (``D_{<z}(k)`` = lower-row detections at scan k; the ``r!/f!`` part
    of the class weight) and ``j = 1 +`` the number of lower-row tracks born at s (the ``1/b!``
    part). The sum of the ℓ equals the class objective J of the extracted counts.

    Parameters
    ----------
    r : (T,) measured counts.
    model : CountModel
    variant : {"row_dp", "group"}
        ``"row_dp"``: within each group choose the best set of disjoint tracks by a 1-D
        weighted-interval dynamic programme (recommended, reconstruction §3.4);
        ``"group"``: the paper-literal rule, each group one candidate kept iff ``ℓ > 0``.

    Returns
    -------
    TetrisResult
    """
    if variant not in ("row_dp", "group"):
        raise ValueError(f"variant must be 'row_dp' or 'group', got {variant!r}")
    r = check_counts(r)
    T = len(r)
    K = k_rule(model.p_d, model.p_chi, model.lambda_b)
    D = np.zeros(T, dtype=np.int64)  # detections already explained by lower rows
    B = np.zeros(T, dtype=np.int64)  # births already placed by lower rows
    tracks = []
    for z in range(1, int(r.max(initial=0)) + 1):
        present = np.flatnonzero(r >= z)
        breaks = np.flatnonzero(np.diff(present) - 1 > K) + 1
        new_D = np.zeros(T, dtype=np.int64)
        for ks in np.split(present, breaks):
            lnv = np.log((r[ks] - D[ks]) / model.lambda_fa)
            ell = _row_candidates(ks, lnv, B, model, T)
            if variant == "row_dp":
                chosen = _best_intervals(ell)
            else:
                chosen = [(0, len(ks) - 1)] if ell[0, -1] > 0 else []
            for a, i in chosen:
                tracks.append(Track(z, int(ks[a]), int(ks[i]), tuple(int(k) for k in ks[a : i + 1]), float(ell[a, i])))
                new_D[ks[a : i + 1]] += 1
                B[ks[a]] += 1
        D += new_D
    n = np.zeros(T, dtype=np.int64)
    for t in tracks:
        n[t.start : t.end + 1] += 1
    return TetrisResult(tracks, n, float(sum(t.log_score for t in tracks)), K)


def counts_from_tracks(tracks, n_scans: int):
    """Per-scan ``(χ, d, b)`` of a set of tracks (for scoring them with :func:`count_objective`)."""
    T = check_int(n_scans, "n_scans", minimum=0)
    chi = np.zeros(T, dtype=np.int64)
    d = np.zeros(T, dtype=np.int64)
    b = np.zeros(T, dtype=np.int64)
    for t in tracks:
        b[t.start] += 1
        if t.end + 1 < T:
            chi[t.end + 1] += 1
        for k in t.scans[1:]:
            d[k] += 1
    return chi, d, b


def constant_count_estimate(n_scans: int, model: CountModel) -> np.ndarray:
    """The data-free estimate ``n̂_k = λ_b/p_χ`` at every scan: the steady-state population of the
    birth–death process (reconstruction §1, the consistency check of Eqs. 2.1–2.2).

    A negative control of the cardinality claims: it ignores the data, so any check it passes cannot
    tell a tracker from no tracking at all."""
    T = check_int(n_scans, "n_scans", minimum=0)
    return np.full(T, model.lambda_b / model.p_chi)


def per_scan_count_estimate(r, model: CountModel) -> np.ndarray:
    """The per-scan moment estimate ``n̂_k = max(0, (r_k − λ_fa)/p_d)``.

    ``E[r_k | n_k] = p_d n_k + λ_fa`` (each of the n_k targets is detected with probability p_d and
    Poisson(λ_fa) false alarms are added, the measurement model of Eq. 4.1), so ``(r_k − λ_fa)/p_d``
    is unbiased for n_k before the clip at zero. It uses one scan at a time (no tracks, no
    dynamics): a negative control of the claims that tracking improves the count."""
    counts = check_counts(r)
    return np.maximum(0.0, (counts - model.lambda_fa) / model.p_d)


class _CountTracker:
    """Batch tracker surface: ``step(r_k)`` appends a scan's count, ``estimates()`` re-solves."""

    def __init__(self, p_d, p_chi, lambda_b, lambda_fa):
        self.model = CountModel(p_d, p_chi, lambda_b, lambda_fa)
        self._r: list[int] = []
        self._cache = None

    def step(self, r_k) -> None:
        """Add the count of one scan (a non-negative integer)."""
        self._r.append(check_int(r_k, "r_k", minimum=0))
        self._cache = None

    @property
    def counts(self) -> np.ndarray:
        return np.asarray(self._r, dtype=np.int64)

    def estimates(self) -> np.ndarray:
        """Estimated number of targets at every scan so far (optimal in batch)."""
        if self._cache is None:
            self._cache = self._solve()
        return self._cache.n

    def _solve(self):  # pragma: no cover - abstract
        raise NotImplementedError


class CardinalityTracker(_CountTracker):
    """The cardinality tracker: Tetris extraction of the MAP equivalence class (§4).

    Parameters
    ----------
    p_d, p_chi, lambda_b, lambda_fa : float
        See :class:`CountModel`.
    variant : {"row_dp", "group"}
        Extraction variant of :func:`tetris_extract`.
    """

    def __init__(self, p_d, p_chi, lambda_b, lambda_fa, *, variant: str = "row_dp"):
        super().__init__(p_d, p_chi, lambda_b, lambda_fa)
        if variant not in ("row_dp", "group"):
            raise ValueError(f"variant must be 'row_dp' or 'group', got {variant!r}")
        self.variant = variant

    def _solve(self):
        return tetris_extract(self.counts, self.model, variant=self.variant)

    def tracks(self) -> list:
        """The extracted tracks (row, start, end, detection scans, score)."""
        self.estimates()
        return self._cache.tracks


class ClassicalCountMHT(_CountTracker):
    """Classical track-oriented MHT on counts: the exact MAP single global hypothesis (Eq. 4.1).

    ``max_alive`` bounds the dynamic programme as in :func:`exact_count_dp`.
    """

    def __init__(self, p_d, p_chi, lambda_b, lambda_fa, *, max_alive: int | None = None):
        super().__init__(p_d, p_chi, lambda_b, lambda_fa)
        self.max_alive = None if max_alive is None else check_int(max_alive, "max_alive", minimum=0)

    def _solve(self):
        return exact_count_dp(self.counts, self.model, equivalence_class=False, max_alive=self.max_alive)

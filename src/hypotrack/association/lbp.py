"""Approximate JPDA marginals by loopy belief propagation (Williams & Lau 2014).

The exact marginals of :mod:`hypotrack.association.marginals` sum over every feasible joint event
(efficiently, but a dense cluster still grows exponentially). Williams & Lau write the same
distribution as a graphical model on the bipartite association graph and run the sum-product
algorithm (SPA) on it: with ``n`` tracks and ``m`` returns, track ``i`` chooses
``a_i ∈ {0 (missed), 1..m}``, return ``j`` chooses ``b_j ∈ {0 (clutter / new target), 1..n}``, and
the pairwise factor ``ψ_ij(a_i, b_j) = 0`` if exactly one of ``a_i = j``, ``b_j = i`` holds (the
two sides must agree; this is what forbids one return to two tracks), ``1`` otherwise. The
track factors are the JPDA weights ``w_i(a_i)`` of :func:`~hypotrack.association.marginals.jpda_marginals`
(``w_i(0)`` missed, ``w_i(j)`` return ``j``, zero outside the gate); the return factors are ``1``
(the clutter density is already divided out of ``w_i(j)``; a return weight ``u_j`` for "unassigned",
as in the PMB filter, is the same as dividing it out, see ``log_unassigned``). The joint is then exactly the JPDA
event distribution, ``p(a) ∝ Π_i w_i(a_i)`` over feasible events.

The SPA messages on this graph collapse to one number per gated pair (Williams & Lau 2014, the
simplified message-passing equations of their algorithm; Meyer et al. 2018 write the same pair):

    μ_{i→j} = w_i(j) / ( w_i(0) + Σ_{j' ≠ j} w_i(j') ν_{j'→i} ),           (track i to return j)
    ν_{j→i} = 1 / ( 1 + Σ_{i' ≠ i} μ_{i'→j} ),                              (return j to track i)

started from ``ν = 1`` and iterated to a fixed point, which Williams & Lau prove is unique and
reached from any start when every missed weight ``w_i(0) > 0`` (``P_D P_G < 1``), which is why this
module requires it. The approximate marginals are the track-side beliefs

    β_i(0) ∝ w_i(0),    β_i(j) ∝ w_i(j) ν_{j→i},    Σ_c β_i(c) = 1,

and at the fixed point they agree with the return-side beliefs ``P(b_j = i) ∝ μ_{i→j}``, so each
return's total ``Σ_i β_i(j) ≤ 1`` (up to the convergence tolerance). On a graph without cycles
(a tree or forest: one return shared by two tracks, a chain) the SPA is exact; on a loopy graph it
is an approximation whose error Williams & Lau found small in tracking problems; the tests measure
it (``tests/unit/association/test_lbp.py``: up to 0.08 on 3 × 3 fully gated problems with N(0, 1)
log weights, 0.05 on a 200-track line, 0.17 on the worst of the JPDA test scenes).

Each iteration costs ``O(number of gated pairs)``: the leave-one-out sums are formed from prefix
and suffix sums over each track's (and each return's) gated pairs, never by subtracting a term
from the total, so nothing cancels. All messages are kept as logarithms, so weights of any range
(log-likelihood ratios in the hundreds) neither overflow nor underflow.

In the JPDA filter: ``jpda_probabilities(gated, model, marginals="lbp")`` of
:mod:`hypotrack.trackers.jpda` uses these marginals for the targets that share returns (the
default, ``"exact"``, stays the exact recursion); :func:`lbp_benchmark` tabulates the cost per pass.

References
----------
J. Williams & R. Lau, "Approximate evaluation of marginal association probabilities with belief
propagation", IEEE Trans. Aerospace and Electronic Systems 50(4), 2014.
F. Meyer et al., "Message passing algorithms for scalable multitarget tracking", Proc. IEEE 106(2), 2018.
The papers' texts were not at hand when this was written: the equations are stated in full above
rather than by number.
"""

from __future__ import annotations

import time as _time
from typing import NamedTuple

import numpy as np
from numba import njit

from .._validation import check_int, check_positive

__all__ = ["LbpMarginals", "lbp_marginals", "lbp_benchmark"]

DEFAULT_TOL = 1e-10
DEFAULT_MAX_ITER = 1000


class LbpMarginals(NamedTuple):
    """Result of :func:`lbp_marginals` (unpacks as ``beta, iterations, change``).

    Attributes
    ----------
    beta : (n, m + 1) ndarray
        ``beta[i, 0]`` ≈ P(track i missed), ``beta[i, 1 + j]`` ≈ P(track i ↔ return j).
    iterations : int
        Message passes made (one pass updates every ``μ`` and then every ``ν``).
    change : float
        ``max |Δ log ν_{j→i}|`` over the gated pairs in the last pass; below ``tol`` when the
        iteration converged. Every marginal then moved by less than ``exp(2 change) − 1`` in the
        last pass.
    """

    beta: np.ndarray
    iterations: int
    change: float


def lbp_marginals(log_weights, *, log_unassigned=None, tol: float = DEFAULT_TOL,
                  max_iter: int = DEFAULT_MAX_ITER) -> LbpMarginals:
    """Approximate marginal association probabilities by loopy belief propagation.

    Parameters
    ----------
    log_weights : (n, m + 1) array_like
        The JPDA weights in the convention of
        :func:`hypotrack.association.marginals.jpda_marginals` and
        :func:`hypotrack.trackers.jpda.jpda_log_weights`: column 0 the log weight of track ``i``
        being missed (finite: ``P_D P_G < 1``, which the convergence proof needs), column ``1 + j``
        the log weight of track ``i`` having produced return ``j``, ``-inf`` outside the gate.
        A constant added to a row changes nothing.
    log_unassigned : (m,) array_like, optional
        Log weight of return ``j`` being associated with no track (clutter or a new object), as in
        Williams & Lau's and the PMB filter's formulation; default ``0`` for every return (the JPDA
        convention, where the clutter density is already divided into the track weights). It is
        the same as subtracting ``log_unassigned[j]`` from column ``1 + j``, which is how it is
        applied. Finite.
    tol : float, optional
        Stop when no log message ``log ν_{j→i}`` changes by more than ``tol`` in a pass (> 0).
    max_iter : int, optional
        Largest number of passes (≥ 1). Reaching it is not an error: compare ``change`` with
        ``tol``.

    Returns
    -------
    LbpMarginals
        ``(beta, iterations, change)``: ``beta`` of shape ``(n, m + 1)``, every row summing to 1.

    Raises
    ------
    ValueError
        On a wrong shape, NaN or ``+inf`` weights, a ``-inf`` (zero) missed weight, a
        ``log_unassigned`` of the wrong length or not finite, ``tol <= 0`` or ``max_iter < 1``.

    Notes
    -----
    Cost: ``O(n m)`` once, to find the gated pairs in the dense input and to write the beliefs
    back, then ``O(gated pairs)`` per pass. Measured with :func:`lbp_benchmark` (shared 2-core
    machine, tracks on a line with ~4 returns per gate): 0.9–1.8e-7 s per pass per gated pair,
    flat from 807 to 12,821 pairs; 36–41 passes to ``tol = 1e-10``.

    Examples
    --------
    One track, two returns: LBP is the PDAF softmax ``β = w / Σ w`` (no message is ever needed).

    >>> r = lbp_marginals(np.log([[1.0, 2.0, 1.0]]))
    >>> r.beta.round(4).tolist(), r.iterations
    ([[0.25, 0.5, 0.25]], 1)

    Two tracks sharing one return (a tree, so LBP is exact): events {both missed: 1·1,
    track 0 gets it: 3·1, track 1 gets it: 1·1} give P(track 0 ↔ return) = 3/5.

    >>> lw = np.log([[1.0, 3.0], [1.0, 1.0]])
    >>> r = lbp_marginals(lw)
    >>> r.beta.round(12).tolist()
    [[0.4, 0.6], [0.8, 0.2]]
    """
    lw = np.asarray(log_weights, dtype=float)
    if lw.ndim != 2 or lw.shape[1] < 1:
        raise ValueError(f"log_weights must have shape (n, m + 1), got {lw.shape}")
    if np.isnan(lw).any() or np.isposinf(lw).any():
        raise ValueError("log_weights must not contain NaN or +inf (use -inf for gated-out pairs)")
    if not np.isfinite(lw[:, 0]).all():
        bad = np.flatnonzero(~np.isfinite(lw[:, 0])).tolist()
        raise ValueError(
            f"log_weights[:, 0] (missed) must be finite (missed weight > 0, P_D P_G < 1) for loopy belief "
            f"propagation; rows {bad} are -inf (use jpda_marginals for exact marginals with P_D P_G = 1)"
        )
    tol = check_positive(tol, "tol")
    max_iter = check_int(max_iter, "max_iter", minimum=1)
    n, m1 = lw.shape
    if log_unassigned is not None:
        lu = np.asarray(log_unassigned, dtype=float)
        if lu.shape != (m1 - 1,):
            raise ValueError(f"log_unassigned must have shape (m,) = ({m1 - 1},), got {lu.shape}")
        if not np.isfinite(lu).all():
            raise ValueError("log_unassigned must be finite (an unassigned weight in (0, inf))")
        lw = lw.copy()
        lw[:, 1:] -= lu  # -inf (gated out) stays -inf
    if n == 0:
        return LbpMarginals(np.zeros((0, m1)), 0, 0.0)
    t_idx, j_idx, graph = _gated_pairs(lw)
    log_nu, iterations, change = _iterate(*graph, tol, max_iter)
    lw_e = graph[1]
    # Beliefs: β_i(0) ∝ w_i(0), β_i(j) ∝ w_i(j) ν_{j→i}, normalised per row in log space.
    logb = np.full((n, m1), -np.inf)
    logb[:, 0] = lw[:, 0]
    logb[t_idx, 1 + j_idx] = lw_e + log_nu
    logb -= logb.max(axis=1, keepdims=True)
    beta = np.exp(logb)
    beta /= beta.sum(axis=1, keepdims=True)
    return LbpMarginals(beta, int(iterations), float(change))


def _gated_pairs(lw):
    """The gated pairs (track, return) in track order, and the kernel's graph: missed log weights,
    pair log weights, track pointers (CSR rows), the pairs in return order and return pointers."""
    n, m1 = lw.shape
    t_idx, j_idx = np.nonzero(np.isfinite(lw[:, 1:]))
    row_ptr = np.zeros(n + 1, np.int64)
    np.cumsum(np.bincount(t_idx, minlength=n), out=row_ptr[1:])
    by_col = np.argsort(j_idx, kind="stable").astype(np.int64)
    col_ptr = np.zeros(m1, np.int64)
    np.cumsum(np.bincount(j_idx, minlength=m1 - 1), out=col_ptr[1:])
    graph = (np.ascontiguousarray(lw[:, 0]), lw[t_idx, 1 + j_idx], row_ptr, by_col, col_ptr)
    return t_idx, j_idx, graph


@njit(cache=True)
def _lse2(a, b):
    """log(exp(a) + exp(b)) without overflow; -inf + -inf gives -inf."""
    if a < b:
        a, b = b, a
    if b == -np.inf:
        return a
    return a + np.log1p(np.exp(b - a))


@njit(cache=True)
def _leave_one_out(base, terms, out):
    """out[k] = log(exp(base) + Σ_{l≠k} exp(terms[l])) by prefix and suffix sums (no subtraction)."""
    d = terms.shape[0]
    acc = base
    for k in range(d):  # prefix: base + terms[:k]
        out[k] = acc
        acc = _lse2(acc, terms[k])
    acc = -np.inf
    for k in range(d - 1, -1, -1):  # add suffix terms[k+1:]
        out[k] = _lse2(out[k], acc)
        acc = _lse2(acc, terms[k])


@njit(cache=True)
def _iterate(lw0, lw_e, row_ptr, by_col, col_ptr, tol, max_iter):
    """The SPA passes in log space; returns (log ν per gated pair, passes, last change)."""
    n_e = lw_e.shape[0]
    n = lw0.shape[0]
    m = col_ptr.shape[0] - 1
    log_nu = np.zeros(n_e)  # ν = 1 initially
    log_mu = np.empty(n_e)
    buf_t = np.empty(n_e)
    buf_o = np.empty(n_e)
    change = 0.0
    it = 0
    while it < max_iter:
        it += 1
        # Track → return: log μ_{i→j} = log w_i(j) − log(w_i(0) + Σ_{j'≠j} w_i(j') ν_{j'→i}).
        for i in range(n):
            a, b = row_ptr[i], row_ptr[i + 1]
            for e in range(a, b):
                buf_t[e] = lw_e[e] + log_nu[e]
            _leave_one_out(lw0[i], buf_t[a:b], buf_o[a:b])
            for e in range(a, b):
                log_mu[e] = lw_e[e] - buf_o[e]
        # Return → track: log ν_{j→i} = −log(1 + Σ_{i'≠i} μ_{i'→j}).
        change = 0.0
        for j in range(m):
            a, b = col_ptr[j], col_ptr[j + 1]
            for k in range(a, b):
                buf_t[k] = log_mu[by_col[k]]
            _leave_one_out(0.0, buf_t[a:b], buf_o[a:b])
            for k in range(a, b):
                e = by_col[k]
                new = -buf_o[k]
                d = abs(new - log_nu[e])
                if d > change:
                    change = d
                log_nu[e] = new
        if change < tol:
            break
    return log_nu, it, change


def lbp_benchmark(sizes=((200, 300), (800, 1200), (3200, 4800)), *, gated_per_track: float = 4.0, seed=0,
                  repeats: int = 3, passes: int = 50):
    """Time per LBP pass on random sparse problems of a few sizes (a benchmark table, not a test).

    Tracks and returns are scattered on a line of length ``n``; a track gates the returns within
    a distance chosen so that it gates ``gated_per_track`` returns on average
    (:func:`random_line_problem`). A call of :func:`lbp_marginals` has two costs: turning the dense
    ``(n, m + 1)`` input into lists of gated pairs and the beliefs back into a matrix (``O(n m)``,
    once), and the passes (``O(gated pairs)`` each). Both are reported: the whole converged call
    (``seconds``) and the message passes alone, timed on ``passes`` passes of the compiled kernel
    (``seconds_per_pass``), which should grow linearly with the gated pairs, so
    ``seconds_per_pass_per_pair`` should stay roughly constant across sizes (up to cache effects).

    Parameters
    ----------
    sizes : sequence of (n, m)
        Numbers of tracks and returns.
    gated_per_track : float
        Mean number of returns in a track's gate (> 0).
    seed : int or numpy Generator
    repeats : int
        Timed calls per measurement (≥ 1); the fastest is kept.
    passes : int
        Passes timed for the per-pass cost (≥ 1).

    Returns
    -------
    pandas.DataFrame
        One row per size: ``n``, ``m``, ``gated_pairs``, ``iterations`` and ``change`` of a converged
        call (default ``tol``), its wall time ``seconds``, ``seconds_per_pass`` and
        ``seconds_per_pass_per_pair``.
    """
    import pandas as pd

    gated_per_track = check_positive(gated_per_track, "gated_per_track")
    repeats = check_int(repeats, "repeats", minimum=1)
    passes = check_int(passes, "passes", minimum=1)
    rng = np.random.default_rng(seed)
    lbp_marginals(np.log([[1.0, 1.0], [1.0, 1.0]]))  # compile outside the timing
    rows = []
    for n, m in sizes:
        lw = random_line_problem(rng, n, m, gated_per_track=gated_per_track)
        seconds, per_pass, res = np.inf, np.inf, None
        graph = _gated_pairs(lw)[2]
        for _ in range(repeats):
            t0 = _time.perf_counter()
            res = lbp_marginals(lw)
            seconds = min(seconds, _time.perf_counter() - t0)
            t0 = _time.perf_counter()
            _, done, _ = _iterate(*graph, 1e-300, passes)  # tol so small that every pass runs
            per_pass = min(per_pass, (_time.perf_counter() - t0) / done)
        pairs = int(graph[1].size)
        rows.append(dict(n=n, m=m, gated_pairs=pairs, iterations=res.iterations, change=res.change,
                         seconds=seconds, seconds_per_pass=per_pass,
                         seconds_per_pass_per_pair=per_pass / max(pairs, 1)))
    return pd.DataFrame(rows)


def random_line_problem(rng, n: int, m: int, *, gated_per_track: float = 4.0, p_D: float = 0.9) -> np.ndarray:
    """A random sparse JPDA problem: ``n`` tracks and ``m`` returns uniform on ``[0, n]``.

    Track ``i`` gates the returns within ``h = gated_per_track · n / (2 m)`` of it (so about
    ``gated_per_track`` each); log weights are ``log(1 − p_D)`` (missed) and
    ``log(p_D N(z; x, σ²) / λ)`` with ``σ = h / 2`` and clutter density ``λ = 1`` per unit length.
    Along a line the exact recursion's frontier stays small, so exact marginals remain computable
    at sizes where enumeration is not.
    """
    x = np.sort(rng.uniform(0, n, n))
    z = rng.uniform(0, n, m)
    h = gated_per_track * n / (2 * max(m, 1))
    sigma = h / 2
    d = z[None, :] - x[:, None]
    lw = np.empty((n, m + 1))
    lw[:, 0] = np.log1p(-p_D)
    ll = np.log(p_D) - 0.5 * (d / sigma) ** 2 - np.log(np.sqrt(2 * np.pi) * sigma)
    lw[:, 1:] = np.where(np.abs(d) <= h, ll, -np.inf)
    return lw

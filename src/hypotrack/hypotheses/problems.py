"""Synthetic association problems with a known true association (document 000 Fig. 15).

Document 000 Sec. V-B times the generation of the children of one parent as the number of possible
associations ``A(M, m)`` grows. :func:`synthetic_problem` draws such a parent: ``M`` objects with
Gaussian predicted measurements spread over a square, a true association (which objects were
detected, which returns are clutter), the ``m`` returns it produced, shuffled, and the
association problem of the chosen weight model built by the engine itself
(:meth:`WeightModel.problem` on a :class:`ScanContext`), so that the benchmark times exactly
what the filter runs.

The paper-style problem (``difficulty="paper"``) is easy by construction: an 8σ grid, every
object detected when ``M <= m`` and no clutter when ``M >= m``, so the true association is
the heaviest child. The *difficulty axis* (``difficulty="1sigma" … "8sigma"``) draws problems
with real ambiguity: objects ``1, 2, 4`` or ``8`` standard deviations apart (gates overlap at
small spacing), each detected with ``p_D = 0.9`` (missed objects), and Poisson clutter with
mean ``max(1, (1 − p_D) M)`` so that the number of returns ``m`` scatters around ``M`` and
both ``m > M`` and ``m < M`` occur. Usage::

    sp = synthetic_problem(30, difficulty="4sigma", seed=7)      # m drawn
    sp = synthetic_problem(30, 30, seed=7)                       # the paper's problem, m = 30
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int, check_positive, check_probability
from .association_problem import CLUTTER, AssociationProblem
from .scan_context import ScanContext
from .weights import make_weight_model

__all__ = ["DIFFICULTIES", "DIFFICULTY_SPACING", "SyntheticProblem", "synthetic_problem", "truth_rank"]

#: Object spacing in measurement standard deviations of the ambiguous difficulties.
DIFFICULTY_SPACING = {"1sigma": 1.0, "2sigma": 2.0, "4sigma": 4.0, "8sigma": 8.0}
#: ``"paper"`` (document 000 Fig. 15's well separated problem) then hardest to easiest.
DIFFICULTIES = ("paper", *DIFFICULTY_SPACING)
#: Detection probability of the ambiguous difficulties.
AMBIGUOUS_P_D = 0.9


@dataclass(frozen=True, eq=False)
class SyntheticProblem:
    """A parent's association problem and the event that generated its returns.

    Attributes
    ----------
    problem : AssociationProblem
    truth : (m,) int event (object index or −1 for clutter per return).
    context : ScanContext the problem was built from.
    """

    problem: AssociationProblem
    truth: np.ndarray
    context: ScanContext


def synthetic_problem(n_objects, n_returns=None, rng=None, *, difficulty="paper", seed=None, weights="hfisst",
                      p_D=None, clutter_rate=None, sigma=1.0, spacing=None, sigma_spread=0.25) -> SyntheticProblem:
    """Draw an ``M``-object association problem from a known truth.

    Objects sit on a jittered square grid with ``spacing`` (in units of ``sigma``) between
    neighbours (jitter uniform within ±``spacing``/4); object ``j``'s innovation covariance is
    ``S_j = (sigma s_j)² I₂`` with ``log s_j ~ N(0, sigma_spread²)``. Detected objects produce a
    return drawn from ``N(ẑ_j, S_j)``; clutter is uniform over the square (whose area is the
    clutter volume ``V``). Returns are shuffled.

    * ``difficulty="paper"``: ``m = n_returns`` is given; ``min(M, m)`` random objects are
      detected and the other returns are clutter (defaults ``p_D = 0.95``, ``λV = 1``,
      ``spacing = 8``).
    * ``difficulty`` in :data:`DIFFICULTY_SPACING`: each object is detected with ``p_D``
      (default 0.9) and a Poisson number of clutter returns with mean ``clutter_rate``
      (default ``max(1, (1 − p_D) M)``, so that ``E[m] ≈ M``) is added; ``m`` is drawn, so
      ``n_returns`` must be ``None``.

    Parameters
    ----------
    n_objects : int
        ``M``.
    n_returns : int, optional
        ``m`` (paper difficulty only).
    rng : numpy.random.Generator, optional
        Source of every draw; or give ``seed`` instead (exactly one of the two).
    difficulty : str
        One of :data:`DIFFICULTIES`.
    seed : int, optional
        Seed of ``numpy.random.default_rng`` when ``rng`` is not given.
    weights : {"hfisst", "fisst_poisson", "reid"}
        Weight model of the problem (R-FISST uses ``"hfisst"``, HOMHT ``"reid"``).
    p_D : float, optional
        Detection probability in (0, 1).
    clutter_rate : float, optional
        Expected clutter returns per scan ``λV`` (> 0), used by the weight models (and, for the
        ambiguous difficulties, to draw the clutter).
    """
    if difficulty not in DIFFICULTIES:
        raise ValueError(f"difficulty must be one of {DIFFICULTIES}, got {difficulty!r}")
    if (rng is None) == (seed is None):
        raise ValueError("give exactly one of rng (a numpy Generator) and seed (an int)")
    if rng is None:
        rng = np.random.default_rng(check_int(seed, "seed", minimum=0))
    if difficulty != "paper":
        if n_returns is not None:
            raise ValueError(f"n_returns must be None for difficulty {difficulty!r} (m is drawn), got {n_returns!r}")
        return _ambiguous_problem(n_objects, rng, weights=weights, p_D=AMBIGUOUS_P_D if p_D is None else p_D,
                                  clutter_rate=clutter_rate, sigma=sigma,
                                  spacing=DIFFICULTY_SPACING[difficulty] if spacing is None else spacing,
                                  sigma_spread=sigma_spread)
    if n_returns is None:
        raise ValueError("n_returns (m >= 0) is required for the paper difficulty")
    p_D = 0.95 if p_D is None else p_D
    clutter_rate = 1.0 if clutter_rate is None else clutter_rate
    spacing = 8.0 if spacing is None else spacing
    M = check_int(n_objects, "n_objects", minimum=0)
    m = check_int(n_returns, "n_returns", minimum=0)
    p_D = check_probability(p_D, "p_D", low_open=True, high_open=True)
    clutter_rate = check_positive(clutter_rate, "clutter_rate")
    sigma = check_positive(sigma, "sigma")
    spacing = check_positive(spacing, "spacing")
    z_pred, scale, side = _objects(M, rng, sigma, spacing, sigma_spread)
    n_det = min(M, m)
    detected = rng.permutation(M)[:n_det]
    return _build(M, z_pred, scale, side, detected, m - n_det, rng, weights, p_D, clutter_rate)


def _objects(M, rng, sigma, spacing, sigma_spread):
    side_n = max(1, int(np.ceil(np.sqrt(max(M, 1)))))
    side = side_n * spacing * sigma
    cells = rng.permutation(side_n * side_n)[:M]
    centres = (np.stack([cells % side_n, cells // side_n], axis=1) + 0.5) * spacing * sigma
    z_pred = centres + rng.uniform(-0.25, 0.25, size=(M, 2)) * spacing * sigma
    scale = sigma * np.exp(sigma_spread * rng.standard_normal(M))
    return z_pred, scale, side


def _build(M, z_pred, scale, side, detected, n_clutter, rng, weights, p_D, clutter_rate):
    """Returns of the ``detected`` objects plus ``n_clutter`` uniform ones, shuffled, and the problem."""
    n_det = len(detected)
    m = n_det + n_clutter
    Z = np.vstack([
        z_pred[detected] + scale[detected, None] * rng.standard_normal((n_det, 2)),
        rng.uniform(0.0, side, size=(n_clutter, 2)),
    ]).reshape(m, 2)
    origin = np.concatenate([detected, np.full(n_clutter, CLUTTER)]).astype(np.int64)
    order = rng.permutation(m)
    Z, origin = Z[order], origin[order]
    if M:
        r2 = np.sum((Z[:, None, :] - z_pred[None, :, :]) ** 2, axis=-1) / scale[None, :] ** 2
        loglik = -0.5 * r2 - 2 * np.log(scale)[None, :] - np.log(2 * np.pi)
    else:
        loglik = np.zeros((m, 0))
    ctx = ScanContext(
        Z=Z, loglik=loglik, allowed=np.ones((m, M), dtype=bool), p_detect=np.full(M, p_D),
        birth_loglik=np.zeros((m, 0)), p_detect_birth=p_D, clutter_rate=clutter_rate,
        clutter_volume=side * side,
    )
    problem = make_weight_model(weights).problem(ctx, np.arange(M))
    return SyntheticProblem(problem, origin, ctx)


def _ambiguous_problem(n_objects, rng, *, weights, p_D, clutter_rate, sigma, spacing, sigma_spread):
    M = check_int(n_objects, "n_objects", minimum=0)
    p_D = check_probability(p_D, "p_D", low_open=True, high_open=True)
    clutter_rate = max(1.0, (1.0 - p_D) * M) if clutter_rate is None else check_positive(clutter_rate, "clutter_rate")
    sigma = check_positive(sigma, "sigma")
    spacing = check_positive(spacing, "spacing")
    z_pred, scale, side = _objects(M, rng, sigma, spacing, sigma_spread)
    detected = np.flatnonzero(rng.random(M) < p_D)
    n_clutter = int(rng.poisson(clutter_rate))
    return _build(M, z_pred, scale, side, detected, n_clutter, rng, weights, p_D, clutter_rate)


def truth_rank(events, log_weights, truth) -> int | None:
    """1-based rank of ``truth`` among generated children by weight (``None`` if not generated).

    Ties are ranked optimistically for none: a child with exactly the truth's weight that comes
    first in ``events`` counts as better.
    """
    events = np.asarray(events)
    hit = np.flatnonzero(np.all(events == np.asarray(truth)[None, :], axis=1))
    if not len(hit):
        return None
    lw = np.asarray(log_weights)
    t = hit[0]
    return int(np.sum(lw > lw[t]) + np.sum((lw == lw[t])[:t]) + 1)

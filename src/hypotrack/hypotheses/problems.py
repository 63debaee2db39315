"""Synthetic association problems with a known true association (seed 000 Fig. 15).

Seed 000 Sec. V-B times the generation of the children of one parent as the number of possible
associations ``A(M, m)`` grows. :func:`synthetic_problem` draws such a parent: ``M`` objects with
Gaussian predicted measurements spread over a square, a true association (which objects were
detected, which returns are clutter), the ``m`` returns it produced, shuffled, and the
association problem of the chosen weight model built by the engine itself
(:meth:`WeightModel.problem` on a :class:`ScanContext`), so that the benchmark times exactly
what the filter runs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int, check_positive, check_probability
from .association_problem import CLUTTER, AssociationProblem
from .scan_context import ScanContext
from .weights import make_weight_model

__all__ = ["SyntheticProblem", "synthetic_problem", "truth_rank"]


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


def synthetic_problem(n_objects, n_returns, rng, *, weights="hfisst", p_D=0.95, clutter_rate=1.0,
                      sigma=1.0, spacing=8.0, sigma_spread=0.25) -> SyntheticProblem:
    """Draw an ``M``-object, ``m``-return association problem from a known truth.

    Objects sit on a jittered square grid with ``spacing`` (in units of ``sigma``) between
    neighbours; object ``j``'s innovation covariance is ``S_j = (sigma s_j)² I₂`` with
    ``log s_j ~ N(0, sigma_spread²)``. ``min(M, m)`` randomly chosen objects are detected (a
    return drawn from ``N(ẑ_j, S_j)``); the other returns are clutter, uniform over the square
    (whose area is the clutter volume ``V``). Returns are shuffled.

    Parameters
    ----------
    n_objects, n_returns : int
        ``M`` and ``m``.
    rng : numpy.random.Generator
    weights : {"hfisst", "fisst_poisson", "reid"}
        Weight model of the problem (R-FISST uses ``"hfisst"``, HOMHT ``"reid"``).
    p_D : float
        Detection probability in (0, 1).
    clutter_rate : float
        Expected clutter returns per scan ``λV`` (> 0), used by the Poisson-clutter models.
    """
    M = check_int(n_objects, "n_objects", minimum=0)
    m = check_int(n_returns, "n_returns", minimum=0)
    p_D = check_probability(p_D, "p_D", low_open=True, high_open=True)
    clutter_rate = check_positive(clutter_rate, "clutter_rate")
    sigma = check_positive(sigma, "sigma")
    spacing = check_positive(spacing, "spacing")
    side_n = max(1, int(np.ceil(np.sqrt(max(M, 1)))))
    side = side_n * spacing * sigma
    cells = rng.permutation(side_n * side_n)[:M]
    centres = (np.stack([cells % side_n, cells // side_n], axis=1) + 0.5) * spacing * sigma
    z_pred = centres + rng.uniform(-0.25, 0.25, size=(M, 2)) * spacing * sigma
    scale = sigma * np.exp(sigma_spread * rng.standard_normal(M))
    n_det = min(M, m)
    detected = rng.permutation(M)[:n_det]
    Z = np.vstack([
        z_pred[detected] + scale[detected, None] * rng.standard_normal((n_det, 2)),
        rng.uniform(0.0, side, size=(m - n_det, 2)),
    ]).reshape(m, 2)
    origin = np.concatenate([detected, np.full(m - n_det, CLUTTER)]).astype(np.int64)
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

"""Reid's births seeded at a return: one Gaussian, or one option per component of a Gaussian mixture.

Reid (1979; document 001 Eq. 35) gives every return the row option "a new target seeded at this return",
factor ``λ_B`` (new targets per unit measurement volume per scan), the newborn's track started from the
return by a birth density ``p_B(x | z)`` (``birth_density.initial_state(z, R)``: one Gaussian).

A **mixture** birth density (``birth_density.components(z) -> (w (K,), means (K, d), covs (K, d, d))``,
``Σ_c w_c = 1``; e.g. the admissible region of a radar return, DeMars & Jah, *JGCD* 36(5), 2013:
:class:`hypotrack.scenarios.catalogue.admissible.SeededAdmissibleBirth`) makes the seeded option of return
``i`` one option per component, ``t = 1 + c`` (event code ``a_i = −1 − t = −2 − c``, the
:mod:`.association_problem` convention), with factor ``λ_B w_c``. Why this is Reid's Eq. 35 unchanged:

* the child "new target at ``z_i``" of Reid's tree has weight ``Π(rest) · λ_B`` and the newborn's density
  ``p_B(x | z_i) = Σ_c w_c N(x; m_c, P_c)``; splitting it into the children "new target at ``z_i`` in
  component ``c``" of weights ``Π(rest) · λ_B w_c`` and tracks ``N(m_c, P_c)`` — the Gaussian-mixture
  form of a hypothesis whose track is a mixture, one hypothesis per term — keeps their sum equal to
  Reid's child's weight and their mixture equal to its track: the marginal posterior over the
  targets is the same;
* ``w_c`` is already the posterior weight of the component given ``z_i``: the mixture is the density of
  the unmeasured angle rates over the admissible region (uniform: ``w_c`` ∝ area) and ``z_i`` measures
  none of them, so the return's likelihood is the same under every component (its predictive
  ``N(z_i; h(m_c), H_c P_c H_cᵀ + R)`` is ``N(0; 0, 2R)`` for every ``c``: ``h`` maps every component's
  mean back to ``z_i`` and its covariance to ``R``; the tests check it) and cancels into ``λ_B`` exactly
  as Reid's one-Gaussian option carries no likelihood factor either;
* a return no admissible state can give (``K = 0``: e.g. a clutter range-rate above escape speed) has
  no seeded option — ``p_B(· | z_i)`` has no mass — and can only be clutter or a known target's.

The component children of one return are alternatives of the same newborn object (one event holds
at most one option per return); the factored engine keeps them in one object
(:meth:`hypotrack.hypotheses.factored.planner.ObjectIds.register_births`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["is_mixture", "mixture_table", "mixture_weights", "prime_scan", "seeded_moments", "seeded_option_scores",
           "seeded_state"]


def is_mixture(density) -> bool:
    """Whether ``density`` is a mixture birth density (has ``components(z)``)."""
    return hasattr(density, "components")


def mixture_weights(density, z):
    """``(w (K,), means (K, d))`` of a mixture density's components at return ``z``: its ``component_weights(z)``
    when it has one (the mixture without the covariances: e.g.
    :meth:`hypotrack.scenarios.catalogue.admissible.SeededAdmissibleBirth.component_weights`, whose covariances
    are mapped only for the births a kept child holds), else the first two of ``components(z)``."""
    if hasattr(density, "component_weights"):
        return density.component_weights(z)
    return density.components(z)[:2]


def mixture_table(density, Z):
    """:func:`mixture_weights` of every return ``Z`` ``(n, p)``: ``(K (n,) int64, w (ΣK,), means (ΣK, d))``, return 0's
    components first; the density's ``component_table(Z)`` when it has one (one call for a scan's returns)."""
    if hasattr(density, "component_table"):
        return density.component_table(Z)
    parts = [mixture_weights(density, z) for z in Z]
    K = np.array([len(p[0]) for p in parts], dtype=np.int64)
    if not parts:
        return K, np.zeros(0), None
    return K, np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def prime_scan(weights, Z) -> None:
    """Before a scan's steps: let a mixture birth density with ``prime(Z)`` compute the mixtures of all the
    scan's returns ``Z`` at once (e.g. :meth:`hypotrack.scenarios.catalogue.admissible.SeededAdmissibleBirth.prime`,
    one vectorised pass in place of one per return, the factored engine's steps each asking for the returns
    of their gate). Nothing for weights without seeded births or a density without ``prime``."""
    density = getattr(weights, "birth_density", None)
    if getattr(weights, "seeded_births", False) and hasattr(density, "prime") and len(Z):
        density.prime(Z)


def seeded_option_scores(density, Z, log_intensity: float) -> np.ndarray:
    """Scores ``(m, T_s)`` of the seeded options of returns ``Z`` (m, p): ``log λ_B`` in one column for a
    one-Gaussian density; ``log λ_B + log w_c(z_i)`` in column ``c`` for a mixture (``−inf`` past a return's
    own ``K_i`` components; ``T_s = max_i K_i``, 0 when no return has an admissible component)."""
    Z = np.asarray(Z, dtype=float)
    if not is_mixture(density):
        return np.full((len(Z), 1), float(log_intensity))
    weights = [np.asarray(mixture_weights(density, z)[0], dtype=float) for z in Z]
    out = np.full((len(Z), max((len(w) for w in weights), default=0)), -np.inf)
    for i, w in enumerate(weights):
        with np.errstate(divide="ignore"):
            out[i, :len(w)] = float(log_intensity) + np.log(w)
    return out


def seeded_state(density, z, R, c: int = 0):
    """``(mean, cov)`` of the track seeded at return ``z`` in component ``c`` (``c = 0`` for a one-Gaussian
    density's ``initial_state(z, R)``)."""
    if not is_mixture(density):
        if c != 0:
            raise ValueError(f"a one-Gaussian birth density has one seeded option (component 0), got component {c}")
        return density.initial_state(z, R)
    w, means, covs = density.components(np.asarray(z, dtype=float))
    if not 0 <= c < len(w):
        raise ValueError(f"component must lie in [0, {len(w) - 1}] for this return, got {c}")
    return means[c].copy(), covs[c].copy()


def seeded_moments(density, Z, R, returns, comps, ndim: int, covariances: bool = True):
    """``(means (n, d), covs (n, d, d) or None)`` of the tracks seeded at returns ``Z[returns]`` in components
    ``comps`` (:func:`seeded_state` pair by pair, the same numbers): a mixture's components asked once per distinct
    return (an engine step's children hold several components of the same return), and without ``covariances``
    only its weights and means (:func:`mixture_weights`: the validity test reads the means alone, and a density
    with ``component_weights`` then maps no covariance)."""
    returns, comps = np.asarray(returns, dtype=np.int64), np.asarray(comps, dtype=np.int64)
    means = np.zeros((len(returns), ndim))
    covs = np.zeros((len(returns), ndim, ndim)) if covariances else None
    if not is_mixture(density):
        for q, (r, c) in enumerate(zip(returns.tolist(), comps.tolist())):
            m, P = seeded_state(density, Z[r], R, c)
            means[q] = m
            if covariances:
                covs[q] = P
        return means, covs
    for r in np.unique(returns).tolist():
        rows = np.flatnonzero(returns == r)
        z = np.asarray(Z[r], dtype=float)
        parts = density.components(z) if covariances else mixture_weights(density, z)
        c = comps[rows]
        bad = (c < 0) | (c >= len(parts[0]))
        if bad.any():
            raise ValueError(f"component must lie in [0, {len(parts[0]) - 1}] for this return, got {int(c[bad][0])}")
        means[rows] = parts[1][c]
        if covariances:
            covs[rows] = parts[2][c]
    return means, covs

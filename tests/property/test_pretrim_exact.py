"""Pre-trimming is exact: the children a step keeps are the top ``H∞`` of the full expansion.

``HypothesisFilter`` asks its generator for only the best ``H∞`` association children of a
parent when no twin (undetected birth, death) can outweigh its association child. A death twin
drops the dead object's ``(1 − p_D)`` factor, so with a large ``p_D`` it can outweigh its child
even when the population ratio ``β / P(no event)`` is < 1; these random scenes (β up to 0.5,
``p_D`` up to 0.999, both population models, objects in and out of view, ``H∞`` of 1–4)
check the kept set against the exact top ``H∞`` of :meth:`HypothesisFilter.expand`.
"""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from hypotrack.hypotheses import BinomialPopulation, hfisst
from hypotrack.hypotheses.population_events import SingleEventPopulation
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

VIEW = Box([-10.0, -10.0], [10.0, 10.0])
HALVES = [Box([-10.0, -10.0], [0.0, 10.0]), Box([0.0, -10.0], [10.0, 10.0])]
MOTION = ConstantVelocity(0.01)


def _population(kind, alpha, beta, n_regions):
    densities = [UniformBirthDensity(h, np.eye(2)) for h in HALVES[:n_regions]]
    if kind == "single":
        return SingleEventPopulation(SingleEventBirthDeath(alpha, beta, n_regions), birth_densities=densities)
    return BinomialPopulation(densities, alpha=alpha, p_survive=1.0 - beta)


@st.composite
def scenes(draw):
    """Discrete shape from the strategy; continuous parameters from a seeded generator, log-uniform
    where the failure lives (``1 − p_D`` from 0.001 to 0.95, β from 0.003 to 0.5)."""
    kind = draw(st.sampled_from(["single", "binomial"]))
    n_regions = draw(st.integers(1, 2))
    n_obj = draw(st.sampled_from([2, 3, 1, 0]))
    m = draw(st.sampled_from([2, 3, 1, 0]))
    H = draw(st.sampled_from([2, 3, 4, 1]))
    out_of_view = draw(st.lists(st.sampled_from([False, False, True]), min_size=n_obj, max_size=n_obj))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    p_D = 1.0 - 10.0 ** rng.uniform(-3.0, -0.02)
    beta = 10.0 ** rng.uniform(-2.5, np.log10(0.5))
    alpha = 10.0 ** rng.uniform(-3.0, -0.7)
    if kind == "single":
        assume(n_regions * alpha + n_obj * beta < 0.99)
    X = np.zeros((n_obj, 4))
    X[:, :2] = rng.uniform(-5.0, 5.0, size=(n_obj, 2))  # close enough for ambiguous associations
    X[out_of_view, 0] = rng.uniform(11.0, 14.0, size=sum(out_of_view))
    Z = rng.uniform(-10.0, 10.0, size=(m, 2))
    k = min(m, n_obj)
    Z[:k] = X[:k, :2] + rng.normal(size=(k, 2))
    return kind, p_D, alpha, beta, n_regions, X, Z, H, rng.uniform(0.1, 2.0), rng.uniform(0.5, 4.0)


def _keys(children, idx):
    return {(int(children.parent[i]), int(children.kind[i]), int(children.arg[i]), children.events[i].tobytes())
            for i in idx}


@settings(max_examples=120, deadline=None)
@given(scenes())
def test_kept_children_are_exact_top_h(scene):
    kind, p_D, alpha, beta, n_regions, X, Z, H, rate, spread = scene
    sensor = position_sensor(0.5, p_D, VIEW, rate)
    f = hfisst(MOTION, sensor, population=_population(kind, alpha, beta, n_regions), max_hypotheses=H,
               means=X, covs=spread * np.repeat(np.eye(4)[None], len(X), axis=0))
    full = f.expand(Z)
    lw = full.log_weights[np.isfinite(full.log_weights)]
    f.step(Z)
    kept = f.last_kept
    order = np.argsort(-full.log_weights, kind="stable")
    exact = np.sort(full.log_weights[order[:H]])[::-1]
    np.testing.assert_allclose(np.sort(kept.log_weights)[::-1], exact, rtol=0, atol=1e-9)
    if len(lw) > H and full.log_weights[order[H - 1]] - full.log_weights[order[H]] > 1e-9:
        # no tie at the boundary: the kept set itself is determined
        kept_keys = {(int(p), int(k), int(a), e.tobytes())
                     for p, k, a, e in zip(kept.parent, kept.kind, kept.arg, kept.events)}
        assert kept_keys == _keys(full, order[:H])


def test_death_twin_of_a_trimmed_child_is_kept():
    """Shrunk counterexample of the old pre-trim rule (population ratio ≤ 0): one object in
    view, two returns, β = 0.39, α = 0.002, p_D = 0.97, H∞ = 2.

    Association children by weight: "object takes return 0" (best), "object takes 0, return 1
    is a birth" (2nd), "all clutter" (3rd). The death twin of the 3rd weighs
    ``w₃ · β / (1 − α − β) / (1 − p_D) = w₃ · 0.6414 / 0.03`` ≈ 21 w₃ > w₂, so it is the exact
    2nd child; trimming to the best two association children first loses it.
    """
    sensor = position_sensor(0.5, 0.97, VIEW, 1.0)
    f = hfisst(MOTION, sensor, population=_population("single", 0.002, 0.39, 1), max_hypotheses=2,
               means=np.array([[4.5, -1.9, 0.0, 0.0]]), covs=1.65 * np.eye(4)[None])
    Z = np.array([[4.8, -1.85], [-1.8, 1.0]])
    full = f.expand(Z)
    assoc = full.kind == 0
    w = {tuple(e): lw for e, lw in zip(full.events[assoc].tolist(), full.log_weights[assoc])}
    death = full.log_weights[(full.kind == 2) & np.all(full.events == -1, axis=1)][0]
    assert death == pytest.approx(w[(-1, -1)] + np.log(0.39 / (1 - 0.002 - 0.39)) - np.log(0.03), abs=1e-12)
    assert w[(0, -1)] > death > w[(0, 1)] > w[(-1, -1)]
    f.step(Z)
    assert f.last_kept.kind.tolist() == [0, 2]
    np.testing.assert_array_equal(f.last_kept.events, [[0, -1], [-1, -1]])
    np.testing.assert_allclose(f.last_kept.log_weights, [w[(0, -1)], death], rtol=0, atol=1e-12)

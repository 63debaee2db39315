"""A lone birth term with its one return, *born detected*: the closed form of its engine step (``fast_path``).

With an adaptive birth nearly every return no track explains becomes a birth term of the next scan, and
the term's component is then often that term and its return alone (no group, no singleton, no other
return). The general step of such a component (:meth:`~..filter.HypothesisFilter.advance` on the labeled
multi-Bernoulli population with δ-GLMB weights, Vo, Vo & Hoang 2017, Eq. 12) has three children, whose
log-weights relative to each other are (the return clutter in the last two; the constants common to the
three cancel; :meth:`~..weights_glmb.GLMBWeights.labeled_problem`)

=======================  ==============================================
born, detected           ``log r_B + log p_D + ℓ_B(z) − log κ``
born, undetected         ``log r_B + log(1 − p_D)``
not born                 ``log(1 − r_B)``
=======================  ==============================================

(``ℓ_B(z)``: the return's birth log-likelihood, ``p_D`` the engine's birth detection probability, ``κ``
the clutter intensity). When each of the last two lies below ``min_weight`` (by the relative margin of
:mod:`.fast_path`) even when normalised against the detected child alone (so against any set of children a
search finds that holds the detected one) and the detected child's track passes the engine's validity
test, the step followed by the factored filter's pruning keeps the detected child alone: one track, the
term's first update with the return (:meth:`~..population_events._Population.birth_track`), weight 1 — a
singleton of the lane (``r = 1``). Its label is the first the step uses: the kept children are ranked
heaviest first (:func:`~..generators.top_k`), so the detected child's pair comes first. The step also
uses a label for the born-undetected child whenever it keeps it before the pruning — it holds the term's
prior, which the search always finds here: the Gibbs chain starts from it (row option 0, "exists,
missed"), the exhaustive generator makes every child, Murty's with ``k ≥ 3`` the three best — unless its
prior fails the validity test; the "not born" child holds no track and uses none. So the labels the step
uses are ``1 + [prior valid]`` whichever children a sampler found, and the rule is taken only with those
generators, a cap keeping at least three children by weight (``cap = "top"``: a sampled cap ranks by
perturbed keys) and with the lane's singletons (the silent or Bernoulli lane, where a singleton keeps only
its moments and label).

For the other components the general step's children depend on what a sampler finds (a light detected or
"not born" child found or not changes the labels used); those keep the general path. The first component
taken is also stepped by the engine, and the rule is used only when that step agrees with it
(:func:`check_template`), as :func:`~.fast_path.born_template` does for lone birth terms without a return.
"""

from __future__ import annotations

import numpy as np

from ..filter import HypothesisFilter
from ..generators import ExhaustiveGenerator, MurtyGenerator
from ..gibbs import GibbsGenerator
from ..population_lmb import LabeledMultiBernoulliPopulation
from ..state import FilterState
from ..tracks import TrackStore
from ..weights_glmb import GLMBWeights
from .fast_path import born_state
from .planner import prune
from .pool import engine_step
from .seeded_birth import lone_seeded_step

__all__ = ["born_detected_applies", "takes_born_detected", "born_detected_moments", "check_template",
           "born_detected_state", "born_detected_plan", "birth_step"]


def born_detected_applies(engine, rule, mode: str) -> bool:
    """Whether the engine's step of a lone birth term with its return has the children of the module
    docstring, found as it says: the plain engine with the labeled multi-Bernoulli population and δ-GLMB
    weights, Gibbs, exhaustive or Murty (``k ≥ 3``) children, ``H∞ ≥ 3`` kept by weight, the fast path's
    ``rule`` (``None``: off) and a lane ``mode`` ``"silent"`` or ``"bernoulli"``."""
    if rule is None or mode not in ("silent", "bernoulli") or type(engine) is not HypothesisFilter:
        return False
    gen = engine.generator
    return (type(engine.population) is LabeledMultiBernoulliPopulation and type(engine.weights) is GLMBWeights
            and (type(gen) in (GibbsGenerator, ExhaustiveGenerator) or (type(gen) is MurtyGenerator and gen.k >= 3))
            and engine.max_hypotheses >= 3 and engine.cap != "sample")


def takes_born_detected(rule, r_b: float, loglik: float) -> bool:
    """Whether the detected child outweighs each alternative so that, normalised against it alone, the
    alternative lies below ``min_weight`` by the margin (``rule.log_threshold``; module docstring's table,
    ``rule.det_offset`` = ``log κ`` for δ-GLMB weights, ``rule.p_detect_birth`` = ``p_D``)."""
    p = rule.p_detect_birth
    if not (0.0 < r_b < 1.0 and 0.0 < p < 1.0 and np.isfinite(loglik)):
        return False
    det = np.log(r_b) + np.log(p) + loglik - rule.det_offset
    alts = np.array([np.log(r_b) + np.log1p(-p), np.log1p(-r_b)])
    return bool(np.all(alts - np.logaddexp(det, alts) < rule.log_threshold))


def born_detected_moments(population, b: int, z, R):
    """``(mean, cov)`` of term ``b`` updated with return ``z`` and ``(mean, cov)`` of its prior (undetected):
    the pairs the engine's step materialises (:meth:`~..filter.HypothesisFilter.pair_moments`)."""
    return population.birth_track(b, z, R), population.birth_track(b, None, R)


def born_detected_state(mean, cov, label: int, key) -> FilterState:
    """The pruned result: one hypothesis (log-weight 0) holding the born-detected track under ``label``."""
    d = len(mean)
    store = TrackStore(np.asarray(mean, dtype=float).reshape(1, d).copy(), np.asarray(cov, dtype=float).reshape(1, d, d).copy(),
                       np.array([label], dtype=np.int64))
    return FilterState(store, np.zeros(1), [np.zeros(1, dtype=np.int64)], [key])


def check_template(result, min_weight: float, mean, cov, n_new: int):
    """The key of the kept hypothesis, from the engine's step ``(state, sources, n_new, stats)`` of a component
    the rule takes (labels from 0), when that step agrees with the rule: after the pruning one hypothesis of one
    track, label 0, the term's first update (bit for bit), and ``n_new`` labels used; else ``None``."""
    new, sources, used, _ = result
    kept = prune(new, min_weight)
    if kept is None or used != n_new or len(kept.log_w) != 1 or len(kept.store) != 1 or kept.log_w[0] != 0.0:
        return None
    if not (kept.store.labels[0] == 0 and np.array_equal(kept.store.means[0], mean)
            and np.array_equal(kept.store.covs[0], cov) and [-1, 0] in sources.tolist()):
        return None
    return kept.keys[0]


def born_detected_plan(engine, rule, min_weight: float, b: int, row: int, Z, birth_ll, templates: dict, general):
    """The plan ``("born_detected", mean, cov, n_new, key)`` of the component of birth term ``b`` and return
    ``row`` alone when the rule takes it (:func:`takes_born_detected`, the detected track valid), else ``None``.
    ``templates`` holds the kept hypothesis's key once the engine's step of a first such component (its plan
    ``general()``, :func:`~.planner.touched_plan`; labels from 0, seed 0) agreed (:func:`check_template`; ``None`` there: never taken)."""
    if not takes_born_detected(rule, float(engine.population.r_birth[b]), float(birth_ll[row, b])):
        return None
    (mean, cov), (prior, _) = born_detected_moments(engine.population, b, Z[row], engine.R)
    n_new = 2
    if engine.validity is not None:  # one call, row by row: the detected track and the prior
        ok = np.asarray(engine.validity(np.stack([mean, prior])), dtype=bool)
        if not ok[0]:
            return None
        n_new = 1 + int(ok[1])
    if "key" not in templates:
        templates["key"] = check_template(engine_step(engine, *general()[1:], 0, 0), min_weight, mean, cov, n_new)
    if templates["key"] is None:
        return None
    return ("born_detected", mean, cov, n_new, templates["key"])


def birth_step(plan, engine, label: int, objects, stats, ndim: int):
    """``(state, parts, labels used)`` of a closed-form birth plan: a lone birth term's ``("born", b, template)``
    (:func:`~.fast_path.born_state`), ``("born_detected", …)`` (:func:`born_detected_plan`) or a lone return's
    ``("seeded", …)`` (:func:`~.seeded_birth.lone_seeded_step`), its newborn
    registered as one object (:meth:`~.planner.ObjectIds.register_births`) and counted as the step's ``n_touched``."""
    if plan[0] == "seeded":  # a return in no gate, HOMHT's seeded birth (:mod:`.seeded_birth`)
        return lone_seeded_step(plan, engine, label, objects, stats, ndim)
    stats["n_touched"] += 1
    if plan[0] == "born":
        _, b, template = plan
        new = born_state(template, engine.population, b, engine.R, label, ndim)
        st, used = template[-1], 1
        stats["n_duplicates_merged"] += st["n_duplicates_merged"]
        stats["mass_retained_min"] = min(stats["mass_retained_min"], st["mass_retained"])
    else:
        _, mean, cov, used, key = plan
        new = born_detected_state(mean, cov, label, key)
        stats["n_fast_born_detected"] += 1
    objects.register_births(new.store, np.array([[-1, -1 if plan[0] == "born" else 0]], dtype=np.int64), 1)
    return new, np.zeros(1, dtype=np.int64), used

"""The fast path: undisturbed singletons stepped in one batch (``fast_path``; package docstring).

At catalogue scale nearly every component a scan touches is one singleton of the lane (one object,
one hypothesis, one track) with one return in its gate that no other group, singleton or birth term
gates. The engine's step of such a component (:meth:`~..filter.HypothesisFilter.advance`) makes the
children "detected with the return" and the alternatives "missed, the return clutter" (and, with
Reid's births seeded at the returns, "missed, the return a new object"), caps them at ``H∞`` and
the factored filter then drops the hypotheses below ``min_weight``. Their log-weights relative to
each other are closed forms in the return's log-likelihood ``ℓ`` and the track's ``p_D``:

=======================  ==================================  =========================================
weight model             detected                            alternatives (each ``+ log(1 − p_D)``)
=======================  ==================================  =========================================
δ-GLMB (``p_S = 1``)     ``log p_D + ℓ − log κ``             missed: ``0``
Reid (HOMHT)             ``log p_D + ℓ``                     clutter ``log λ_C``; seeded birth ``log λ_B``
H-FISST / R-FISST        ``log p_D + ℓ`` (count term 0)      clutter ``−log V``
FISST, Poisson clutter   ``log p_D + ℓ``                     clutter ``log(λV) − log V``
=======================  ==================================  =========================================

(the parent's weight, the population's no-event probability — 1 for a silent population with no
birth term in the component — and the constants common to all children cancel). When every
alternative's normalised weight lies below ``min_weight`` (by a relative margin of ``1e-9``, so
that rounding cannot decide), the general path keeps exactly one hypothesis: the track's Joseph
update with the return, weight 1 — a singleton again. The fast path computes the decision for all
candidates at once, updates the ones it takes in one batch (:func:`~...gaussian.update_unchecked`)
and puts them back into the lane where the general path would (the plan order); a seeded birth
child, kept by the cap and then pruned, still uses a label (:attr:`FastRule.n_new`), as there.
Everything else — several returns, a birth term or another group in the gate, an alternative
heavy enough to be kept — takes the general path.

Two more kinds of component keep no object after the general step, and the fast path drops them:

* returns no group or birth term gates (without seeded births): clutter in every child;
* a birth term no return reaches (*lone birth term*), whose children are "not born" (``1 − r_B``)
  and "born undetected" (``r_B (1 − p_D)``; the binomial population's ``α`` for ``r_B``): when the
  second's normalised weight is below ``min_weight`` the first, with no object, is all that is
  kept. The born-undetected child, kept by the cap and then pruned, used a label, as above.

With the engine's ``validity`` test (:mod:`..validity`) a child holding a track that fails it has
weight 0 and is not kept (its label not used): the fast path tests the tracks of every child as the
general step does — the detected child's update (it must pass, else the general path takes the
component), the predicted track of the missed and clutter children, a seeded birth's track, a birth
term's undetected prior — and normalises over the valid children only.

The rule holds for the engine itself (not a subclass that overrides its extension points), the four
weight models above with a silent population (no population, or labeled multi-Bernoulli / binomial
with ``p_S = 1``: the lane's condition; or the lane's Bernoulli singletons, whose "not" child, weight
``1 − r p_S`` against the others' ``r p_S``, is one more alternative per clutter or seeded-birth one), a cap that
keeps every child (``H∞`` ≥ the number of children) and a generator that finds the detected child: exhaustive, Murty, Gibbs, MCMC — for the
two samplers with certainty only up to the chance that they never leave the alternative
(``< min_weight^n_sweeps``). With seeded births the generator must make all three children
(exhaustive, or Murty with ``k ≥ 3``), since the birth child's label counts; a mixture birth density (one
seeded child per component, :mod:`..seeded`) has its own closed form, :mod:`.fast_mixture`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...gaussian import update_unchecked
from ..filter import HypothesisFilter
from ..generators import ExhaustiveGenerator, MCMCGenerator, MurtyGenerator
from ..gibbs import GibbsGenerator
from ..population_events import BinomialPopulation
from ..population_lmb import LabeledMultiBernoulliPopulation
from ..seeded import is_mixture
from ..state import FilterState
from ..tracks import TrackStore
from ..weights import FISSTPoissonWeights, HFISSTWeights, ReidWeights
from ..weights_glmb import GLMBWeights
from .fast_mixture import mixture_takes

__all__ = ["FastRule", "FastBatch", "fast_rule", "fast_components", "lone_update", "born_template", "born_state"]

#: relative margin of ``min_weight`` an alternative must stay under (rounding never decides)
MARGIN = 1e-9


@dataclass(frozen=True)
class FastRule:
    """The closed form of a lone track's children: detected ``log p_D + ℓ − det_offset``, each
    alternative ``log(1 − p_D) + alt_offsets[k]``; ``n_new`` labels each such step uses (a seeded
    birth child); alternatives below ``log_threshold`` (normalised) are dropped."""

    det_offset: float
    alt_offsets: np.ndarray
    n_new: int
    log_threshold: float
    p_detect_birth: float
    validity: object = None
    seeded_density: object = None
    bernoulli_children: bool = True  #: the cap keeps every child of a Bernoulli singleton's two hypotheses
    max_hypotheses: int = 0  #: ``H∞`` (a mixture's children: :mod:`.fast_mixture`)
    seeded_children: float = np.inf  #: association children the generator makes per parent (a mixture's)

    def takes_births(self, r_birth, valid=None) -> np.ndarray:
        """Whether each lone birth term (its existence ``r_B``; whether its born-undetected track is
        ``valid``) keeps only its "not born" child."""
        r = np.clip(r_birth, 1e-300, 1 - 1e-16)
        born = np.log(r) + np.log1p(-self.p_detect_birth)
        light = born - np.logaddexp(born, np.log1p(-r)) < self.log_threshold
        return (r_birth > 0) & (r_birth < 1) & (light if valid is None else light | ~valid)

    def keeps_born(self, r_birth) -> bool:
        """Whether a lone birth term (existence ``r_B``) keeps both its children, "not born" and "born
        undetected", after the pruning (the second's normalised weight above ``min_weight`` by the
        margin): the result of its step is then the same two hypotheses for every term of that
        ``r_B``, only the born track's moments (the term's prior) and label differ. Only with no
        validity test (the prior might fail it)."""
        r = float(r_birth)
        if self.validity is not None or not 0.0 < r < 1.0:
            return False
        born = np.log(r) + np.log1p(-self.p_detect_birth)
        return bool(born - np.logaddexp(born, np.log1p(-r)) > self.log_threshold - 2 * np.log1p(-MARGIN))

    def takes(self, loglik, p_detect, valid=None, extra=None, extra_valid=None) -> np.ndarray:
        """Whether each lone track (its return's log-likelihood, its ``p_D``) keeps only its detected
        child; ``valid`` (n, alternatives): whether each alternative child passes the validity test
        (an invalid one is not kept, nor counted in the normalisation); ``extra`` (n,): the log-weight of one
        more alternative per track, relative to the others' base (a Bernoulli singleton's "not" child,
        ``log(1 − r p_S) − log(r p_S)``: the δ-GLMB row's children all carry ``r p_S`` but this one; it holds
        no track, so it is always valid), the return's clutter factor added (``alt_offsets``, without the
        ``1 − p_D`` of a missed track: 0 for δ-GLMB, ``−log V`` for H-FISST, ``log λ_C`` for Reid); with Reid's
        seeded births also "died"/"not" with the return a new object (``log λ_B``), whose newborn is the missed
        child's — one (source, return) pair, one label (:meth:`~..filter.HypothesisFilter.advance`).
        ``extra_valid`` (n, alternatives): whether each of these "died"/"not" children passes the test — its own
        tracks only: none with clutter, the newborn alone with the seeded birth, so not the missed child's verdict,
        which also needs the predicted track (``None``: all valid)."""
        ok = (p_detect > 0) & (p_detect < 1) & np.isfinite(loglik)
        p = np.where(ok, p_detect, 0.5)
        det = np.log(p) + np.where(ok, loglik, 0.0) - self.det_offset
        alt = np.log1p(-p)[:, None] + self.alt_offsets[None, :]
        if valid is not None:
            alt = np.where(valid, alt, -np.inf)
        if extra is not None:
            ext = np.asarray(extra, dtype=float)[:, None] + self.alt_offsets[None, :]
            if extra_valid is not None:
                ext = np.where(extra_valid, ext, -np.inf)
            alt = np.concatenate([alt, ext], axis=1)
        total = np.logaddexp(det, np.logaddexp.reduce(alt, axis=1))
        return ok & np.all(alt - total[:, None] < self.log_threshold, axis=1)

    def quiet_group_dies(self, log_w, tracks, p_detect) -> bool:
        """Whether a quiet group (no return, no birth term; hypotheses ``log_w``, ``tracks``, each
        track's ``p_D``) keeps no object after its engine step on the empty scan and the pruning.

        Its only child of each hypothesis is "every object missed", weight ``w_h Π_{i∈h} (1 − p_D,i)``
        (a silent population: no event, no birth term). The hypotheses holding a track weigh
        ``W`` in all, normalised; when ``W < min_weight`` (by the margin) each of them, and each
        non-empty projection of a split part, lies below ``min_weight`` and the empty hypothesis
        (weight ``1 − W > 1/2``) is the heaviest, so pruning leaves no object. Only with no validity
        test (which would drop children before the normalisation)."""
        if self.validity is not None:
            return False
        log_miss = np.log1p(-np.asarray(p_detect, dtype=float))
        lw = np.asarray(log_w, dtype=float) + np.array([log_miss[t].sum() for t in tracks])
        held = np.array([len(t) > 0 for t in tracks], dtype=bool)
        if held.all() or not np.isfinite(lw[~held]).any():
            return False
        return bool(np.logaddexp.reduce(lw[held]) - np.logaddexp.reduce(lw) < self.log_threshold)


def fast_rule(engine, lane_on: bool, min_weight: float) -> FastRule | None:
    """The :class:`FastRule` of ``engine`` (package docstring, "The fast path"), or ``None`` where the
    fast path cannot reproduce the general one (then every component takes the general path)."""
    if not lane_on or min_weight <= 0 or type(engine) is not HypothesisFilter:
        return None
    pop, w, gen = engine.population, engine.weights, engine.generator
    if not (pop is None or type(pop) in (LabeledMultiBernoulliPopulation, BinomialPopulation)):
        return None
    if type(gen) not in (ExhaustiveGenerator, MurtyGenerator, GibbsGenerator, MCMCGenerator):
        return None
    clutter = engine.sensor.clutter
    rate, volume = float(clutter.rate), float(clutter.region.area)
    if not (rate > 0 and volume > 0):  # (the general path refuses a zero clutter intensity)
        return None
    kappa = rate / volume
    n_new, tw, seeded_children = 0, type(w), np.inf
    if tw is GLMBWeights:
        if type(pop) is not LabeledMultiBernoulliPopulation:
            return None
        k = kappa if w.clutter_intensity is None else w.clutter_intensity
        det, alt = float(np.log(k)), [0.0]
    elif type(pop) is LabeledMultiBernoulliPopulation:
        return None
    elif tw is ReidWeights:
        lam_c = kappa if w.clutter_intensity is None else w.clutter_intensity
        det, alt = 0.0, [float(np.log(lam_c))]
        if w.seeded_births:
            alt.append(float(np.log(w.birth_intensity)))
            n_new = 1
            if not (type(gen) is ExhaustiveGenerator or (type(gen) is MurtyGenerator and gen.k >= 3)):
                return None
            if is_mixture(w.birth_density):  # one child per component: how many each track's gets, :mod:`.fast_mixture`
                seeded_children = np.inf if type(gen) is ExhaustiveGenerator else min(gen.k, engine.max_hypotheses)
    elif tw is HFISSTWeights:
        det, alt = 0.0, [-float(np.log(volume))]
    elif tw is FISSTPoissonWeights:
        lam_v = rate if w.clutter_rate is None else w.clutter_rate
        det, alt = 0.0, [float(np.log(lam_v) - np.log(volume))]
    else:
        return None
    if not np.all(np.isfinite(alt)) or engine.max_hypotheses < 1 + len(alt):
        return None
    # a Bernoulli singleton's children: its track's 1 + len(alt) and "died" with each alternative, "not"'s len(alt)
    return FastRule(det, np.array(alt), n_new, float(np.log(min_weight) + np.log1p(-MARGIN)), float(engine.p_D),
                    engine.validity, w.birth_density if n_new else None, engine.max_hypotheses >= 1 + 3 * len(alt),
                    engine.max_hypotheses, seeded_children)


def birth_existence(population) -> np.ndarray | None:
    """``r_B`` of each birth term of ``population`` (the binomial population's ``α``), or ``None``
    where a lone birth term's children are not the two of :meth:`FastRule.takes_births`."""
    if type(population) is LabeledMultiBernoulliPopulation:
        return np.asarray(population.r_birth, dtype=float)
    if type(population) is BinomialPopulation and not population.poisson_limit:
        return np.full(population.n_birth_regions, float(population.alpha))
    return None


@dataclass(frozen=True, eq=False)
class FastBatch:
    """The components the fast path took, in plan order: ``comps`` (graph components) and ``keys``
    (their plan keys: the lone tracks' lane nodes, the lone birth terms' nodes, each ascending, then
    the lone returns'); the lone tracks' updated ``store`` (one track each, plan order) and its
    ``store_keys``; ``n_new``: the labels each component uses (a seeded birth child, a birth term's
    born-undetected child); ``n_births`` and ``n_clutter``: the lone birth terms and returns dropped."""

    comps: np.ndarray
    keys: np.ndarray
    store: TrackStore
    store_keys: np.ndarray
    n_new: np.ndarray
    n_births: int
    n_clutter: int

    def __len__(self) -> int:
        return len(self.keys)

    def labels_before(self, k) -> np.ndarray:
        """Labels used by the first ``k`` components (``k`` an int or an array)."""
        return np.concatenate([[0], np.cumsum(self.n_new)])[k]


def born_template(result):
    """The template :func:`born_state` reuses, from the engine step (``(state, sources, n_new, stats)``)
    of a lone birth term that kept both children: its weights, hypotheses' tracks and lineage, and the
    step's statistics; ``None`` when the step is not of that shape."""
    new, sources, n_new, st = result
    if n_new == 1 and len(new.log_w) == 2 and len(new.store) == 1 and np.array_equal(sources, [[-1, -1]]):
        return new.log_w, new.tracks, new.keys, st
    return None


def born_state(template, population, b: int, R, label: int, ndim: int) -> FilterState:
    """The step of lone birth term ``b`` (:meth:`FastRule.keeps_born`) from the template of a term of the
    same ``r_B`` (:func:`born_template`): the same two hypotheses ("not born", "born undetected"), whose
    weights depend on ``r_B`` and ``p_D`` alone, with the term's undetected prior as the born track (as
    :meth:`~..filter.HypothesisFilter.pair_moments` gives it) under ``label``."""
    log_w, tracks, keys, _ = template
    means, covs = np.zeros((1, ndim)), np.zeros((1, ndim, ndim))
    means[0], covs[0] = population.birth_track(b, None, R)
    store = TrackStore(means, covs, np.array([label], dtype=np.int64))
    return FilterState(store, log_w.copy(), [t.copy() for t in tracks], list(keys))


def lone_update(means, covs, Z, H, R):
    """The lone tracks' measurement update, ``(means, covs)``: one batched Kalman update in Joseph
    form (:func:`~...gaussian.update_unchecked`) of predicted tracks ``means``/``covs`` with their
    returns ``Z`` (row for row), or with ``H`` a measurement model, that model's own update (the radar's EKF
    in the sensor frame, :mod:`hypotrack.models.measurement`). The fast path's only linear algebra of the update."""
    if hasattr(H, "update"):
        return H.update(means, covs, Z)
    return update_unchecked(means, covs, Z, H, R)


def fast_components(rule: FastRule, graph, scores, pred: TrackStore, first_lane_col: int, Z, H, R,
                    seeded: bool, r_birth=None, population=None, lane_exist=None) -> FastBatch:
    """The components of ``graph`` the fast path takes and their results.

    A lone track is a component of one lane singleton (node ``G + j``, its track column
    ``first_lane_col + j`` of ``pred`` and ``scores``) with one return and nothing else;
    :meth:`FastRule.takes` decides. A lone return (a component of returns and no node: nothing gates
    them and, without ``seeded`` births, nothing can start there) is clutter in every child of its
    general step, which keeps no object: it is dropped. Its plan key is the graph's node count (after
    every node's), as in :meth:`~.planner.ScanGraph.components`. A lone birth term (node
    ``G + L + b``, alone, no return; ``r_birth``: each term's existence, ``None``: none taken) is
    dropped when :meth:`FastRule.takes_births` says so (``population``: its born-undetected tracks, for
    the validity test). ``lane_exist`` (per lane singleton, optional): its ``r p_S`` (Bernoulli singletons,
    :mod:`.lane`): its "not" child is one more alternative (:meth:`FastRule.takes`), and a taken track's
    result is the detected child alone, ``r = 1``.
    """
    G, L, n_comp = graph.G, graph.L, graph.n_comp
    n_nodes = np.bincount(graph.node_lab, minlength=n_comp)
    n_rets = np.bincount(graph.ret_lab, minlength=n_comp)
    lone = np.zeros(0, np.int64) if seeded else np.flatnonzero((n_nodes == 0) & (n_rets > 0))
    lane_comp = graph.node_lab[G:G + L]
    ret_of = np.full(n_comp, -1, np.int64)
    ret_of[graph.ret_lab] = np.arange(len(graph.ret_lab))
    j = np.flatnonzero((n_nodes[lane_comp] == 1) & (n_rets[lane_comp] == 1))
    rows = ret_of[lane_comp[j]]
    cols = first_lane_col + j
    Z = np.asarray(Z)
    loglik, p_detect = scores.at(rows, cols), scores.p_detect[cols]
    n_new = np.full(len(j), rule.n_new, np.int64)
    # with per-track survival only a track that surely survives (no "died" child: the lane's condition)
    sure = np.ones(len(cols), dtype=bool) if scores.p_survive is None or lane_exist is not None else \
        scores.p_survive[cols] == 1.0
    extra = None
    if lane_exist is not None:
        with np.errstate(divide="ignore"):
            rp = np.asarray(lane_exist, dtype=float)[j]
            extra = np.log1p(-rp) - np.log(rp)
        if not rule.bernoulli_children:  # the cap would drop children of r < 1: the general path
            sure = rp == 1.0
    if rule.seeded_density is not None and is_mixture(rule.seeded_density):  # (HOMHT's admissible-region births)
        x, P = lone_update(pred.means[cols], pred.covs[cols], Z[rows], H, R)
        take, n_new = mixture_takes(rule, loglik, p_detect, pred.means[cols], Z[rows], extra,
                                    None if rule.validity is None else _valid(rule.validity, x))
        take &= sure
        x, P = x[take], P[take]
    elif rule.validity is None:
        take = rule.takes(loglik, p_detect, extra=extra) & sure
        x, P = lone_update(pred.means[cols[take]], pred.covs[cols[take]], Z[rows[take]], H, R)
    else:  # every child's tracks tested, as the general step tests them
        x, P = lone_update(pred.means[cols], pred.covs[cols], Z[rows], H, R)
        v = _valid(rule.validity, np.concatenate([pred.means[cols], x]))  # one call, row by row: prior and update
        valid = np.repeat(v[:len(cols), None], len(rule.alt_offsets), axis=1)
        ext_valid = None if extra is None else np.ones_like(valid)  # "died"/"not" with clutter: no track
        if rule.n_new:  # the seeded birth children also hold the newborn track: "died"/"not" it alone
            born = np.array([rule.seeded_density.initial_state(z, R)[0] for z in Z[rows]])
            born = born.reshape(len(rows), pred.means.shape[1])  # (no rows: an empty (0, d), not -1)
            born_ok = _valid(rule.validity, born)
            valid[:, -1] &= born_ok
            died = np.zeros(len(cols), dtype=bool)
            if extra is not None:
                ext_valid[:, -1] = born_ok
                died = extra > -np.inf  # r p_S < 1: the "died"/"not" children exist
            # the newborn's label is used when a kept child holds it: the missed one (predicted track valid) or "died"
            n_new = (born_ok & (v[:len(cols)] | died)).astype(np.int64)
        take = v[len(cols):] & rule.takes(loglik, p_detect, valid, extra, ext_valid) & sure
        x, P = x[take], P[take]
    j, cols, n_new = j[take], cols[take], n_new[take]
    keys = (G + j).astype(np.int64)
    b, b_new = np.zeros(0, np.int64), np.zeros(0, np.int64)
    if r_birth is not None and graph.B:
        birth_comp = graph.node_lab[G + L:G + L + graph.B]
        b = np.flatnonzero((n_nodes[birth_comp] == 1) & (n_rets[birth_comp] == 0))
        valid = None
        if rule.validity is not None and len(b):
            prior = np.array([population.birth_track(int(t), None, R)[0] for t in b]).reshape(len(b), -1)
            valid = _valid(rule.validity, prior)
        take_b = rule.takes_births(np.asarray(r_birth, dtype=float)[b], valid)
        b_new = (np.ones(len(b), np.int64) if valid is None else valid.astype(np.int64))[take_b]
        b = b[take_b]
    comps = np.concatenate([lane_comp[j], graph.node_lab[G + L + b], lone]).astype(np.int64)
    return FastBatch(comps, np.concatenate([keys, G + L + b, np.full(len(lone), len(graph.node_lab))]).astype(np.int64),
                     TrackStore(x, P, pred.labels[cols]), keys,
                     np.concatenate([n_new, b_new, np.zeros(len(lone), np.int64)]).astype(np.int64), len(b), len(lone))


def _valid(validity, means) -> np.ndarray:
    """``validity(means)`` as a bool per row (no call for no rows)."""
    if len(means) == 0:
        return np.zeros(0, dtype=bool)
    ok = np.asarray(validity(means), dtype=bool)
    if ok.shape != (len(means),):
        raise ValueError(f"validity must return one bool per track, shape ({len(means)},), got {ok.shape}")
    return ok

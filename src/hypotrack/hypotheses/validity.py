"""Physics on every hypothesis: the cap keeps only children whose every track passes a validity test.

A hypothesis holding a track no real object can follow (for the catalogue: an unbound orbit, or a
perigee inside the atmosphere, :func:`hypotrack.models.plausibility.plausible_orbits`) has probability 0
under a model that knows the physics; the standard model gives it a positive weight only because its
motion model (two-body, J2) propagates such states as happily as real ones. The filter's ``validity``
option (:class:`~.filter.HypothesisFilter`) applies the test before the cap:

1. the children (after duplicate merging) are visited best key first — the key the cap ranks by
   (log-weight, or the Gumbel-perturbed log-weight of ``cap="sample"``);
2. each child's tracks are the ``(source, return)`` pairs of the next store (:func:`.child_pairs`); the
   means of the pairs not seen yet are computed (Kalman update, a birth term's first update or prior)
   and tested once each, in one call of ``validity(means) -> bool (n,)``;
3. a child with a failing track has weight 0 (it is skipped); the first ``H∞`` passing children are
   kept and normalised (:meth:`~.filter.HypothesisFilter.advance`), so the survivors' weights are
   renormalised over the valid children only.

Only the children visited are tested: about ``H∞`` plus the invalid ones among the best, not the
whole child set. Every one of the next ``H∞ − kept`` children is visited (each is kept or rejected), so their
new pairs are updated and tested in one batch (one call of each per round, not one per child: a round per
rejection streak, the same children and verdicts). If no child passes, the step takes the fallbacks of
:func:`advance_with_fallbacks`; if none is valid either, it raises (``RuntimeError``; the filter is left as it
was, :meth:`~.filter.HypothesisFilter.step`). Without the option nothing changes.
"""

from __future__ import annotations

import numpy as np

from .state import FilterState

__all__ = ["NoValidChild", "PairMemo", "advance_with_fallbacks", "valid_top_k"]


class NoValidChild(RuntimeError):
    """Every child of a step fails the validity test (:func:`advance_with_fallbacks` takes the fallbacks)."""


def advance_with_fallbacks(advance, state, pred, validity):
    """One step, ``advance(state, with_null) -> StepResult``, with the fallbacks for a step with no valid child.

    A generator that searches (MCMC, Gibbs, k-best) may return only children holding an unphysical track (a return
    that pulls a widely spread track onto an impossible orbit, the other children too light to be found). The step
    then falls back to each parent's null association alone (``with_null``: every return clutter, with its
    population twins, deaths; a labeled multi-Bernoulli parent's "every object missed" and "every object died"),
    a bounded child set whose children hold only predicted tracks. When a prediction ``pred`` itself fails the test
    (a state that passed it when last updated can fail it later: the test reads two-body elements from a state the
    J2 motion moves, whose osculating perigee oscillates by kilometres) and no child lacks it (no death), every
    track whose prediction fails is deleted from every parent of ``state``, as a single-hypothesis tracker deletes
    an unphysical track, and the step is taken again from those parents, search then null association
    (``stats["n_invalid_deleted"]``). Raises ``RuntimeError`` when no prediction fails and still no child is valid.
    """
    for with_null in (False, True):
        try:
            return advance(state, with_null)
        except NoValidChild:
            pass
    ok = np.asarray(validity(pred.means), dtype=bool) if len(pred) else np.zeros(0, dtype=bool)
    if ok.all():
        raise RuntimeError("no child hypothesis is valid: every child holds a track that fails validity")
    kept = FilterState(state.store, state.log_w, [t[ok[t]] for t in state.tracks], state.keys, state.next_label)
    try:
        result = advance(kept, False)
    except NoValidChild:
        result = advance(kept, True)
    result.stats["n_invalid_deleted"] = int(np.sum(~ok))
    return result


def valid_top_k(keys, k: int, pairs_of, moments_of, validity):
    """Indices of the best ``k`` children (by ``keys``, best first) whose every track passes ``validity``.

    Parameters
    ----------
    keys : (E,) float
        Ranking keys of the children; ``−inf`` never kept.
    k : int
        ``H∞``.
    pairs_of : callable ``c -> list of (source, return)``
        The store pairs of child ``c`` (:func:`.child_pairs`).
    moments_of : callable ``(sources, returns) -> (means (P, d), covs (P, d, d))``
        The moments of pairs (:meth:`~.filter.HypothesisFilter.pair_moments`).
    validity : callable ``means (P, d) -> bool (P,)``

    Returns
    -------
    sel : (≤ k,) int64 indices; n_invalid : number of children visited and rejected.
    """
    keys = np.asarray(keys, dtype=float)
    order = np.argsort(-keys, kind="stable")
    finite = np.isfinite(keys[order])
    order = order[:len(order) if finite.all() else int(np.argmin(finite))].tolist()  # the visit stops at the first non-finite
    verdict: dict = {}
    sel, n_invalid, tested = [], 0, 0
    for i, c in enumerate(order):
        if len(sel) == k:
            break
        if i == tested:  # the next k − |sel| children are all visited (each is kept or rejected): test them at once
            tested = i + k - len(sel)
            new = list(dict.fromkeys(p for d in order[i:tested] for p in pairs_of(d) if p not in verdict))
            if new:
                src = np.array([p[0] for p in new], dtype=np.int64)
                ret = np.array([p[1] for p in new], dtype=np.int64)
                means, _ = moments_of(src, ret)
                ok = np.asarray(validity(means), dtype=bool)
                if ok.shape != (len(new),):
                    raise ValueError(f"validity must return one bool per track, shape ({len(new)},), got {ok.shape}")
                verdict.update(zip(new, ok.tolist()))
        if all(verdict[p] for p in pairs_of(c)):
            sel.append(c)
        else:
            n_invalid += 1
    return np.asarray(sel, dtype=np.int64), n_invalid



class PairMemo:
    """One engine step's child pairs, each child's computed once: the validity test visits the best children
    (:func:`valid_top_k`) and the kept ones are then materialised from the same pairs
    (:meth:`~.filter.HypothesisFilter._materialise`). ``pairs_of(c)``: the store pairs of child ``c``
    (:func:`.child_pairs`); ``known``: the pairs of every child, already computed (:func:`.duplicates.merge_few`).

    The pairs' moments are not kept from the test to the materialisation: the radar's EKF (its batched
    matrix products) rounds a pair's update differently in a different batch, and a newborn's ill-conditioned
    track turns one rounding into ~1e-11 of its hypotheses' log-weights scans later — the kept pairs are
    updated in one batch, as they always were, so the posterior is the same to the bit."""

    def __init__(self, pairs_of, known=None):
        self._pairs_of, self._pairs = pairs_of, ({} if known is None else dict(enumerate(known)))

    def pairs(self, c: int) -> list:
        """The store pairs of child ``c``."""
        if c not in self._pairs:
            self._pairs[c] = self._pairs_of(c)
        return self._pairs[c]

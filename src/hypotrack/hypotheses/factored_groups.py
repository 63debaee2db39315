"""Group algebra of the factored engine: product (merge), factorisation check and split.

A *group* is a hypothesis set over its own objects — a :class:`~.tracks.TrackStore`,
normalised log-weights and, per hypothesis, the indices of its tracks: the state of a
:class:`~.filter.HypothesisFilter` (:class:`~.state.FilterState`, here also called :data:`GroupState`). The factored posterior is the
product of the groups': a joint hypothesis takes one hypothesis of every group, its weight is
the product, its tracks the union (the labeled-RFS product of independent labeled sets, Beard,
Vo & Vo, "A solution for large-scale multi-object tracking", IEEE TSP 68, 2020, Sec. III).

* :func:`product` — the merge: the product of two or more groups' hypotheses, capped at
  ``H∞`` like the engine caps children (top by weight, or a Gumbel-top-``k`` weighted sample).
  For the top cap the product is capped after each factor, which is exact: a joint hypothesis
  in the top ``k`` of ``A × B × C`` has its ``A × B`` part in the top ``k`` of ``A × B``.
* :func:`factorise` — the split: given a partition of a group's tracks into parts (by object),
  each hypothesis is *projected* on each part (the set of its tracks in the part), the
  marginal of a projection is the summed weight of the hypotheses with it, and the product of
  marginals ``Q`` is compared with the joint ``P``. The joint factorises exactly iff every
  combination of projections is a hypothesis (``|P| = Π_c n_c``; hypotheses are distinct sets
  of tracks, :mod:`.duplicates`) and ``log P = log Q`` on each. Otherwise the split is the
  marginal-product approximation of Beard, Vo & Vo (2020, Sec. IV): of all products of
  per-part distributions, the product of the marginals minimises ``KL(P ‖ Q)``, and that
  ``KL`` and the ``L1`` distance ``Σ |P − Q|`` (over the product space: ``Q`` also puts mass on
  combinations that ``P`` lacks) are measured and returned with the split.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..association.clustering import graph_components
from .generators import top_k
from .state import FilterState
from .tracks import TrackStore

__all__ = ["GroupState", "SplitRecord", "product", "factorise", "restrict_population", "components"]


GroupState = FilterState
"""A group's hypotheses: the engine's :class:`~.state.FilterState` (its ``next_label`` unused, 0:
the factored filter numbers newborn objects itself)."""


def _concat(stores, ndim):
    if not stores:
        return TrackStore.from_arrays(np.zeros((0, ndim)), None, ndim=ndim)
    return TrackStore(np.concatenate([s.means for s in stores]), np.concatenate([s.covs for s in stores]),
                      np.concatenate([s.labels for s in stores]))


def compact(store: TrackStore, tracks):
    """Drop store entries no hypothesis holds; returns ``(store, tracks, kept entry indices)``."""
    used = np.unique(np.concatenate(tracks)) if tracks and any(len(t) for t in tracks) else np.zeros(0, np.int64)
    remap = np.full(len(store), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    new = TrackStore(store.means[used], store.covs[used], store.labels[used])
    return new, [remap[t] for t in tracks], used


def product(states, max_hypotheses: int, cap: str = "top", rng=None):
    """Joint hypotheses of independent groups, capped at ``max_hypotheses``.

    Returns ``(GroupState, index)``: ``index`` maps the merged store's entries to the
    concatenation of the members' stores (to gather their predicted tracks and scores).
    """
    states = list(states)
    ndim = states[0].store.ndim
    sizes = [len(s.store) for s in states]
    offsets = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    lw = states[0].log_w.copy()
    idx = np.arange(len(lw), dtype=np.int64)[:, None]
    for s in states[1:]:
        joint = (lw[:, None] + s.log_w[None, :]).ravel()
        a, b = np.divmod(np.arange(len(joint), dtype=np.int64), len(s.log_w))
        lw, idx = joint, np.hstack([idx[a], b[:, None]])
        if cap == "top" and len(lw) > max_hypotheses:
            sel = top_k(lw, max_hypotheses)
            lw, idx = lw[sel], idx[sel]
    if len(lw) > max_hypotheses:
        keys = lw + rng.gumbel(size=lw.shape) if cap == "sample" else lw
        sel = top_k(keys, max_hypotheses)
        lw, idx = lw[sel], idx[sel]
    total = np.logaddexp.reduce(lw)
    tracks = [np.concatenate([states[g].tracks[i] + offsets[g] for g, i in enumerate(row)]).astype(np.int64)
              for row in idx]
    keys = [tuple(states[g].keys[i] for g, i in enumerate(row)) for row in idx]
    store, tracks, used = compact(_concat([s.store for s in states], ndim), tracks)
    return GroupState(store, lw - total, tracks, keys), used


@dataclass(frozen=True, eq=False)
class SplitRecord:
    """One split of a group (or the check that found it could not be split exactly).

    Attributes
    ----------
    scan : int
    parts : tuple of label arrays, one per part.
    exact : bool — the joint was the product of its marginals (within ``tol`` in log-weight).
    kl : float — ``KL(P ‖ Q) = Σ_h P(h) log(P(h) / Q(h))`` in nats, ``Q`` the product of marginals.
    l1 : float — ``Σ |P − Q|`` over the product space (0 ≤ l1 ≤ 2).
    n_joint : int — hypotheses of the joint; ``n_parts`` those of each part.
    applied : bool — whether the group was split (``False``: kept joint, ``split="exact"``).
    """

    scan: int
    parts: tuple
    exact: bool
    kl: float
    l1: float
    n_joint: int
    n_parts: tuple
    applied: bool = True


def _group_logsumexp(ids, lw, n):
    mx = np.full(n, -np.inf)
    np.maximum.at(mx, ids, lw)
    fin = np.where(np.isfinite(mx), mx, 0.0)
    acc = np.zeros(n)
    np.add.at(acc, ids, np.exp(lw - fin[ids]))
    with np.errstate(divide="ignore"):
        return fin + np.log(acc)


def factorise(state: GroupState, part_of_track, tol: float = 1e-10, scan: int = 0):
    """Marginals of ``state`` on the parts of its tracks and the loss of their product.

    Parameters
    ----------
    state : GroupState
    part_of_track : (n_store,) int — the part of every store entry (all tracks of one object
        in one part).
    tol : float
        Largest ``|log P − log Q|`` still called exact (rounding of the log-sum-exp).

    Returns
    -------
    (SplitRecord, list of GroupState) — one state per part, with the marginal weights.
    """
    part_of_track = np.asarray(part_of_track, dtype=np.int64)
    parts, pidx = np.unique(part_of_track, return_inverse=True)
    P, H = len(parts), len(state.log_w)
    # the projection of every hypothesis on every part (its sorted tracks there), numbered per part
    # in order of first appearance; one sort per hypothesis, not one mask per (part, hypothesis)
    tables = [{} for _ in range(P)]
    ids_all = np.empty((P, H), dtype=np.int64)
    for h, t in enumerate(state.tracks):
        t = np.sort(np.asarray(t, dtype=np.int64))
        pi = pidx[t]
        order = np.argsort(pi, kind="stable")
        tl, pl = t[order].tolist(), pi[order].tolist()
        present, a = {}, 0
        for b in range(1, len(tl) + 1):
            if b == len(tl) or pl[b] != pl[a]:
                present[pl[a]] = tuple(tl[a:b])
                a = b
        for c in range(P):
            table = tables[c]
            ids_all[c, h] = table.setdefault(present.get(c, ()), len(table))
    proj_ids = [ids_all[c] for c in range(P)]
    uniq = [list(t) for t in tables]
    margs = [_group_logsumexp(ids, state.log_w, len(t)) for ids, t in zip(proj_ids, tables)]
    q = sum(m[ids] for m, ids in zip(margs, proj_ids))
    n_parts = tuple(len(u) for u in uniq)
    complete = H == int(np.prod(n_parts, dtype=object))
    exact = bool(complete and np.max(np.abs(state.log_w - q)) <= tol)
    p = np.exp(state.log_w)
    kl = float(np.sum(p * (state.log_w - q)))
    l1 = float(np.sum(np.abs(p - np.exp(q))) + max(0.0, 1.0 - float(np.sum(np.exp(q)))))
    out = []
    by_part = np.argsort(pidx, kind="stable")
    starts = np.searchsorted(pidx[by_part], np.arange(P + 1))
    remap = np.empty(len(state.store), dtype=np.int64)
    for j, (c, ids, marg, keys) in enumerate(zip(parts, proj_ids, margs, uniq)):
        entries = by_part[starts[j]:starts[j + 1]]  # ascending: the stable sort keeps store order
        remap[entries] = np.arange(len(entries))
        first = np.unique(ids, return_index=True)[1]  # ids number first appearances: the first hypothesis of each
        store = TrackStore(state.store.means[entries], state.store.covs[entries], state.store.labels[entries])
        tracks = [remap[np.asarray(k, dtype=np.int64)] for k in keys]
        lineage = [("split", scan, int(c), state.keys[f]) for f in first]
        out.append(GroupState(store, marg - np.logaddexp.reduce(marg), tracks, lineage))
    # KL >= 0 and L1 >= 0; rounding can make an exact split's sums a hair negative
    record = SplitRecord(scan, tuple(np.unique(s.store.labels) for s in out), exact, max(kl, 0.0), l1, H, n_parts)
    return record, out


def components(n_nodes: int, n_returns: int, node, ret):
    """Connected components of the bipartite graph nodes–returns with edges ``(node[k], ret[k])``.

    Returns ``(n, labels)``: ``labels[:n_nodes]`` the component of each node,
    ``labels[n_nodes:]`` of each return.
    """
    node = np.asarray(node, dtype=np.int64)
    return graph_components(n_nodes + n_returns, node, np.asarray(ret, dtype=np.int64) + n_nodes)


def restrict_population(population, regions):
    """The population with only birth terms/regions ``regions`` (all their other terms unchanged).

    A group receives the birth terms that its returns couple it to (or a new group a term that
    no return couples to anything); every term is given to exactly one group per scan. For the
    labeled multi-Bernoulli and the binomial population each term is an independent factor, so
    the restriction is exact; the single-event population's ``P(no event)`` is then evaluated per
    group (see :mod:`.factored`).
    """
    return None if population is None else population.restricted_to(regions)

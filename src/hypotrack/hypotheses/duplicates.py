"""Identical children of different parents: one hypothesis, weights added.

A hypothesis is a *set of tracks* — in the engine the set of its tracks' ``(source, return)``
pairs, which :meth:`HypothesisFilter._materialise` turns into store entries — not the path that
led to it. Seed 000 Eq. 11 sums the probability of a hypothesis over every way of reaching it,
and in the δ-GLMB a component is indexed by its label set and association history (Vo & Vo,
IEEE TSP 61(13), 2013, Eq. 14), so two children holding the same tracks are one component
whose weight is the sum of theirs. After deaths they do occur: parent ``{a, b}`` whose ``b``
dies and parent ``{a}`` (``b`` died a scan earlier) both produce ``{a updated with z}``.

Kept apart, the posterior *density* is unchanged (the two entries carry identical pdfs), but
the cap and the summaries are not: each half can fall below the ``H∞``-th weight while the
whole would have been kept, a MAP estimate compares halves, and the factored engine's
factorisation check (:mod:`.factored`) counts hypotheses. :func:`merge_duplicates` therefore
merges them before the cap, the weight being the log-sum-exp of the copies.

Which children can coincide
---------------------------
If neither of two children has a death, each holds a descendant of *every* track of its parent,
so equal children have parents with equal track sets, i.e. the same parent (the current
hypotheses are distinct — this merge keeps them so), and within one parent the pairs determine
the event and the silent events. Hence duplicates need a death in at least one of the two, and
a scan whose children have no death is skipped at the cost of one mask. Otherwise each child
gets a 64-bit hash, the XOR of a splitmix64 mix of each of its pairs (order-free, vectorised);
children sharing a hash are compared by their exact pair sets before merging, so a hash
collision cannot merge different hypotheses.

With a cap the parents' children are pre-trimmed to the best ``H∞`` each (:mod:`.filter`), so
a child trimmed at one parent cannot add to its copy at another: the merge is exact when
nothing is trimmed (``max_hypotheses`` above the number of children).
"""

from __future__ import annotations

import numpy as np
from .._logspace import logsumexp

from .association_problem import SEEDED_BIRTH
from .hypothesis import ChildSet

__all__ = ["child_pairs", "pairs_function", "silent_masks", "child_hashes", "merge_duplicates", "merge_few"]

#: Up to this many children with a death among them, :func:`merge_few` groups them by their pair sets directly.
FEW = 48

_CHUNK = 1 << 15
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


def _mix(x):
    """splitmix64 finaliser, elementwise on uint64 (wrapping arithmetic)."""
    with np.errstate(over="ignore"):
        x = x.astype(np.uint64) + _GOLDEN
        x = (x ^ (x >> np.uint64(30))) * _MIX1
        x = (x ^ (x >> np.uint64(27))) * _MIX2
    return x ^ (x >> np.uint64(31))


def child_pairs(children: ChildSet, c: int, tracks, n_birth: int) -> list:
    """The ``(source, return)`` pairs of child ``c`` whose parent holds store tracks ``tracks``.

    ``source >= 0`` a parent track (return −1: missed), ``−1 − r`` birth term/region ``r``
    (return −1: born undetected), ``−1 − n_birth − c`` a seeded birth in component ``c`` of its
    birth density (HOMHT; ``c = 0`` for one Gaussian, :mod:`.seeded`). The order is the
    order of the child's tracks in the next store list.
    """
    # on Python ints: a child has a few tracks and returns, where numpy's per-call overhead is the cost
    ev = children.events[c].tolist()
    M = len(tracks)
    ret = [-1] * M
    for i, a in enumerate(ev):
        if 0 <= a < M:
            ret[a] = i
    dead, unseen_births = children.silent_events(c, M)
    tr = tracks.tolist() if isinstance(tracks, np.ndarray) else [int(t) for t in tracks]
    keys = [(tr[j], ret[j]) for j in range(M) if j not in dead]
    keys += [(-1 - (a - M), i) for i, a in enumerate(ev) if a >= M]
    keys += [(-1 - n_birth - (SEEDED_BIRTH - a), i) for i, a in enumerate(ev) if a <= SEEDED_BIRTH]
    keys += [(-1 - int(r), -1) for r in unseen_births]
    return keys


def pairs_function(children: ChildSet, track_lists, n_birth: int):
    """``pairs(c)``: :func:`child_pairs` of child ``c`` of ``children`` (its parent's tracks in ``track_lists``) — the
    same list — with the children's events, kinds, arguments and parents read into Python lists once for all of
    them and each parent's track list once (an engine step asks for the pairs of every child it visits)."""
    events, kinds, args, parents = (children.events.tolist(), children.kind.tolist(), children.arg.tolist(),
                                    children.parent.tolist())
    tracks_of = {}
    death, unseen_birth, silent_set = ChildSet.DEATH, ChildSet.UNDETECTED_BIRTH, ChildSet.POPULATION_SET

    def pairs(c: int) -> list:
        h = parents[c]
        tr = tracks_of.get(h)
        if tr is None:
            t = track_lists[h]
            tr = tracks_of[h] = t.tolist() if isinstance(t, np.ndarray) else [int(x) for x in t]
        ev, M, kind = events[c], len(tr), kinds[c]
        # child_pairs in one pass over the event (the parent's tracks, the born, the seeded: the same order)
        ret = [-1] * M
        born, seeded = [], []
        for i, a in enumerate(ev):
            if a >= M:
                born.append((-1 - (a - M), i))
            elif a >= 0:
                ret[a] = i
            elif a <= SEEDED_BIRTH:
                seeded.append((-1 - n_birth - (SEEDED_BIRTH - a), i))
        if kind == death:
            d = int(args[c])
            keys = [(tr[j], ret[j]) for j in range(M) if j != d]
        elif kind == silent_set:
            dead, unseen = children.silent_events(c, M)
            keys = [(tr[j], ret[j]) for j in range(M) if j not in dead]
            return keys + born + seeded + [(-1 - int(r), -1) for r in unseen]
        else:
            keys = list(zip(tr, ret))
        if born:
            keys += born
        if seeded:
            keys += seeded
        if kind == unseen_birth:
            keys.append((-1 - int(args[c]), -1))
        return keys

    return pairs


def silent_masks(children: ChildSet, lens: np.ndarray, n_birth: int):
    """``(dead (E, M_max), unseen (E, B))`` bool: the parent-local objects each child kills and
    the birth terms born undetected (``lens[e]`` objects in child ``e``'s parent)."""
    E = len(children)
    m_max = int(lens.max()) if E else 0
    dead = np.zeros((E, m_max), dtype=bool)
    unseen = np.zeros((E, n_birth), dtype=bool)
    kind, arg = children.kind, children.arg
    rows = np.flatnonzero(kind == ChildSet.DEATH)
    dead[rows, arg[rows].astype(np.int64)] = True
    rows = np.flatnonzero(kind == ChildSet.UNDETECTED_BIRTH)
    unseen[rows, arg[rows].astype(np.int64)] = True
    rows = np.flatnonzero(kind == ChildSet.POPULATION_SET)
    if len(rows):
        if arg.dtype == object:  # more than 62 objects: exact Python integers
            for e in rows:
                dead_e, unseen_e = children.silent_events(int(e), int(lens[e]))
                dead[e, dead_e] = True
                unseen[e, unseen_e] = True
        else:
            a = arg[rows].astype(np.int64)[:, None]
            M = lens[rows][:, None]
            j = np.arange(m_max)[None, :]
            dead[rows] = ((a >> j) & 1).astype(bool) & (j < M)
            if n_birth:
                unseen[rows] = ((a >> (M + np.arange(n_birth)[None, :])) & 1).astype(bool)
    return dead, unseen


def child_hashes(children: ChildSet, track_lists, n_birth: int, dead=None, unseen=None) -> np.ndarray:
    """(E,) uint64: XOR of ``splitmix64(code(pair))`` over each child's pairs (order-free)."""
    E = len(children)
    lens = np.array([len(t) for t in track_lists], dtype=np.int64)
    m = children.events.shape[1]
    if dead is None:
        dead, unseen = silent_masks(children, lens[children.parent], n_birth)
    m_max = dead.shape[1]
    padded = np.full((len(track_lists), m_max), -1, dtype=np.int64)
    for h, t in enumerate(track_lists):
        padded[h, : len(t)] = t
    stride = m + 1
    out = np.zeros(E, dtype=np.uint64)
    cols = np.arange(m_max)[None, :]
    ret_idx = np.arange(m)[None, :]
    for start in range(0, E, _CHUNK):
        sl = slice(start, start + _CHUNK)
        par = children.parent[sl]
        ev = children.events[sl].astype(np.int64)
        M = lens[par][:, None]
        ret = np.full((len(par), m_max), -1, dtype=np.int64)
        r, i = np.nonzero((ev >= 0) & (ev < M))
        ret[r, ev[r, i]] = i
        live = (cols < M) & ~dead[sl]
        codes = (padded[par] + n_birth + 1) * stride + ret + 1
        h = np.bitwise_xor.reduce(np.where(live, _mix(codes), np.uint64(0)), axis=1)
        born = ev >= M
        if born.any():
            codes = (n_birth - (ev - M)) * stride + ret_idx + 1
            h ^= np.bitwise_xor.reduce(np.where(born, _mix(codes), np.uint64(0)), axis=1)
        seeded = ev <= SEEDED_BIRTH
        if seeded.any():  # component c >= 1 of a mixture: a negative code, disjoint from every other one
            comp = SEEDED_BIRTH - ev
            codes = np.where(comp > 0, -(comp * stride + ret_idx + 1), ret_idx + 1)
            h ^= np.bitwise_xor.reduce(np.where(seeded, _mix(codes), np.uint64(0)), axis=1)
        if n_birth and unseen[sl].any():
            codes = (n_birth - np.arange(n_birth)[None, :]) * stride
            h ^= np.bitwise_xor.reduce(np.where(unseen[sl], _mix(np.broadcast_to(codes, unseen[sl].shape)),
                                                np.uint64(0)), axis=1)
        out[sl] = h
    return out


def merge_duplicates(children: ChildSet, keys: np.ndarray, track_lists, n_birth: int):
    """Merge children holding the same tracks; returns ``(children, keys, n_removed)``.

    Each set of identical children becomes its heaviest member with log-weight the
    log-sum-exp of theirs; its cap key (the log-weight, or the log-weight plus a Gumbel draw
    for the sampled cap) moves by the same amount, so the sampled cap still draws each
    distinct hypothesis with one Gumbel key. The order of the remaining children is kept.
    ``keys`` has one entry per child, shape ``(len(children),)``.
    """
    E = len(children)
    if np.ndim(keys) != 1 or len(keys) != E:
        raise ValueError(f"keys must have shape ({E},), one cap key per child, got shape {np.shape(keys)}")
    if E < 2:
        return children, keys, 0
    lens = np.array([len(track_lists[p]) for p in children.parent], dtype=np.int64)
    dead, unseen = silent_masks(children, lens, n_birth)
    if not dead.any():
        return children, keys, 0
    h = child_hashes(children, track_lists, n_birth, dead, unseen)
    order = np.argsort(h, kind="stable")
    hs = h[order]
    same = np.zeros(E, dtype=bool)
    eq = hs[1:] == hs[:-1]
    same[1:] |= eq
    same[:-1] |= eq
    if not same.any():
        return children, keys, 0
    groups, pairs_of = {}, pairs_function(children, track_lists, n_birth)
    for c in order[same].tolist():
        groups.setdefault((int(h[c]), frozenset(pairs_of(c))), []).append(c)
    merged, keys, keep = _merge_groups(children, keys, groups.values())
    return merged, keys, E - len(keep)


def _merge_groups(children: ChildSet, keys, groups):
    """Merge each group of duplicate children (lists of indices in index order): the heaviest member, the first of
    equals, takes the log-sum-exp of the members' log-weights and its key moves by as much; the others are dropped.
    Returns ``(merged children, their keys, the kept indices)``."""
    lw = children.log_weights.copy()
    keys = np.asarray(keys, dtype=float).copy()
    drop = np.zeros(len(children), dtype=bool)
    w, k = lw.tolist(), keys.tolist()  # (Python floats: the same IEEE sums; argmax's first of equals is max's)
    nan = any(x != x for x in w)
    for members in groups:
        if len(members) < 2:
            continue
        members = np.asarray(members)
        rep = int(members[np.argmax(lw[members])]) if nan else max(members.tolist(), key=w.__getitem__)
        total = float(logsumexp(lw[members]))
        k[rep] += total - w[rep]
        w[rep] = lw[rep] = total
        drop[members[members != rep]] = True
    keys = np.array(k)
    keep = np.flatnonzero(~drop)
    merged = ChildSet(children.parent[keep], children.events[keep], children.kind[keep], children.arg[keep], lw[keep])
    return merged, keys[keep], keep


def _set_kills(children: ChildSet, track_lists) -> bool:
    """Whether a silent-event set (``POPULATION_SET``) of ``children`` kills one of its parent's objects: a bit
    ``j < M`` of its mask (:meth:`~.hypothesis.ChildSet.silent_events`)."""
    rows = np.flatnonzero(children.kind == ChildSet.POPULATION_SET).tolist()
    args, parents = children.arg, children.parent
    return any(int(args[e]) & ((1 << len(track_lists[parents[e]])) - 1) for e in rows)


def merge_few(children: ChildSet, keys: np.ndarray, track_lists, n_birth: int):
    """:func:`merge_duplicates` of a step with few children, and the children's pairs: ``(children, keys, n_removed,
    pairs)``, ``pairs`` the :func:`child_pairs` of each returned child or ``None`` (not computed).

    The same merge bit for bit: duplicates need a death (module docstring), so a step whose children have none
    (no ``DEATH`` child, no silent-event set killing an object) is returned as it is, pairs not computed. Otherwise,
    with at most :data:`FEW` children, each child's pairs are computed (:func:`pairs_function`, one Python pass each,
    where the hashes' vectorised pass costs some forty numpy calls)
    and the children are grouped by their exact pair sets, each group's members in index order — the groups
    and member order the hashes give (equal pair sets have equal hashes; children of one hash are compared by
    their pair sets in index order) — and merged as :func:`merge_duplicates` merges them (the heaviest, the first
    of equals, takes the log-sum-exp of the members' log-weights, its key moved by as much). The pairs are the
    step's to reuse (:class:`~.validity.PairMemo`): a merged child keeps its own events, kind and argument, so
    its pairs. Anything else: :func:`merge_duplicates` itself, pairs ``None``."""
    E = len(children)
    if np.ndim(keys) != 1 or len(keys) != E or E < 2 or E > FEW:
        return (*merge_duplicates(children, keys, track_lists, n_birth), None)
    kind = children.kind
    if ChildSet.DEATH not in kind and not _set_kills(children, track_lists):
        return children, keys, 0, None
    pairs_of = pairs_function(children, track_lists, n_birth)
    pairs = [pairs_of(c) for c in range(E)]
    groups = {}
    for c in range(E):
        groups.setdefault(frozenset(pairs[c]), []).append(c)
    if len(groups) == E:
        return children, keys, 0, pairs
    merged, keys, keep = _merge_groups(children, keys, groups.values())
    return merged, keys, E - len(keep), [pairs[c] for c in keep.tolist()]

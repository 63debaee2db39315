"""The factored filter's scan planner: which groups a scan couples, and how they are split again.

Package docstring, steps 2–4: the bipartite graph groups/singletons/birth terms — returns
(:func:`scan_graph`), its components in a deterministic order (:meth:`ScanGraph.components`), the
:class:`~..scan_context.ScanContext` of a component (:func:`component_context`), the objects that
interacted (:func:`interaction_parts`), and the split of a stepped group (:func:`split_group`,
Beard, Vo & Vo 2020, Sec. IV) and its pruning (:func:`prune`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..factored_groups import SplitRecord, compact, components, factorise, product
from ..scan_context import ScanContext
from ..seeded import prime_scan
from ..state import FilterState
from ..tracks import TrackStore
from .lane import GroupSet, bernoulli, empty_state, singleton, take
from .scorable_kernels import certify
from .scores import Scores, score_tracks
from .sleeping import sleeping_step

__all__ = ["Scores", "MAX_SCALED_CONDITION", "scorable", "innovation_covariances", "score_scorable", "ScanData",
           "ScanGraph", "scan_graph", "component_context",
           "touched_plan", "quiet_plan", "interaction_parts", "ObjectIds", "split_group", "prune"]


def innovation_covariances(measurement, means, covs) -> np.ndarray:
    """``S = H P Hᵀ + R`` (n, p, p) of each track, ``H`` the measurement's matrix or, for a nonlinear one, its
    Jacobian at the mean (no gain: a singular ``S`` is what :func:`scorable` looks for)."""
    H = measurement.H if getattr(measurement, "linear", False) else measurement.jacobian(means)
    return H @ covs @ np.swapaxes(H, -1, -2) + measurement.R


#: The largest condition number of an innovation covariance scaled to a unit diagonal that a scan still scores:
#: beyond it ``S⁻¹`` keeps fewer than six correct digits (units do not count: the scaling removes them).
MAX_SCALED_CONDITION = 1e10


def scorable(S) -> np.ndarray:
    """Whether each innovation covariance ``S`` (n, p, p) of the predicted tracks is finite, positive definite
    (Cholesky succeeds) and invertible in working precision — the condition number of ``D^-1/2 S D^-1/2``
    (``D = diag S``) at most :data:`MAX_SCALED_CONDITION`: the tracks a scan can score. A track whose covariance
    diverged (a one-Gaussian seeded birth, 8 km/s velocity spread, predicted over an hour out of view: position
    variances of 1e16 km² against the radar's 1e-6 rad²) can pass Cholesky by rounding and then stop the scan in
    the gain's solve (an exact zero pivot, depending on the BLAS)."""
    S = np.asarray(S, dtype=float)
    status = certify(S)  # the matrices certified well conditioned need no eigenvalues (:mod:`.scorable_kernels`)
    ok = status > 0
    undecided = np.flatnonzero(status == 2)
    if len(undecided):
        d = np.einsum("nii->ni", S[undecided])
        s = 1.0 / np.sqrt(d)
        lam = np.linalg.eigvalsh(S[undecided] * s[:, :, None] * s[:, None, :])
        ok[undecided[lam[:, 0] * MAX_SCALED_CONDITION <= lam[:, -1]]] = False
    else:  # every finite matrix certified: Cholesky succeeds on each (:mod:`.scorable_kernels`)
        return ok
    try:
        np.linalg.cholesky(S[ok])
        return ok
    except np.linalg.LinAlgError:
        pass
    for i in np.flatnonzero(ok):  # rare: find the ones that fail
        try:
            np.linalg.cholesky(S[i])
        except np.linalg.LinAlgError:
            ok[i] = False
    return ok


def score_scorable(engine, pred, Z, *, gate_out_of_view: bool, survival) -> Scores:
    """:func:`~.scores.score_tracks` of the tracks whose innovation covariance is finite and positive definite
    (:func:`scorable`); a track whose prediction diverged takes no return and is not missed (``p_D = 0``,
    ``p_S = 1``): the scan goes on without it. Every track scorable: :func:`~.scores.score_tracks` itself.
    A mixture birth density's per-return mixtures (Reid's seeded births) are computed here for all the scan's
    returns in one batch (:func:`~..seeded.prime_scan`), before the steps ask for those of their gates."""
    prime_scan(engine.weights, Z)
    if len(pred):
        with np.errstate(invalid="ignore", over="ignore"):
            ok = scorable(innovation_covariances(engine.measurement, pred.means, pred.covs))
    else:
        ok = np.ones(0, dtype=bool)
    if ok.all():
        return score_tracks(engine, pred, Z, gate_out_of_view=gate_out_of_view, survival=survival)
    good = np.flatnonzero(ok)
    sub = score_tracks(engine, take(pred, good), Z, gate_out_of_view=gate_out_of_view, survival=survival)
    m, n = len(Z), len(pred)
    loglik, allowed = np.full((m, n), -np.inf), np.zeros((m, n), dtype=bool)
    p_detect = np.zeros(n)
    p_survive = None if sub.p_survive is None else np.ones(n)
    block = sub.block(np.arange(m), np.arange(len(good)))
    loglik[:, good], allowed[:, good], p_detect[good] = block[:3]
    if p_survive is not None:
        p_survive[good] = block[3]
    return Scores(m, p_detect, p_survive, loglik=loglik, allowed=allowed)


@dataclass(frozen=True, eq=False)
class ScanGraph:
    """The scan's graph: ``G`` groups, then ``L`` singletons, then ``B`` birth terms, then the
    returns in no gate that are nodes of their own (seeded births); each node's and each return's
    component; which components a return or birth term reaches; the returns no gate and no
    birth term explains."""

    G: int
    L: int
    B: int
    n_comp: int
    node_lab: np.ndarray
    ret_lab: np.ndarray
    touched: np.ndarray
    unexplained: np.ndarray

    def components(self, skip=None):
        """``(key, component, members, regions, rows)`` in the order of each component's first node
        (deterministic): a quiet group (component ``None``: only its group index ``key``) or a
        touched component with its groups/singletons ``members`` (node indices, ascending), birth
        terms ``regions`` and returns ``rows``. ``skip``: touched components left out (the fast path's)."""
        G, L, B, n_comp, node_lab, ret_lab = self.G, self.L, self.B, self.n_comp, self.node_lab, self.ret_lab
        n_nodes = len(node_lab)
        first = np.full(n_comp, n_nodes, dtype=np.int64)
        np.minimum.at(first, node_lab, np.arange(n_nodes))
        order_n = np.argsort(node_lab, kind="stable")
        starts_n = np.searchsorted(node_lab[order_n], np.arange(n_comp + 1))
        order_r = np.argsort(ret_lab, kind="stable")
        starts_r = np.searchsorted(ret_lab[order_r], np.arange(n_comp + 1))
        quiet_groups = np.flatnonzero(~self.touched[node_lab[:G]])
        touched = self.touched
        if skip is not None and len(skip):
            touched = touched.copy()
            touched[skip] = False
        keyed = [(int(g), None) for g in quiet_groups] + [(int(first[c]), int(c)) for c in np.flatnonzero(touched)]
        keyed.sort(key=lambda kc: kc[0])
        for key, c in keyed:
            if c is None:
                yield key, None, None, None, None
                continue
            nodes = order_n[starts_n[c]:starts_n[c + 1]]  # ascending: the stable sort keeps node order
            members = nodes[nodes < G + L]
            regions = nodes[(nodes >= G + L) & (nodes < G + L + B)] - (G + L)
            yield key, c, members, regions, order_r[starts_r[c]:starts_r[c + 1]]

    def touching(self, nodes) -> "ScanGraph":
        """This graph with the components of ``nodes`` touched (stepped even with no return or birth term)."""
        if len(nodes) == 0:
            return self
        touched = self.touched.copy()
        touched[self.node_lab[nodes]] = True
        return ScanGraph(self.G, self.L, self.B, self.n_comp, self.node_lab, self.ret_lab, touched, self.unexplained)

    def quiet_singletons(self) -> np.ndarray:
        """Whether each singleton's component is untouched (no return, no birth term)."""
        return ~self.touched[self.node_lab[self.G:self.G + self.L]]


def scan_graph(col_node, G: int, L: int, scores: Scores, birth_ll, births: str, seeded: bool) -> ScanGraph:
    """The graph of a scan (package docstring, step 2): a group (or singleton, node ``col_node`` of
    each track column) is linked to the returns in its gate, a birth term to the returns it could be
    the first detection of (finite likelihood; with ``births="free"`` only those in no gate), and with
    ``seeded`` births each return in no gate becomes a node of its own."""
    m, B = birth_ll.shape
    gr, c_a = scores.gated()
    gi = col_node[c_a]
    explained = np.zeros(m, dtype=bool)
    explained[gr] = True
    bgate = np.isfinite(birth_ll)
    if births == "free":
        bgate &= ~explained[:, None]
    unexplained = ~explained & ~bgate.any(axis=1)
    free = np.flatnonzero(unexplained) if seeded else np.zeros(0, int)
    bi, br = np.nonzero(bgate.T)
    n_nodes = G + L + B + len(free)
    node = np.concatenate([gi, G + L + bi, G + L + B + np.arange(len(free))])
    ret = np.concatenate([gr, br, free])
    n_comp, lab = components(n_nodes, m, node, ret)
    node_lab, ret_lab = lab[:n_nodes], lab[n_nodes:]
    touched = np.zeros(n_comp, dtype=bool)
    touched[ret_lab] = True
    touched[node_lab[G + L:G + L + B]] = True
    return ScanGraph(G, L, B, n_comp, node_lab, ret_lab, touched, unexplained)


def component_context(engine, Z, rows, scores, birth_ll, regions) -> ScanContext:
    """The :class:`ScanContext` of returns ``rows`` against a component's track columns ``scores``
    (``(loglik, allowed, p_detect, p_survive)``, their rows those returns: :meth:`~.scores.Scores.block`)
    and its birth terms ``regions`` (document 000 Eq. 8, 18, 30)."""
    loglik, allowed, p_detect, p_survive = scores
    clutter = engine.sensor.clutter
    return ScanContext(Z=Z[rows], loglik=loglik, allowed=allowed, p_detect=p_detect,
                       birth_loglik=birth_ll[np.ix_(rows, regions)], p_detect_birth=engine.p_D,
                       clutter_rate=float(clutter.rate), clutter_volume=float(clutter.region.area),
                       p_survive=p_survive)


def touched_plan(engine, rng, members, regions, rows, groups, bounds, pred, scores, Z, birth_ll, stats, lane_r=None):
    """The plan of one engine step on a touched component (package docstring, step 2): its groups
    and singletons merged (:func:`~..factored_groups.product`, capped as the engine caps), with its
    returns ``rows`` and birth terms ``regions``. ``members``: graph nodes (``< len(groups)``: a
    group, its track columns ``bounds[g]:bounds[g + 1]`` of ``pred``; else a singleton, its track
    the column ``bounds[-1] + node − len(groups)``, of existence ``lane_r[node − len(groups)]`` when given
    (Bernoulli singletons, :func:`~.lane.bernoulli`))."""
    G = len(groups)
    if len(members) == 0:
        state, cols = empty_state(pred.ndim), np.zeros(0, dtype=np.int64)
    else:
        states, col_sets = [], []
        for g in members:
            if g < G:
                states.append(groups[g])
                col_sets.append(np.arange(bounds[g], bounds[g + 1]))
            else:
                col = bounds[-1] + g - G
                states.append(singleton(pred, col) if lane_r is None else bernoulli(pred, col, float(lane_r[g - G])))
                col_sets.append(np.array([col]))
        if len(states) == 1:
            state, cols = states[0], col_sets[0]
        else:
            state, used = product(states, engine.max_hypotheses, engine.cap, rng)
            cols = np.concatenate(col_sets)[used]
            stats["n_merges"] += len(states) - 1
    sc = scores.block(rows, cols)
    return ("touched", state, take(pred, cols), component_context(engine, Z, rows, sc, birth_ll, regions), regions)


def quiet_plan(engine, lane_on: bool, objects, state, pred, sc, Z, birth_ll, stats, fast=None):
    """A group no return or birth term reaches (package docstring, step 3): only predicted when
    that is exact (a silent population, ``lane_on``, and the same ``Π (1 − p_D)`` in all its
    hypotheses), else the plan of an engine step on an empty scan — or, the fast path on (``fast``:
    its rule), that step itself, ``("slept", state, parts)``, when it has a closed form (:mod:`.sleeping`)."""
    if lane_on:  # (the Π (1 − p_D) of each hypothesis only read here)
        log_miss = np.log1p(-sc[2])
        miss = np.array([log_miss[t].sum() for t in state.tracks])
        if np.ptp(miss) <= 1e-12:
            stats["n_predict_only"] += 1
            new = state.with_store(pred)
            return ("done", new, objects.of(new.store.labels))  # no interaction: every object its own part
    none = np.zeros(0, dtype=np.int64)
    ctx = component_context(engine, Z, none, sc, birth_ll, none)
    slept = None if fast is None else sleeping_step(engine, state, pred, ctx)  # one-track hypotheses: closed form
    if slept is not None:
        stats["n_duplicates_merged"] += slept[1]
        return ("slept", slept[0], objects.of(slept[0].store.labels))
    return ("quiet", state, pred, ctx, none)


def interaction_parts(pred_objects, ctx, sources, n_regions):
    """Part of each new store entry: objects linked by a return they both gated this scan,
    newborn objects with their birth term (or, seeded, their return)."""
    m = ctx.n_returns
    objects = np.unique(pred_objects)
    L = len(objects)
    col_node = np.searchsorted(objects, pred_objects)
    r_a, c_a = np.nonzero(ctx.allowed)
    r_b, b_b = np.nonzero(np.isfinite(ctx.birth_loglik))
    node = np.concatenate([col_node[c_a], L + b_b, L + n_regions + np.arange(m)])
    ret = np.concatenate([r_a, r_b, np.arange(m)])
    n_nodes = L + n_regions + m
    _, lab = components(n_nodes, m, node, ret)
    src, r = sources[:, 0], sources[:, 1]
    tnode = np.empty(len(src), dtype=np.int64)
    old = src >= 0
    tnode[old] = col_node[src[old]]
    seeded = src <= -1 - n_regions  # (every component of a mixture seeded at return r: r's node)
    tnode[seeded] = L + n_regions + r[seeded]
    born = ~old & ~seeded
    tnode[born] = L + (-1 - src[born])
    return lab[tnode]


class ObjectIds:
    """Object id of each label. The engine gives every (birth term, return) pair of a scan its
    own label, but a birth term yields at most one object per scan: all its newborn labels
    of that scan are one object (id: the smallest of them), which a split keeps in one part.
    Other labels are their own object."""

    def __init__(self, mapping=None):
        self.mapping = dict(mapping or {})

    def copy(self) -> "ObjectIds":
        return ObjectIds(self.mapping)

    def of(self, labels) -> np.ndarray:
        get = self.mapping.get
        return np.array([get(int(x), int(x)) for x in labels], dtype=np.int64)

    def register_births(self, store, sources, n_regions):
        """The newborn labels of each birth term (``sources``, :class:`~..state.StepResult`) become one object,
        and those of the components of a mixture seeded at one return (alternatives of one newborn, :mod:`..seeded`)."""
        born = np.flatnonzero((sources[:, 0] < 0) & (sources[:, 0] > -1 - n_regions))
        seeded = np.flatnonzero(sources[:, 0] < -1 - n_regions)  # components c >= 1 only: a one-Gaussian's stays
        groups = [born[sources[born, 0] == r] for r in np.unique(sources[born, 0])]
        if len(seeded):
            on = np.flatnonzero(sources[:, 0] <= -1 - n_regions)
            groups += [on[sources[on, 1] == r] for r in np.unique(sources[seeded, 1])]
        for g in groups:
            labels = store.labels[g]
            for x in labels:
                self.mapping[int(x)] = int(labels.min())

    def keep_held(self, held):
        """Forget the labels no longer held (``held``: every label of every group)."""
        if self.mapping:
            ks = np.fromiter(self.mapping, dtype=np.int64, count=len(self.mapping))
            held = np.asarray(held, dtype=np.int64)
            # only the held labels in the mapping's range can match (a scan's few newborns among 10⁶ objects)
            held = set(held[(held >= ks.min()) & (held <= ks.max())].tolist())  # (few: np.isin's set-up costs more)
            self.mapping = {k: v for k, v in self.mapping.items() if k in held}


def split_group(state, parts, split: str, tol: float, scan: int, records: list, stats: dict) -> list:
    """The group ``state`` split by interaction ``parts`` (package docstring, step 4):
    ``"marginal"`` always (Beard, Vo & Vo 2020's marginal product, its KL and L1 recorded),
    ``"exact"`` each part exactly independent of the rest, ``"never"`` not at all. Every split
    (and with ``"exact"`` every rejected check) is appended to ``records``."""
    if split == "never" or len(state.store) == 0 or len(np.unique(parts)) < 2:
        return [state]
    if split == "marginal":
        record, pieces = factorise(state, parts, tol, scan)
        _record(record, records, stats)
        return pieces
    # "exact": peel off every part that is exactly independent of the rest of the group
    pieces, rest, rest_parts = [], state, np.asarray(parts)
    for c in np.unique(parts)[:-1]:
        record, (rest_new, piece) = factorise(rest, (rest_parts == c).astype(np.int64), tol, scan)
        if record.exact:
            _record(record, records, stats)
            pieces.append(piece)
            rest, rest_parts = rest_new, rest_parts[rest_parts != c]
    if not pieces:
        record, _ = factorise(state, parts, tol, scan)
        records.append(SplitRecord(record.scan, record.parts, False, record.kl, record.l1,
                                   record.n_joint, record.n_parts, applied=False))
    return [rest, *pieces]


def _record(record, records, stats):
    records.append(record)
    stats["n_splits"] += 1
    stats["n_exact_splits"] += int(record.exact)
    stats["split_kl"] += record.kl
    stats["split_l1"] += record.l1


def prune(state, min_weight: float):
    """Drop hypotheses below ``min_weight`` (the heaviest always kept); ``None`` for a group that holds
    no object in any hypothesis."""
    if min_weight > 0 and len(state.log_w) > 1:
        keep = np.exp(state.log_w) >= min_weight
        keep[np.argmax(state.log_w)] = True
        if not keep.all():
            idx = np.flatnonzero(keep)
            lw = state.log_w[idx]
            store, tracks, _ = compact(state.store, [state.tracks[i] for i in idx])
            state = FilterState(store, lw - np.logaddexp.reduce(lw), tracks, [state.keys[i] for i in idx])
    if not any(len(t) for t in state.tracks):
        return None
    return state


@dataclass(frozen=True, eq=False)
class ScanData:
    """Step 1's results: the groups to step and those left for later, each group's track columns
    ``bounds``, the lane's candidates (and every singleton's mean advanced, ``lazy``), the predicted
    tracks (the groups' then the candidates'), their scores, the birth likelihoods, each column's graph node."""

    groups: list
    asleep: GroupSet
    bounds: np.ndarray
    cand: np.ndarray
    view: np.ndarray | None
    pred: TrackStore
    scores: Scores
    birth_ll: np.ndarray
    col_node: np.ndarray
    G: int
    L: int

"""Child generators: which association events of a parent are weighted.

One interface, three strategies (DESIGN.md §3, §4.3)::

    events, log_weights = generator.generate(problem, rng, keep=None)

``events`` (E, m) int32 (always: events from different generators compare bytewise) in the codes of :mod:`.association_problem`, ``log_weights`` their exact
log-weights (:meth:`AssociationProblem.log_weights`); ``keep`` asks for the ``keep`` best only
(the filter passes its cap H∞ when that is exact).

:class:`ExhaustiveGenerator`
    Every feasible event (HOMHT / H-FISST): vectorised enumeration from
    :func:`hypotrack.association.enumerate_associations` (gating through ``allowed``), weights
    as one compiled gather-sum. Refuses, naming its budget, before allocating more than
    ``max_events``; with ``keep`` it streams chunks and holds only the running best.
:class:`MurtyGenerator`
    The k best events by Murty's algorithm on the extended assignment matrix. Exact when the
    count term is constant (HOMHT); otherwise (H-FISST's ``−log(C(m,k) k!)``) Murty runs
    within each block of equal counts and the blocks are merged best first
    (:func:`hypotrack.association.cardinality_assignment.cardinality_k_best`, polynomial); with
    a second row option (seeded births) and a count term the k-best list is grown until the
    k-th exact weight beats every unseen event's upper bound.
:class:`MCMCGenerator`
    R-FISST (document 000 Sec. III): the distinct events an MCMC chain visits after burn-in, each
    weighted exactly (:func:`hypotrack.association.samplers.mcmc_search`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int, check_positive
from ..association import (
    EnumerationBudgetError,
    association_score_matrix,
    best_assignment,
    columns_to_event,
    count_gated_associations,
    enumerate_associations,
    iter_association_chunks,
    murty_k_best,
)
from ..association.cardinality_assignment import cardinality_k_best
from ..association.samplers import MCMC_VARIANTS, checked_search, completion_limit, state_log_weight, to_state
from .association_problem import SEEDED_BIRTH, AssociationProblem
from .one_return import one_return_k_best

__all__ = ["ChildGenerator", "ExhaustiveGenerator", "MurtyGenerator", "MCMCGenerator", "top_k"]


def top_k(log_weights, k):
    """Indices of the ``k`` largest log-weights, best first (stable for ties)."""
    lw = np.asarray(log_weights)
    if k is None or k >= len(lw):
        return np.argsort(-lw, kind="stable")
    part = np.argpartition(-lw, k - 1)[:k]
    return part[np.argsort(-lw[part], kind="stable")]


def _empty_scan(problem: AssociationProblem):
    ev = np.zeros((1, 0), dtype=np.int32)
    return ev, problem.log_weights(ev)


def _feasible(events, lw):
    ok = np.isfinite(lw)
    return (events, lw) if ok.all() else (events[ok], lw[ok])


class ChildGenerator:
    """Base class of the child generators."""

    name = "base"

    def generate(self, problem: AssociationProblem, rng=None, keep=None):  # pragma: no cover - abstract
        raise NotImplementedError


def _enumeration_columns(problem: AssociationProblem):
    """Allowed matrix for the enumerator: exclusive columns, plus one diagonal block (a column per
    return) for each seeded-birth option ``t >= 1`` (a seeded birth, or one of a mixture's components,
    :mod:`.seeded`, is another kind of non-exclusive choice; the enumerator knows only one, clutter)."""
    allowed = problem.allowed
    if problem.n_options > 1:
        seeded = [np.diag(np.isfinite(problem.option_scores[:, t])) for t in range(1, problem.n_options)]
        allowed = np.hstack([allowed] + seeded)
    return allowed


def _decode_enumerated(events, problem):
    """Column ``n_exclusive + (t − 1) m + i`` of the extended matrix → option ``t``'s code ``−1 − t``."""
    if problem.n_options > 1:
        extra = events - problem.n_exclusive
        events = np.where(extra >= 0, SEEDED_BIRTH - extra // max(problem.n_returns, 1), events)
    return events


@dataclass(frozen=True)
class ExhaustiveGenerator(ChildGenerator):
    """Every feasible child (with gating), weighted exactly; bounded by ``max_events``.

    Parameters
    ----------
    max_events : int
        Budget: a parent with more candidate events than this raises
        :class:`hypotrack.association.EnumerationBudgetError` (a ``ValueError`` naming the
        budget) before anything is allocated. This is HOMHT's "break" of document 000 Fig. 15.
    chunk_size : int
        Events per block when streaming (``keep`` given).
    """

    max_events: int = 10**7
    chunk_size: int = 1 << 18
    name = "exhaustive"

    def __post_init__(self):
        check_int(self.max_events, "max_events", minimum=1)
        check_int(self.chunk_size, "chunk_size", minimum=1)

    def generate(self, problem, rng=None, keep=None):
        if problem.n_returns == 0:
            return _empty_scan(problem)
        allowed = _enumeration_columns(problem)
        n_cols = allowed.shape[1]
        if keep is None:
            events = enumerate_associations(n_cols, problem.n_returns, allowed=allowed, max_events=self.max_events)
            events = _decode_enumerated(events, problem)
            return _feasible(events.astype(np.int32, copy=False), problem.log_weights(events))
        n_events = count_gated_associations(allowed, cap=self.max_events)
        if n_events > self.max_events:
            raise EnumerationBudgetError(n_events, self.max_events, exact=False)
        best_ev = np.zeros((0, problem.n_returns), dtype=np.int32)
        best_lw = np.zeros(0)
        for chunk in iter_association_chunks(n_cols, problem.n_returns, allowed=allowed, chunk_size=self.chunk_size):
            chunk = _decode_enumerated(chunk, problem)
            lw = problem.log_weights(chunk)
            sel = top_k(lw, keep)
            best_ev = np.vstack([best_ev, chunk[sel].astype(np.int32)])
            best_lw = np.concatenate([best_lw, lw[sel]])
            sel = top_k(best_lw, keep)
            best_ev, best_lw = best_ev[sel], best_lw[sel]
        return _feasible(best_ev, best_lw)


def _murty_matrix(problem):
    targets = problem.target_scores
    for t in range(1, problem.n_options):  # a diagonal block per seeded option (see _enumeration_columns)
        seeded = np.full((problem.n_returns, problem.n_returns), -np.inf)
        np.fill_diagonal(seeded, problem.option_scores[:, t])
        targets = np.hstack([targets, seeded])
    return association_score_matrix(targets, problem.option_scores[:, 0]), targets.shape[1]


@dataclass(frozen=True)
class MurtyGenerator(ChildGenerator):
    """The ``k`` best children by Murty's k-best assignment (HOMHT-kbest).

    Parameters
    ----------
    k : int
        Children per parent (the filter's ``keep`` overrides it when smaller).
    max_solutions : int
        Budget of assignments ranked while proving the top ``k`` exact for a non-separable
        count term; the best found are returned if it is reached.
    """

    k: int = 100
    max_solutions: int = 100_000
    name = "murty"

    def __post_init__(self):
        check_int(self.k, "k", minimum=1)
        check_int(self.max_solutions, "max_solutions", minimum=1)

    def generate(self, problem, rng=None, keep=None):
        if problem.n_returns == 0:
            return _empty_scan(problem)
        k = self.k if keep is None else min(self.k, keep)
        if problem.n_options == 1 and not problem.count_term_is_constant:
            events, lw = cardinality_k_best(problem.target_scores, problem.option_scores[:, 0], problem.n_objects,
                                            problem.count_term, k)
            return events, lw + problem.constant
        if problem.n_returns == 1 and problem.count_term_is_constant:
            one = one_return_k_best(problem, k)  # Murty's k best of a one-row matrix, its tie order kept
            if one is not None:
                return one
        score, n_cols = _murty_matrix(problem)
        finite_phi = problem.count_term[np.isfinite(problem.count_term)]
        phi_max = float(finite_phi.max()) if finite_phi.size else -np.inf
        exact_order = problem.count_term_is_constant
        request = k
        while True:
            sols = murty_k_best(score, request)
            if not sols:
                return np.zeros((0, problem.n_returns), dtype=np.int32), np.zeros(0)
            cols = np.array([np.asarray(c) for _, c in sols], dtype=np.int64).reshape(len(sols), problem.n_returns)
            events = np.where(cols < n_cols, cols, -1).astype(np.int32)  # columns_to_event of each, in one pass
            events = _decode_enumerated(events, problem)
            lw = problem.log_weights(events)
            events, lw = events[np.isfinite(lw)], lw[np.isfinite(lw)]
            sel = top_k(lw, k)
            exhausted = len(sols) < request
            if exact_order or exhausted or request >= self.max_solutions:
                return events[sel], lw[sel]
            # Every unseen event has a separable total <= the last one ranked, hence an exact
            # weight <= constant + that total + max φ: once the k-th exact weight found beats
            # this bound the top k are proven.
            bound = problem.constant + sols[-1][0] + phi_max
            if len(sel) == k and lw[sel[-1]] >= bound:
                return events[sel], lw[sel]
            request = min(2 * request, self.max_solutions)


@dataclass(frozen=True)
class MCMCGenerator(ChildGenerator):
    """R-FISST's MCMC search (document 000 Sec. III-B).

    Parameters
    ----------
    n_steps : int
        Proposals per parent (document 000 Fig. 15: 100,000).
    burn_in : int, optional
        Steps before recording (default ``n_steps // 10``).
    variant : {"paper", "symmetric", "gibbs"}
        Proposal; ``"paper"`` is document 000's (random return, random column, conflict → clutter).
    init : {"random", "clutter", "best"}
        Starting event: the paper's random assignment ("a row vector … containing a permutation
        of column numbers"), all returns clutter, or the best assignment of the separable part.
    temperature : float
        The chain targets ``w^(1/T)`` (1 = the paper's Metropolis test). As a search a flatter
        target visits more of the light children; their weights are exact regardless.
    completion_rounds, completion_threshold :
        After the chain, add the single-move neighbours of the found children that weigh at
        least ``completion_threshold`` times the best (repeated ``completion_rounds`` times;
        :func:`hypotrack.association.samplers.neighbour_completion`). ``0`` rounds is the paper's
        search alone. The chain finds the modes; the completion finds the light children next
        to them that a 10⁵-step chain meets too rarely (tests: every child above 10⁻⁶ found).
    completion_memory_mb : float
        The completion's memory bound (MiB, > 0; default 2048): it holds at most
        :func:`~hypotrack.association.samplers.completion_limit` events (with the copy returned when no ``keep`` is
        asked), keeping the heaviest (near the mode of a group of hundreds of returns the single moves above
        ``completion_threshold`` number tens of millions; unbounded they outgrew 16 GB). Below the bound nothing
        changes. With ``keep`` (the filter's cap) the search holds only what can be among the ``keep`` heaviest in
        the completion's last round and returns those, exactly the ``keep`` heaviest of the search without
        ``keep`` (:func:`hypotrack.association.samplers.mcmc_search`; ties at the ``keep``-th weight: the first
        found): in a group of 876 returns (the catalogue cloned to N = 10⁶) the last round's moves filled the 2 GiB
        bound without it (~600,000 events, and their copies), 20 with it.
    """

    n_steps: int = 100_000
    burn_in: int | None = None
    variant: str = "paper"
    init: str = "random"
    temperature: float = 1.0
    completion_rounds: int = 2
    completion_threshold: float = 1e-9
    completion_memory_mb: float = 2048.0
    name = "mcmc"

    def __post_init__(self):
        check_int(self.n_steps, "n_steps", minimum=1)
        if self.burn_in is not None:
            check_int(self.burn_in, "burn_in", minimum=0, maximum=self.n_steps)
        if self.variant not in MCMC_VARIANTS:
            raise ValueError(f"variant must be one of {MCMC_VARIANTS}, got {self.variant!r}")
        check_positive(self.temperature, "temperature")
        check_int(self.completion_rounds, "completion_rounds", minimum=0)
        check_positive(self.completion_memory_mb, "completion_memory_mb")
        if not 0 < self.completion_threshold < 1:
            raise ValueError(f"completion_threshold must lie in (0, 1), got {self.completion_threshold!r}")
        if self.init not in ("random", "clutter", "best"):
            raise ValueError(f"init must be 'random', 'clutter' or 'best', got {self.init!r}")

    def _initial_event(self, problem, rng):
        m = problem.n_returns
        init = np.full(m, -1, dtype=np.int64)
        if self.init == "random":
            perm = rng.permutation(problem.n_exclusive + 1)  # the +1 is the clutter column
            # Return i takes column perm[i] when that is an exclusive column it may take.
            cols = perm[: min(m, len(perm))]
            rows = np.flatnonzero(cols < problem.n_exclusive)
            rows = rows[np.isfinite(problem.target_scores[rows, cols[rows]])]
            init[rows] = cols[rows]
        elif self.init == "best":
            score, n_cols = _murty_matrix(problem)
            _, cols = best_assignment(score)
            init = _decode_enumerated(np.asarray(columns_to_event(cols, n_cols))[None], problem)[0]
        # Feasibility as problem.log_weights(init[None]) decides it (the same sum, in the same order).
        score, n_obj, n_excl, count_term = problem.checked
        if not np.isfinite(problem.constant + state_log_weight(score, to_state(init, n_excl), n_obj, n_excl, count_term)):
            init = np.full(m, -1, dtype=np.int64)
        return init

    def generate(self, problem, rng=None, keep=None):
        if problem.n_returns == 0:
            return _empty_scan(problem)
        rng = np.random.default_rng(rng)
        init = self._initial_event(problem, rng)
        burn_in = self.n_steps // 10 if self.burn_in is None else self.burn_in
        # mcmc_search without re-validating the problem (checked once) and this generator's options
        # (checked at construction); the starting event is feasible by construction.
        score, n_obj, n_excl, count_term = problem.checked
        events, lw = checked_search(
            score, n_obj, n_excl, count_term, to_state(init, n_excl),
            n_steps=self.n_steps, burn_in=burn_in, seed=int(rng.integers(2**63 - 1)),
            variant=self.variant, temperature=float(self.temperature),
            completion_rounds=self.completion_rounds, completion_threshold=float(self.completion_threshold),
            completion_max_events=completion_limit(problem.n_returns, self.completion_memory_mb,
                                                   returned=keep is None),
            keep=keep,
        )
        lw = lw + problem.constant
        if keep is not None:  # the search's keep heaviest, best first (ties: the first visited)
            return events, lw
        sel = top_k(lw, None)
        return events[sel], lw[sel]

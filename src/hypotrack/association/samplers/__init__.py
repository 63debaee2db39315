"""The association samplers: searches over the association events of one parent hypothesis.

One floor, five modules, read in this order:

:mod:`.events`
    An event's two encodings (public codes, the samplers' state codes), the problem's
    validation, exact log-weights ``Σ_i score[i, a_i] + φ[k, b]`` (compiled gather-sum).
:mod:`.visited`
    The visited set: the distinct events met, in order of first visit, with their weights
    (Zobrist-hashed open addressing, exact row comparison on a hash hit).
:mod:`.selection`
    The ``k`` heaviest of a search's events, ties at the ``k``-th decided by order of first visit.
:mod:`.gibbs`
    The exact conditional draw of one row, and the systematic-scan Gibbs sweeps of the δ-GLMB
    filter (Vo, Vo & Hoang 2017).
:mod:`.chain`
    R-FISST's MCMC chain (document 000 Sec. III-B) with its symmetric and random-scan Gibbs
    variants, and the neighbour completion that follows it (asked for the ``keep`` heaviest, it holds only what
    can be among them).

Every sampler is used as a *search* (DESIGN.md §4.3): it returns the distinct events visited,
each with its exact log-weight, never visit counts. The child generators of
:mod:`hypotrack.hypotheses` (``MCMCGenerator``, ``GibbsGenerator``) are adapters over these.
"""

from .chain import MCMC_VARIANTS, checked_search, completion_limit, mcmc_search, neighbour_completion
from .events import (
    check_problem,
    checked_event_log_weights,
    count_delta,
    event_log_weights,
    gather_sum,
    owners_and_counts,
    state_log_weight,
    to_events,
    to_state,
)
from .gibbs import checked_sweep_search, gibbs_draw, move_row, sweep_search
from .selection import heaviest_heap, top_k_first
from .visited import Visited, clear_table, insert_rows, lookup_or_insert, zobrist_keys

__all__ = [
    "MCMC_VARIANTS",
    "mcmc_search",
    "checked_search",
    "neighbour_completion",
    "completion_limit",
    "top_k_first",
    "heaviest_heap",
    "sweep_search",
    "checked_sweep_search",
    "gibbs_draw",
    "move_row",
    "check_problem",
    "event_log_weights",
    "checked_event_log_weights",
    "gather_sum",
    "state_log_weight",
    "owners_and_counts",
    "count_delta",
    "to_state",
    "to_events",
    "Visited",
    "lookup_or_insert",
    "insert_rows",
    "clear_table",
    "zobrist_keys",
]

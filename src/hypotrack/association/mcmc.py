"""R-FISST's MCMC search: the former home of the samplers, kept for existing callers.

The chain, its Gibbs variants, the event weights and the visited set now live in
:mod:`hypotrack.association.samplers` (one module per job); this module re-exports the public
names it has always had, so ``from hypotrack.association.mcmc import mcmc_search`` keeps working.
"""

from .samplers.chain import MCMC_VARIANTS, checked_search, mcmc_search, neighbour_completion
from .samplers.events import check_problem, checked_event_log_weights, event_log_weights, to_state

__all__ = [
    "MCMC_VARIANTS",
    "check_problem",
    "checked_event_log_weights",
    "checked_search",
    "event_log_weights",
    "mcmc_search",
    "neighbour_completion",
    "to_state",
]

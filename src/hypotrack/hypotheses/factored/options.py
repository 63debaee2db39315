"""The factored filter's options, stated and validated once: :class:`FactoredOptions`."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..._validation import check_int
from ..population_adaptive import AdaptiveBirth

__all__ = ["FactoredOptions", "SPLITS", "BIRTHS", "PARALLEL"]

SPLITS = ("marginal", "exact", "never")
BIRTHS = ("coupled", "free")
PARALLEL = ("process", "thread")


@dataclass(frozen=True)
class FactoredOptions:
    """How :class:`~.filter.FactoredFilter` factors, prunes and parallelises (the engine's own
    settings — models, cap, gate — are the :class:`~..filter.HypothesisFilter`'s).

    Every option has its one default here; a bad value raises an error naming the option and its
    allowed values.

    Parameters
    ----------
    split : {"marginal", "exact", "never"}
        When groups whose objects no longer interact are split (package docstring, step 4).
    births : {"coupled", "free"}
        ``"coupled"``: a birth term is linked to every return it could be the first detection
        of (exact). ``"free"``: only to returns in no group's gate — returns near an existing
        object are never births (an approximation unless the birth terms and the gates are
        disjoint); use it for birth pdfs that cover the whole view (document 000/001 regions),
        which would otherwise merge every group with a return into one.
    factor_tol : float
        Largest ``|log P − log Π marginals|`` for a split to count as exact (finite, > 0).
    min_weight : float
        Hypotheses of a group below this normalised weight are dropped after each scan
        (in [0, 1); 0 keeps all — needed for exactness; > 0 stops undetected-birth groups of
        negligible existence from accumulating).
    adaptive_birth : AdaptiveBirth, optional
        Measurement-driven birth: the returns a scan leaves unexplained become the next scan's
        birth terms (:class:`~..population_adaptive.AdaptiveBirth`). Needs a population with no
        birth terms of its own (labeled multi-Bernoulli or binomial), whose terms it then sets every scan.
    workers : int
        Processes (or threads) sharing a scan's engine steps (≥ 1). The components of a scan are
        independent problems; ``workers = 1`` runs them here, in order; more splits them into
        ``workers`` chunks of similar cost (hypotheses × returns), one run here and the others in
        a pool. Each step draws from its own random stream (seeded from the filter's generator,
        in component order) and new labels are renumbered in component order, so the posterior
        is the same for any ``workers``.
    parallel : {"process", "thread"}
        Pool kind: processes (the template engine and the groups' states pickled each scan) or
        threads (useful only where the step's kernels release the GIL).
    measure_transfer : bool
        Record in ``last_stats`` the pickled bytes of the steps' inputs (``bytes_to_workers``: the
        groups' hypotheses, track moments and the returns of their gates) and results
        (``bytes_from_workers``) even when ``workers = 1``.
    lazy : bool
        Predict a singleton, or a group, only when the predicted mean of one of its tracks is in the
        field of view (package docstring, "Singletons and lazy prediction"). ``False`` (the default)
        predicts every track every scan, as the unfactored engine does; the SSA catalogue
        experiment's configuration turns it on (its trackers' ``factored: {lazy: true}``). A track left unpredicted
        gates nothing. The covariance predicted over a long gap is an approximation (package docstring: over an
        orbit's gap between passes, far from the scan-by-scan one).
    gate_out_of_view : bool
        ``True`` (default): a track's gate is geometric, the field of view entering only through
        ``p_D`` — a track out of view still links the returns in its gate to its group (a merge
        that changes no weight, since it cannot take them, and is split again exactly).
        ``False``: a track whose predicted mean is out of view (``p_D = 0``) gates nothing. The
        posterior is the same; only merges that cannot matter are avoided — at catalogue scale an
        undetected newborn out of view, whose covariance grows by ~80 km a scan, otherwise gates
        every return in view and merges every object there into one group.
    replay : bool
        With ``lazy``: predict a track woken after a gap over that gap in steps of the scan interval
        (:func:`~.lane.predict_each` with ``step``), the predictions the eager filter makes, instead of in
        one step (whose process noise is far off over an orbit's gap between passes, package
        docstring). ``False`` (the default) keeps the one step. The scan's predictions only:
        :attr:`~.engine.FactoredFilter.posterior` and ``groups`` still predict the tracks left
        asleep in one step.
    fast_path : bool
        Step the components that are one lone track with one return nothing else gates, and whose
        general step would keep only the detected child (every alternative below ``min_weight``),
        in one batch instead of one engine step each (:mod:`.fast_path`); also drops the quiet groups
        whose empty-scan step keeps no object and steps the lone birth terms keeping both children
        from a template, and steps the quiet groups of one-track hypotheses under per-track deaths in
        closed form (:mod:`.sleeping`): the same posterior, the same random streams and labels for the
        other steps.
        ``False`` (the default) steps every component through the engine. Takes nothing with
        ``min_weight = 0``.
    bernoulli_lane : bool
        With a labeled multi-Bernoulli population whose tracks may die (``p_S < 1``, or a per-track
        ``survival``): the lane holds every singleton as a Bernoulli (its existence ``r`` beside its moments,
        :func:`~.lane.bernoulli`), so a track of ``p_S < 1`` stays in the lane instead of becoming a group
        stepped every scan; the posterior is the general engine's (one track, two hypotheses: exists / not).
        ``False`` (the default): the lane holds only the tracks of ``p_S = 1``. No effect with a silent
        population (every ``r`` stays 1) or another population. Turns the fast path off (its rule assumes
        ``r = 1``).

    Examples
    --------
    >>> FactoredOptions(lazy=True).with_changes(workers=2).workers
    2
    >>> FactoredOptions(min_weight=1.0)
    Traceback (most recent call last):
    ...
    ValueError: min_weight must lie in [0, 1), got 1.0
    """

    split: str = "marginal"
    births: str = "coupled"
    factor_tol: float = 1e-10
    min_weight: float = 0.0
    adaptive_birth: object = None
    workers: int = 1
    parallel: str = "process"
    measure_transfer: bool = False
    lazy: bool = False
    gate_out_of_view: bool = True
    fast_path: bool = False
    replay: bool = False
    bernoulli_lane: bool = False

    def __post_init__(self):
        for name, allowed in (("split", SPLITS), ("births", BIRTHS), ("parallel", PARALLEL)):
            if getattr(self, name) not in allowed:
                raise ValueError(f"{name} must be one of {allowed}, got {getattr(self, name)!r}")
        tol = _number(self.factor_tol, "factor_tol", "a finite number > 0")
        if not (math.isfinite(tol) and tol > 0):
            raise ValueError(f"factor_tol must be a finite number > 0, got {self.factor_tol!r}")
        w = _number(self.min_weight, "min_weight", "a number in [0, 1)")
        if not 0.0 <= w < 1.0:
            raise ValueError(f"min_weight must lie in [0, 1), got {self.min_weight!r}")
        workers = check_int(self.workers, "workers", minimum=1)
        if self.adaptive_birth is not None and not isinstance(self.adaptive_birth, AdaptiveBirth):
            raise TypeError(f"adaptive_birth must be an AdaptiveBirth or None, got {type(self.adaptive_birth).__name__}")
        for name in ("measure_transfer", "lazy", "gate_out_of_view", "fast_path", "replay", "bernoulli_lane"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise TypeError(f"{name} must be True or False, got {getattr(self, name)!r}")
        object.__setattr__(self, "factor_tol", tol)
        object.__setattr__(self, "min_weight", w)
        object.__setattr__(self, "workers", workers)
        for name in ("measure_transfer", "lazy", "gate_out_of_view", "fast_path", "replay", "bernoulli_lane"):
            object.__setattr__(self, name, bool(getattr(self, name)))

    @classmethod
    def names(cls) -> tuple:
        """The options' names, in order."""
        return tuple(f.name for f in fields(cls))

    @classmethod
    def from_keywords(cls, **options) -> "FactoredOptions":
        """The options from keywords, refusing unknown ones (their names listed in the error)."""
        unknown = set(options) - set(cls.names())
        if unknown:
            raise ValueError(f"unknown options {sorted(unknown)}; allowed: {', '.join(cls.names())}")
        return cls(**options)

    def with_changes(self, **changes) -> "FactoredOptions":
        """These options with ``changes`` (validated like the constructor's)."""
        unknown = set(changes) - set(self.names())
        if unknown:
            raise ValueError(f"unknown options {sorted(unknown)}; allowed: {', '.join(self.names())}")
        return replace(self, **changes)


def _number(value, name: str, what: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {what}, got {value!r}") from None


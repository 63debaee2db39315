"""The ledger's verdict rules: an equivalence test for Monte Carlo rows, and negative controls.

Monte Carlo rows (an equivalence test)
--------------------------------------
With n runs, mean x̄ and standard error s, the row's interval is ``x̄ ± q·s`` where q is the
Student-t quantile of n − 1 degrees of freedom with the two-sided coverage of ±3 normal standard
errors (:data:`COVERAGE` = 99.73 %; q = 3 for large n, 4.09 at n = 10, 5.5 at n = 5). When the
published number is itself a Monte Carlo estimate over ``published_runs`` runs, its own standard
error, sd/√published_runs with sd = s·√n this project's spread, is added in quadrature. Against
the published value p with the stated tolerance τ (every tolerance carries its reason in the config):

* *reproduced* when the whole interval lies inside [p − τ, p + τ];
* *not reproduced* when it lies entirely outside;
* *inconclusive* otherwise, with the number of runs that would decide it (:attr:`Verdict.runs_to_decide`).

A wide interval therefore never reproduces: 0.899 ± 0.067 over 10 seeds against 1 ± 0.01 is
*inconclusive* (it would have been *reproduced* by |z| ≤ 3), and 50.064 ± 0.008 against 50 ± 0.1
is *reproduced*.

Negative controls (power)
-------------------------
A *reproduced* or *qualitative* check is informative only when a control built to break what the
claim is about (a blind tracker that predicts without measurements, a trivial estimator, a single
linear assignment, the engine with a known defect) *fails* it. :func:`control_text` writes the
ledger's ``control`` column; :func:`with_control` demotes a row whose control also passes to
*uninformative*.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import NamedTuple

from scipy import stats

__all__ = ["COVERAGE", "Verdict", "control_text", "interval_quantile", "monte_carlo_verdict", "parse_control",
           "with_control"]

COVERAGE = 0.9973  # two-sided coverage of +/- 3 standard errors under a normal law
CONTROL_FAILS, CONTROL_PASSES = "fails", "also passes"


class Verdict(NamedTuple):
    """A Monte Carlo row's verdict: z (for reference), status, the interval and the runs that would decide."""

    z: float
    status: str
    low: float
    high: float
    runs_to_decide: float | None  # inconclusive rows only; inf when no number of runs can decide


def interval_quantile(n: int | None) -> float:
    """q of the row's interval x̄ ± q·s: the t quantile of n − 1 d.o.f. at :data:`COVERAGE` (3 without n)."""
    if n is None:
        return 3.0
    if int(n) < 2:
        raise ValueError(f"n must be >= 2, got {n}")
    return float(stats.t.ppf(0.5 + COVERAGE / 2, df=int(n) - 1))


def monte_carlo_verdict(mean: float, se: float, published: float, tolerance: float, n: int | None = None,
                        published_runs: int | None = None) -> Verdict:
    """The equivalence verdict of one Monte Carlo row (module docstring).

    Parameters
    ----------
    mean, se : the row's mean and standard error over ``n`` runs.
    published : the document's number; ``tolerance`` (>= 0, absolute, units of ``mean``) around it.
    published_runs : the number of runs behind ``published`` when it is a Monte Carlo estimate.
    """
    for name, v in (("mean", mean), ("published", published)):
        if not math.isfinite(v):
            raise ValueError(f"{name} must be finite, got {v!r}")
    if not (se >= 0 and math.isfinite(se)):
        raise ValueError(f"se must be finite and >= 0, got {se!r}")
    if not tolerance >= 0:
        raise ValueError(f"tolerance must be >= 0, got {tolerance!r}")
    if published_runs is not None and int(published_runs) < 1:
        raise ValueError(f"published_runs must be >= 1, got {published_runs!r}")
    if published_runs is not None and n is None:
        raise ValueError("published_runs needs n (the spread sd = se * sqrt(n) gives the published s.e.)")
    diff = mean - published
    sd = se * math.sqrt(n) if n is not None else None
    total_se = math.hypot(se, sd / math.sqrt(published_runs)) if published_runs is not None else se
    z = diff / total_se if total_se > 0 else (0.0 if diff == 0 else math.copysign(math.inf, diff))
    half = interval_quantile(n) * total_se
    low, high = mean - half, mean + half
    lo_tol, hi_tol = published - tolerance, published + tolerance
    if lo_tol <= low and high <= hi_tol:
        return Verdict(z, "reproduced", low, high, None)
    if high < lo_tol or low > hi_tol:
        return Verdict(z, "not reproduced", low, high, None)
    return Verdict(z, "inconclusive", low, high, _runs_to_decide(abs(diff), tolerance, sd, published_runs))


_MAX_RUNS = 10 ** 15


def _runs_to_decide(gap: float, tolerance: float, sd: float | None, published_runs: int | None) -> float | None:
    """The fewest runs n' (at least 2) at which the rule's own interval around the same mean,
    q(n')·sqrt(sd²/n' + sd²/published_runs) with q the t quantile of n' − 1 d.o.f. (:func:`interval_quantile`),
    would clear the tolerance's edge; inf when no number of runs can (the published number's own error too
    large, or the mean on the edge)."""
    if sd is None:
        return None
    margin = abs(tolerance - gap)  # room inside the tolerance, or distance beyond it
    published_var = sd ** 2 / published_runs if published_runs else 0.0
    room = (margin / 3.0) ** 2 - published_var  # q >= 3 for every n': a lower bound on n'
    if margin == 0 or room <= 0:
        return math.inf

    def decides(k: int) -> bool:
        return interval_quantile(k) ** 2 * (sd ** 2 / k + published_var) <= margin ** 2

    lo = max(2, math.ceil(sd ** 2 / room))
    if lo > _MAX_RUNS:  # q is 3 to many digits there (and the t quantile takes no such integer): the bound is n'
        return float(lo)
    if decides(lo):
        return float(lo)
    hi = 2 * lo
    while not decides(hi):  # q(n') falls to 3 and sd²/n' to 0, so some n' decides when room > 0 ...
        if hi > _MAX_RUNS:  # ... and beyond this size q is 3 to many digits: the lower bound is the answer
            return float(hi)
        hi *= 2
    while hi - lo > 1:  # decides() is monotone in n': bisect for the fewest
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if decides(mid) else (mid, hi)
    return float(hi)


def control_text(what: str, value: str, passes: bool) -> str:
    """The ``control`` cell: what ran, its value, and whether it *fails* the row's check (as it should)."""
    if not what or ":" in what:
        raise ValueError(f"what must name the control without ':' , got {what!r}")
    return f"{what}: {value} -> {CONTROL_PASSES if passes else CONTROL_FAILS}"


def parse_control(text: str) -> tuple[str, str, bool] | None:
    """``(what, value, passes)`` of a ``control`` cell, None when the cell is empty."""
    if not text:
        return None
    head, sep, outcome = text.rpartition(" -> ")
    what, colon, value = head.partition(": ")
    if not sep or not colon or outcome not in (CONTROL_FAILS, CONTROL_PASSES):
        raise ValueError(f"control must read '<what>: <value> -> fails|also passes', got {text!r}")
    return what, value, outcome == CONTROL_PASSES


def with_control(claim, what: str, value: str, passes: bool):
    """``claim`` with its control; a *reproduced* or *qualitative* row whose control also passes becomes
    *uninformative* (the check has no power: it cannot tell the method from its broken form)."""
    status = claim.status
    if passes and status in ("reproduced", "qualitative"):
        status = "uninformative"
    return replace(claim, control=control_text(what, value, passes), status=status)

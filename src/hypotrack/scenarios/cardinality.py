"""Counts-only scenario of the cardinality-tracking example (document 003, §4, Fig. 4.2).

Targets are born Poisson(λ_b) per scan and each dies before the next scan with probability
p_χ (the discrete-time statistics of Eqs. 2.1–2.2); every live target is detected with
probability p_d and Poisson(λ_fa) false alarms are added. Only the number of returns per scan
is observed. By default the truth starts in steady state, Poisson(λ_b/p_χ) targets at the first
scan, which is what the trackers assume for tracks present at the start of the data
(reconstruction §6.1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_int, check_nonnegative, check_positive, check_probability, check_seed

__all__ = ["CardinalityRealisation", "simulate_cardinality"]


@dataclass(frozen=True)
class CardinalityRealisation:
    """Ground truth and data of one counts-only realisation.

    Attributes
    ----------
    birth, death : (n_targets,) int arrays
        Scan of each target's birth and the first scan it is no longer alive (``n_scans`` if
        it survives to the end); a target is alive on scans ``birth .. death − 1``.
    n_true : (T,) number of live targets per scan.
    n_detected : (T,) number of detected targets per scan.
    n_false : (T,) number of false alarms per scan.
    r : (T,) measured counts ``n_detected + n_false``.
    """

    birth: np.ndarray
    death: np.ndarray
    n_true: np.ndarray
    n_detected: np.ndarray
    n_false: np.ndarray

    @property
    def r(self) -> np.ndarray:
        return self.n_detected + self.n_false


def simulate_cardinality(
    *, n_scans: int, p_chi: float, lambda_b: float, p_d: float, lambda_fa: float, rng, start: str = "steady_state"
) -> CardinalityRealisation:
    """Simulate births, deaths, detections and false alarms; return the counts.

    Parameters
    ----------
    n_scans : int
        Number of scans T (250 in Fig. 4.2).
    p_chi : float
        Per-scan death probability, in (0, 1).
    lambda_b : float
        Mean births per scan, >= 0.
    p_d : float
        Detection probability, in [0, 1] (not stated in the paper).
    lambda_fa : float
        Mean false alarms per scan, >= 0.
    rng : numpy.random.Generator or int
    start : {"steady_state", "empty"}
        Steady state: Poisson(λ_b/p_χ) targets at the first scan; empty: only the first scan's
        Poisson(λ_b) births ("no targets at t₀", paper §2).
    """
    T = check_int(n_scans, "n_scans", minimum=1)
    p_chi = check_probability(p_chi, "p_chi", low_open=True, high_open=True)
    lambda_b = check_nonnegative(lambda_b, "lambda_b")
    p_d = check_probability(p_d, "p_d")
    lambda_fa = check_nonnegative(lambda_fa, "lambda_fa")
    if start not in ("steady_state", "empty"):
        raise ValueError(f"start must be 'steady_state' or 'empty', got {start!r}")
    rng = np.random.default_rng(check_seed(rng, "rng"))
    births_per_scan = rng.poisson(lambda_b, size=T)
    if start == "steady_state":
        births_per_scan[0] = rng.poisson(check_positive(lambda_b, "lambda_b") / p_chi) if lambda_b > 0 else 0
    birth = np.repeat(np.arange(T), births_per_scan)
    # Lifetime in scans: alive at birth, then survives each later scan with probability 1 − p_χ.
    death = np.minimum(birth + rng.geometric(p_chi, size=birth.size), T)
    n_true = np.zeros(T + 1, dtype=np.int64)
    np.add.at(n_true, birth, 1)
    np.add.at(n_true, death, -1)
    n_true = np.cumsum(n_true)[:T]
    n_detected = rng.binomial(n_true, p_d)
    n_false = rng.poisson(lambda_fa, size=T)
    return CardinalityRealisation(birth, death, n_true, n_detected, n_false)

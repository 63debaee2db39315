"""The ideal filter's MOSPA on the two-target OU problem in closed form (document 003 Table 6.1).

With known measurement origin each target has its own scalar Kalman filter on the N-sensor
average (variance r = R/N). Everything is linear and Gaussian with zero mean, so the pair
``(x_k, x̂_k)`` of one target — truth and estimate — is a zero-mean Gaussian whose 2×2
covariance follows an exact recursion (the filter's gain sequence comes from the Riccati
recursion of Eqs. 5.7–5.11; the truth from Eqs. 5.1–5.3). For two independent targets, with
``e_j = x̂_j − x_j``, ``Δ = x_2 − x_1`` and ``s = x̂_2 − x̂_1``, the squared OSPA of
:func:`~hypotrack.trackers.ecmht.mospa_two_targets` (p = 2, no cut-off, reconstruction §5.4) is

    d_k = min(½ Σ e_j², ½[(x̂_1 − x_2)² + (x̂_2 − x_1)²]) = ½ Σ e_j² + min(0, Δ s),

and ``E[min(0, XY)]`` of a zero-mean bivariate normal with standard deviations σ_x, σ_y and
correlation ρ is ``σ_x σ_y (ρ/2 − (√(1 − ρ²) + ρ arcsin ρ)/π)`` (half of ``E[XY] − E|XY|``).
So ``E[d_k]`` needs no integral at all. This module shares no code with the trackers: it is the
independent reference the Monte Carlo ideal filter is tested against, and the tool that finds
which unstated convention of the paper gives the published 0.0363.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pandas as pd

from ..._validation import check_int, check_nonnegative, check_positive

__all__ = [
    "expected_negative_part",
    "ideal_mospa_per_scan",
    "ideal_mospa",
    "riccati_steady_prediction",
    "ideal_conventions_table",
    "parameters_reaching",
]

SCORINGS = ("pairing", "labelled")
ESTIMATES = ("predicted", "filtered")
INITIALISATIONS = ("measurement", "prior")


def expected_negative_part(var_x: float, var_y: float, cov: float) -> float:
    """``E[min(0, XY)]`` for ``(X, Y)`` zero-mean bivariate normal with the given moments."""
    if var_x <= 0 or var_y <= 0:
        return 0.0
    sd = math.sqrt(var_x * var_y)
    rho = min(1.0, max(-1.0, cov / sd))
    return sd * (rho / 2 - (math.sqrt(1 - rho * rho) + rho * math.asin(rho)) / math.pi)


def _ou(sigma2, gamma, dt):
    A = math.exp(-gamma * dt)
    return A, sigma2 / (2 * gamma) * (1 - A * A)  # Eqs. 5.2-5.3


def riccati_steady_prediction(*, sigma2: float, gamma: float, n_sensors: int, R: float, dt: float = 1.0) -> float:
    """Steady state ``P(k|k−1)`` of the scalar Riccati recursion with measurement variance R/N.

    The fixed point of ``P = A² P r/(P + r) + Q`` is the positive root of
    ``P² + (r(1 − A²) − Q) P − Q r = 0``.
    """
    A, Q = _ou(check_positive(sigma2, "sigma2"), check_positive(gamma, "gamma"), check_positive(dt, "dt"))
    r = check_positive(R, "R") / check_int(n_sensors, "n_sensors", minimum=1)
    b = r * (1 - A * A) - Q
    return (-b + math.sqrt(b * b + 4 * Q * r)) / 2


def ideal_mospa_per_scan(*, sigma2: float, gamma: float, n_scans: int, n_sensors: int, R: float, dt: float = 1.0,
                         initial_variance: float = 0.01, scoring: str = "pairing", estimate: str = "predicted",
                         initialisation: str = "measurement") -> np.ndarray:
    """Expected squared OSPA of the ideal filter at scans 2..n_scans, ``(n_scans − 1,)`` (m²).

    Parameters
    ----------
    sigma2, gamma, dt : float
        OU intensity (m²/s), mean-reversion rate (1/s), scan interval (s).
    n_scans, n_sensors : int
    R : float
        Per-sensor measurement variance (m²); the filter sees the N-sensor average, variance R/N.
    initial_variance : float
        Variance v₀ of each target's initial position, ``X₀ ~ N(0, v₀)``.
    scoring : {"pairing", "labelled"}
        ``pairing``: the better of the two track–truth pairings per scan (the OSPA of §5.4);
        ``labelled``: each track against its own target (the error the Riccati variance describes).
    estimate : {"predicted", "filtered"}
        Score ``X(k|k−1)`` (reconstruction §6.4) or ``X(k|k)``.
    initialisation : {"measurement", "prior"}
        ``measurement``: ``X(1|1)`` = the first average, ``P(1|1) = R/N`` (Eqs. 6.1–6.3);
        ``prior``: a Bayes update of the prior ``N(0, v₀)`` with the first average.
    """
    for name, value, allowed in (("scoring", scoring, SCORINGS), ("estimate", estimate, ESTIMATES),
                                 ("initialisation", initialisation, INITIALISATIONS)):
        if value not in allowed:
            raise ValueError(f"{name} must be one of {allowed}, got {value!r}")
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    v0 = check_nonnegative(initial_variance, "initial_variance")
    A, Q = _ou(check_positive(sigma2, "sigma2"), check_positive(gamma, "gamma"), check_positive(dt, "dt"))
    r = check_positive(R, "R") / check_int(n_sensors, "n_sensors", minimum=1)
    # C = Cov(x, x̂) of one target: [[xx, xh], [xh, hh]].
    if initialisation == "measurement":
        xx, xh, hh = v0, v0, v0 + r
    else:
        g = v0 / (v0 + r)
        xx, xh, hh = v0, g * v0, g * g * (v0 + r)
    out = np.empty(n_scans - 1)
    for k in range(n_scans - 1):
        pxx, pxh, phh = A * A * xx + Q, A * A * xh, A * A * hh  # x_k = A x + w, x̂(k|k−1) = A x̂
        P = pxx - 2 * pxh + phh  # the actual error variance of X(k|k−1)
        L = P / (P + r)  # Eq. 5.11 with S of Eq. 6.4
        # x̂(k|k) = (1 − L) x̂(k|k−1) + L (x_k + v̄)
        uxh = (1 - L) * pxh + L * pxx
        uhh = (1 - L) ** 2 * phh + 2 * L * (1 - L) * pxh + L * L * (pxx + r)
        sxx, sxh, shh = (pxx, pxh, phh) if estimate == "predicted" else (pxx, uxh, uhh)
        err = sxx - 2 * sxh + shh
        # (Δ, s) of two independent targets: twice one target's (x, x̂) moments.
        out[k] = err + (expected_negative_part(2 * sxx, 2 * shh, 2 * sxh) if scoring == "pairing" else 0.0)
        xx, xh, hh = pxx, uxh, uhh
    return out


def ideal_mospa(*, transient_scans: int = 0, **kwargs) -> float:
    """Mean of :func:`ideal_mospa_per_scan` over the scored scans after the first ``transient_scans``."""
    per_scan = ideal_mospa_per_scan(**kwargs)
    transient_scans = check_int(transient_scans, "transient_scans", minimum=0, maximum=len(per_scan) - 1)
    return float(per_scan[transient_scans:].mean())


def ideal_conventions_table(*, sigma2, gamma, n_scans, n_sensors, R, dt, initial_variances, transient_scans,
                            published: float, rounding: float) -> pd.DataFrame:
    """The ideal MOSPA in closed form under every combination of the conventions the paper leaves open.

    Rows: initial variance × scoring × estimate × initialisation × window (all scored scans, or
    after ``transient_scans``), plus the Riccati steady state. ``matches_published`` marks the
    values within ``rounding`` of ``published`` (half a unit of its last printed digit).
    """
    rows = []
    for v0, scoring, estimate, init, skip in itertools.product(initial_variances, SCORINGS, ESTIMATES,
                                                                INITIALISATIONS, (0, transient_scans)):
        value = ideal_mospa(sigma2=sigma2, gamma=gamma, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
                            initial_variance=v0, scoring=scoring, estimate=estimate, initialisation=init,
                            transient_scans=skip)
        rows.append({"initial_variance": v0, "scoring": scoring, "estimate": estimate, "initialisation": init,
                     "transient_scans": skip, "closed_form": value})
    df = pd.DataFrame(rows).drop_duplicates(subset=["initial_variance", "scoring", "estimate", "initialisation",
                                                    "transient_scans"])
    steady = riccati_steady_prediction(sigma2=sigma2, gamma=gamma, n_sensors=n_sensors, R=R, dt=dt)
    df = pd.concat([df, pd.DataFrame([{"initial_variance": np.nan, "scoring": "labelled", "estimate": "predicted",
                                       "initialisation": "steady state", "transient_scans": -1,
                                       "closed_form": steady}])], ignore_index=True)
    df["published"] = published
    df["relative_difference"] = df["closed_form"] / published - 1
    df["matches_published"] = (df["closed_form"] - published).abs() <= rounding
    return df


def parameters_reaching(target: float, *, sigma2, gamma, n_scans, n_sensors, R, dt, initial_variance) -> dict:
    """How far a stated parameter would have to move for the best-pairing MOSPA (all scans) to equal ``target``.

    Returns the per-sensor variance ``R`` and the OU intensity ``sigma2`` that reach it
    (scipy.optimize.brentq, the MOSPA increases with both), and the MOSPA with one sensor fewer.
    """
    from scipy.optimize import brentq

    kw = dict(gamma=gamma, n_scans=n_scans, dt=dt, initial_variance=initial_variance)
    r_star = brentq(lambda r: ideal_mospa(**kw, sigma2=sigma2, n_sensors=n_sensors, R=r) - target, R / 4, 4 * R)
    s_star = brentq(lambda s: ideal_mospa(**kw, sigma2=s, n_sensors=n_sensors, R=R) - target, sigma2 / 4, 4 * sigma2)
    fewer = ideal_mospa(**kw, sigma2=sigma2, n_sensors=n_sensors - 1, R=R) if n_sensors > 1 else math.nan
    return {"R": r_star, "sigma2": s_star, "one_sensor_fewer": fewer}

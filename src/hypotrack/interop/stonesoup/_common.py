"""Names shared by the adapter's modules."""

from __future__ import annotations

import datetime
import math
from numbers import Real

import numpy as np

from ..._validation import check_covariance
from ...registry import preset

__all__ = ["SINGLE_HYPOTHESIS", "HYPOTHESIS_FILTERS", "GLMB", "PMBM", "LABELED_BIRTHS", "ALGORITHMS", "require_stonesoup",
           "check_tracker_inputs", "check_scan_time"]

#: hypotrack's own kinds, which the adapter's tests run (every kind of hypotrack.registry is accepted).
SINGLE_HYPOTHESIS = ("gnn", "jpda", "pdaf")
GLMB = ("glmb", "glmb_murty")
PMBM = ("pmbm_murty", "pmbm_gibbs")
#: kinds whose births are a labeled multi-Bernoulli population (Stone Soup's ``birth_states`` options)
LABELED_BIRTHS = GLMB + PMBM
HYPOTHESIS_FILTERS = ("hfisst", "rfisst", "homht", "homht_kbest") + GLMB + PMBM
ALGORITHMS = SINGLE_HYPOTHESIS + HYPOTHESIS_FILTERS


def require_stonesoup():
    try:
        import stonesoup  # noqa: F401
    except ImportError as err:  # pragma: no cover - exercised only without Stone Soup
        raise ImportError(
            "hypotrack.interop.stonesoup needs Stone Soup (>= 1.9): pip install 'hypotrack[stonesoup]'"
        ) from err


def _real(value, name):
    if isinstance(value, bool) or not isinstance(value, (Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    return float(value)


def check_tracker_inputs(algorithm, detection_probability, clutter_rate, initial_states, ndim_state):
    """The adapter's own parameters checked with their own names and ranges (the hypotrack trackers
    behind it would name theirs: ``p_D``, ``rate``, ``covs``)."""
    p = _real(detection_probability, "detection_probability")
    if preset(algorithm).family == "poisson_mb" and algorithm not in PMBM:
        raise ValueError(f"algorithm {algorithm!r}: a PMB filter's Bernoullis mix several returns each scan, and the "
                         f"Stone Soup adapter reports single associations; use one of {PMBM}")
    single = preset(algorithm).family == "single"
    if single:
        if not 0.0 < p <= 1.0:
            raise ValueError(f"detection_probability must lie in (0, 1] for {algorithm}, got {detection_probability!r}")
    elif not 0.0 < p < 1.0:
        raise ValueError(f"detection_probability must lie in (0, 1) for the hypothesis filter {algorithm} (its "
                         f"weights hold log(1 - P_D) for every missed object), got {detection_probability!r}")
    rate = _real(clutter_rate, "clutter_rate")
    if (single or preset(algorithm).family == "poisson_mb") and not (math.isfinite(rate) and rate > 0.0):
        raise ValueError(f"clutter_rate must be a finite number > 0 for {algorithm} (its scores divide by the clutter density), "
                         f"got {clutter_rate!r}")
    if not (math.isfinite(rate) and rate >= 0.0):
        raise ValueError(f"clutter_rate (expected clutter returns per scan) must be a finite number >= 0, got {clutter_rate!r}")
    if initial_states is None:
        return
    if isinstance(initial_states, (str, bytes)) or not hasattr(initial_states, "__iter__"):
        raise TypeError(f"initial_states must be a list of GaussianStates, got {type(initial_states).__name__}")
    d = int(ndim_state)
    for k, s in enumerate(initial_states):
        name = f"initial_states[{k}]"
        if not (hasattr(s, "state_vector") and hasattr(s, "covar")):
            raise TypeError(f"{name} must be a GaussianState (state_vector and covar), got {type(s).__name__}")
        try:
            mean = np.asarray(s.state_vector, dtype=float)
        except (TypeError, ValueError):
            raise TypeError(f"{name}.state_vector must hold numbers") from None
        if mean.shape not in ((d,), (d, 1)) or not np.all(np.isfinite(mean)):
            raise ValueError(f"{name}.state_vector must hold {d} finite components (the transition model's "
                             f"state), got shape {mean.shape}")
        check_covariance(np.asarray(s.covar, dtype=float), f"{name}.covar", dim=d)
        stamp = getattr(s, "timestamp", None)
        if stamp is not None and not isinstance(stamp, datetime.datetime):
            raise TypeError(f"{name}.timestamp must be a datetime.datetime or None, got {type(stamp).__name__}")


def check_scan_time(time):
    """A scan's time is a ``datetime.datetime`` (Stone Soup's timestamps), not seconds."""
    if not isinstance(time, datetime.datetime):
        raise TypeError(f"time must be a datetime.datetime (the scan's timestamp, as Stone Soup's detectors "
                        f"yield it), got {type(time).__name__} {time!r}")
    return time

"""Names shared by the adapter's modules."""

from __future__ import annotations

__all__ = ["SINGLE_HYPOTHESIS", "HYPOTHESIS_FILTERS", "GLMB", "ALGORITHMS", "require_stonesoup"]

#: hypotrack's own kinds, which the adapter's tests run (every kind of hypotrack.registry is accepted).
SINGLE_HYPOTHESIS = ("gnn", "jpda", "pdaf")
GLMB = ("glmb", "glmb_murty")
HYPOTHESIS_FILTERS = ("hfisst", "rfisst", "homht", "homht_kbest") + GLMB
ALGORITHMS = SINGLE_HYPOTHESIS + HYPOTHESIS_FILTERS


def require_stonesoup():
    try:
        import stonesoup  # noqa: F401
    except ImportError as err:  # pragma: no cover - exercised only without Stone Soup
        raise ImportError(
            "hypotrack.interop.stonesoup needs Stone Soup (>= 1.9): pip install 'hypotrack[stonesoup]'"
        ) from err

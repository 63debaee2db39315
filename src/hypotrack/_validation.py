"""Input validation shared by every public constructor and function.

Each checker raises ``ValueError`` (or ``TypeError`` for the wrong kind of object) whose
message names the parameter and the allowed range, so that bad input never turns into a
silent NaN further down the pipeline.
"""

from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np

__all__ = [
    "check_probability",
    "check_positive",
    "check_nonnegative",
    "check_int",
    "check_finite_array",
    "check_covariance",
    "check_psd",
    "check_measurements",
    "check_state_dimension",
    "check_seed",
]


def _as_float(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    return float(value)


def check_probability(value, name: str, *, low_open: bool = False, high_open: bool = False) -> float:
    """Return ``value`` as float if it lies in [0, 1] (ends open as requested).

    ``check_probability(p_D, "p_D", low_open=True)`` enforces ``p_D in (0, 1]``.
    """
    v = _as_float(value, name)
    lo = "(" if low_open else "["
    hi = ")" if high_open else "]"
    ok = (v > 0 if low_open else v >= 0) and (v < 1 if high_open else v <= 1)
    if not ok or math.isnan(v):
        raise ValueError(f"{name} must lie in {lo}0, 1{hi}, got {value!r}")
    return v


def check_positive(value, name: str) -> float:
    """Return ``value`` as float if it is finite and > 0."""
    v = _as_float(value, name)
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return v


def check_nonnegative(value, name: str) -> float:
    """Return ``value`` as float if it is finite and >= 0."""
    v = _as_float(value, name)
    if not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return v


def check_int(value, name: str, *, minimum: int | None = 0, maximum: int | None = None) -> int:
    """Return ``value`` as int if it is an integer within [minimum, maximum]."""
    if isinstance(value, bool) or not isinstance(value, (Integral, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    v = int(value)
    if (minimum is not None and v < minimum) or (maximum is not None and v > maximum):
        lo = "-inf" if minimum is None else str(minimum)
        hi = "inf" if maximum is None else str(maximum)
        raise ValueError(f"{name} must be an integer in [{lo}, {hi}], got {value!r}")
    return v


def check_finite_array(a, name: str, *, ndim: int | None = None, shape: tuple | None = None) -> np.ndarray:
    """Return ``a`` as a float array, checking dimensionality, shape and finiteness.

    ``shape`` may contain ``None`` for a free axis, e.g. ``(None, 2)``.
    """
    arr = _as_float_array(a, name)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got shape {arr.shape}")
    if shape is not None:
        if arr.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, arr.shape)):
            want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
            raise ValueError(f"{name} must have shape {want}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    return arr


def check_covariance(P, name: str, dim: int | None = None, *, batched: bool = False) -> np.ndarray:
    """Return ``P`` symmetrised, after checking it is symmetric positive definite.

    A Cholesky factorisation is the test of positive definiteness. With ``batched=True``
    ``P`` has shape (n, d, d).
    """
    arr = np.asarray(P, dtype=float)
    want_ndim = 3 if batched else 2
    if arr.ndim != want_ndim or arr.shape[-1] != arr.shape[-2]:
        form = "(n, d, d)" if batched else "(d, d)"
        raise ValueError(f"{name} must be a square matrix of shape {form}, got shape {arr.shape}")
    if dim is not None and arr.shape[-1] != dim:
        raise ValueError(f"{name} must be {dim}x{dim}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    scale = max(1.0, float(np.max(np.abs(arr)))) if arr.size else 1.0
    asym = np.max(np.abs(arr - np.swapaxes(arr, -1, -2))) if arr.size else 0.0
    if asym > 1e-8 * scale:
        raise ValueError(f"{name} must be symmetric (max asymmetry {asym:.3g})")
    sym = 0.5 * (arr + np.swapaxes(arr, -1, -2))
    try:
        np.linalg.cholesky(sym)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name} must be positive definite (Cholesky failed)") from None
    return sym


def check_psd(M, name: str, *, definite: bool = False, what: str | None = None) -> np.ndarray:
    """Check a matrix, or a stack of matrices ``(..., d, d)``, is finite, symmetric and positive
    (semi-)definite; return it as a float array.

    A Cholesky factorisation is the test: of ``M`` itself with ``definite=True``, otherwise of
    ``M + ε I`` with ``ε`` a round-off allowance (``1e-9`` times the largest entry), so that a
    singular but valid covariance (a noise-free component, ``Q = 0``) passes while an indefinite
    one (a negative variance) does not. ``what`` describes ``M`` in the message (default: name).
    """
    arr = np.asarray(M, dtype=float)
    what = what or name
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name} must be a square matrix (d, d) or a stack (n, d, d), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite (no NaN or inf)")
    if arr.size == 0:
        return arr
    scale = max(1.0, float(np.max(np.abs(arr))))
    asym = float(np.max(np.abs(arr - np.swapaxes(arr, -1, -2))))
    if asym > 1e-8 * scale:
        raise ValueError(f"{what} must be symmetric (max asymmetry {asym:.3g})")
    test = arr if definite else arr + (1e-9 * scale) * np.eye(arr.shape[-1])
    try:
        np.linalg.cholesky(test)
    except np.linalg.LinAlgError:
        kind = "positive definite" if definite else "positive semi-definite"
        why = "a zero or negative variance" if definite else "a negative variance"
        raise ValueError(f"{what} must be {kind} (Cholesky failed: {why})") from None
    return arr


def _as_float_array(a, name: str) -> np.ndarray:
    """``np.asarray(a, dtype=float)``, refusing strings and ragged nesting with a message that
    names the parameter (NumPy's own says neither which argument nor what was expected)."""
    if isinstance(a, np.ndarray):
        if a.dtype.kind in "USO" and a.size and any(isinstance(v, (str, bytes)) for v in a.flat):
            raise TypeError(f"{name} must hold numbers, got strings (dtype {a.dtype})")
    elif isinstance(a, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers, got a string {a!r}")
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a rectangular array of numbers (an (m, d) array or a list of "
                        f"equal-length rows), got {type(a).__name__} that NumPy cannot convert: {exc}") from None
    if arr.dtype.kind == "f" and not isinstance(a, np.ndarray) and _holds_strings(a):
        raise TypeError(f"{name} must hold numbers, got strings")
    return arr


def _holds_strings(a) -> bool:
    """Whether a (nested) list or tuple holds a string anywhere; one look per level along the first
    element only would miss a string further on, so this walks every element (lists are small)."""
    if isinstance(a, (str, bytes)):
        return True
    if isinstance(a, (list, tuple)):
        return any(_holds_strings(v) for v in a)
    return False


def check_seed(seed, name: str = "seed"):
    """Return ``seed`` unchanged if ``numpy.random.default_rng`` takes it as a seed: ``None``, an integer
    >= 0, a sequence of such integers, a ``SeedSequence``, a ``BitGenerator`` or a ``Generator``."""
    if seed is None or isinstance(seed, (np.random.Generator, np.random.BitGenerator, np.random.SeedSequence)):
        return seed
    if isinstance(seed, bool):
        raise TypeError(f"{name} must be None, an integer >= 0 or a numpy Generator, got bool {seed!r}")
    if isinstance(seed, (Integral, np.integer)):
        if int(seed) < 0:
            raise ValueError(f"{name} must be an integer >= 0, got {seed!r}")
        return seed
    if isinstance(seed, (list, tuple, np.ndarray)) and len(seed) > 0 and all(
            isinstance(v, (Integral, np.integer)) and not isinstance(v, bool) and int(v) >= 0
            for v in np.ravel(np.asarray(seed, dtype=object))):
        return seed
    raise TypeError(f"{name} must be None, an integer >= 0, a sequence of such integers or a numpy Generator, "
                    f"got {type(seed).__name__} {seed!r}")


def check_measurements(Z, name: str, dim: int) -> np.ndarray:
    """Return a scan as an (m, dim) float array; ``m = 0`` (an empty scan) is allowed."""
    arr = _as_float_array(Z, name)
    if arr.size == 0:
        return np.zeros((0, dim))
    if arr.ndim == 1 and dim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise ValueError(f"{name} must have shape (m, {dim}), got {arr.shape}")
    if not np.isfinite(arr).all():
        bad = np.flatnonzero(~np.all(np.isfinite(arr), axis=1))
        raise ValueError(f"{name} must be finite; rows {bad.tolist()} contain NaN or inf")
    return arr


def check_state_dimension(motion, d: int, what: str) -> int:
    """Check that a motion model's states have dimension ``d`` (that of ``what``), at construction
    rather than as a matmul error inside the first ``step``. Returns ``d``."""
    if not callable(getattr(motion, "transition", None)) or not callable(getattr(motion, "Q", None)):
        raise TypeError(f"motion must be a motion model with transition(x, dt) and Q(dt), got {type(motion).__name__}")
    nd = getattr(motion, "ndim", None)
    if nd is None:
        nd = np.shape(motion.Q(1.0))[-1]
    if int(nd) != d:
        raise ValueError(f"the motion model's states are {int(nd)}-dimensional but {what} expects {d}-dimensional states")
    return d


def check_labels(labels, n: int, *, held=None, name: str = "labels") -> np.ndarray:
    """``n`` distinct integer labels (int64), none of them in ``held``; an error naming ``name`` otherwise."""
    a = np.asarray(labels)
    if a.shape != (n,):
        raise ValueError(f"{name} must hold one label per track, shape ({n},), got shape {a.shape}")
    if n and not (np.issubdtype(a.dtype, np.integer) or (np.issubdtype(a.dtype, np.floating)
                                                          and np.all(np.isfinite(a)) and np.all(a == np.round(a)))):
        raise ValueError(f"{name} must be integers, got {labels!r}")
    a = a.astype(np.int64)
    if len(np.unique(a)) != n:
        raise ValueError(f"{name} must be distinct, got {a.tolist()}")
    if held is not None and len(held) and np.isin(a, held).any():
        raise ValueError(f"{name} {sorted(set(a[np.isin(a, held)].tolist()))} are already held by the tracker")
    return a


def check_finite_float(value, name: str) -> float:
    """``value`` as a finite float (``ValueError`` naming ``name`` otherwise, a non-number included)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number, got {value!r}") from None
    if not np.isfinite(v):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return v


def check_time(value, name: str = "time") -> float:
    """A scan or state time as a finite float: ``TypeError`` for a non-number, ``ValueError`` for NaN or inf
    (the single-hypothesis trackers' convention; the engine's is :func:`check_finite_float`)."""
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a scalar number, got {value!r}") from None
    if not np.isfinite(t):
        raise ValueError(f"{name} must be finite, got {t}")
    return t

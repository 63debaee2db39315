"""The tidy-table schema shared by every scenario generator, and helpers to use it.

Every scenario produces two long-format :class:`pandas.DataFrame` tables, one row per
observation of a thing, so they can be saved as CSV, filtered with pandas and re-read
without any custom parser.

Truth table (one row per target per scan in which the target exists)
    ======== ======= ===========================================================
    column   dtype   meaning
    ======== ======= ===========================================================
    scan     int64   scan index k = 0, 1, ..., K-1
    time     float64 scan time t_k (s)
    target   int64   target id (stable over the target's life, >= 0)
    state_0  float64 state component 0 (units of the scenario's motion model)
    ...
    state_D  float64 state component d-1
    in_view  bool    whether the target lies inside the sensor's field of view
    ======== ======= ===========================================================

    State columns are generic (``state_0 .. state_{d-1}``) rather than named, so one schema
    serves the 1-D Ornstein–Uhlenbeck, 2-D constant-velocity and planar-orbit scenarios; the
    order is the motion model's state order (e.g. ``[x, y, vx, vy]``).

Scans table (one row per return)
    ======== ======= ===========================================================
    column   dtype   meaning
    ======== ======= ===========================================================
    scan     int64   scan index k
    time     float64 scan time t_k (s)
    sensor   int64   sensor index within a synchronous sensor array (0 if one)
    return   int64   index of the return within its (scan, sensor), 0..m-1, in the
                     random order in which the sensor reported it
    z_0      float64 measurement component 0
    ...
    z_P      float64 measurement component p-1
    origin   int64   id of the target that produced the return, or -1 for clutter
    ======== ======= ===========================================================

A scan with no returns has no rows, so the list of scan times cannot be recovered from
the scans table alone: pass ``times`` (every scenario object carries it) to
:func:`scans_to_list` to get an entry, with an empty ``(0, p)`` array, for every scan.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np
import pandas as pd

__all__ = [
    "CLUTTER",
    "TRUTH_KEYS",
    "SCANS_KEYS",
    "state_columns",
    "measurement_columns",
    "truth_table",
    "scans_table",
    "validate_truth",
    "validate_scans",
    "scans_to_list",
    "scans_by_sensor",
    "truth_to_list",
    "write_table",
]

CLUTTER = -1
"""``origin`` value of a clutter (false-alarm) return."""

TRUTH_KEYS = ("scan", "time", "target")
SCANS_KEYS = ("scan", "time", "sensor", "return")

_STATE = re.compile(r"state_(\d+)$")
_MEAS = re.compile(r"z_(\d+)$")


def state_columns(d: int) -> list[str]:
    """Names of the ``d`` state columns: ``["state_0", ..., "state_{d-1}"]``."""
    return [f"state_{i}" for i in range(d)]


def measurement_columns(p: int) -> list[str]:
    """Names of the ``p`` measurement columns: ``["z_0", ..., "z_{p-1}"]``."""
    return [f"z_{i}" for i in range(p)]


def _numbered(df: pd.DataFrame, pattern: re.Pattern, what: str) -> list[str]:
    found = sorted((int(m.group(1)), c) for c in df.columns if (m := pattern.match(str(c))))
    idx = [i for i, _ in found]
    if idx != list(range(len(idx))):
        raise ValueError(f"{what} columns must be numbered 0..n-1 without gaps, got {[c for _, c in found]}")
    return [c for _, c in found]


def truth_table(scan, time, target, states, in_view) -> pd.DataFrame:
    """Build a truth table from flat per-row arrays (all of length ``N``).

    Parameters
    ----------
    scan, target : (N,) int arrays.
    time : (N,) float array (s).
    states : (N, d) float array.
    in_view : (N,) bool array.
    """
    states = np.asarray(states, dtype=float)
    if states.ndim != 2:
        raise ValueError(f"states must have shape (N, d), got {states.shape}")
    df = pd.DataFrame(
        {
            "scan": np.asarray(scan, dtype=np.int64),
            "time": np.asarray(time, dtype=float),
            "target": np.asarray(target, dtype=np.int64),
        }
    )
    for c, col in zip(state_columns(states.shape[1]), states.T):
        df[c] = col
    df["in_view"] = np.asarray(in_view, dtype=bool)
    return validate_truth(df)


def scans_table(scan, time, sensor, Z, origin, *, p: int | None = None) -> pd.DataFrame:
    """Build a scans table from flat per-return arrays (all of length ``N``).

    ``return`` is numbered 0..m-1 within each (scan, sensor) in row order, so rows must be
    given grouped by (scan, sensor) in the order the sensor reported them. ``p`` is needed
    only when ``N = 0`` (to name the measurement columns).
    """
    Z = np.asarray(Z, dtype=float)
    if Z.size == 0:
        if p is None and Z.ndim != 2:
            raise ValueError("p (measurement dimension) is required for an empty scans table")
        Z = np.zeros((0, p if p is not None else Z.shape[1]))
    if Z.ndim != 2:
        raise ValueError(f"Z must have shape (N, p), got {Z.shape}")
    df = pd.DataFrame(
        {
            "scan": np.asarray(scan, dtype=np.int64).reshape(-1),
            "time": np.asarray(time, dtype=float).reshape(-1),
            "sensor": np.asarray(sensor, dtype=np.int64).reshape(-1),
        }
    )
    df["return"] = (
        df.groupby(["scan", "sensor"]).cumcount().astype(np.int64) if len(df) else np.zeros(0, np.int64)
    )
    for c, col in zip(measurement_columns(Z.shape[1]), Z.T):
        df[c] = col
    df["origin"] = np.asarray(origin, dtype=np.int64).reshape(-1)
    return validate_scans(df)


def _check_columns(df: pd.DataFrame, required: Sequence[str], name: str) -> None:
    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"{name} must be a pandas DataFrame, got {type(df).__name__}")
    missing = [c for c in required if c not in df.columns]
    if missing:
        raise ValueError(f"{name} is missing columns {missing}; see hypotrack.scenarios.tables")


def _coerce(df: pd.DataFrame, ints: Sequence[str], floats: Sequence[str], name: str) -> pd.DataFrame:
    df = df.copy()
    for c in ints:
        col = pd.to_numeric(df[c])
        if len(col) and not np.all(np.asarray(col) == np.round(np.asarray(col, dtype=float))):
            raise ValueError(f"{name} column {c!r} must hold integers")
        df[c] = col.astype(np.int64)
    for c in floats:
        df[c] = pd.to_numeric(df[c]).astype(float)
        if not np.all(np.isfinite(df[c].to_numpy())):
            raise ValueError(f"{name} column {c!r} must be finite (no NaN or inf)")
    return df


def validate_truth(df: pd.DataFrame) -> pd.DataFrame:
    """Check a truth table against the schema and return it with canonical dtypes."""
    _check_columns(df, [*TRUTH_KEYS, "in_view"], "truth table")
    states = _numbered(df, _STATE, "state")
    if not states:
        raise ValueError("truth table needs at least one state_<i> column")
    out = _coerce(df, ["scan", "target"], ["time", *states], "truth table")
    if out["in_view"].dtype != bool:
        # CSV round trips give bool or the strings "True"/"False".
        out["in_view"] = out["in_view"].map({True: True, False: False, "True": True, "False": False})
        if out["in_view"].isna().any():
            raise ValueError("truth table column 'in_view' must be boolean")
        out["in_view"] = out["in_view"].astype(bool)
    if (out["scan"] < 0).any() or (out["target"] < 0).any():
        raise ValueError("truth table columns 'scan' and 'target' must be >= 0")
    if out.duplicated(["scan", "target"]).any():
        raise ValueError("truth table has more than one row for some (scan, target)")
    return out[[*TRUTH_KEYS, *states, "in_view"]]


def validate_scans(df: pd.DataFrame) -> pd.DataFrame:
    """Check a scans table against the schema and return it with canonical dtypes."""
    _check_columns(df, [*SCANS_KEYS, "origin"], "scans table")
    zs = _numbered(df, _MEAS, "measurement")
    if not zs:
        raise ValueError("scans table needs at least one z_<i> column")
    out = _coerce(df, ["scan", "sensor", "return", "origin"], ["time", *zs], "scans table")
    if (out["scan"] < 0).any() or (out["sensor"] < 0).any() or (out["return"] < 0).any():
        raise ValueError("scans table columns 'scan', 'sensor' and 'return' must be >= 0")
    if (out["origin"] < CLUTTER).any():
        raise ValueError(f"scans table column 'origin' must be a target id >= 0 or {CLUTTER} (clutter)")
    if out.duplicated(["scan", "sensor", "return"]).any():
        raise ValueError("scans table has more than one row for some (scan, sensor, return)")
    return out[[*SCANS_KEYS, *zs, "origin"]]


def _scan_times(df: pd.DataFrame, times) -> np.ndarray:
    if times is not None:
        return np.asarray(times, dtype=float).reshape(-1)
    if df.empty:
        return np.zeros(0)
    first = df.groupby("scan")["time"].first()
    out = np.full(int(first.index.max()) + 1, np.nan)
    out[first.index.to_numpy()] = first.to_numpy()
    if np.isnan(out).any():
        raise ValueError("some scans have no returns: pass times= to recover their times")
    return out


def scans_to_list(
    df: pd.DataFrame, *, times=None, sensor: int | None = None, with_origin: bool = False
) -> list:
    """Split a scans table into one ``(time, Z)`` pair per scan, in scan order.

    Parameters
    ----------
    df : scans table (see module docstring).
    times : (K,) array, optional
        Time of every scan ``0..K-1``; scans without rows get an empty ``(0, p)`` array.
        Without it, the scans are those present in the table (which must be contiguous).
    sensor : int, optional
        Which sensor's returns to take; required when the table holds several sensors.
    with_origin : bool
        Return ``(time, Z, origin)`` triples instead, ``origin`` an (m,) int array.

    Returns
    -------
    list of ``(float, (m, p) ndarray)`` (or triples), ``Z`` rows in ``return`` order.
    """
    df = validate_scans(df)
    if sensor is None:
        sensors = df["sensor"].unique()
        if len(sensors) > 1:
            raise ValueError(
                f"scans table holds sensors {sorted(sensors.tolist())}: pass sensor= or use scans_by_sensor"
            )
    else:
        df = df[df["sensor"] == sensor]
    zs = _numbered(df, _MEAS, "measurement")
    t = _scan_times(df, times)
    df = df.sort_values(["scan", "return"])
    Z_all = df[zs].to_numpy(dtype=float)
    origin_all = df["origin"].to_numpy(dtype=np.int64)
    scans = df["scan"].to_numpy()
    if len(scans) and scans.max() >= len(t):
        raise ValueError(f"scans table has scan {scans.max()} but times has only {len(t)} entries")
    bounds = np.searchsorted(scans, np.arange(len(t) + 1))
    out = []
    for k in range(len(t)):
        a, b = bounds[k], bounds[k + 1]
        item = (float(t[k]), Z_all[a:b])
        out.append((*item, origin_all[a:b]) if with_origin else item)
    return out


def scans_by_sensor(df: pd.DataFrame, n_sensors: int, *, times=None, with_origin: bool = False) -> list:
    """Synchronous multi-sensor scans: one ``(time, [Z_0, ..., Z_{S-1}])`` per scan.

    With ``with_origin`` each entry is ``(time, [Z_s], [origin_s])``.
    """
    df = validate_scans(df)
    t = _scan_times(df, times)
    per = [scans_to_list(df, times=t, sensor=s, with_origin=True) for s in range(n_sensors)]
    out = []
    for k in range(len(t)):
        Zs = [per[s][k][1] for s in range(n_sensors)]
        item = (float(t[k]), Zs)
        out.append((*item, [per[s][k][2] for s in range(n_sensors)]) if with_origin else item)
    return out


def truth_to_list(df: pd.DataFrame, *, times=None, in_view_only: bool = False) -> list:
    """Split a truth table into one ``(time, ids (n,), X (n, d))`` triple per scan.

    ``times`` plays the same role as in :func:`scans_to_list` (scans with no targets get
    empty arrays); ``in_view_only`` keeps only targets inside the field of view.
    """
    df = validate_truth(df)
    states = _numbered(df, _STATE, "state")
    t = _scan_times(df, times)
    if in_view_only:
        df = df[df["in_view"]]
    df = df.sort_values(["scan", "target"])
    X = df[states].to_numpy(dtype=float)
    ids = df["target"].to_numpy(dtype=np.int64)
    scans = df["scan"].to_numpy()
    bounds = np.searchsorted(scans, np.arange(len(t) + 1))
    return [
        (float(t[k]), ids[bounds[k] : bounds[k + 1]], X[bounds[k] : bounds[k + 1]]) for k in range(len(t))
    ]


def write_table(df: pd.DataFrame, path) -> None:
    """Write a table as CSV with fixed float formatting, so equal tables give equal bytes."""
    df.to_csv(path, index=False, float_format="%.10g")

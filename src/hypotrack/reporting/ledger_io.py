"""The ledger's files: claims files (``claims.csv``) and the experiments' ``macros.csv``.

Columns are :data:`~.claims.CLAIM_COLUMNS` and :data:`MACRO_COLUMNS`; every value is read as
text (``dtype=str``, empty cells as empty strings), so a file read and written back is unchanged.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import pandas as pd

from .claims import CLAIM_COLUMNS, EVIDENCE, KEY_PATTERN, OPTIONAL_COLUMNS, STATUSES, format_value
from .macros import macro_name

__all__ = ["MACRO_COLUMNS", "is_timing_table", "read_claims", "read_macros", "write_claims", "write_macros"]

#: Columns of an experiment's ``macros.csv`` (numbers the paper quotes that are not ledger rows).
MACRO_COLUMNS = ["experiment", "name", "value"]


def write_claims(claims, path) -> pd.DataFrame:
    """Write claims as CSV with :data:`CLAIM_COLUMNS`; returns the table."""
    df = pd.DataFrame([asdict(c) for c in claims], columns=CLAIM_COLUMNS)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def is_timing_table(path) -> bool:
    """Timing tables (and timing claims) are named so (``*timing*``): their values are measured run
    times, not byte-reproducible; the paper rule writes their rows to ``ledger_timing.csv``."""
    return "timing" in Path(path).name


def read_claims(paths) -> pd.DataFrame:
    """Concatenate claims files (missing columns are an error naming the file)."""
    frames = []
    for p in sorted(map(Path, paths)):
        df = pd.read_csv(p, dtype=str, keep_default_na=False)
        for col in OPTIONAL_COLUMNS:
            if col not in df.columns:
                df[col] = ""
        missing = set(CLAIM_COLUMNS) - set(df.columns)
        if missing:
            raise ValueError(f"{p}: claims file lacks columns {sorted(missing)}")
        bad = set(df["status"]) - set(STATUSES)
        if bad:
            raise ValueError(f"{p}: status must be one of {STATUSES}, got {sorted(bad)}")
        bad = set(df["evidence"]) - set(EVIDENCE) - {""}
        if bad:
            raise ValueError(f"{p}: evidence must be one of {EVIDENCE}, got {sorted(bad)}")
        frames.append(df[CLAIM_COLUMNS])
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=CLAIM_COLUMNS)


def write_macros(experiment: str, values: dict, path) -> pd.DataFrame:
    """Write an experiment's non-claim numbers as ``macros.csv`` (``experiment,name,value``).

    ``values`` maps a stable name (letters, digits, underscore; never a config value) to a value;
    floats are written with 4 significant digits unless already formatted as text.
    """
    rows = []
    for name, value in values.items():
        if not KEY_PATTERN.fullmatch(str(name)):
            raise ValueError(f"macro name must be letters, digits and underscores, got {name!r}")
        if isinstance(value, float):
            value = format_value(value, 4)
        rows.append((experiment, name, str(value)))
    df = pd.DataFrame(rows, columns=MACRO_COLUMNS)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(path, index=False)
    return df


def read_macros(paths) -> dict:
    """Macros ``\\ht<Experiment><Name>`` from ``macros.csv`` files; a name defined twice is an error."""
    values = {}
    for p in sorted(map(Path, paths)):
        df = pd.read_csv(p, dtype=str, keep_default_na=False)
        if list(df.columns) != MACRO_COLUMNS:
            raise ValueError(f"{p}: macros file must have columns {MACRO_COLUMNS}, got {list(df.columns)}")
        for r in df.to_dict("records"):
            if not KEY_PATTERN.fullmatch(r["name"]):
                raise ValueError(f"{p}: macro name must be letters, digits and underscores, got {r['name']!r}")
            name = macro_name(r["experiment"], r["name"])
            if name in values:
                raise ValueError(f"{p}: macro {name} defined twice")
            values[name] = r["value"]
    return values

"""Two-line element sets: read them into a catalogue table, load the bundled catalogues, select subsets.

The catalogue table (:func:`parse_tle`) has one row per object, in file order:

==================== ======== ===============================================================
column               dtype    meaning
==================== ======== ===============================================================
group                str      the catalogue it came from (``active``, ``fengyun-1c-debris``, ...)
name                 str      object name (the 3-line format's line 0, stripped)
norad                int64    NORAD catalogue number (the scenario's target id)
intl_designator      str      international designator (``98067A``)
epoch                datetime element epoch, UTC (``datetime64[ns]``, tz-naive)
epoch_jd, epoch_fr   float64  the same epoch as SGP4 holds it: Julian date ``jd + fr`` in two parts
inclination_deg      float64  mean inclination
raan_deg             float64  right ascension of the ascending node
eccentricity         float64  mean eccentricity
arg_perigee_deg      float64  argument of perigee
mean_anomaly_deg     float64  mean anomaly at epoch
mean_motion_rev_day  float64  Kozai mean motion (revolutions per day), as in the TLE
bstar                float64  SGP4 drag term B* (1 / Earth radii)
semi_major_axis_km   float64  SGP4's (Brouwer) mean semi-major axis
perigee_alt_km       float64  ``a (1 − e) − R_E`` (R_E = 6378.135 km, WGS-72, SGP4's Earth)
apogee_alt_km        float64  ``a (1 + e) − R_E``
period_min           float64  ``1440 / mean_motion_rev_day``
line1, line2         str      the TLE lines (SGP4 is initialised from them)
==================== ======== ===============================================================

Every selection (:func:`select_groups`, :func:`sample_objects`, :func:`select_altitude`) returns rows
in catalogue order with a fresh index, so a selection is a deterministic function of the catalogue
and its arguments (and, for sampling, the seed).
"""

from __future__ import annotations

import gzip
import hashlib
from collections.abc import Sequence
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
from sgp4.api import Satrec, SatrecArray

from ..._validation import check_int, check_nonnegative

__all__ = [
    "BUNDLED",
    "GROUPS",
    "DEBRIS_GROUPS",
    "parse_tle",
    "read_tle",
    "load_catalogue",
    "select_groups",
    "check_catalogue",
    "sample_objects",
    "select_altitude",
    "satrec_array",
    "tle_checksum",
    "groups_in",
]

# name -> (bundled file, SHA-256 of the uncompressed file, number of objects). The hashes are those
# of the shared data folder's SHA256SUMS and of hypotrack/data/tle/README.md.
BUNDLED = {
    "active": (
        "active_2022-11-03.tle.gz",
        "85104aa6ca5389f92c10f2e44e89b3483cf0c53c1f9fd1147d7ba6d1d0666008",
        6789,
    ),
    "fengyun-1c-debris": (
        "fengyun-1c-debris_2021-10-02.tle.gz",
        "afd3d9c17cfb7e2231c0029b4d3ff86b65cfbc94c1ed3597162161eb99ecc9de",
        2686,
    ),
    "cosmos-2251-debris": (
        "cosmos-2251-debris_2021-10-02.tle.gz",
        "6a82b07aac783fab6f26f545812757110f705b0ff180db9fc51a5abd25f70cff",
        1048,
    ),
    "iridium-33-debris": (
        "iridium-33-debris_2021-10-02.tle.gz",
        "d22d1ffd95283919f01498ef11919424dbd113a12eb52090767a465cdfa4bb2b",
        332,
    ),
}
GROUPS = tuple(BUNDLED)
DEBRIS_GROUPS = ("fengyun-1c-debris", "cosmos-2251-debris", "iridium-33-debris")

UNIX_EPOCH_JD = 2440587.5
_COLUMNS = [
    "group",
    "name",
    "norad",
    "intl_designator",
    "epoch",
    "epoch_jd",
    "epoch_fr",
    "inclination_deg",
    "raan_deg",
    "eccentricity",
    "arg_perigee_deg",
    "mean_anomaly_deg",
    "mean_motion_rev_day",
    "bstar",
    "semi_major_axis_km",
    "perigee_alt_km",
    "apogee_alt_km",
    "period_min",
    "line1",
    "line2",
]


def tle_checksum(line: str) -> int:
    """The modulo-10 checksum of a TLE line's first 68 characters (digits count, '-' counts 1)."""
    return sum(int(c) if c.isdigit() else (c == "-") for c in line[:68]) % 10


def _check_line(line: str, number: int, lineno: int, source: str) -> str:
    where = f"{source}, line {lineno}"
    if len(line) < 69 or not line.startswith(f"{number} "):
        raise ValueError(
            f"{where}: expected TLE line {number} (69 characters starting '{number} '), got {line[:30]!r}"
        )
    line = line[:69]
    if not line[68].isdigit() or tle_checksum(line) != int(line[68]):
        raise ValueError(f"{where}: TLE checksum is {tle_checksum(line)}, the line says {line[68]!r}")
    return line


def parse_tle(text: str, *, group: str = "", source: str = "<text>") -> pd.DataFrame:
    """Parse element sets in three-line format (name, TLE line 1, TLE line 2) into a catalogue table.

    Blank lines are skipped; a name line's optional ``"0 "`` prefix (Space-Track's 3LE) is dropped.
    Every line's checksum, the NORAD number's agreement between lines 1 and 2 and SGP4's own
    initialisation are checked.

    Parameters
    ----------
    text : str
        The file's content.
    group : str
        Value of the ``group`` column.
    source : str
        Named in error messages (the file name).

    Returns
    -------
    pandas.DataFrame
        The catalogue table (module docstring).

    Raises
    ------
    ValueError
        A malformed or inconsistent element set (the message names the line), or a repeated
        NORAD number.
    """
    if not isinstance(text, str):
        raise TypeError(f"text must be a str, got {type(text).__name__}")
    lines = [(i + 1, ln.rstrip()) for i, ln in enumerate(text.splitlines()) if ln.strip()]
    if len(lines) % 3:
        raise ValueError(
            f"{source}: {len(lines)} non-blank lines is not a whole number of three-line element sets"
        )
    rows = []
    for j in range(0, len(lines), 3):
        (_, name), (n1, l1), (n2, l2) = lines[j : j + 3]
        if name.startswith(("1 ", "2 ")) and len(name) >= 69:
            raise ValueError(f"{source}, line {lines[j][0]}: expected a name line, got a TLE line")
        l1 = _check_line(l1, 1, n1, source)
        l2 = _check_line(l2, 2, n2, source)
        if l1[2:7] != l2[2:7]:
            raise ValueError(f"{source}, lines {n1}-{n2}: NORAD numbers differ ({l1[2:7]!r} vs {l2[2:7]!r})")
        sat = Satrec.twoline2rv(l1, l2)
        if sat.error:
            raise ValueError(f"{source}, lines {n1}-{n2}: SGP4 rejects the element set (error {sat.error})")
        rows.append(((name[2:] if name.startswith("0 ") else name).strip(), sat, l1, l2))
    return _table(rows, group, source)


def _table(rows, group, source) -> pd.DataFrame:
    sats = [r[1] for r in rows]
    get = lambda attr: np.array([getattr(s, attr) for s in sats], dtype=float)  # noqa: E731
    re_km = sats[0].radiusearthkm if sats else 6378.135
    jd, fr = get("jdsatepoch"), get("jdsatepochF")
    # Whole microseconds since the Unix epoch: exact for the TLE's 1e-8-day resolution (0.864 ms).
    us = np.round(((jd - UNIX_EPOCH_JD) + fr) * 86400e6).astype(np.int64)
    n_rev_day = get("no_kozai") * 1440.0 / (2 * np.pi)
    a_km = get("a") * re_km
    ecc = get("ecco")
    df = pd.DataFrame(
        {
            "group": pd.Series([group] * len(rows), dtype=object),
            "name": pd.Series([r[0] for r in rows], dtype=object),
            "norad": np.array([s.satnum for s in sats], dtype=np.int64),
            "intl_designator": pd.Series([s.intldesg for s in sats], dtype=object),
            "epoch": pd.to_datetime(us, unit="us"),
            "epoch_jd": jd,
            "epoch_fr": fr,
            "inclination_deg": np.rad2deg(get("inclo")),
            "raan_deg": np.rad2deg(get("nodeo")),
            "eccentricity": ecc,
            "arg_perigee_deg": np.rad2deg(get("argpo")),
            "mean_anomaly_deg": np.rad2deg(get("mo")),
            "mean_motion_rev_day": n_rev_day,
            "bstar": get("bstar"),
            "semi_major_axis_km": a_km,
            "perigee_alt_km": a_km * (1 - ecc) - re_km,
            "apogee_alt_km": a_km * (1 + ecc) - re_km,
            "period_min": 1440.0 / n_rev_day if len(rows) else np.zeros(0),
            "line1": pd.Series([r[2] for r in rows], dtype=object),
            "line2": pd.Series([r[3] for r in rows], dtype=object),
        },
        columns=_COLUMNS,
    )
    dup = df["norad"].duplicated(keep=False)
    if dup.any():
        raise ValueError(f"{source}: NORAD numbers repeat: {sorted(set(df.loc[dup, 'norad'].tolist()))[:10]}")
    return df


def read_tle(path, *, group: str | None = None, sha256: str | None = None) -> pd.DataFrame:
    """Read a three-line element file (plain, or gzip when the name ends in ``.gz``).

    Parameters
    ----------
    path : str or Path
    group : str, optional
        The ``group`` column; default: the file name up to its first ``_`` or ``.``.
    sha256 : str, optional
        Expected SHA-256 (hex) of the uncompressed bytes; a mismatch raises ``ValueError``.

    Raises
    ------
    ValueError
        Each naming the file: a ``.gz`` file that is not gzip, content that is not ASCII, a file with
        no element set (empty or blank), or any error of :func:`parse_tle`.
    """
    path = Path(path)
    raw = path.read_bytes()
    try:
        data = gzip.decompress(raw) if path.name.endswith(".gz") else raw
    except (OSError, EOFError) as exc:  # gzip.BadGzipFile is an OSError; a truncated stream an EOFError
        raise ValueError(f"{path}: not a valid gzip file (the name ends in .gz): {exc}") from None
    if sha256 is not None:
        got = hashlib.sha256(data).hexdigest()
        if got != sha256.lower():
            raise ValueError(
                f"{path.name}: SHA-256 of the uncompressed content is {got}, expected {sha256.lower()} "
                "(a corrupted or different catalogue)"
            )
    if group is None:
        group = path.name.split("_")[0].split(".")[0]
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise ValueError(f"{path}: not an ASCII element-set file: byte {data[exc.start]:#04x} at offset "
                         f"{exc.start} (line {line})") from None
    cat = parse_tle(text, group=group, source=path.name)
    if len(cat) == 0:
        raise ValueError(f"{path}: the file holds no element set (it is empty or blank)")
    return cat


def _bundled_path(name: str):
    return resources.files("hypotrack").joinpath("data", "tle", BUNDLED[name][0])


def _check_groups(groups) -> tuple[str, ...]:
    if isinstance(groups, str):
        groups = GROUPS if groups == "all" else (groups,)
    groups = tuple(groups)
    bad = [g for g in groups if g not in BUNDLED]
    if bad or not groups:
        raise ValueError(
            f"groups must be 'all' or names among {list(GROUPS)}, got {list(groups) or groups!r}"
        )
    if len(set(groups)) != len(groups):
        raise ValueError(f"groups must not repeat a name, got {list(groups)}")
    return groups


def load_catalogue(groups="all") -> pd.DataFrame:
    """The bundled catalogue(s), checksum-verified, concatenated in the order given.

    Parameters
    ----------
    groups : "all", a group name or a sequence of them
        Among :data:`GROUPS`: ``active`` (6,789 objects), ``fengyun-1c-debris`` (2,686),
        ``cosmos-2251-debris`` (1,048), ``iridium-33-debris`` (332); "all" = the four, 10,855.
    """
    frames = []
    for g in _check_groups(groups):
        with resources.as_file(_bundled_path(g)) as p:
            frames.append(read_tle(p, group=g, sha256=BUNDLED[g][1]))
    cat = pd.concat(frames, ignore_index=True)
    if cat["norad"].duplicated().any():  # pragma: no cover - the bundled files share no object
        raise ValueError("the bundled catalogues share NORAD numbers")
    return cat


def check_catalogue(cat) -> pd.DataFrame:
    """``cat`` itself when it is a catalogue table (a DataFrame with the columns of :func:`parse_tle`), else
    a ``TypeError`` or a ``ValueError`` naming the missing columns."""
    if not isinstance(cat, pd.DataFrame):
        raise TypeError(f"catalogue must be a pandas DataFrame (see parse_tle), got {type(cat).__name__}")
    missing = [c for c in _COLUMNS if c not in cat.columns]
    if missing:
        raise ValueError(f"catalogue is missing columns {missing}; build it with parse_tle or load_catalogue")
    return cat


def select_groups(cat: pd.DataFrame, groups) -> pd.DataFrame:
    """Rows of ``cat`` whose ``group`` is among ``groups`` (a name or a sequence), catalogue order."""
    cat = check_catalogue(cat)
    names = (groups,) if isinstance(groups, str) else tuple(groups)
    present = sorted(set(cat["group"]))
    bad = [g for g in names if g not in present]
    if bad or not names:
        raise ValueError(f"groups must be names among {present}, got {list(names)}")
    return cat[cat["group"].isin(names)].reset_index(drop=True)


def sample_objects(cat: pd.DataFrame, n: int, seed) -> pd.DataFrame:
    """A simple random sample of ``n`` objects without replacement, kept in catalogue order.

    ``numpy.random.default_rng(seed).choice(len(cat), n, replace=False)``: the same catalogue, n
    and seed give the same objects.
    """
    cat = check_catalogue(cat)
    n = check_int(n, "n", minimum=0, maximum=len(cat))
    seed = seed if isinstance(seed, np.random.SeedSequence) else check_int(seed, "seed")
    idx = np.sort(np.random.default_rng(seed).choice(len(cat), n, replace=False))
    return cat.iloc[idx].reset_index(drop=True)


def select_altitude(cat: pd.DataFrame, low_km: float, high_km: float) -> pd.DataFrame:
    """Objects whose whole orbit lies in an altitude band: ``perigee >= low_km`` and ``apogee <= high_km``.

    Altitudes above SGP4's spherical Earth (R_E = 6378.135 km) from the mean elements; e.g.
    ``(200, 2000)`` is LEO, ``(35286, 36286)`` the geosynchronous belt ±500 km.
    """
    cat = check_catalogue(cat)
    low = check_nonnegative(low_km, "low_km")
    high = check_nonnegative(high_km, "high_km")
    if not high > low:
        raise ValueError(f"high_km must be > low_km = {low} km, got {high_km!r}")
    keep = (cat["perigee_alt_km"] >= low) & (cat["apogee_alt_km"] <= high)
    return cat[keep].reset_index(drop=True)


def satrec_array(cat: pd.DataFrame) -> SatrecArray:
    """SGP4 satellites (WGS-72 constants, as the elements are fitted) for every row, in order."""
    cat = check_catalogue(cat)
    if len(cat) == 0:
        raise ValueError("catalogue must hold at least one object to propagate")
    return SatrecArray([Satrec.twoline2rv(a, b) for a, b in zip(cat["line1"], cat["line2"])])


def groups_in(cat: pd.DataFrame) -> Sequence[str]:
    """The groups present in ``cat``, in order of first appearance."""
    return list(dict.fromkeys(check_catalogue(cat)["group"]))

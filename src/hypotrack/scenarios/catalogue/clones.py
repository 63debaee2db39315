"""Populations of 10⁵–10⁶ objects cloned from the real catalogue, their truth streamed in chunks.

The bundled catalogue holds 10,855 objects (:func:`.load_catalogue`). A larger population with the
same altitude and inclination structure is made of **copies**: copy 0 is the catalogue itself, copy
``c ≥ 1`` each catalogue object again with its mean anomaly and right ascension of the ascending node
shifted by seeded offsets uniform in [0, 2π) — the same mean motion (semi-major axis), eccentricity,
inclination, argument of perigee, drag term and epoch, hence the same SGP4 theory (Hoots & Roehrich
1980, Spacetrack Report #3: the secular rates of M, Ω and ω depend on n, e, i alone), only elsewhere
on the orbit and the orbit turned about the Earth's axis. Row ``k`` of a population of size ``N`` is
copy ``k // N₀`` of catalogue object ``π(k mod N₀)`` (``N₀`` the catalogue size, ``π`` a permutation drawn
from ``default_rng([seed])``), so a population is a prefix of every larger one and every population —
a part of a copy included — is the same mix of the catalogue's groups, up to sampling (a seeded simple
random sample of the catalogue for ``N < N₀``).

Offsets: copy ``c``'s are drawn from ``numpy.random.default_rng([seed, c])`` (ΔM for every catalogue
object, then ΔΩ), so they depend on the seed and the copy only — not on the population size nor on
how the population is cut into chunks. A clone's SGP4 record is :meth:`sgp4.api.Satrec.sgp4init` with
its parent's element set (WGS-72, improved mode, as :meth:`~sgp4.api.Satrec.twoline2rv`) and the
shifted angles; copy 0 uses the parent's own record.

Truth is streamed: :func:`clone_states` propagates ``chunk`` objects at a time (their SGP4 records,
then their states at all requested times), so memory is bounded by the chunk, not the population;
:func:`simulate_clones` keeps of each chunk only the rows in the radar's field of view and then draws
the scans exactly as :func:`.simulate_catalogue` does (same random streams in the same order; for a
population of copy 0 alone, the same scenario).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from sgp4.api import WGS72, Satrec, SatrecArray

from ..._validation import check_int
from ..tables import scans_table, truth_table
from .frames import gmst, teme_to_ef
from .propagation import check_epoch_span, reference_epoch, sgp4_states, time_grid_jd
from .scenario import CatalogueScenario, _check_sensors, range_rate_ef
from .tle import check_catalogue

__all__ = ["CLONE_ID_BASE", "clone_offsets", "clone_population", "clone_satrecs", "clone_states", "simulate_clones",
           "CloneScenario"]

#: A clone's id (its ``norad``) is ``CLONE_ID_BASE · copy + parent row``: above every NORAD number of copy 0.
CLONE_ID_BASE = 1_000_000
_SGP4_EPOCH_JD = 2433281.5  # 1949 December 31 00:00 UT, sgp4init's epoch origin


def clone_offsets(n_parents: int, copy: int, seed: int):
    """``(ΔM, ΔΩ)`` (rad, each ``(n_parents,)``) of copy ``copy``: zeros for copy 0, else uniform in
    [0, 2π) from ``default_rng([seed, copy])`` (module docstring)."""
    if copy == 0:
        return np.zeros(n_parents), np.zeros(n_parents)
    u = np.random.default_rng([int(seed), int(copy)]).random((2, n_parents))
    return 2 * np.pi * u[0], 2 * np.pi * u[1]


def clone_population(cat: pd.DataFrame, n: int, seed: int) -> pd.DataFrame:
    """``n`` objects: copy 0 (the catalogue ``cat``), then clones (module docstring).

    The table has the catalogue's columns (``norad`` the clone id, ``raan_deg`` and
    ``mean_anomaly_deg`` shifted, ``line1``/``line2`` empty for a clone: its element set is not a TLE)
    plus ``parent`` (row of ``cat``), ``copy``, ``d_mean_anomaly_rad`` and ``d_raan_rad``.
    """
    cat = check_catalogue(cat).reset_index(drop=True)
    n = check_int(n, "n", minimum=0)
    n0 = len(cat)
    if n0 == 0:
        raise ValueError("cat must hold at least one object to clone")
    k = np.arange(n)
    parent, copy = np.random.default_rng([int(seed)]).permutation(n0)[k % n0], k // n0
    dM, dO = np.zeros(n), np.zeros(n)
    for c in np.unique(copy):
        rows = np.flatnonzero(copy == c)
        m, o = clone_offsets(n0, int(c), seed)
        dM[rows], dO[rows] = m[parent[rows]], o[parent[rows]]
    out = cat.iloc[parent].reset_index(drop=True)
    clone = copy > 0
    out["norad"] = np.where(clone, CLONE_ID_BASE * copy + parent, out["norad"].to_numpy(np.int64))
    # a clone keeps its parent's element epoch, drag and shape; only the two angles below move
    out["raan_deg"] = np.mod(out["raan_deg"].to_numpy(float) + np.rad2deg(dO), 360.0)
    out["mean_anomaly_deg"] = np.mod(out["mean_anomaly_deg"].to_numpy(float) + np.rad2deg(dM), 360.0)
    for col in ("line1", "line2"):
        out[col] = pd.Series(np.where(clone, "", out[col].to_numpy(object)), dtype=object)
    out["parent"], out["copy"] = parent, copy
    out["d_mean_anomaly_rad"], out["d_raan_rad"] = dM, dO
    return out


def clone_satrecs(clones: pd.DataFrame, cat: pd.DataFrame) -> SatrecArray:
    """The SGP4 records of the rows of ``clones`` (from :func:`clone_population` of ``cat``)."""
    cat = check_catalogue(cat).reset_index(drop=True)
    parents = {}
    sats = []
    for p, c, dM, dO in zip(clones["parent"].to_numpy(np.int64), clones["copy"].to_numpy(np.int64),
                            clones["d_mean_anomaly_rad"].to_numpy(float), clones["d_raan_rad"].to_numpy(float)):
        s = parents.get(p)
        if s is None:
            s = parents[p] = Satrec.twoline2rv(cat.at[p, "line1"], cat.at[p, "line2"])
        if c == 0:
            sats.append(s)
            continue
        t = Satrec()
        t.sgp4init(WGS72, "i", s.satnum, s.jdsatepoch - _SGP4_EPOCH_JD + s.jdsatepochF, s.bstar, s.ndot, s.nddot,
                   s.ecco, s.argpo, s.inclo, np.mod(s.mo + dM, 2 * np.pi), s.no_kozai, np.mod(s.nodeo + dO, 2 * np.pi))
        sats.append(t)
    return SatrecArray(sats)


def clone_states(clones: pd.DataFrame, cat: pd.DataFrame, jd, fr, *, chunk: int = 20_000):
    """SGP4 states of the population at instants ``(jd, fr)``, ``chunk`` objects at a time.

    Yields ``(first row, error (n, K), r (n, K, 3), v (n, K, 3))`` per chunk, rows in population
    order (:func:`~.propagation.sgp4_states`: NaN where SGP4 fails or the state is implausible).
    """
    chunk = check_int(chunk, "chunk", minimum=1)
    a_mean = clones["semi_major_axis_km"].to_numpy(float)
    for i0 in range(0, len(clones), chunk):
        part = clones.iloc[i0:i0 + chunk]
        e, r, v = sgp4_states(clone_satrecs(part, cat), jd, fr, a_mean[i0:i0 + chunk])
        yield i0, e, r, v


@dataclass(frozen=True, eq=False)
class CloneScenario(CatalogueScenario):
    """A :class:`~.scenario.CatalogueScenario` of a cloned population: ``catalogue`` is the population
    (:func:`clone_population`), ``parents`` the catalogue it was cloned from."""

    parents: pd.DataFrame = None
    chunk: int = 20_000

    def states(self, times) -> tuple[np.ndarray, np.ndarray]:
        """SGP4 TEME states ``(N, K', 6)`` of every object at ``times`` (s since start), and validity."""
        jd, fr = time_grid_jd(self.start, np.asarray(times, dtype=float))
        parts = [(np.concatenate([r, v], axis=-1), e == 0)
                 for _, e, r, v in clone_states(self.catalogue, self.parents, jd, fr, chunk=self.chunk)]
        return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def simulate_clones(cat: pd.DataFrame, n: int, sensors, *, n_scans: int, seed, clone_seed: int,
                    start=None, chunk: int = 20_000) -> CloneScenario:
    """The scans of ground radars observing ``n`` objects cloned from ``cat`` (module docstring).

    As :func:`~.scenario.simulate_catalogue` with ``truth_rows="in_view"`` (same ``seed`` streams, same
    draws), the truth propagated ``chunk`` objects at a time over all scans; ``start`` defaults to the
    reference epoch of ``cat``. Peak memory: one chunk's states (``chunk × n_scans × 6`` floats) plus
    the rows in view.
    """
    cat = check_catalogue(cat).reset_index(drop=True)
    sensors = _check_sensors(sensors)
    K = check_int(n_scans, "n_scans", minimum=1)
    pop = clone_population(cat, n, clone_seed)
    if len(pop) == 0:
        raise ValueError("n must be at least 1")
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(check_int(seed, "seed"))
    rngs = [np.random.default_rng(s) for s in ss.spawn(len(sensors))]
    start = reference_epoch(cat) if start is None else pd.Timestamp(start)
    times = np.arange(K) * sensors[0].revisit_s
    jd, fr = time_grid_jd(start, times)
    check_epoch_span(cat, jd, fr)
    theta = gmst(jd, fr)
    norad = pop["norad"].to_numpy(np.int64)
    S = len(sensors)
    n_in_view = np.zeros((K, S), np.int64)
    decayed, truth_parts, seen = [], [], [[] for _ in range(S)]
    for i0, e, r, v in clone_states(pop, cat, jd, fr, chunk=chunk):
        bad = e != 0
        decayed.append(np.flatnonzero(bad.any(axis=1)) + i0)
        r_ef, v_ef = teme_to_ef(r, v, theta)
        seen_any = np.zeros(bad.shape, bool)
        for s, sen in enumerate(sensors):
            rae = sen.rae(r_ef)
            vis = sen.fov.contains(rae.reshape(-1, 3)).reshape(bad.shape)
            n_in_view[:, s] += vis.sum(axis=0)
            seen_any |= vis
            obj, kk = np.nonzero(vis)
            if sen.measurement == "rae_rate":  # the documented radar's range-rate too
                rae = np.concatenate([rae, range_rate_ef(r_ef, v_ef, sen.site)[..., None]], axis=-1)
            seen[s].append((kk, obj + i0, rae[obj, kk]))
        obj, kk = np.nonzero(seen_any)
        truth_parts.append((kk, obj + i0, np.concatenate([r[obj, kk], v[obj, kk]], axis=1)))
    scan_parts = []
    per_sensor = []
    for s in range(S):
        kk = np.concatenate([p[0] for p in seen[s]])
        obj = np.concatenate([p[1] for p in seen[s]])
        rae = np.concatenate([p[2] for p in seen[s]])
        order = np.lexsort((obj, kk))  # per scan, in population order: simulate_catalogue's rows
        per_sensor.append((kk[order], obj[order], rae[order]))
    bounds = [np.searchsorted(p[0], np.arange(K + 1)) for p in per_sensor]
    for k in range(K):
        for s, sen in enumerate(sensors):
            _, obj, rae = per_sensor[s]
            sl = slice(bounds[s][k], bounds[s][k + 1])
            Z, origin = sen.observe_rae(rae[sl], rngs[s])
            label = np.full(len(origin), -1, np.int64)
            label[origin >= 0] = norad[obj[sl][origin[origin >= 0]]]
            scan_parts.append((k, s, Z, label))
    kk = np.concatenate([p[0] for p in truth_parts])
    obj = np.concatenate([p[1] for p in truth_parts])
    X = np.concatenate([p[2] for p in truth_parts])
    order = np.lexsort((obj, kk))
    truth = truth_table(kk[order], times[kk[order]], norad[obj[order]], X[order], np.ones(len(order), bool))
    scan_idx = np.concatenate([np.full(len(p[2]), p[0]) for p in scan_parts])
    scans = scans_table(scan_idx, times[scan_idx], np.concatenate([np.full(len(p[2]), p[1]) for p in scan_parts]),
                        np.vstack([p[2] for p in scan_parts]), np.concatenate([p[3] for p in scan_parts]),
                        p=4 if sensors[0].measurement == "rae_rate" else 3)
    return CloneScenario(catalogue=pop, sensors=sensors, start=start, times=times, theta=theta, truth=truth,
                         scans=scans, n_in_view=n_in_view, decayed=norad[np.concatenate(decayed)], parents=cat,
                         chunk=chunk)

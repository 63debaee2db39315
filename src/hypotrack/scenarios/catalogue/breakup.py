"""A fresh breakup cloud: a real parent orbit fragmented by the NASA standard breakup model, seen by a radar.

The event
---------
The **parent** is one element set of the bundled catalogue (:func:`.load_catalogue`), by NORAD number
(the experiment's default: NOAA 18, 28654, a sun-synchronous weather satellite at about 850 km, of the
NOAA/POES family whose members NOAA 16 and NOAA 17 broke up in 2015 and 2021). At the **event time**
(the parent's element epoch floored to the minute, plus ``event_offset_s``) its SGP4 TEME state
``x_p = [r_p, v_p]`` is split into fragments (:func:`.sbm.sample_breakup`): fragment i starts at
``[r_p, v_p + Δv_i]`` with ``Δv_i`` the model's isotropic ejection velocity.

**Perigee handling.** A fragment whose osculating orbit is unbound or has its perigee below 100 km altitude
(:func:`hypotrack.models.plausibility.plausible_orbits`) re-enters within the revolution: it is removed at
the event and counted (``n_removed``); no other fragment is removed, and none decays inside the window (no
drag in the truth model, below).

**Truth motion.** Two-body + J2 with the WGS-84/EGM-96 constants (μ = 398600.4418 km³/s², R = 6378.137 km,
J2 = 1.08262668e-3), RK4 with 10-s steps (:class:`hypotrack.models.orbit3d.J2Orbit3D`). The trackers'
model uses SGP4's WGS-72 constants, a median 59 m apart after 1 h (that class's docstring): the truth is
not the trackers' model. Drag, J3+ and third bodies are left out; SGP4 needs element sets, which the
fragments do not have (the project fits none from states).

**Sensor and scans.** One ground radar (:class:`.GroundRadar`, ENU returns) at a high-latitude site: a
near-polar orbit passes within its view on every revolution, so the cloud is seen several times. It
scans every ``revisit_s`` from ``obs_start_s`` to ``obs_end_s`` after the event (scan 0 at ``obs_start_s``),
between the cloud's passes too (clutter only then). Each scan: detection with ``p_D``, isotropic ENU noise,
Poisson clutter (:meth:`.GroundRadar.observe_rae`).

Randomness: ``SeedSequence(seed).spawn(2)`` — the fragments, then the radar (drawn scan by scan).

The result is a :class:`BreakupScenario` with the attributes a catalogue tracker run reads
(``catalogue`` — one row per fragment with ``norad`` its id —, ``sensors``, ``start``, ``times``,
``theta``, ``truth``, ``scans``, ``n_in_view``, :meth:`BreakupScenario.states`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..._validation import check_int, check_positive
from ...models.orbit3d import J2Orbit3D
from ...models.plausibility import plausible_orbits
from ..tables import scans_table, scans_to_list, truth_table
from .frames import gmst, teme_to_ef
from .scenario import range_rate_ef
from .propagation import propagate, time_grid_jd
from .sbm import Fragments, sample_breakup
from .sensors import GroundRadar
from .tle import load_catalogue

__all__ = ["BreakupEvent", "BreakupScenario", "simulate_breakup", "TRUTH_MOTION", "FRAGMENT_ID_BASE",
           "nearest_neighbour_km", "gate_radius_km"]

#: The truth's two-body + J2 model (WGS-84/EGM-96 constants, 10-s RK4 steps, no process noise).
TRUTH_MOTION = J2Orbit3D(q=0.0, mu=398600.4418, j2=1.08262668e-3, radius=6378.137, max_step=10.0)
#: Fragment ids are ``FRAGMENT_ID_BASE + i`` (above every NORAD number of the bundled catalogue).
FRAGMENT_ID_BASE = 900_000


@dataclass(frozen=True)
class BreakupEvent:
    """What breaks up and how (module docstring). ``lc_min_m``: smallest fragment (m); ``scaling``: S of the
    explosion law; ``mass_kg``: the collision law's M; ``event_offset_s``: event time after the parent's epoch
    (floored to the minute)."""

    parent_norad: int = 28654
    kind: str = "explosion"
    parent_kind: str = "spacecraft"
    lc_min_m: float = 0.05
    scaling: float = 1.0
    mass_kg: float | None = None
    event_offset_s: float = 0.0


@dataclass(frozen=True, eq=False)
class BreakupScenario:
    """The simulated breakup (module docstring). ``times`` are seconds since ``start`` (= the event time +
    ``obs_start_s``); ``fragments`` the model's draws of the kept fragments; ``x0`` their TEME states at
    the event; ``n_removed`` the fragments removed at the event (perigee below 100 km or unbound);
    ``parent`` the parent's catalogue row; ``event_time`` the UTC instant of the breakup."""

    catalogue: pd.DataFrame
    sensors: tuple
    start: pd.Timestamp
    event_time: pd.Timestamp
    times: np.ndarray
    theta: np.ndarray
    truth: pd.DataFrame
    scans: pd.DataFrame
    n_in_view: np.ndarray
    decayed: np.ndarray
    fragments: Fragments
    x0: np.ndarray
    n_removed: int
    parent: pd.Series

    @property
    def offset_s(self) -> float:
        """Seconds from the event to ``start``."""
        return float((self.start - self.event_time).total_seconds())

    def scan_list(self, sensor: int = 0, *, with_origin: bool = False) -> list:
        """``[(t_k, Z_k)]`` of one sensor for every scan."""
        return scans_to_list(self.scans, times=self.times, sensor=sensor, with_origin=with_origin)

    def states(self, times) -> tuple[np.ndarray, np.ndarray]:
        """Truth TEME states ``(N, K', 6)`` of every fragment at ``times`` (s since ``start``) and the
        ``(N, K')`` validity mask (all true: no fragment decays in the truth model). Stepped from one
        sorted time to the next (the truth model is deterministic: the same states as from the event)."""
        t = np.asarray(times, dtype=float).reshape(-1)
        N = len(self.x0)
        out = np.empty((N, len(t), 6))
        if N == 0 or len(t) == 0:
            return out, np.ones((N, len(t)), bool)
        order = np.argsort(t, kind="stable")
        X, now = self.x0, -self.offset_s
        for j in order:
            X = TRUTH_MOTION.propagate(X, t[j] - now) if t[j] != now else X
            now = t[j]
            out[:, j] = X
        return out, np.ones((N, len(t)), bool)


def _parent(norad: int) -> pd.DataFrame:
    cat = load_catalogue()
    row = cat[cat["norad"] == int(norad)]
    if len(row) != 1:
        raise ValueError(f"parent_norad must be the NORAD number of one bundled element set, got {norad!r}")
    return row.reset_index(drop=True)


def simulate_breakup(event: BreakupEvent, radar: GroundRadar, *, obs_start_s: float, obs_end_s: float,
                     seed: int) -> BreakupScenario:
    """Simulate the breakup ``event`` and the ``radar``'s scans from ``obs_start_s`` to ``obs_end_s``
    (s after the event; module docstring). Deterministic in ``seed``."""
    if not isinstance(radar, GroundRadar):
        raise TypeError(f"radar must be a GroundRadar, got {type(radar).__name__}")
    t0 = check_positive(obs_start_s, "obs_start_s")
    if not obs_end_s > t0:
        raise ValueError(f"obs_end_s must be > obs_start_s = {t0} s, got {obs_end_s!r}")
    seed = check_int(seed, "seed")
    frag_ss, radar_ss = np.random.SeedSequence(seed).spawn(2)
    parent = _parent(event.parent_norad)
    event_time = parent["epoch"].iloc[0].floor("min") + pd.Timedelta(seconds=float(event.event_offset_s))
    p = propagate(parent, np.array([0.0]), event_time)
    if not p.valid[0, 0]:
        raise ValueError(f"parent {event.parent_norad}: SGP4 gives no state at the event time {event_time}")
    xp = np.r_[p.r[0, 0], p.v[0, 0]]
    frags = sample_breakup(event.kind, event.lc_min_m, np.random.default_rng(frag_ss), parent=event.parent_kind,
                           scaling=event.scaling, mass_kg=event.mass_kg)
    x0 = np.tile(xp, (len(frags), 1))
    x0[:, 3:] += frags.dv_km_s
    keep = plausible_orbits(x0) if len(x0) else np.zeros(0, bool)
    frags = Fragments(frags.lc_m[keep], frags.chi[keep], frags.dv_m_s[keep], frags.dv_km_s[keep])
    x0 = x0[keep]
    N = len(x0)
    ids = FRAGMENT_ID_BASE + np.arange(N, dtype=np.int64)
    start = event_time + pd.Timedelta(seconds=t0)

    grid = np.arange(0.0, float(obs_end_s) - t0 + 1e-9, radar.revisit_s)
    jd, fr = time_grid_jd(start, grid)
    theta_all = gmst(jd, fr)
    rng = np.random.default_rng(radar_ss)
    X = TRUTH_MOTION.propagate(x0, t0) if N else np.zeros((0, 6))
    kept_t, kept_theta, n_view, truth_parts, scan_parts = [], [], [], [], []
    for j, t in enumerate(grid):
        if j:
            X = TRUTH_MOTION.propagate(X, radar.revisit_s) if N else X
        r_ef, v_ef = teme_to_ef(X[:, None, :3], X[:, None, 3:], theta_all[j:j + 1])
        rae = radar.rae(r_ef[:, 0])
        vis = radar.fov.contains(rae) if N else np.zeros(0, bool)
        if radar.measurement == "rae_rate":  # the documented radar: its range-rate too
            rae = np.column_stack([rae, range_rate_ef(r_ef[:, 0], v_ef[:, 0], radar.site)])
        k = len(kept_t)
        rows = np.flatnonzero(vis)
        Z, origin = radar.observe_rae(rae[rows], rng)
        label = np.full(len(origin), -1, np.int64)
        label[origin >= 0] = ids[rows[origin[origin >= 0]]]
        scan_parts.append((k, t, Z, label))
        truth_parts.append((k, t, rows, X[rows].copy()))
        kept_t.append(t)
        kept_theta.append(theta_all[j])
        n_view.append(len(rows))
    times = np.array(kept_t, float)
    p_meas = 4 if radar.measurement == "rae_rate" else 3
    truth = truth_table(
        np.concatenate([np.full(len(p[2]), p[0]) for p in truth_parts]) if truth_parts else np.zeros(0, np.int64),
        np.concatenate([np.full(len(p[2]), p[1]) for p in truth_parts]) if truth_parts else np.zeros(0),
        np.concatenate([ids[p[2]] for p in truth_parts]) if truth_parts else np.zeros(0, np.int64),
        np.vstack([p[3] for p in truth_parts]) if truth_parts else np.zeros((0, 6)),
        np.ones(sum(len(p[2]) for p in truth_parts), bool))
    scans = scans_table(
        np.concatenate([np.full(len(p[2]), p[0]) for p in scan_parts]) if scan_parts else np.zeros(0, np.int64),
        np.concatenate([np.full(len(p[2]), p[1]) for p in scan_parts]) if scan_parts else np.zeros(0),
        np.zeros(sum(len(p[2]) for p in scan_parts), np.int64),
        np.vstack([p[2] for p in scan_parts]) if scan_parts else np.zeros((0, p_meas)),
        np.concatenate([p[3] for p in scan_parts]) if scan_parts else np.zeros(0, np.int64), p=p_meas)
    catalogue = pd.DataFrame({"norad": ids, "group": "breakup", "name": [f"fragment {i}" for i in range(N)],
                              "lc_m": frags.lc_m, "chi": frags.chi, "dv_m_s": frags.dv_m_s})
    return BreakupScenario(catalogue=catalogue, sensors=(radar,), start=start, event_time=event_time, times=times,
                           theta=np.array(kept_theta, float), truth=truth, scans=scans,
                           n_in_view=np.array(n_view, np.int64)[:, None], decayed=np.zeros(0, np.int64),
                           fragments=frags, x0=x0, n_removed=int((~keep).sum()), parent=parent.iloc[0])


def nearest_neighbour_km(truth: pd.DataFrame) -> np.ndarray:
    """Per (scan, object in view): the distance (km) to the nearest other object in view at that scan
    (NaN when it is alone), from a truth table's in-view rows."""
    out = []
    tv = truth[truth["in_view"]]
    for _, g in tv.groupby("scan", sort=True):
        P = g[["state_0", "state_1", "state_2"]].to_numpy()
        if len(P) < 2:
            out.append(np.full(len(P), np.nan))
            continue
        D = np.linalg.norm(P[:, None] - P[None], axis=-1)
        np.fill_diagonal(D, np.inf)
        out.append(D.min(axis=1))
    return np.concatenate(out) if out else np.zeros(0)


def gate_radius_km(sigma_km: float, gate_probability: float) -> float:
    """The smallest gate a 3-D position return can have: ``sqrt(χ²₃(P_G)) σ`` (innovation covariance ``σ² I``,
    the track's own uncertainty neglected; a real gate is larger)."""
    from scipy.stats import chi2

    return float(np.sqrt(chi2.ppf(gate_probability, 3)) * check_positive(sigma_km, "sigma_km"))

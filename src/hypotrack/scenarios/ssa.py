"""Space-situational-awareness scenarios of document 000 (Sec. IV–V): planar orbits and one FOV sensor.

Two cases, both deterministic functions of (parameters, seed):

* ``ssa50`` (Figs 6, 8–11): 50 objects on LEO–MEO orbits; the initial hypothesis knows 45 of
  them; the other 5 are "births" — unknown objects that first enter the field of view
  during the run.
* ``ssa15`` (Figs 12–14): 15 objects, all known and all starting inside the field of view.

The paper gives the geometry (a sensor looking 15° above the +x axis with a 30° field of
view, measuring x–y position) but not the numbers; the defaults of DESIGN.md §5 fill them:
semi-major axes 6,778–26,578 km, eccentricity ≤ 0.1 with perigee ≥ 200 km altitude, FOV
range 6,578–30,000 km, σ = 1 km, p_D = 0.95, about one clutter return per scan uniform in the
FOV, Δt = 60 s, 720 scans (one period of the longest orbit, 43,121 s), white-acceleration
process noise q = 1e-10 km²/s³, and an initial hypothesis ``N(truth + N(0, P₀), P₀)`` with
``P₀ = diag(1 km², 1 km², (1 m/s)², (1 m/s)²)``.

Orbit design (why every object passes through the FOV). All orbits are prograde, so an
object's polar angle increases monotonically and sweeps the FOV's 30° sector once per
revolution; perigee ≥ r_min and apogee ≤ r_max (checked) keep it inside the FOV's range
limits while it does. Each known object is placed so that it crosses the FOV's centre line
at a time drawn uniformly over ``min(its period, the run)`` — a uniform orbital phase when
the run covers its period, and still a guaranteed pass in a shortened (quick) run. Each
unknown object is given a first-entry time, stratified over ``birth_window`` (fractions of
the run) so the births are spread out, and an orbit long enough (period > entry time, out
of view at t = 0) that this is its first pass. Object ids: known objects ``0..n_known−1``,
births ``n_known..n_objects−1``.

Random streams (``numpy.random.SeedSequence(seed).spawn(4)``): orbits, process noise,
measurements, initial-hypothesis errors — so changing the sensor (σ, p_D, clutter) leaves
the orbits and the truth unchanged.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from functools import partial

import numpy as np
import pandas as pd

from .._validation import check_finite_array, check_int, check_nonnegative, check_positive, check_probability
from ..models.orbit import (
    EARTH_RADIUS,
    MU_EARTH,
    TwoBodyOrbit,
    circular_velocity,
    elements_to_state,
    orbital_period,
)
from ..models.population import SingleEventBirthDeath
from ..models.sensors import DetectionModel, FieldOfView, LinearPositionSensor, PoissonClutter, Sensor
from .tables import (
    scans_table,
    scans_to_list,
    state_columns,
    truth_table,
    truth_to_list,
)

__all__ = [
    "SSAParams",
    "SSAScenario",
    "simulate_ssa",
    "params_from_config",
    "scenario_from_config",
    "prior_table",
    "read_prior",
    "ssa_sensor",
]

_MAX_BIRTH_TRIES = 10_000


@dataclass(frozen=True)
class SSAParams:
    """Parameters of an SSA scenario (units: km, s). Defaults: the 50-object case.

    Parameters
    ----------
    n_objects, n_known : int
        Objects in the scenario and how many of them the initial hypothesis contains
        (``0 <= n_known <= n_objects``); the rest are births.
    start_in_view : bool
        Put every known object inside the FOV at t = 0 (the 15-object case).
    n_scans : int
        Number of scans ``K >= 1`` at times ``0, dt, ..., (K−1) dt``.
    dt : float
        Scan interval (s).
    a_min, a_max : float
        Range of semi-major axes (km), drawn uniformly.
    e_max : float
        Largest eccentricity; each orbit's ``e ~ U(0, min(e_max, 1 − (R_E + h_min)/a))``.
    min_perigee_altitude : float
        ``h_min``: perigee altitude floor (km) above ``R_E = 6378.137`` km.
    look_angle_deg, full_angle_deg, r_min, r_max : float
        The sensor's FOV wedge (sensor at the origin).
    sigma : float
        Position-measurement noise standard deviation (km); ``R = σ² I``.
    p_D : float
        Detection probability inside the FOV, in (0, 1].
    clutter_rate : float
        Expected clutter returns per scan, uniform over the FOV.
    q : float
        White-acceleration noise intensity (km²/s³) of the truth and of the model.
    mu : float
        Gravitational parameter (km³/s²).
    prior_position_std, prior_velocity_std : float
        Square roots of the diagonal of ``P₀`` (km, km/s).
    birth_window : (float, float)
        Fractions of the run between which the unknown objects first enter the FOV.
    """

    n_objects: int = 50
    n_known: int = 45
    start_in_view: bool = False
    n_scans: int = 720
    dt: float = 60.0
    a_min: float = 6778.0
    a_max: float = 26578.0
    e_max: float = 0.1
    min_perigee_altitude: float = 200.0
    look_angle_deg: float = 15.0
    full_angle_deg: float = 30.0
    r_min: float = 6578.0
    r_max: float = 30000.0
    sigma: float = 1.0
    p_D: float = 0.95
    clutter_rate: float = 1.0
    q: float = 1e-10
    mu: float = MU_EARTH
    prior_position_std: float = 1.0
    prior_velocity_std: float = 1e-3
    birth_window: tuple = (0.1, 0.5)

    def __post_init__(self):
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731 (frozen dataclass)
        set_("n_objects", check_int(self.n_objects, "n_objects", minimum=0))
        set_("n_known", check_int(self.n_known, "n_known", minimum=0, maximum=self.n_objects))
        if not isinstance(self.start_in_view, (bool, np.bool_)):
            raise TypeError(f"start_in_view must be a bool, got {type(self.start_in_view).__name__}")
        set_("n_scans", check_int(self.n_scans, "n_scans", minimum=1))
        for name in ("dt", "a_min", "a_max", "sigma", "mu", "prior_position_std", "prior_velocity_std"):
            set_(name, check_positive(getattr(self, name), name))
        for name in ("min_perigee_altitude", "clutter_rate", "q"):
            set_(name, check_nonnegative(getattr(self, name), name))
        set_("p_D", check_probability(self.p_D, "p_D", low_open=True))
        set_("e_max", check_probability(self.e_max, "e_max", high_open=True))
        perigee_floor = EARTH_RADIUS + self.min_perigee_altitude
        if self.a_min < perigee_floor:
            raise ValueError(
                f"a_min must be >= Earth radius + min_perigee_altitude = {perigee_floor} km, got {self.a_min}"
            )
        if self.a_max < self.a_min:
            raise ValueError(f"a_max must be >= a_min = {self.a_min} km, got {self.a_max}")
        # The FOV must contain every orbit's range band, or an object could cross the
        # FOV's sector above r_max / below r_min and never be seen.
        self.fov  # noqa: B018 (the property validates the wedge parameters)
        if perigee_floor < self.r_min:
            raise ValueError(
                f"r_min must be <= Earth radius + min_perigee_altitude = {perigee_floor} km so every perigee "
                f"is in range, got r_min = {self.r_min}"
            )
        apogee = self.a_max * (1 + self.e_max)
        if apogee > self.r_max:
            raise ValueError(f"a_max * (1 + e_max) = {apogee:.1f} km must be <= r_max = {self.r_max} km")
        w = tuple(float(v) for v in check_finite_array(self.birth_window, "birth_window", shape=(2,)))
        if not 0.0 <= w[0] <= w[1] <= 1.0:
            raise ValueError(f"birth_window must satisfy 0 <= start <= end <= 1, got {self.birth_window!r}")
        set_("birth_window", w)

    @property
    def fov(self) -> FieldOfView:
        return FieldOfView(self.look_angle_deg, self.full_angle_deg, self.r_min, self.r_max)

    @property
    def times(self) -> np.ndarray:
        return np.arange(self.n_scans) * self.dt

    @property
    def P0(self) -> np.ndarray:
        """Initial-hypothesis covariance ``diag(σ_r², σ_r², σ_v², σ_v²)``."""
        return np.diag([self.prior_position_std**2] * 2 + [self.prior_velocity_std**2] * 2)


@dataclass(frozen=True, eq=False)
class SSAScenario:
    """An SSA scenario: parameters, models, truth and scans tables, initial hypothesis.

    Attributes
    ----------
    params : SSAParams
    times : (K,) scan times (s).
    truth : DataFrame
        Truth table (:mod:`hypotrack.scenarios.tables`); ``state_0..3`` = x, y (km), vx, vy (km/s).
    scans : DataFrame
        Scans table; ``z_0, z_1`` = measured x, y (km); ``origin`` = object id or −1.
    prior_ids : (n_known,) ids of the objects in the initial hypothesis.
    prior_means : (n_known, 4), prior_covs : (n_known, 4, 4)
        The initial hypothesis: means = truth at t = 0 + N(0, P₀), covariances P₀.
    birth_ids : ids of the objects unknown to the initial hypothesis.
    first_in_view_scan : (n_objects,) first scan at which each object is in the FOV (−1: never).
    motion : TwoBodyOrbit
    sensor : Sensor
    """

    params: SSAParams
    times: np.ndarray
    truth: pd.DataFrame
    scans: pd.DataFrame
    prior_ids: np.ndarray
    prior_means: np.ndarray
    prior_covs: np.ndarray
    birth_ids: np.ndarray
    first_in_view_scan: np.ndarray
    motion: TwoBodyOrbit
    sensor: Sensor

    @property
    def fov(self) -> FieldOfView:
        return self.params.fov

    def scan_list(self, *, with_origin: bool = False) -> list:
        """``[(t_k, Z_k)]`` for every scan (empty scans included)."""
        return scans_to_list(self.scans, times=self.times, with_origin=with_origin)

    def truth_list(self, *, in_view_only: bool = False) -> list:
        """``[(t_k, ids, X_k)]`` for every scan."""
        return truth_to_list(self.truth, times=self.times, in_view_only=in_view_only)

    def birth_model(
        self, alpha=1e-3, beta=1e-4, n_birth_regions=10, velocity_std=0.5
    ) -> SingleEventBirthDeath:
        """Document 000's single-event birth/death model over this scenario's FOV (Eq. 30).

        Birth pdfs are uniform in position over each of ``n_birth_regions`` equal-angle
        sub-wedges, with velocity ``N(v_circ(r), velocity_std² I)`` (km/s) around the
        prograde circular-orbit velocity at the position: for e ≤ 0.1 the radial and
        tangential deviations from it are at most ~0.1·v_circ ≈ 0.4–0.8 km/s.
        """
        return SingleEventBirthDeath(
            alpha,
            beta,
            n_birth_regions,
            fov=self.fov,
            velocity_cov=np.eye(2) * check_positive(velocity_std, "velocity_std") ** 2,
            velocity_mean=partial(circular_velocity, mu=self.params.mu),
        )


def ssa_sensor(p: SSAParams) -> Sensor:
    """The scenario's sensor: position measurements (σ² I), detection with ``p_D`` inside the FOV wedge,
    Poisson clutter at ``clutter_rate`` returns per scan uniform over the FOV."""
    fov = p.fov
    return Sensor(
        LinearPositionSensor(np.eye(2) * p.sigma**2, 4, (0, 1)),
        DetectionModel(p.p_D, fov),
        PoissonClutter(p.clutter_rate, fov),
    )


def _draw_orbit(p: SSAParams, rng, a_low: float):
    a = rng.uniform(a_low, p.a_max)
    e_cap = min(p.e_max, 1.0 - (EARTH_RADIUS + p.min_perigee_altitude) / a)
    return a, rng.uniform(0.0, max(e_cap, 0.0)), rng.uniform(0.0, 2 * np.pi)


def _state_at_angle_before(motion, a, e, w, angle_deg, t):
    """State at t = 0 of the orbit (a, e, w) that is at polar angle ``angle_deg`` at time t."""
    x_t = elements_to_state(a, e, w, np.deg2rad(angle_deg) - w, motion.mu)
    return motion.propagate(x_t, -t)


def _initial_states(p: SSAParams, motion: TwoBodyOrbit, rng) -> np.ndarray:
    fov = p.fov
    lo, hi = fov.angle_limits_deg
    run = (p.n_scans - 1) * p.dt
    X0 = np.zeros((p.n_objects, 4))
    for i in range(p.n_known):
        a, e, w = _draw_orbit(p, rng, p.a_min)
        if p.start_in_view:
            X0[i] = elements_to_state(a, e, w, np.deg2rad(rng.uniform(lo, hi)) - w, p.mu)
        else:
            t_c = rng.uniform(0.0, min(orbital_period(a, p.mu), run))
            X0[i] = _state_at_angle_before(motion, a, e, w, p.look_angle_deg, t_c)
    n_births = p.n_objects - p.n_known
    edges = np.linspace(*p.birth_window, n_births + 1) * run
    for j in range(n_births):
        t_e = rng.uniform(edges[j], edges[j + 1])
        # Smallest semi-major axis whose period exceeds t_e: then t_e is the first entry.
        a_low = max(p.a_min, (p.mu * (t_e / (2 * np.pi)) ** 2) ** (1 / 3))
        if a_low > p.a_max:
            raise ValueError(
                f"no orbit with a <= a_max = {p.a_max} km has a period longer than the birth time "
                f"{t_e:.0f} s; "
                f"lower birth_window or raise a_max"
            )
        for _ in range(_MAX_BIRTH_TRIES):
            a, e, w = _draw_orbit(p, rng, a_low)
            x0 = _state_at_angle_before(motion, a, e, w, lo, t_e)
            if not fov.contains(x0[None, :2])[0]:
                break
        else:
            raise RuntimeError(f"could not place birth {j} out of view at t = 0; widen birth_window")
        X0[p.n_known + j] = x0
    return X0


def simulate_ssa(params: SSAParams, seed) -> SSAScenario:
    """Generate an SSA scenario: orbits, truth with process noise, scans, initial hypothesis.

    Parameters
    ----------
    params : SSAParams
    seed : int or numpy.random.SeedSequence
        Everything random flows from it (see the module docstring for the streams).

    Returns
    -------
    SSAScenario
    """
    if not isinstance(params, SSAParams):
        raise TypeError(f"params must be an SSAParams, got {type(params).__name__}")
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(check_int(seed, "seed"))
    rng_orbit, rng_noise, rng_meas, rng_prior = (np.random.default_rng(s) for s in ss.spawn(4))
    p = params
    motion = TwoBodyOrbit(p.mu, p.q)
    sensor = ssa_sensor(p)
    times = p.times
    N, K = p.n_objects, p.n_scans

    X = _initial_states(p, motion, rng_orbit)
    L_Q = np.linalg.cholesky(motion.Q(p.dt)) if p.q > 0 else np.zeros((4, 4))
    states = np.empty((K, N, 4))
    Z_rows, origin_rows, scan_rows = [], [], []
    for k in range(K):
        if k > 0:
            X = motion.propagate(X, p.dt) + rng_noise.standard_normal((N, 4)) @ L_Q.T
        states[k] = X
        Z, origin = sensor.observe(X, rng_meas)  # origin is a row index = object id
        Z_rows.append(Z)
        origin_rows.append(origin)
        scan_rows.append(np.full(len(Z), k))

    in_view = sensor.in_view(states.reshape(-1, 4)).reshape(K, N)
    truth = truth_table(
        np.repeat(np.arange(K), N),
        np.repeat(times, N),
        np.tile(np.arange(N), K),
        states.reshape(-1, 4),
        in_view.ravel(),
    )
    scan_idx = np.concatenate(scan_rows) if K else np.zeros(0, int)
    scans = scans_table(
        scan_idx,
        times[scan_idx],
        np.zeros(len(scan_idx)),
        np.vstack(Z_rows),
        np.concatenate(origin_rows),
        p=2,
    )
    prior_ids = np.arange(p.n_known)
    L0 = np.linalg.cholesky(p.P0)
    prior_means = states[0, : p.n_known] + rng_prior.standard_normal((p.n_known, 4)) @ L0.T
    seen = in_view.any(axis=0)
    first = np.where(seen, in_view.argmax(axis=0), -1)
    return SSAScenario(
        params=p,
        times=times,
        truth=truth,
        scans=scans,
        prior_ids=prior_ids,
        prior_means=prior_means,
        prior_covs=np.broadcast_to(p.P0, (p.n_known, 4, 4)).copy(),
        birth_ids=np.arange(p.n_known, N),
        first_in_view_scan=first,
        motion=motion,
        sensor=sensor,
    )


# --- configuration ----------------------------------------------------------------------------

_CASE_KEYS = ("n_objects", "n_known", "start_in_view", "seed")


def params_from_config(section: Mapping, case: str) -> SSAParams:
    """:class:`SSAParams` from the pipeline's ``ssa`` config section and a case name.

    The section holds the shared parameters and one sub-mapping per case (``ssa50``,
    ``ssa15``) with ``n_objects``, ``n_known``, ``start_in_view`` and ``seed``.
    """
    if case not in section:
        raise ValueError(
            f"unknown SSA case {case!r}; the config defines "
            f"{sorted(k for k in section if isinstance(section[k], Mapping))}"
        )
    names = {f.name for f in fields(SSAParams)}
    shared = {k: v for k, v in section.items() if k in names}
    own = {k: v for k, v in section[case].items() if k in names}
    if "birth_window" in shared:
        shared["birth_window"] = tuple(shared["birth_window"])
    return SSAParams(**(shared | own))


def scenario_from_config(config: Mapping, case: str) -> SSAScenario:
    """The scenario of ``case`` under a full pipeline config (top-level ``seed`` + ``ssa``).

    The seed is ``SeedSequence([config["seed"], config["ssa"][case]["seed"]])``, so each
    case has its own streams and the master seed changes all of them.
    """
    section = config["ssa"]
    params = params_from_config(section, case)
    seed = np.random.SeedSequence(
        [check_int(config["seed"], "seed"), check_int(section[case]["seed"], f"ssa.{case}.seed")]
    )
    return simulate_ssa(params, seed)


# --- initial-hypothesis table -----------------------------------------------------------------


def prior_table(scenario: SSAScenario) -> pd.DataFrame:
    """The initial hypothesis as a table: ``target``, ``state_0..3``, ``cov_i_j`` (i, j = 0..3)."""
    df = pd.DataFrame({"target": scenario.prior_ids.astype(np.int64)})
    for c, col in zip(state_columns(4), scenario.prior_means.T):
        df[c] = col
    for i in range(4):
        for j in range(4):
            df[f"cov_{i}_{j}"] = scenario.prior_covs[:, i, j]
    return df


def read_prior(df: pd.DataFrame):
    """Inverse of :func:`prior_table`: ``(ids (n,), means (n, 4), covs (n, 4, 4))``."""
    cov_cols = [f"cov_{i}_{j}" for i in range(4) for j in range(4)]
    missing = [c for c in ["target", *state_columns(4), *cov_cols] if c not in df.columns]
    if missing:
        raise ValueError(f"prior table is missing columns {missing}")
    ids = df["target"].to_numpy(dtype=np.int64)
    means = check_finite_array(df[state_columns(4)].to_numpy(dtype=float), "prior means")
    covs = check_finite_array(df[cov_cols].to_numpy(dtype=float), "prior covariances").reshape(-1, 4, 4)
    return ids, means, covs

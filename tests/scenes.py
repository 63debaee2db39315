"""Scene builders shared by the tests.

Most hypothesis-filter and tracker tests use one kind of scene: objects with a 2-D
constant-velocity state ``(x, y, vx, vy)``, a linear sensor of their positions with a detection
probability inside a field of view, and Poisson clutter uniform over a region. The builders
below write that scene once; each test module keeps its own numbers (noise, rates, regions), so
the values it asserts do not change.

Import them as ``from scenes import ...``: pyproject's ``[tool.pytest.ini_options] pythonpath``
puts ``tests/`` on the import path (test modules are imported with ``--import-mode=importlib``,
which does not, and cannot import from ``conftest``).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from hypotrack.hypotheses.population_events import SingleEventPopulation
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.measurement import ExtendedMeasurement
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor

#: Measurement matrix of a position sensor on ``(x, y, vx, vy)``.
H_POSITION = np.hstack([np.eye(2), np.zeros((2, 2))])

#: The 100 x 100 field of view centred on the origin, and its left and right halves (two birth regions).
REGION = Box([-50.0, -50.0], [50.0, 50.0])
HALVES = (Box([-50.0, -50.0], [0.0, 50.0]), Box([0.0, -50.0], [50.0, 50.0]))

#: Three objects in view, moving apart, with a common prior covariance (the small filter scene).
THREE_MEANS = np.array([[0.0, 0.0, 1.0, 0.0], [4.0, 1.0, 0.0, 1.0], [-10.0, 5.0, 0.5, -0.5]])
THREE_COVS = np.repeat(np.diag([1.0, 1.0, 0.2, 0.2])[None], 3, axis=0)
for _shared in (H_POSITION, THREE_MEANS, THREE_COVS):  # shared by several modules: read-only
    _shared.setflags(write=False)


def position_sensor(R=0.5, p_D=0.9, view=REGION, clutter_rate=1.0, clutter_region=None, ndim_state=4) -> Sensor:
    """A linear sensor of the positions (the first two state components).

    ``R`` is the measurement-noise covariance (a scalar ``r`` means ``r I``); objects are detected with
    probability ``p_D`` inside ``view`` (``None``: everywhere); clutter is Poisson with mean
    ``clutter_rate`` uniform over ``clutter_region`` (default: ``view``). ``clutter_rate=None``: no clutter.
    """
    R = np.eye(2) * R if np.ndim(R) == 0 else R
    detection = DetectionModel(p_D) if view is None else DetectionModel(p_D, view)
    if clutter_rate is None:
        return Sensor(LinearPositionSensor(R, ndim_state), detection)
    return Sensor(LinearPositionSensor(R, ndim_state), detection,
                  PoissonClutter(clutter_rate, view if clutter_region is None else clutter_region))


def single_event_population(alpha, beta, max_events, regions=(REGION,), birth_cov=None) -> SingleEventPopulation:
    """H-FISST's single-event population: birth probability ``alpha``, death probability ``beta``, at
    most ``max_events`` births or deaths per scan, a uniform birth density on each region (position
    covariance ``birth_cov``, default ``I``)."""
    cov = np.eye(2) if birth_cov is None else birth_cov
    return SingleEventPopulation(SingleEventBirthDeath(alpha, beta, max_events),
                                 birth_densities=[UniformBirthDensity(r, cov) for r in regions])


def observed_scans(X, motion, sensor, n_scans, seed, dt=1.0):
    """``n_scans`` scans of ``sensor`` observing objects at ``X`` moved by ``motion``'s mean (no process
    noise), one generator seeded with ``seed``; the scans and the objects' final states."""
    rng = np.random.default_rng(seed)
    F, scans = motion.F(dt), []
    for _ in range(n_scans):
        X = X @ F.T
        scans.append(sensor.observe(X, rng)[0])
    return scans, X


@lru_cache(maxsize=4)
def sgp4_in_view(n_objects: int, span_s: float, step_s: float):
    """The first ``n_objects`` bundled active satellites propagated by SGP4 every ``step_s`` over ``span_s``
    from the catalogue's epoch, and which of them the default radar sees when: ``(cat, start, p, theta, vis)``
    (``p`` the TEME propagation, ``theta`` the Greenwich sidereal angles, ``vis`` ``(n_objects, n_times)``).

    Built once per argument set for the whole session (several modules check the radar and the births on these
    real states); the arrays are read-only."""
    from hypotrack.scenarios.catalogue import DEFAULT_RADAR, load_catalogue, propagate, select_groups
    from hypotrack.scenarios.catalogue.frames import gmst, teme_to_ef
    from hypotrack.scenarios.catalogue.propagation import reference_epoch, time_grid_jd

    cat = select_groups(load_catalogue(), "active").iloc[:n_objects].reset_index(drop=True)
    start = reference_epoch(cat)
    t = np.arange(0.0, span_s, step_s)
    p = propagate(cat, t, start)
    theta = gmst(*time_grid_jd(start, t))
    r_ef, _ = teme_to_ef(p.r, p.v, theta)
    vis = DEFAULT_RADAR.in_view(r_ef)
    for a in (p.r, p.v, theta, vis):
        if isinstance(a, np.ndarray):
            a.setflags(write=False)
    return cat, start, p, theta, vis


def hypotheses_by_label(f) -> dict:
    """Per label of a factored filter (its ``groups``), the ``(weight, mean, cov)`` of every hypothesis holding it,
    heaviest first: what the lane-against-general-engine tests compare."""
    out = {}
    for g in f.groups:
        for w, t in zip(np.exp(g.log_w), g.tracks):
            for j in t:
                out.setdefault(int(g.store.labels[j]), []).append((float(w), g.store.means[j], g.store.covs[j]))
    return {lab: sorted(v, key=lambda e: -e[0]) for lab, v in out.items()}


def label_existence(f, label) -> float:
    """The total weight of a factored filter's hypotheses holding ``label`` (its existence probability)."""
    return sum(w for w, _, _ in hypotheses_by_label(f).get(label, []))


def fake_catalogue_run(results) -> None:
    """A whole-catalogue run's tables as the ``ssa_catalogue`` table job writes them, under ``results``: two sizes of
    δ-GLMB (300 and 10,855 objects), and the configuration of ``full.yaml`` with the seed its runs use (the section's
    evaluated one). The record tests feed it to the record step."""
    import json
    from pathlib import Path

    from hypotrack.experiments.ssa_catalogue.run import evaluated_on
    from hypotrack.reporting.record import full_config

    full = full_config()
    src = Path(results) / "ssa_catalogue"
    src.mkdir(parents=True)
    (src / "summary.csv").write_text("tracker,n_objects,n_scans,mean_in_view,gospa_km,born,unknown_in_view\n"
                                     "glmb,300,60,2.0,1.5,1,1\nglmb,10855,60,105.7,52.0,34,39\n")
    (src / "summary_timing.csv").write_text(
        "tracker,n_objects,cpu_s_per_scan,cpu_ms_per_object_in_view,peak_bytes,mean_in_view\n"
        "glmb,10855,0.0709,0.67,40031470,105.7\nglmb,300,0.0066,3.3,1283569,2.0\n")
    seed = evaluated_on(full["ssa_catalogue"], full["seed"])[0]
    (src / "run_config.json").write_text(json.dumps({"seed": seed, "ssa_catalogue": full["ssa_catalogue"]}))


class RangeBearing(ExtendedMeasurement):
    """``(√(x² + y²), atan2(y, x))`` of a state ``(x, y, vx, vy)``; :meth:`one_point` the polar-to-Cartesian
    initiation, ``J R Jᵀ + position_std² I`` on the position and ``velocity_std² I`` on the velocity."""

    wrapped = (1,)
    ndim_state = 4

    def __init__(self):
        self.R = np.diag([0.04, 1e-4])

    def h(self, means):
        return np.column_stack([np.hypot(means[:, 0], means[:, 1]), np.arctan2(means[:, 1], means[:, 0])])

    def jacobian(self, means):
        x, y = means[:, 0], means[:, 1]
        r2 = x * x + y * y
        r = np.sqrt(r2)
        J = np.zeros((len(means), 2, 4))
        J[:, 0, 0], J[:, 0, 1] = x / r, y / r
        J[:, 1, 0], J[:, 1, 1] = -y / r2, x / r2
        return J

    def one_point(self, Z, position_std=0.0, velocity_std=8.0):
        Z = np.atleast_2d(np.asarray(Z, dtype=float))
        x0, P0 = np.zeros((len(Z), 4)), np.zeros((len(Z), 4, 4))
        for i, (r, b) in enumerate(Z):
            x0[i, :2] = r * np.cos(b), r * np.sin(b)
            J = np.array([[np.cos(b), -r * np.sin(b)], [np.sin(b), r * np.cos(b)]])
            P0[i, :2, :2] = J @ self.R @ J.T + position_std**2 * np.eye(2)
            P0[i, 2:, 2:] = velocity_std**2 * np.eye(2)
        return x0, P0


def default_catalogue_config(n_scans: int) -> dict:
    """The default configuration's ``ssa_catalogue`` section with ``n_scans`` scans (run from the repository root)."""
    import yaml

    with open("workflows/config/default.yaml") as fh:
        return dict(yaml.safe_load(fh)["ssa_catalogue"], n_scans=n_scans)


def catalogue_scene(cfg: dict, n_objects: int, snr: bool = True):
    """The catalogue experiment's scene as its run steps it (:mod:`hypotrack.experiments.ssa_catalogue.run`): the
    first ``n_objects`` of the bundled catalogue under ``cfg``, its tracker sensor (``snr``: p_D from the
    signal-to-noise ratio, as the experiment's), the initial tracks and the scans.

    Returns a namespace: ``problem()`` (a new tracking problem of the initial tracks each call), ``sensor``,
    ``scans`` (``(t, returns, theta)`` per scan, the sensor's returns read at that scan's rotation), ``labels``
    (the catalogued labels) and ``scenario``."""
    from types import SimpleNamespace

    from hypotrack.experiments.ssa_breakup.run import attach_tracker_snr
    from hypotrack.experiments.ssa_catalogue.run import (build_scenario, initial_tracks, make_motion, make_problem,
                                                        tracker_sensor)

    _, unknown, sc, init_seed = build_scenario(cfg, n_objects, 1)
    tsensor = tracker_sensor(sc.sensors[0])
    if snr:
        tsensor = attach_tracker_snr(cfg, tsensor)
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    scans = []
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        scans.append((float(t_k), tsensor.returns(Z), sc.theta[k]))
    return SimpleNamespace(problem=lambda: make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels),
                           sensor=tsensor, scans=scans, labels=labels, scenario=sc)

"""The registry's fused trackers (hypotrack.registry on a MultiSensorProblem).

Scene: three known objects and two sensors with different noise, p_D, clutter and fields of view — A sees
x <= 1, B sees x >= -1 with a p_D that is a function of the state (0.6 below y = 3, 0.8 above) — so that a is
seen by A only, b by both and c by B only until it leaves B's view (x > 10, seen by no sensor); N1 is born at
t = 2 in both views, N2 at t = 3 in B's only. Six instants, A's scan then B's at each (a zero interval).

The oracle of the registry's construction is the fused tracker wrapped by hand from the presets and the
single-hypothesis tracker's own classes (the problem's births translated by hand: δ-GLMB's labeled
multi-Bernoulli population, the FISST presets' binomial one, HOMHT's births seeded at the returns, GNN/JPDA's
β_NT), equal after every scan: every hypothesis weight and track moment (engine), every track, tentative track
and miss count (GNN/JPDA/PDAF).
"""

from types import SimpleNamespace

import numpy as np
import pytest

from hypotrack.hypotheses import BinomialPopulation, GaussianBirthTerm, LabeledMultiBernoulliPopulation, presets
from hypotrack.hypotheses.factored import AdaptiveBirth
from hypotrack.hypotheses.factored.multisensor import MultiSensorFactored
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box
from hypotrack.protocol import Tracker
from hypotrack.registry import (MeasurementBirths, MultiSensorProblem, SensorEntry, TrackerSpec, TrackingProblem,
                                build, kinds, preset, register, unregister)
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker
from hypotrack.trackers.multisensor import MultiSensorSHT
from scenes import position_sensor

MOTION = ConstantVelocity(q=0.02)
R_A, R_B = np.eye(2) * 0.3, np.diag([0.1, 0.6])
BOX_A, BOX_B = Box([-10.0, -10.0], [1.0, 10.0]), Box([-1.0, -10.0], [10.0, 10.0])
SENSOR_A = position_sensor(R_A, 0.85, BOX_A, 1.0)
BASE_B = position_sensor(R_B, 0.7, BOX_B, 0.5)
X0 = np.array([[-6.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.0, 0.5], [6.0, 0.0, 1.0, 0.0]])  # a, b, c
P0 = np.repeat(np.diag([0.3, 0.3, 0.02, 0.02])[None], 3, axis=0)
LABELS = [10, 11, 12]
GATE, R_BIRTH, V_STD, SEED = 0.999, 0.3, 1.0, 3
INTENSITY = (0.01, 0.02)  # HOMHT's λ_B and GNN/JPDA's β_NT per sensor


class _ByY:
    """B's detection: its fov; p_D 0.6 below y = 3, 0.8 above (``p_D_of`` of the predicted means)."""

    def __init__(self, base):
        self.p_D, self.fov, self._base = base.p_D, base.fov, base

    def in_view(self, z):
        return self._base.in_view(z)

    def p_D_of(self, means):
        return np.where(np.asarray(means)[:, 1] < 3.0, 0.6, 0.8)


SENSOR_B = SimpleNamespace(measurement=BASE_B.measurement, detection=_ByY(BASE_B.detection), clutter=BASE_B.clutter)
SENSORS = (SENSOR_A, SENSOR_B)
BOXES = (BOX_A, BOX_B)


def _view(box):
    return lambda x: box.contains(np.asarray(x)[:, :2])


def _births(s):
    """Sensor ``s``'s births at its returns: its own one-point spreads, seeded intensity and density."""
    return MeasurementBirths(AdaptiveBirth(position_std=0.2 * s, velocity_std=V_STD * (1.0 - 0.3 * s),
                                           r_birth=R_BIRTH, gate_probability=GATE),
                             r_birth=R_BIRTH, seeded_intensity=INTENSITY[s],
                             seeded_density=UniformBirthDensity(BOXES[s], np.eye(2) * V_STD**2))


def _problem():
    return MultiSensorProblem(MOTION, [SensorEntry(SENSORS[s], _view(BOXES[s]), _births(s)) for s in (0, 1)],
                              X0, P0, LABELS, time=0.0, dt=1.0)


def _scans():
    """(time, sensor, returns): the objects moved by the motion's mean, each sensor's detections and clutter."""
    rng = np.random.default_rng(5)
    X, F, out = X0.copy(), MOTION.F(1.0), []
    for t in range(1, 7):
        X = X @ F.T
        if t == 2:
            X = np.vstack([X, [0.2, 6.0, 0.0, 0.2]])  # N1
        if t == 3:
            X = np.vstack([X, [5.0, -6.0, 0.0, 0.0]])  # N2
        for s in (0, 1):
            out.append((float(t), s, (SENSOR_A if s == 0 else BASE_B).observe(X, rng)[0]))
    return out


SCANS = _scans()
FACTORED = {"split": "marginal", "lazy": True, "gate_out_of_view": False, "min_weight": 0.001}
ENGINE_SPECS = {
    "glmb": {"kind": "glmb", "n_sweeps": 30, "max_hypotheses": 15, "gate_probability": GATE},
    "glmb_murty": {"kind": "glmb_murty", "max_hypotheses": 15, "gate_probability": GATE},
    "rfisst": {"kind": "rfisst", "n_steps": 60, "max_hypotheses": 15, "gate_probability": GATE},
    "fisst_kbest": {"kind": "fisst_kbest", "max_hypotheses": 15, "gate_probability": GATE},
    "homht_kbest": {"kind": "homht_kbest", "population": True, "max_hypotheses": 15, "gate_probability": GATE},
    "homht": {"kind": "homht", "max_hypotheses": 15, "gate_probability": GATE},
}
SINGLE_SPECS = {a: {"kind": a, "gate_probability": GATE, "m_of_n": [2, 3], "initial_velocity_std": V_STD}
                for a in ("gnn", "jpda", "pdaf")}
SPECS = {**{k: {**v, "factored": FACTORED} for k, v in ENGINE_SPECS.items()}, **SINGLE_SPECS}


def _engine_by_hand(kind, s):
    """Sensor ``s``'s engine from the presets, the problem's births in the preset's own terms (by hand)."""
    sensor, b = SENSORS[s], _births(s)
    common = dict(dt=1.0, max_hypotheses=15, cap="top", gate_probability=GATE, merge_duplicates=True, seed=SEED)
    lmb = LabeledMultiBernoulliPopulation([], r_birth=R_BIRTH, p_survive=1.0)
    binomial = BinomialPopulation([], alpha=R_BIRTH, p_survive=1.0)
    f = {"glmb": lambda: presets.glmb(MOTION, sensor, population=lmb, n_sweeps=30, **common),
         "glmb_murty": lambda: presets.glmb_murty(MOTION, sensor, population=lmb, **common),
         "rfisst": lambda: presets.rfisst(MOTION, sensor, n_steps=60, population=binomial, **common),
         "fisst_kbest": lambda: presets.fisst_kbest(MOTION, sensor, population=binomial, **common),
         "homht_kbest": lambda: presets.homht_kbest(MOTION, sensor, birth_intensity=b.seeded_intensity,
                                                    birth_density=b.seeded_density, **common),
         "homht": lambda: presets.homht(MOTION, sensor, **common)}[kind]()
    f.initialise(X0, P0, LABELS, time=0.0)
    return f, (b.adaptive if f.population is not None else None)


def _single_by_hand(association, s):
    """Sensor ``s``'s GNN/JPDA/PDAF: its scan model (β_FA = λ/V, β_NT the seeded intensity), M-of-N initiation."""
    sensor = SENSORS[s]
    model = ScanModel(sensor.measurement.H, sensor.measurement.R, sensor.detection.p_D, GATE,
                      sensor.clutter.rate / sensor.clutter.region.area, INTENSITY[s])
    ini = MOfNInitiator(MOTION, model, m=2, n=3, initial_velocity_std=V_STD)
    t = SingleHypothesisTracker(MOTION, model, association=association, initiator=ini, max_misses=3,
                                in_view=_view(BOXES[s]), p_detect=getattr(sensor.detection, "p_D_of", None))
    t.initialise(X0, P0, LABELS, time=0.0)
    return t


def _by_hand(kind):
    if kind in ENGINE_SPECS:
        filters, births = zip(*(_engine_by_hand(kind, s) for s in (0, 1)))
        return MultiSensorFactored.from_filters(list(filters), list(births), **FACTORED)
    return MultiSensorSHT.from_trackers([_single_by_hand(kind, s) for s in (0, 1)])


def _engine_table(ff):
    """Every group's hypotheses: (log weights, track lists, labels, means, covariances)."""
    return [(np.asarray(g.log_w), [list(t) for t in g.tracks], g.store.labels, g.store.means, g.store.covs)
            for g in ff.groups]


def _single_table(t):
    ini = t.initiator
    return [t.ids, t.x, t.P, t.misses, ini.x, ini.P]


@pytest.mark.parametrize("kind", list(SPECS))
def test_registry_fused_tracker_equals_the_hand_wrapped_one(kind):
    reg, hand = build(SPECS[kind], _problem(), seed=SEED), _by_hand(kind)
    assert type(reg) is type(hand) is (MultiSensorFactored if kind in ENGINE_SPECS else MultiSensorSHT)
    grew = False
    for t, s, Z in SCANS:
        reg.step(Z, t, sensor=s)
        hand.step(Z, t, sensor=s)
        if kind in ENGINE_SPECS:
            a, b = _engine_table(reg), _engine_table(hand)
            assert len(a) == len(b)
            for ga, gb in zip(a, b):
                assert ga[1] == gb[1]
                np.testing.assert_array_equal(ga[2], gb[2])
                for x, y in zip(ga[:1] + ga[3:], gb[:1] + gb[3:]):
                    np.testing.assert_allclose(x, y, rtol=0, atol=1e-12)
            assert reg.same_posterior(hand)  # and bit for bit (lane and lazy times included)
            grew |= any(len(g[1]) > 1 for g in a)
        else:
            for x, y in zip(_single_table(reg), _single_table(hand), strict=True):
                assert np.shape(x) == np.shape(y)
                np.testing.assert_allclose(x, y, rtol=0, atol=1e-12)
            grew |= len(reg.ids) > 3
    # the scene did something: several hypotheses in a group (engine), or a confirmed newborn (GNN/JPDA/PDAF)
    assert grew
    assert sorted(reg.estimates().labels.tolist())[:2] == [10, 11]


# ------------------------------------------------------------------------------------------ the step contract
def _estimates(tr):
    e = tr.estimates()
    return e.labels, e.x


def _same(e1, e2):
    assert np.array_equal(e1[0], e2[0])
    np.testing.assert_allclose(e1[1], e2[1], rtol=0, atol=1e-12)


@pytest.mark.parametrize("kind", list(SPECS))
def test_step_with_sensor_contract(kind):
    """Shared by every kind that fuses: ``step(Z, time, sensor=s)`` (default 0) takes a scan of sensor s with
    sensor s's model; a bad sensor index or a failed scan leaves the tracker as it was (the sensor included)."""
    problem = _problem()
    tr = build(SPECS[kind], problem, seed=SEED)
    assert isinstance(tr, Tracker) and tr.sensor == 0
    # sensor s's first scan is what sensor s's own (single-sensor) registry tracker makes of it
    t, s, Z = SCANS[1]
    single = build(SPECS[kind], problem.problem(1), seed=SEED)
    assert not isinstance(single, (MultiSensorFactored, MultiSensorSHT))
    tr.step(Z, t, sensor=1)
    single.step(Z, t)
    _same(_estimates(tr), _estimates(single))
    assert tr.sensor == 1
    # and not what sensor 0's model would make of it (B's return of c, x = 7: A would not see c)
    other = build(SPECS[kind], problem, seed=SEED)
    other.step(Z, t, sensor=0)
    e, o = _estimates(tr), _estimates(other)
    c_tr, c_o = e[1][list(e[0]).index(12)], o[1][list(o[0]).index(12)]
    assert np.linalg.norm(c_tr - c_o) > 1e-3
    before = _estimates(tr)
    for bad, err in ((2, ValueError), (-1, ValueError), (True, TypeError), (1.0, TypeError)):
        with pytest.raises(err, match="sensor"):
            tr.step(SCANS[2][2], 2.0, sensor=bad)
        assert tr.sensor == 1
        _same(_estimates(tr), before)
    with pytest.raises(ValueError):
        tr.step(np.zeros((1, 3)), 2.0, sensor=0)  # returns of the wrong dimension
    assert tr.sensor == 1
    _same(_estimates(tr), before)
    # the default sensor is 0, and a retried scan is the scan
    twin = build(SPECS[kind], problem, seed=SEED)
    twin.step(Z, t, sensor=1)
    tr.step(SCANS[2][2], 2.0)
    twin.step(SCANS[2][2], 2.0, sensor=0)
    assert tr.sensor == twin.sensor == 0
    _same(_estimates(tr), _estimates(twin))
    tr.step(np.zeros((0, 2)), 2.0, sensor=1)  # an empty scan at a zero interval
    assert tr.sensor == 1


def test_every_kind_fuses_or_says_why_not():
    """The engine and single families fuse, but for hfisst (its preset says why); the poisson_mb family does not."""
    problem = _problem()
    assert set(SPECS) | {"hfisst"} == set(kinds("engine")) | set(kinds("single"))
    with pytest.raises(ValueError, match=r"^hfisst: kind 'hfisst' cannot fuse several sensors: H-FISST is document "
                                         r"000's exhaustive reference"):
        build({"kind": "hfisst", "factored": {}}, problem)
    assert preset("hfisst").no_fusion and not preset("rfisst").no_fusion
    for kind in kinds("poisson_mb"):
        with pytest.raises(ValueError, match=rf"^cfg\.{kind}: kind '{kind}' \(family poisson_mb\) has no multi-sensor "
                                             "form"):
            build({"kind": kind}, problem, where=f"cfg.{kind}")
    with pytest.raises(ValueError, match=r"^glmb\.factored: kind 'glmb' fuses sensors on the factored engine"):
        build({"kind": "glmb"}, problem)
    # factored: {} is the factored engine with its defaults
    assert isinstance(build({"kind": "glmb", "n_sweeps": 5, "factored": {}}, problem, seed=1), MultiSensorFactored)


def test_a_single_sensor_problem_builds_what_it_built():
    """A TrackingProblem is not fused: the registry's single-sensor tracker, as before."""
    p = _problem().problem(0)
    assert isinstance(p, TrackingProblem)
    assert type(build(SPECS["gnn"], p)) is SingleHypothesisTracker
    assert type(build(ENGINE_SPECS["glmb"], p, seed=1)).__name__ == "HypothesisFilter"
    assert type(build(SPECS["glmb"], p, seed=1)).__name__ == "FactoredFilter"


# ------------------------------------------------------------------------------------------ the problem
def _entry(s=0, **changes):
    kw = dict(sensor=SENSORS[s], in_view=_view(BOXES[s]), births=_births(s))
    kw.update(changes)
    return SensorEntry(**kw)


@pytest.mark.parametrize("sensors, err, match", [
    ([], ValueError, r"^sensors must hold one SensorEntry per sensor, got none$"),
    (None, TypeError, r"^sensors must be a sequence of SensorEntry"),
    ("ab", TypeError, r"^sensors must be a sequence of SensorEntry"),
    ([SENSOR_A], TypeError, r"^sensors\[0\] must be a SensorEntry, got Sensor$"),
    ([_entry(0), _entry(1, in_view=None)], ValueError, r"^sensors\[1\]\.in_view is required"),
    ([_entry(0), _entry(1, in_view=3)], TypeError, r"^sensors\[1\]\.in_view must be callable"),
    ([_entry(0), _entry(1, sensor=SimpleNamespace(measurement=BASE_B.measurement))], TypeError,
     r"^sensors\[1\]\.sensor must have a detection model"),
    ([_entry(0), _entry(1, sensor=SimpleNamespace(measurement=BASE_B.measurement, clutter=BASE_B.clutter,
                                                  detection=SimpleNamespace(p_D=0.7, p_D_of=0.7)))],
     TypeError, r"^sensors\[1\]\.sensor\.detection\.p_D_of must be callable"),
    ([_entry(0), _entry(1, sensor=position_sensor(0.5, 0.7, BOX_B, 0.5, ndim_state=6))],
     ValueError, r"^sensors\[1\]\.sensor\.measurement is of 6-D states, sensors\[0\]'s of 4-D"),
    ([_entry(0), _entry(1, births=None)], ValueError,
     r"^sensors\[1\]\.births is a NoneType, sensors\[0\]\.births a MeasurementBirths"),
    ([_entry(0), _entry(1, births=SingleEventBirthDeath(0.1, 0.1, 1))], ValueError,
     r"^sensors\[1\]\.births is a SingleEventBirthDeath"),
    ([_entry(0), _entry(1, births=3)], TypeError, r"^sensors\[1\]\.births must be None, a SingleEventBirthDeath"),
    ([_entry(0), _entry(1, births=MeasurementBirths(AdaptiveBirth(velocity_std=1.0, r_birth=0.2), r_birth=0.2))],
     ValueError, r"^sensors\[1\]\.births\.r_birth = 0\.2 must equal sensors\[0\]\.births\.r_birth = 0\.3"),
])
def test_bad_problem_names_the_parameter(sensors, err, match):
    with pytest.raises(err, match=match):
        MultiSensorProblem(MOTION, sensors, X0, P0, LABELS)


def test_problem_shares_the_known_objects_and_checks_them():
    problem = _problem()
    assert problem.n_sensors == 2 and problem.ndim == 4 and problem.labels.tolist() == LABELS
    for s in (0, 1):
        p = problem.problem(s)
        assert p.sensor is SENSORS[s] and p.motion is MOTION and p.births.seeded_intensity == INTENSITY[s]
        np.testing.assert_array_equal(p.means, X0)
    with pytest.raises(ValueError, match="sensor must be an integer in"):
        problem.problem(2)
    with pytest.raises(ValueError, match="covs must hold one covariance per mean"):
        MultiSensorProblem(MOTION, [_entry(0), _entry(1)], X0, P0[:2])
    # zero known objects, one sensor: a valid problem, and a fused tracker with one sensor
    one = MultiSensorProblem(MOTION, [_entry(1)])
    tr = build(SPECS["jpda"], one)
    tr.step(np.zeros((0, 2)), 1.0, sensor=0)
    assert len(tr.estimates()) == 0 and tr.n_sensors == 1


def test_from_problems_needs_one_motion_and_the_same_known_objects():
    singles = _problem().problems
    again = MultiSensorProblem.from_problems(singles)
    assert [p.sensor for p in again.problems] == list(SENSORS) and again.time == 0.0
    other = TrackingProblem(ConstantVelocity(q=0.02), SENSOR_B, X0, P0, LABELS, births=_births(1),
                            in_view=_view(BOX_B))
    with pytest.raises(ValueError, match=r"^problems\[1\]\.motion must be problems\[0\]\.motion \(the same object\)"):
        MultiSensorProblem.from_problems([singles[0], other])
    moved = TrackingProblem(MOTION, SENSOR_B, X0 + 1.0, P0, LABELS, births=_births(1), in_view=_view(BOX_B))
    with pytest.raises(ValueError, match=r"^problems\[1\]\.means must equal problems\[0\]\.means"):
        MultiSensorProblem.from_problems([singles[0], moved])
    blind = TrackingProblem(MOTION, SENSOR_B, X0, P0, LABELS, births=_births(1))
    with pytest.raises(ValueError, match=r"^sensors\[1\]\.in_view is required"):
        MultiSensorProblem.from_problems([singles[0], blind])
    with pytest.raises(ValueError, match="problems must hold one TrackingProblem per sensor, got none"):
        MultiSensorProblem.from_problems([])


def test_spec_from_config_reaches_the_fused_tracker():
    """A TrackerSpec's options reach every sensor's engine (n_sweeps) and the factored options the fused filter."""
    spec = TrackerSpec.from_config(SPECS["glmb"], "cfg.glmb")
    tr = build(spec, _problem(), seed=SEED)
    assert tr.options.lazy and tr.options.min_weight == 0.001 and tr.options.split == "marginal"
    assert tr.n_sensors == 2


@pytest.mark.parametrize("kind", ["glmb", "homht_kbest", "gnn", "jpda"])
def test_one_sensor_fused_is_the_single_sensor_tracker(kind):
    """One sensor: the fused tracker over sensor A's scans is the single-sensor registry tracker, hypothesis for
    hypothesis (engine) or track for track — births from a fixed labeled-Bernoulli term at N1's place (no
    measurement-driven births, whose first interval differs by design: hypotrack.hypotheses.factored.multisensor)."""
    term = GaussianBirthTerm(np.array([0.0, 6.0, 0.0, 0.0]), np.diag([1.0, 1.0, 0.5, 0.5]), SENSOR_A.measurement.H,
                             R_A, gate_probability=GATE)
    births = LabeledMultiBernoulliPopulation([term], r_birth=0.2, p_survive=0.99)
    single = TrackingProblem(MOTION, SENSOR_A, X0, P0, LABELS, births=births, in_view=_view(BOX_A))
    fused = MultiSensorProblem.from_problems([single])
    a, b = build(SPECS[kind], single, seed=SEED), build(SPECS[kind], fused, seed=SEED)
    assert type(b) is (MultiSensorFactored if kind in ENGINE_SPECS else MultiSensorSHT)
    for t, s, Z in SCANS:
        if s == 0:
            a.step(Z, t)
            b.step(Z, t, sensor=0)
            if kind in ENGINE_SPECS:
                assert a.same_posterior(b)
            else:
                for x, y in zip((a.ids, a.x, a.P, a.misses), (b.ids, b.x, b.P, b.misses), strict=True):
                    np.testing.assert_array_equal(x, y)
    assert len(a.estimates()) >= 2


def _glmb_anyway(problem, *, seed, **options):
    return presets.glmb(MOTION, problem.sensor, population=LabeledMultiBernoulliPopulation([], r_birth=0.3), n_sweeps=5)


def test_a_registered_kind_fuses_through_its_family_or_states_why_not():
    """A kind registered at run time fuses as its family does (here gnn's builder under another name: the same
    fused tracker); ``no_fusion`` refuses it with the reason given; a builder whose tracker is not of its family's
    kind is refused naming the sensor."""
    gnn = preset("gnn").builder
    register("test_fused_nn", gnn, family="single")
    register("test_solo", gnn, family="single", no_fusion="its scores assume one sensor")
    register("test_wrong", _glmb_anyway, family="single")
    try:
        spec = {**SPECS["gnn"], "kind": "test_fused_nn"}
        a, b = build(spec, _problem()), build(SPECS["gnn"], _problem())
        assert isinstance(a, MultiSensorSHT) and a.n_sensors == 2
        for t, s, Z in SCANS:
            a.step(Z, t, sensor=s)
            b.step(Z, t, sensor=s)
            for x, y in zip(_single_table(a), _single_table(b), strict=True):
                np.testing.assert_array_equal(x, y)
        with pytest.raises(ValueError, match=r"^test_solo: kind 'test_solo' cannot fuse several sensors: its scores "
                                             r"assume one sensor$"):
            build({"kind": "test_solo"}, _problem())
        with pytest.raises(ValueError, match=r"^test_wrong: kind 'test_wrong' built a HypothesisFilter for "
                                             r"sensors\[0\], not a SingleHypothesisTracker"):
            build({"kind": "test_wrong"}, _problem())
        with pytest.raises(TypeError, match="no_fusion must be a string"):
            register("test_bad", gnn, family="single", no_fusion=True)
    finally:
        for k in ("test_fused_nn", "test_solo", "test_wrong"):
            unregister(k)

"""hypotrack trackers inside a Stone Soup pipeline (hypotrack.interop.stonesoup).

Stone Soup's models simulate the ground truth and the detections (in Stone Soup's types, from one seeded
stream so that every process sees the same scenario); each hypotrack tracker runs through the
adapter (Stone Soup detections in, Stone Soup tracks out) and, separately, through hypotrack's own
API on numpy scans with hypotrack's own models built by hand. Stone Soup's OSPA and GOSPA metric
generators score both: the numbers must be identical, scan by scan (the adapter only translates).
"""

import datetime

import numpy as np
import pytest

stonesoup = pytest.importorskip("stonesoup")

from stonesoup.measures import Euclidean  # noqa: E402
from stonesoup.metricgenerator.manager import MultiManager  # noqa: E402
from stonesoup.metricgenerator.ospametric import GOSPAMetric, OSPAMetric  # noqa: E402
from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity as SSConstantVelocity,
    RandomWalk,
)
from stonesoup.types.detection import Clutter, TrueDetection  # noqa: E402
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.types.track import Track  # noqa: E402

from hypotrack.hypotheses import hfisst, homht, rfisst  # noqa: E402
from hypotrack.interop.stonesoup import HypotrackTracker, translate_models  # noqa: E402
from hypotrack.models import ConstantVelocity  # noqa: E402
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor  # noqa: E402
from hypotrack.trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker  # noqa: E402

Q, P_D, CLUTTER, REGION = 0.05, 0.9, 3.0, [[-60.0, 60.0], [-60.0, 60.0]]
T0 = datetime.datetime(2025, 1, 1)
STARTS = [[-20.0, 1.0, -5.0, 0.2], [20.0, -1.0, 5.0, -0.2], [0.0, 0.0, 25.0, -1.0]]  # Stone Soup order x, vx, y, vy
PRIOR_VAR = [4.0, 1.0, 4.0, 1.0]
HT = [0, 2, 1, 3]  # hypotrack order x, y, vx, vy, taken from Stone Soup's


def _models():
    tm = CombinedLinearGaussianTransitionModel([SSConstantVelocity(Q, seed=1), SSConstantVelocity(Q, seed=2)])
    return tm, LinearGaussian(4, (0, 2), np.diag([1.0, 2.0]), seed=3)


def _simulate(birth_scan=None, n_steps=25, seed=4):
    """Ground truth paths and scans of detections, in Stone Soup's types, reproducible in every process.

    Stone Soup's simulators draw each path's noise while iterating over a ``set`` of paths, whose
    order follows object ids (memory addresses): the scenario would change from run to run. Here the
    paths are a list, propagated and observed with Stone Soup's model matrices and covariances in list
    order, the noise from one seeded stream (a combined Stone Soup model draws from NumPy's global
    state, not its parts' seeds); with ``birth_scan`` one target is born at that scan, drawn from the birth density
    ``MultiTargetGroundTruthSimulator`` uses here, and clutter is Poisson over ``REGION``.
    """
    tm, mm = _models()
    rng = np.random.default_rng(seed)
    dt = datetime.timedelta(seconds=1)
    F, Lq = tm.matrix(time_interval=dt), np.linalg.cholesky(tm.covar(time_interval=dt))
    H, Lr = mm.matrix(), np.linalg.cholesky(mm.covar())
    birth = GaussianState(np.array([[0.0], [0.0], [0.0], [0.0]]), np.diag([400.0, 1.0, 400.0, 1.0]))
    paths = [GroundTruthPath([GroundTruthState(np.array(s)[:, None], timestamp=T0)]) for s in STARTS]
    scans = []
    for k in range(n_steps):
        t = T0 + k * dt
        if k:
            for path in paths:
                x = F @ path[-1].state_vector + Lq @ rng.standard_normal((4, 1))
                path.append(GroundTruthState(x, timestamp=t))
            if k == birth_scan:
                x0 = birth.state_vector + np.linalg.cholesky(birth.covar) @ rng.standard_normal((4, 1))
                paths.append(GroundTruthPath([GroundTruthState(x0, timestamp=t)]))
        dets = {TrueDetection(H @ path[-1].state_vector + Lr @ rng.standard_normal((2, 1)), timestamp=t,
                              measurement_model=mm, groundtruth_path=path)
                for path in paths if rng.random() < P_D}
        lo, hi = np.array(REGION).T
        dets |= {Clutter(rng.uniform(lo, hi)[:, None], timestamp=t, measurement_model=mm)
                 for _ in range(rng.poisson(CLUTTER))}
        scans.append((t, dets))
    return scans, set(paths)


def _priors():
    t = T0 - datetime.timedelta(seconds=1)
    return [GaussianState(np.array(s)[:, None], np.diag(PRIOR_VAR), timestamp=t) for s in STARTS]


OPTIONS = {
    "gnn": {"m_of_n": [2, 3], "initial_velocity_std": 2.0, "max_misses": 3},
    "jpda": {},
    "rfisst": {"n_steps": 2000, "max_hypotheses": 20, "gate_probability": 0.999, "seed": 7},
    "homht": {"max_hypotheses": 20, "gate_probability": 0.999},
    "hfisst": {"max_hypotheses": 20, "gate_probability": 0.999},
}


def _adapter_tracks(algorithm, scans):
    tm, mm = _models()
    tracker = HypotrackTracker(
        transition_model=tm, measurement_model=mm, algorithm=algorithm, detection_probability=P_D,
        clutter_rate=CLUTTER, clutter_region=REGION, detector=scans, initial_states=_priors(),
        options=OPTIONS[algorithm])
    current = [tracks for _, tracks in tracker]
    return tracker.all_tracks, current


def _native_tracks(algorithm, scans):
    """The same run with hypotrack's own API: hypotrack models by hand, numpy scans, no adapter."""
    motion = ConstantVelocity(q=Q)
    measurement = LinearPositionSensor(np.diag([1.0, 2.0]), ndim_state=4)  # measures x, y = state 0, 1
    means = np.array(STARTS)[:, HT]
    covs = np.tile(np.diag(np.array(PRIOR_VAR)[HT]), (3, 1, 1))
    opts = dict(OPTIONS[algorithm])
    if algorithm in ("gnn", "jpda"):
        model = ScanModel(measurement.H, measurement.R, P_D, 0.99, CLUTTER / 120.0**2)
        m_of_n, v0 = opts.pop("m_of_n", None), opts.pop("initial_velocity_std", None)
        init = m_of_n and MOfNInitiator(motion, model, m=m_of_n[0], n=m_of_n[1], initial_velocity_std=v0)
        tracker = SingleHypothesisTracker(motion, model, association=algorithm, initiator=init, **opts)
        tracker.initialise(means, covs, time=0.0)
    else:
        sensor = Sensor(measurement, DetectionModel(p_D=P_D),
                        PoissonClutter(rate=CLUTTER, region=Box([-60.0, -60.0], [60.0, 60.0])))
        tracker = {"rfisst": rfisst, "homht": homht, "hfisst": hfisst}[algorithm](
            motion, sensor, means=means, covs=covs, **opts)
    start = T0 - datetime.timedelta(seconds=1)  # the priors' time
    tracks = {}
    for time, dets in scans:
        Z = np.array([d.state_vector.ravel() for d in dets]).reshape(-1, 2)
        Z = Z[np.lexsort((Z[:, 1], Z[:, 0]))]
        if algorithm in ("gnn", "jpda"):
            est = tracker.step(Z, (time - start).total_seconds())
            ids, x, P = est.ids, est.x, est.P
        else:
            best = tracker.step(Z, (time - start).total_seconds()).map_estimate
            ids, x, P = best.labels, best.means, best.covs
        inv = np.argsort(HT)
        for i, k in enumerate(ids):
            track = tracks.setdefault(int(k), Track(id=str(k)))
            track.append(GaussianState(x[i][inv][:, None], P[i][np.ix_(inv, inv)], timestamp=time))
    return set(tracks.values())


def _metrics(tracks, truths):
    position = Euclidean(mapping=(0, 2))
    manager = MultiManager([OSPAMetric(c=10.0, p=1, measure=position),
                            GOSPAMetric(c=10.0, p=1, measure=position)])
    manager.add_data({"tracks": tracks, "groundtruth_paths": truths})
    metrics = manager.generate_metrics()
    out = {}
    for generator in metrics.values():
        for name, metric in generator.items():
            if isinstance(metric.value, list):
                out[name] = np.array([m.value if not isinstance(m.value, dict) else m.value["distance"]
                                      for m in metric.value])
    return out


@pytest.mark.parametrize("algorithm", ["gnn", "jpda", "rfisst", "homht", "hfisst"])
def test_adapter_ospa_equals_own_api_run(algorithm):
    scans, truths = _simulate(birth_scan=8 if algorithm == "gnn" else None)
    tracks, current = _adapter_tracks(algorithm, scans)
    native = _native_tracks(algorithm, scans)
    ours, theirs = _metrics(tracks, truths), _metrics(native, truths)
    assert set(ours) == set(theirs) and any("OSPA" in k for k in ours) and any("GOSPA" in k for k in ours)
    for name in ours:
        # Stone Soup sums over Python sets of tracks, whose order differs between runs: 1 ulp.
        np.testing.assert_allclose(ours[name], theirs[name], rtol=1e-13, atol=1e-13, err_msg=name)
    # Underneath, the tracks are bit-for-bit those of the own-API run (same ids, states, covariances).
    mine, own = {t.id: t for t in tracks}, {t.id: t for t in native}
    assert mine.keys() == own.keys()
    for i in mine:
        assert [s.timestamp for s in mine[i]] == [s.timestamp for s in own[i]]
        np.testing.assert_array_equal(np.hstack([s.state_vector for s in mine[i]]),
                                      np.hstack([s.state_vector for s in own[i]]))
        np.testing.assert_array_equal(np.stack([s.covar for s in mine[i]]), np.stack([s.covar for s in own[i]]))
    ospa = next(v for k, v in ours.items() if k.startswith("OSPA"))
    assert len(ospa) == len(scans)
    # Stable ids: the known objects keep ids 0, 1, 2 from the first scan to the last.
    assert {"0", "1", "2"} <= {t.id for t in current[0]} and {"0", "1", "2"} <= {t.id for t in current[-1]}
    by_id = {t.id: t for t in tracks}
    assert all(len(by_id[i]) == len(scans) for i in "012")
    # ... and each is tracked: from the sixth scan on, track i is within 5 m (about 3 sigma of the
    # returns) of object i's true position (false tracks from clutter do not enter this check).
    known = {STARTS.index([float(v) for v in p[0].state_vector.ravel()]): p for p in truths if p[0].timestamp == T0}
    for i, path in known.items():
        track = by_id[str(i)]
        for k in range(5, len(scans)):
            assert track[k].timestamp == path[k].timestamp
            miss = np.hypot(*(track[k].state_vector[[0, 2]] - path[k].state_vector[[0, 2]]).ravel())
            assert miss < 5.0, (algorithm, i, k, miss)


def test_gnn_adapter_confirms_a_stonesoup_birth():
    scans, truths = _simulate(birth_scan=8)
    assert len(truths) > 3  # a target was born after the start
    tracks, _ = _adapter_tracks("gnn", scans)
    assert len({t.id for t in tracks} - {"0", "1", "2"}) >= 1


def test_translated_models_match_stonesoup_matrices():
    tm, mm = _models()
    motion, measurement, perm = translate_models(tm, mm)
    assert list(perm) == HT
    for dt in (0.5, 1.0, 3.0):
        td = datetime.timedelta(seconds=dt)
        np.testing.assert_allclose(motion.F(dt), tm.matrix(time_interval=td)[np.ix_(perm, perm)], rtol=0, atol=1e-15)
        np.testing.assert_allclose(motion.Q(dt), tm.covar(time_interval=td)[np.ix_(perm, perm)], rtol=1e-14)
    np.testing.assert_array_equal(measurement.H, mm.matrix()[:, perm])
    np.testing.assert_array_equal(measurement.R, mm.covar())


def test_unsupported_models_and_bad_options_are_named():
    tm, mm = _models()
    with pytest.raises(ValueError, match="transition_model"):
        translate_models(CombinedLinearGaussianTransitionModel([RandomWalk(0.1), RandomWalk(0.1)]), mm)
    with pytest.raises(ValueError, match="noise_diff_coeff"):
        translate_models(CombinedLinearGaussianTransitionModel([SSConstantVelocity(0.1), SSConstantVelocity(0.2)]), mm)
    with pytest.raises(ValueError, match="ndim_state"):
        translate_models(tm, LinearGaussian(6, (0, 2), np.eye(2)))
    common = dict(transition_model=tm, measurement_model=mm, detection_probability=P_D, clutter_rate=CLUTTER)
    with pytest.raises(ValueError, match="algorithm"):
        HypotrackTracker(algorithm="mht", clutter_region=REGION, **common)
    with pytest.raises(ValueError, match="clutter_region"):
        HypotrackTracker(algorithm="gnn", clutter_region=[-60, 60], **common)


def test_empty_scans_and_no_known_objects():
    tm, mm = _models()
    tracker = HypotrackTracker(transition_model=tm, measurement_model=mm, algorithm="jpda",
                               detection_probability=P_D, clutter_rate=CLUTTER, clutter_region=REGION)
    for k in range(3):
        time, tracks = tracker.update_tracker(T0 + datetime.timedelta(seconds=k), set())
        assert time == T0 + datetime.timedelta(seconds=k) and tracks == set()


def test_readme_stonesoup_example_runs():
    import contextlib
    import io
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    code = next(c for c in re.findall(r"```python\n(.*?)```", readme, re.S) if "interop.stonesoup" in c)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "README.md", "exec"), {})
    first, second = out.getvalue().splitlines()
    ids, n_scans, mean_ospa = re.fullmatch(r"(\[.*\]) (\d+) ([\d.]+)", first).groups()
    assert ids == "['0', '1']" and n_scans == "20"
    assert float(mean_ospa) < 2.0  # both objects tracked to about the measurement noise (R = I)
    # the PMBM, knowing nothing, finds both objects from the data: OSPA from scan 5 on about the noise
    n_tracks, late_ospa = re.fullmatch(r"(\d+) ([\d.]+)", second).groups()
    assert n_tracks == "2" and float(late_ospa) < 2.0

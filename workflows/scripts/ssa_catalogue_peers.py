"""ssa_catalogue: hypotrack's GNN and JPDA against Stone Soup's on the catalogue scans, side by side.

Stone Soup is a benchmark/test-only dependency that the library never imports, so its side (an
adapter with the ``step``/``record`` surface of
:class:`hypotrack.experiments.ssa_catalogue.run.CatalogueSHTStepper`) lives here, as in
``perf_sht_benchmark.py``; without Stone Soup the rule times hypotrack alone. Both sides run the
known objects with no initiation or deletion, the same two-body EKF dynamics (hypotrack's
``TwoBodyOrbit3D`` wrapped as a Stone Soup transition model, integrated once per track and scan),
the same linear TEME position measurement, gate, p_D and clutter density.
"""
import datetime
import math

import numpy as np
import pandas as pd

from hypotrack.experiments.perf_sht.run import run_side_by_side
from hypotrack.experiments.ssa_catalogue.run import CatalogueSHTStepper, peer_rows, peer_scenario
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
T0 = datetime.datetime(2026, 1, 1)

try:
    import stonesoup  # noqa: F401

    HAVE_STONESOUP = True
except ImportError:
    HAVE_STONESOUP = False
    print("ssa_catalogue: Stone Soup is not installed; timing hypotrack only", flush=True)


def two_body_model_class():
    from stonesoup.base import Property
    from stonesoup.models.base import GaussianModel, TimeVariantModel
    from stonesoup.models.transition.base import TransitionModel
    from stonesoup.types.array import CovarianceMatrix, StateVector

    class HypotrackTwoBody(TransitionModel, GaussianModel, TimeVariantModel):
        """hypotrack's two-body EKF dynamics (TwoBodyOrbit3D.transition, Q) as a Stone Soup model."""
        motion: object = Property(doc="hypotrack TwoBodyOrbit3D")

        @property
        def ndim_state(self):
            return 6

        def _transition(self, state, time_interval):
            x = np.asarray(state.state_vector, float).reshape(1, 6)
            dt = time_interval.total_seconds()
            key = (x.tobytes(), dt)
            if getattr(self, "_key", None) != key:  # function and jacobian of one state: integrate once
                xp, F = self.motion.transition(x, dt)
                self._key, self._val = key, (xp[0], F[0])
            return self._val

        def function(self, state, noise=False, time_interval=None, **kwargs):
            return StateVector(self._transition(state, time_interval)[0])

        def jacobian(self, state, time_interval=None, **kwargs):
            return self._transition(state, time_interval)[1]

        def covar(self, time_interval=None, **kwargs):
            return CovarianceMatrix(self.motion.Q(time_interval.total_seconds()))

    return HypotrackTwoBody


class StoneSoupStepper:
    """Stone Soup's tracker of one kind on a PeerScenario: predict + associate + update per scan."""

    def __init__(self, scenario, kind):
        from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
        from stonesoup.dataassociator.probability import JPDAwithEHM2
        from stonesoup.dataassociator.tree import DetectionKDTreeGNN2D
        from stonesoup.hypothesiser.distance import DistanceHypothesiser
        from stonesoup.hypothesiser.probability import PDAHypothesiser
        from stonesoup.measures import Mahalanobis
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.predictor.kalman import ExtendedKalmanPredictor
        from stonesoup.types.detection import Detection
        from stonesoup.types.state import GaussianState
        from stonesoup.types.track import Track
        from stonesoup.updater.kalman import KalmanUpdater
        from stonesoup.updater.probability import PDAUpdater

        model = scenario.model
        predictor = ExtendedKalmanPredictor(two_body_model_class()(motion=scenario.motion))
        meas = LinearGaussian(ndim_state=6, mapping=(0, 1, 2), noise_covar=model.R)
        self.gnn = "GNN" in kind
        if self.gnn:
            self.updater = KalmanUpdater(meas, use_joseph_cov=True)
            hyp = DistanceHypothesiser(predictor, self.updater, Mahalanobis(), missed_distance=math.sqrt(model.gate))
            if kind == "GNNWith2DAssignment":
                self.associator = GNNWith2DAssignment(hyp)
            else:
                # k-d tree of the detections. Stone Soup searches the radius m·max diag(S) (a variance
                # times m). The Mahalanobis gate d² ≤ g lies within Euclidean radius √(g λmax(S)) ≤ √(3 g d),
                # d = max diag(S) ≥ λmin(R); so m = √(3 g / λmin(R)) makes the ball hold the whole gate
                # and the k-d tree changes which pairs are scored, not the association.
                m = math.sqrt(3.0 * model.gate / float(np.linalg.eigvalsh(model.R)[0]))
                self.associator = DetectionKDTreeGNN2D(hyp, predictor, self.updater,
                                                       max_distance_covariance_multiplier=m)
        else:
            self.updater = PDAUpdater(meas, use_joseph_cov=True)
            hyp = PDAHypothesiser(predictor, self.updater, clutter_spatial_density=model.clutter_density,
                                  prob_detect=model.p_D, prob_gate=model.p_gate)
            self.associator = JPDAwithEHM2(hyp)
        t0 = T0 + datetime.timedelta(seconds=float(scenario.times[0]))
        self.tracks = [Track([GaussianState(x.reshape(-1, 1), P, timestamp=t0)])
                       for x, P in zip(scenario.initial_states, scenario.initial_covs)]
        self.scans = []
        for t, Z in scenario.scan_list():
            ts = T0 + datetime.timedelta(seconds=float(t))
            self.scans.append((ts, [Detection(z.reshape(-1, 1), timestamp=ts, measurement_model=meas) for z in Z]))

    def step(self, k):
        ts, dets = self.scans[k]
        self.hyps = self.associator.associate(set(self.tracks), set(dets), ts)
        for tr in self.tracks:
            h = self.hyps[tr]
            tr.append((self.updater.update(h) if h else h.prediction) if self.gnn else self.updater.update(h))
        self.k = k

    def record(self, run):
        dets = self.scans[self.k][1]
        index = {id(d): i for i, d in enumerate(dets)}
        if self.gnn:
            out = np.full(len(dets), -1)
            for i, tr in enumerate(self.tracks):
                h = self.hyps[tr]
                if h:
                    out[index[id(h.measurement)]] = i
        else:
            out = np.zeros((len(self.tracks), len(dets) + 1))
            for i, tr in enumerate(self.tracks):
                for h in self.hyps[tr]:
                    out[i, 0 if not h else 1 + index[id(h.measurement)]] = float(h.probability)
        run.outputs.append(out)
        run.states.append((np.array([np.ravel(t.state_vector) for t in self.tracks]).reshape(-1, 6),
                           np.array([t.covar for t in self.tracks]).reshape(-1, 6, 6)))


PEERS = {"gnn": ["GNNWith2DAssignment", "DetectionKDTreeGNN2D"], "jpda": ["JPDAwithEHM2"]}
pc = cfg["peers"]
tables = []
for n in pc["sizes"]:
    ps = peer_scenario(cfg, n, seed)
    for algorithm, peers in PEERS.items():
        steppers = {"hypotrack": CatalogueSHTStepper(ps, algorithm)}
        for kind in peers if HAVE_STONESOUP else []:
            steppers[kind] = StoneSoupStepper(ps, kind)
        runs = run_side_by_side(steppers, len(ps.times), max_scans=pc["max_scans"])
        t = peer_rows(runs, algorithm, n, len(ps.initial_states))
        for _, r in t.iterrows():
            print(f"N = {n} {algorithm} {r.implementation}: {r.median_ms:.3g} ms/scan, x{r.peer_over_hypotrack:.3g}, "
                  f"same association on {r.scans_same_association} of {r.scans_compared} scans")
        tables.append(t)
write_table(pd.concat(tables, ignore_index=True), snakemake.output.timing)  # noqa: F821

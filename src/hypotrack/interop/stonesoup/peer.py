"""Stone Soup's own GNN and JPDA trackers run scan by scan on hypotrack's scans: the peer side of
the side-by-side timings (:func:`hypotrack.experiments.stepping.run_side_by_side`).

:class:`StoneSoupPeer` has the ``step(k)`` / ``record(run)`` surface of hypotrack's steppers
(:class:`hypotrack.experiments.stepping.SHTStepper`, as
:class:`hypotrack.experiments.perf_sht.run.HypotrackStepper` and
:class:`hypotrack.experiments.ssa_catalogue.run.CatalogueSHTStepper` build it): per scan Stone Soup's
associator predicts, gates and associates, and its updater updates every track (a missed GNN
track keeps its prediction). No initiation and no deletion, as on hypotrack's side, so both solve
the same problem. Detections are built before timing: data ingest is not part of a scan.

The caller gives Stone Soup's predictor (e.g. a ``KalmanPredictor`` on a combined constant-velocity
model, or an ``ExtendedKalmanPredictor`` on hypotrack's orbit dynamics,
:func:`~hypotrack.interop.stonesoup.transition.orbit_transition_model`) and the permutation
``perm`` from hypotrack's state order to Stone Soup's (``[x, y, vx, vy]`` → ``[x, vx, y, vy]`` is
``[0, 2, 1, 3]``); states are mapped in at construction and back in :meth:`StoneSoupPeer.record`.
Stone Soup is imported only when a peer is built.
"""

from __future__ import annotations

import datetime
import math

import numpy as np

from ._common import require_stonesoup

__all__ = ["PEER_KINDS", "StoneSoupPeer"]

#: Stone Soup associators a peer can run, by name.
PEER_KINDS = ("GNNWith2DAssignment", "DetectionKDTreeGNN2D", "JPDAwithEHM2", "JPDA")

_T0 = datetime.datetime(2026, 1, 1)


class StoneSoupPeer:
    """Stone Soup's tracker ``kind`` (one of :data:`PEER_KINDS`) on fixed scans.

    Parameters
    ----------
    kind : str
    predictor : a Stone Soup predictor of the state in Stone Soup's order.
    model : :class:`hypotrack.trackers.ScanModel` — ``R`` (measurement noise of the measured
        components, which are ``mapping`` in Stone Soup's order), ``gate``, ``p_D``, ``p_gate``,
        ``clutter_density``.
    mapping : the measured components in Stone Soup's state order.
    initial_states, initial_covs : ``(n, d)``, ``(n, d, d)`` in hypotrack's state order.
    scans : list of ``(time_s, Z (m, p))``; ``time0``: the time of the initial states (s).
    perm : hypotrack's state order → Stone Soup's (``x_ss = x[perm]``); ``None`` is the identity.
    """

    def __init__(self, kind, predictor, model, mapping, initial_states, initial_covs, scans, time0=0.0, perm=None):
        require_stonesoup()
        from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
        from stonesoup.dataassociator.probability import JPDA, JPDAwithEHM2
        from stonesoup.dataassociator.tree import DetectionKDTreeGNN2D
        from stonesoup.hypothesiser.distance import DistanceHypothesiser
        from stonesoup.hypothesiser.probability import PDAHypothesiser
        from stonesoup.measures import Mahalanobis
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.types.detection import Detection
        from stonesoup.types.state import GaussianState
        from stonesoup.types.track import Track
        from stonesoup.updater.kalman import KalmanUpdater
        from stonesoup.updater.probability import PDAUpdater

        if kind not in PEER_KINDS:
            raise ValueError(f"kind must be one of {PEER_KINDS}, got {kind!r}")
        initial_states = np.asarray(initial_states, dtype=float)
        d = initial_states.shape[1] if initial_states.ndim == 2 else len(np.asarray(perm))
        self.perm = np.arange(d) if perm is None else np.asarray(perm)
        self.inv = np.argsort(self.perm)
        self.ndim = d
        meas = LinearGaussian(ndim_state=d, mapping=tuple(mapping), noise_covar=model.R)
        self.gnn = kind.startswith("GNN") or kind.startswith("DetectionKDTree")
        if self.gnn:
            self.updater = KalmanUpdater(meas, use_joseph_cov=True)
            hyp = DistanceHypothesiser(predictor, self.updater, Mahalanobis(), missed_distance=math.sqrt(model.gate))
            if kind == "GNNWith2DAssignment":
                self.associator = GNNWith2DAssignment(hyp)
            else:
                # k-d tree of the detections. Stone Soup searches the radius m·max diag(S) (a variance
                # times m). The Mahalanobis gate d² ≤ g lies within Euclidean radius √(g λmax(S)) ≤ √(p g s),
                # s = max diag(S) ≥ λmin(R); so m = √(p g / λmin(R)) makes the ball hold the whole gate
                # and the k-d tree changes which pairs are scored, not the association.
                p = np.shape(model.R)[0]
                m = math.sqrt(p * model.gate / float(np.linalg.eigvalsh(model.R)[0]))
                self.associator = DetectionKDTreeGNN2D(hyp, predictor, self.updater,
                                                       max_distance_covariance_multiplier=m)
        else:
            self.updater = PDAUpdater(meas, use_joseph_cov=True)
            hyp = PDAHypothesiser(predictor, self.updater, clutter_spatial_density=model.clutter_density,
                                  prob_detect=model.p_D, prob_gate=model.p_gate)
            self.associator = {"JPDAwithEHM2": JPDAwithEHM2, "JPDA": JPDA}[kind](hyp)
        t0 = _T0 + datetime.timedelta(seconds=float(time0))
        P = self.perm
        self.tracks = [Track([GaussianState(x[P].reshape(-1, 1), C[np.ix_(P, P)], timestamp=t0)])
                       for x, C in zip(initial_states, initial_covs)]
        self.scans = []
        for t, Z in scans:
            ts = _T0 + datetime.timedelta(seconds=float(t))
            self.scans.append((ts, [Detection(z.reshape(-1, 1), timestamp=ts, measurement_model=meas) for z in Z]))

    def step(self, k):
        """Scan ``k``: associate every track with the scan's detections and update it."""
        ts, dets = self.scans[k]
        self.hyps = self.associator.associate(set(self.tracks), set(dets), ts)
        for tr in self.tracks:
            h = self.hyps[tr]
            tr.append((self.updater.update(h) if h else h.prediction) if self.gnn else self.updater.update(h))
        self.k = k

    def record(self, run):
        """Append the scan's output (GNN: the track of each detection, −1 none; JPDA: per track the
        probabilities of missed and of each detection) and the states in hypotrack's order."""
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
        d, inv = self.ndim, self.inv
        run.outputs.append(out)
        run.states.append((np.array([np.ravel(t.state_vector)[inv] for t in self.tracks]).reshape(-1, d),
                           np.array([t.covar[np.ix_(inv, inv)] for t in self.tracks]).reshape(-1, d, d)))

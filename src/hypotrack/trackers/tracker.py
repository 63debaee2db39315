"""A complete single-hypothesis tracker: association (GNN, JPDA or PDAF) + initiation + deletion.

Lecture notes 004, the GNN and JPDAF algorithms, per scan ``k > 0``:

1. predict the confirmed targets and gate the returns (validation matrix);
2. associate — GNN: the best hypothesis of the assignment matrix, then Kalman updates;
   JPDA: per-cluster marginal association probabilities, then PDA updates; PDAF: each target's
   probabilities on its own (conflicts between targets ignored);
3. send the unprocessed returns to the initiation logic (GNN: returns assigned to external
   sources; JPDA/PDAF: returns in no confirmed target's gate) and add any newly confirmed
   tentative track to the confirmed list;
4. delete a confirmed track after ``max_misses`` consecutive scans without a detection (GNN: no
   return assigned; JPDA/PDAF: no return in its gate).

At the first scan every return goes to initiation ("Time k = 0: send all measurements to
initiation logic") unless known initial tracks were given with :meth:`initialise`.
Confirmed tracks get stable integer ids ``0, 1, 2, …`` in order of confirmation.
"""

from __future__ import annotations

import numpy as np

from .._validation import (
    check_covariance,
    check_labels,
    check_finite_array,
    check_int,
    check_measurements,
    check_positive,
    check_state_dimension,
    check_time,
)
from ..protocol import TrackEstimates
from ._sht_common import ScanModel, _gate_scan, _ScanPredictor, with_track_p_D
from .gnn import _associate, gnn_gains, gnn_update, mahalanobis_gains
from .blocks import SPARSE_PAIRS, gate_blocks
from .deferred import ScanTimes, predict_gap, replay
from .initiation import MOfNInitiator
from .jpda import jpda_log_weights, jpda_probabilities, pda_update, pdaf_probabilities

__all__ = ["TrackEstimates", "SingleHypothesisTracker"]

_ASSOCIATIONS = ("gnn", "jpda", "pdaf")
_LAZY_PREDICTIONS = ("replay", "gap")


class SingleHypothesisTracker:
    """GNN / JPDA / PDAF tracker with M-of-N initiation and deletion after misses.

    Parameters
    ----------
    motion : motion model
        E.g. :class:`hypotrack.models.ConstantVelocity`.
    model : ScanModel
        ``H``, ``R``, ``P_D``, ``P_G`` and the clutter / new-target densities.
    association : {"gnn", "jpda", "pdaf"}
    jpda_marginals : {"exact", "lbp"}
        For ``association="jpda"``: the exact marginals (default) or the loopy belief propagation
        approximation of :func:`hypotrack.association.lbp.lbp_marginals` (Williams & Lau 2014),
        whose cost per pass is linear in the gated pairs; see
        :func:`hypotrack.trackers.jpda.jpda_probabilities`.
    initiator : MOfNInitiator or None
        Initiation logic; ``None`` tracks only the targets given to :meth:`initialise`.
    max_misses : int
        Consecutive missed scans after which a confirmed track is deleted (≥ 1).
    gnn_score : {"lecture", "mahalanobis"}
        GNN criterion: the lecture's assignment matrix, or Stone Soup's unsquared-Mahalanobis
        ``GNNWith2DAssignment`` criterion (:func:`hypotrack.trackers.gnn.mahalanobis_gains`).
    missed_distance : float, optional
        For ``gnn_score="mahalanobis"``: the missed distance ``g`` (default: the square root of
        the model's gate).
    in_view : callable, optional
        ``in_view(x) -> (n,) bool`` for states ``x`` ``(n, d)``: where the sensor can see. A track
        whose updated mean is out of view has its miss count reset after each scan, so deletion
        counts misses *in view* only (a catalogue object out of the radar's field of view is not
        missed). ``None``: every track can be missed everywhere (the lecture's rule).
    gate_out_of_view : bool, optional
        ``True``: every track is gated against the scan (the lecture's rule); ``False`` (needs
        ``in_view``): a track whose predicted mean is out of view takes no return (``p_D = 0`` there).
        Default: ``not lazy``.
    lazy : bool
        Defer the prediction of tracks out of view (:mod:`hypotrack.trackers.deferred`; needs
        ``in_view``, implies ``gate_out_of_view=False``): each scan only the tracks' means are
        advanced, and a track is predicted — over every scan it missed, scan by scan — when its
        advanced mean is in view or :meth:`estimates` is called. Same posterior as the eager
        tracker with ``gate_out_of_view=False``.
    lazy_prediction : {"replay", "gap"}
        With ``lazy``, how a deferred track is brought to now: ``"replay"`` (default) predicts it scan by
        scan, the eager posterior exactly; ``"gap"`` predicts it once over its whole gap, as the factored
        engine's lazy lane does without ``replay`` (:func:`hypotrack.trackers.deferred.predict_gap`): cheaper,
        and exact for white-noise acceleration, but over an orbit's pass gap its in-track spread is too
        narrow and its cross-track one too wide.
    validity : callable, optional
        ``validity(x) -> (n,) bool`` of track means (e.g. :func:`hypotrack.models.plausibility.plausible_orbits`):
        after each scan a track whose mean fails it is deleted, and a track the initiator confirms is not
        started — the single-hypothesis counterpart of the engine's ``validity``. ``None``: no test.
    p_detect : callable, optional
        ``p_detect(x) -> (n,)`` detection probabilities in (0, 1] of the predicted tracks (a sensor's
        ``detection.p_D_of``, e.g. the SNR p_D at each predicted range), used in place of the scan model's
        ``p_D`` in the scores (:func:`~._sht_common.with_track_p_D`). ``None``: the model's ``p_D``.
    block_pairs : int or None
        A scan with more (return, track) pairs than this is solved block by block, each block whole components
        of the gate graph (:mod:`.blocks`: the same association and updates, without the ``(m, n)`` matrices;
        ``last_gated`` is then ``None`` and JPDA/PDAF's ``last_association`` too). Default
        :data:`~.blocks.SPARSE_PAIRS`; ``None``: always the whole matrices.

    The tracker follows :class:`hypotrack.protocol.Tracker`: :meth:`initialise` with known objects
    and their labels, :meth:`step` with each scan's returns and time, :meth:`estimates`.

    Attributes
    ----------
    last_gated : GatedTracks or None
        Gating of the confirmed tracks at the last scan (with ``gate_out_of_view=False``: of those in view);
        ``None`` after a scan solved in blocks (``block_pairs``).
    last_association : ndarray or None
        The last scan's association: the event vector (GNN) or ``β`` (JPDA/PDAF).
    last_predicted : int
        Tracks predicted at the last scan (all of them unless ``lazy``).
    miss_view : callable or None
        ``None`` (default): a track out of view has its miss count reset. Several sensors
        (:mod:`.multisensor`): ``miss_view(x)`` is where *some* sensor sees; a track out of this scan's
        view but inside it keeps its count (another sensor's misses are not forgiven), outside it is reset.
    """

    def __init__(
        self,
        motion,
        model: ScanModel,
        *,
        association: str = "gnn",
        jpda_marginals: str = "exact",
        initiator: MOfNInitiator | None = None,
        max_misses: int = 3,
        gnn_score: str = "lecture",
        missed_distance: float | None = None,
        in_view=None,
        gate_out_of_view: bool | None = None,
        lazy: bool = False,
        lazy_prediction: str = "replay",
        validity=None,
        p_detect=None,
        block_pairs: int | None = SPARSE_PAIRS,
    ):
        if not isinstance(model, ScanModel):
            raise TypeError(f"model must be a ScanModel, got {type(model).__name__}")
        if association not in _ASSOCIATIONS:
            raise ValueError(f"association must be one of {_ASSOCIATIONS}, got {association!r}")
        if jpda_marginals not in ("exact", "lbp"):
            raise ValueError(f"jpda_marginals must be 'exact' or 'lbp', got {jpda_marginals!r}")
        if gnn_score not in ("lecture", "mahalanobis"):
            raise ValueError(f"gnn_score must be 'lecture' or 'mahalanobis', got {gnn_score!r}")
        if initiator is not None and not isinstance(initiator, MOfNInitiator):
            raise TypeError(f"initiator must be an MOfNInitiator or None, got {type(initiator).__name__}")
        shape = (model.dim, model.ndim_state)
        check_state_dimension(motion, model.ndim_state, f"the scan model (H of shape {shape})")
        if initiator is not None and (initiator.model.dim, initiator.model.ndim_state) != shape:
            raise ValueError(f"initiator's scan model has H of shape {(initiator.model.dim, initiator.model.ndim_state)}, "
                             f"the tracker's {shape}")
        self.motion = motion
        self._predict = _ScanPredictor(motion)
        self.model = model
        self.association = association
        self.jpda_marginals = jpda_marginals
        self.initiator = initiator
        self.max_misses = check_int(max_misses, "max_misses", minimum=1)
        self.gnn_score = gnn_score
        if in_view is not None and not callable(in_view):
            raise TypeError(f"in_view must be a callable of the track states or None, got {type(in_view).__name__}")
        self.in_view = in_view
        self.miss_view = None
        if validity is not None and not callable(validity):
            raise TypeError(f"validity must be a callable of the track means or None, got {type(validity).__name__}")
        self.validity = validity
        if p_detect is not None and not callable(p_detect):
            raise TypeError(f"p_detect must be a callable of the track states or None, got {type(p_detect).__name__}")
        self.p_detect = p_detect
        if not isinstance(lazy, bool | np.bool_):
            raise TypeError(f"lazy must be True or False, got {lazy!r}")
        gate_out_of_view = not lazy if gate_out_of_view is None else gate_out_of_view
        if not isinstance(gate_out_of_view, bool | np.bool_):
            raise TypeError(f"gate_out_of_view must be True, False or None, got {gate_out_of_view!r}")
        if (lazy or not gate_out_of_view) and in_view is None:
            raise ValueError("lazy=True and gate_out_of_view=False need in_view (where the sensor sees)")
        if lazy and gate_out_of_view:
            raise ValueError("lazy=True needs gate_out_of_view=False (a deferred track takes no return)")
        self.lazy, self.gate_out_of_view = bool(lazy), bool(gate_out_of_view)
        if lazy_prediction not in _LAZY_PREDICTIONS:
            raise ValueError(f"lazy_prediction must be one of {_LAZY_PREDICTIONS}, got {lazy_prediction!r}")
        self.lazy_prediction = lazy_prediction
        self.missed_distance = (
            float(np.sqrt(model.gate)) if missed_distance is None else check_positive(missed_distance, "missed_distance")
        )
        d = model.ndim_state
        self.ids = np.zeros(0, dtype=np.int64)
        self.x = np.zeros((0, d))
        self.P = np.zeros((0, d, d))
        self.misses = np.zeros(0, dtype=np.int64)
        # lazy: the scan each track's (x, P) is predicted to, the scans' times, every track's mean now
        self._since = np.zeros(0, dtype=np.int64)
        self._times = ScanTimes()
        self._view = np.zeros((0, d))
        self.time: float | None = None
        self._next_id = 0
        self.last_gated = None
        self.last_association = None
        self.block_pairs = None if block_pairs is None else check_int(block_pairs, "block_pairs", minimum=0)
        self.last_predicted = 0

    def initialise(self, means, covs, labels=None, *, time: float = 0.0) -> np.ndarray:
        """Add known confirmed tracks (means ``(n, d)``, covariances ``(n, d, d)``) valid at ``time``.

        ``labels`` (``(n,)`` distinct integers, none already held): the tracks' labels in
        :meth:`estimates`; default the next free ones (``0, 1, …`` on a new tracker). Tracks confirmed
        later get labels above every label held so far. May be called again at the current time.
        Returns the labels.
        """
        d = self.model.ndim_state
        x = check_finite_array(np.asarray(means, dtype=float).reshape(-1, d), "means", shape=(None, d))
        P = np.asarray(covs, dtype=float).reshape(-1, d, d)
        if len(P) != len(x):
            raise ValueError(f"covs must hold one covariance per track: {len(x)} means, {len(P)} covariances")
        P = check_covariance(P, "covs", dim=d, batched=True) if len(P) else P
        time = check_time(time)
        if self.time is not None and time != self.time:
            raise ValueError(f"time: initialise() must be called before the first scan or at the current time "
                             f"{self.time}, got {time}")
        if labels is not None:
            labels = check_labels(labels, len(x), held=self.ids)
        if self.time is None:
            self._times.append(time)
        self.time = time
        return self._add(x, P, labels)

    def _add(self, x, P, labels=None) -> np.ndarray:
        if labels is None:
            labels = np.arange(self._next_id, self._next_id + len(x), dtype=np.int64)
        if len(labels):
            self._next_id = max(self._next_id, int(labels.max()) + 1)
        self.ids = np.concatenate([self.ids, labels])
        self.x = np.concatenate([self.x, x])
        self.P = np.concatenate([self.P, P])
        self.misses = np.concatenate([self.misses, np.zeros(len(x), dtype=np.int64)])
        self._since = np.concatenate([self._since, np.full(len(x), self._times.now, dtype=np.int64)])
        self._view = np.concatenate([self._view, x])
        return labels

    def step(self, Z, time=None) -> TrackEstimates:
        """Process one scan: returns ``Z`` (``(m, p)``, possibly empty) observed at ``time``; the estimates.

        The tracks are predicted over ``time − self.time`` (zero: an update without prediction); a
        scan earlier than the previous one is refused and leaves the tracker as it was.
        """
        if isinstance(Z, tuple) and len(Z) == 2 and np.ndim(Z[0]) == 0:
            raise TypeError("step(Z, time) takes the returns and the scan's time; got a (time, Z) pair "
                            "(use run() for a sequence of (time, Z) pairs)")
        if time is None:
            raise TypeError("time is required: step(Z, time) with the scan's time (the single-hypothesis "
                            "trackers have no default scan interval)")
        time = check_time(time)
        Z = check_measurements(Z, "Z", self.model.dim)
        dt = 0.0 if self.time is None else time - self.time
        if dt < 0:
            raise ValueError(f"time: scan times must not decrease, got {time} after {self.time}")

        # Everything is computed into locals and committed at the end, so that a failure (e.g. a
        # JPDA cluster over its marginals budget) leaves the tracker as it was and the scan can
        # be retried.
        # Inputs are checked here and at construction/initialise; the per-scan work below runs on
        # the tracker's own states, in a few batched numpy calls whatever the number of tracks.
        self._times.append(time)
        try:
            rows, x, P, view = self._predicted(dt)
            out = self._scan(Z, x, P)
            new_x, new_P = self.initiator.step(time, Z[out[4]]) if self.initiator is not None else (None, None)
        except BaseException:
            self._times.pop()
            raise
        x, P, detected, gated, association = out[0], out[1], out[2], out[3], out[5]

        prev = self.misses[rows] if rows is not None else self.misses
        misses = prev + 1
        misses[detected] = 0
        if self.in_view is not None and len(x):
            # deletion counts misses in view only: a track out of view is not missed (miss_view: it keeps its count)
            out = ~np.asarray(self.in_view(x), dtype=bool)
            misses[out] = 0 if self.miss_view is None else np.where(self.miss_view(x[out]), prev[out], 0)

        # commit (the initiator's own step above was the last thing that may fail)
        self.time = time
        self.last_gated, self.last_association = gated, association
        self.last_predicted = len(x)
        now = self._times.now
        if rows is None:
            self.x, self.P, self.misses = x, P, misses
            self._since = np.full(len(x), now, dtype=np.int64)
            self._view = x
        else:
            # lazy: the tracks predicted this scan take their posterior; the others keep their moments
            # at their own scan, are not missed (out of view), and only their mean moves
            self.x[rows], self.P[rows], self._since[rows] = x, P, now
            view[rows] = x
            self._view = view
            self.misses = (np.zeros(len(view), dtype=np.int64) if self.miss_view is None
                           else np.where(self.miss_view(view), self.misses, 0).astype(np.int64))
            self.misses[rows] = misses
        keep = self.misses < self.max_misses
        if self.validity is not None and len(keep):
            keep &= np.asarray(self.validity(self._view), dtype=bool)  # an unphysical track is deleted
        if not keep.all():
            self.ids, self.x, self.P, self.misses = self.ids[keep], self.x[keep], self.P[keep], self.misses[keep]
            self._since, self._view = self._since[keep], self._view[keep]
        if new_x is not None and self.validity is not None and len(new_x):
            ok = np.asarray(self.validity(new_x), dtype=bool)
            new_x, new_P = new_x[ok], new_P[ok]
        if new_x is not None:
            self._add(new_x, new_P)
        if len(self._since):
            self._times.trim(int(self._since.min()))
        return self.estimates(covariances=not self.lazy)

    def _predicted(self, dt):
        """``(rows, x, P, view)``: the tracks predicted to this scan (``rows`` their indices, ``None`` for
        all) and, with ``lazy``, every track's mean advanced to it (``view``, a new array)."""
        if not self.lazy:
            x, P = self._predict(self.x, self.P, dt)
            return None, x, P, None
        view = self._predict.mean(self._view, dt)
        view = view.copy() if view is self._view else view
        rows = np.flatnonzero(np.asarray(self.in_view(view), dtype=bool)) if len(view) else np.zeros(0, np.int64)
        x, P = self._catch_up(rows)
        return rows, x, P, view

    def _catch_up(self, rows):
        """The deferred tracks ``rows`` predicted to now (``lazy_prediction``: scan by scan, or over the gap)."""
        if self.lazy_prediction == "replay":
            return replay(self._predict, self.x[rows], self.P[rows], self._since[rows], self._times)
        return predict_gap(self.motion, self.x[rows], self.P[rows], self._since[rows], self._times)

    def _scan(self, Z, x, P):
        """Gate, associate and update predicted tracks ``x, P``: ``(x, P, detected, gated, unused returns,
        association)``. With ``gate_out_of_view=False`` only the tracks whose predicted mean is in view
        are gated (``gated`` and the association are over those, in order)."""
        g = None
        if not self.gate_out_of_view and len(x):
            inside = np.asarray(self.in_view(x), dtype=bool)
            if not inside.all():
                g = np.flatnonzero(inside)
        xg, Pg = (x, P) if g is None else (x[g], P[g])
        if self.block_pairs is not None and len(xg) * len(Z) > self.block_pairs:
            xg, Pg, det, gated, unused, association = self._solve_blocks(Z, xg, Pg)
        else:
            xg, Pg, det, gated, unused, association = self._solve(Z, xg, Pg)
        if g is None:
            return xg, Pg, det, gated, unused, association
        x, P = x.copy(), P.copy()
        x[g], P[g] = xg, Pg
        detected = np.zeros(len(x), dtype=bool)
        detected[g] = det
        return x, P, detected, gated, unused, association

    def _solve(self, Z, xg, Pg):
        """Gate, associate and update the tracks ``xg, Pg`` against returns ``Z`` (the whole matrices):
        ``(x, P, detected, gated, unused returns, association)``."""
        gated = _gate_scan(xg, Pg, Z, self.model, logdet=self.association != "gnn" or self.gnn_score == "lecture")
        model = self.model if self.p_detect is None or not len(xg) else with_track_p_D(self.model, self.p_detect(xg))
        if self.association == "gnn":
            gain = (
                gnn_gains(gated, model)
                if self.gnn_score == "lecture"
                else mahalanobis_gains(gated, self.missed_distance)
            )
            association = _associate(gain)
            xg, Pg, det = gnn_update(gated, association, self.model)
            unused = association < 0
        else:
            lw = jpda_log_weights(gated, model)
            if self.association == "jpda":
                association = jpda_probabilities(gated, model, log_weights=lw, marginals=self.jpda_marginals)
            else:
                association = pdaf_probabilities(lw)
            xg, Pg = pda_update(gated, association, self.model)
            det = gated.valid.any(axis=0)
            unused = ~gated.valid.any(axis=1)
        return xg, Pg, det, gated, unused, association

    def _solve_blocks(self, Z, xg, Pg):
        """:meth:`_solve` block by block (:func:`~.blocks.gate_blocks`: whole components of the gate graph, so
        the same association and updates as the whole matrices, which a large scan never builds). A track in no
        block is missed and keeps its prediction; a return in no block is unused. ``gated`` is ``None`` and
        GNN's ``association`` (return -> track, -1) covers the whole scan; JPDA/PDAF's is ``None`` (its
        ``(n, m + 1)`` probabilities are the matrix avoided)."""
        x, P = xg.copy(), Pg.copy()
        det, unused = np.zeros(len(xg), dtype=bool), np.ones(len(Z), dtype=bool)
        association = np.full(len(Z), -1, dtype=np.int64) if self.association == "gnn" else None
        for t, r in gate_blocks(xg, Pg, Z, self.model):
            xb, Pb, db, _, ub, ab = self._solve(Z[r], xg[t], Pg[t])
            x[t], P[t], det[t], unused[r] = xb, Pb, db, ub
            if association is not None:
                association[r] = np.where(ab >= 0, t[np.maximum(ab, 0)], -1)
        return x, P, det, None, unused, association

    def estimates(self, *, covariances: bool = True) -> TrackEstimates:
        """The confirmed tracks now (copies).

        With ``lazy``, the deferred tracks are first predicted to now (scan by scan, as the eager
        tracker would have: :mod:`hypotrack.trackers.deferred`); ``covariances=False`` skips that and
        gives the means alone (a deferred track's mean advanced a scan at a time, without its
        covariance; ``P`` is then ``None``).
        """
        t = -np.inf if self.time is None else self.time
        if not covariances:
            return TrackEstimates(t, self.ids.copy(), self._view.copy(), None)
        if self.lazy and len(self._since) and self._since.min() < self._times.now:
            late = np.flatnonzero(self._since < self._times.now)
            self.x[late], self.P[late] = self._catch_up(late)
            self._since[late] = self._times.now
            self._view[late] = self.x[late]
        return TrackEstimates(t, self.ids.copy(), self.x.copy(), self.P.copy())

    def state_times(self) -> np.ndarray:
        """The time each stored track (rows of ``x``, ``P``) is valid at: now, except for a lazy
        tracker's deferred tracks, which stay at the last scan they were predicted to until
        :meth:`estimates` brings them to now."""
        if not len(self._since):
            return np.zeros(0)
        first = int(self._since.min())
        return self._times.since(first)[self._since - first]

    def run(self, scans) -> list[TrackEstimates]:
        """:meth:`step` over a sequence of scans; the estimates after each."""
        return [self.step(Z, t) for t, Z in scans]

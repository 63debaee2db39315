"""The Stone Soup ``Tracker`` subclass (built on first use, so that hypotrack never needs Stone Soup)."""

from __future__ import annotations

import contextlib
import datetime

import numpy as np

from ...gaussian import predict_with
from ...hypotheses.association_problem import SEEDED_BIRTH
from ...trackers._sht_common import gate_tracks, predict_tracks
from ...trackers.gnn import gnn_associate, gnn_gains, gnn_update
from ._build import _build, glmb_population, scan_settings
from ...registry import kinds, preset
from ._common import check_scan_time, check_tracker_inputs, require_stonesoup
from ._models import DetectionFrame, _region, translate_models

__all__ = ["tracker_class"]


@contextlib.contextmanager
def _applied(settings):
    """Set ``(object, attribute, value)`` for the duration of one scan, restored whatever happens."""
    saved = [(obj, name, getattr(obj, name)) for obj, name, _ in settings]
    try:
        for obj, name, value in settings:
            setattr(obj, name, value)
        yield
    finally:
        for obj, name, value in reversed(saved):
            setattr(obj, name, value)


def _initiated(initiator, before, Z_unused, dt):
    """Which return confirmed each track the initiator confirmed at this scan, and its prediction.

    The initiator does not report its association, so its step is recomputed with the same
    public functions on the same inputs (the tentative tracks before the scan, the returns the
    confirmed tracks left): GNN of the predicted tentative tracks on the unused returns. Returns
    ``[(index into Z_unused, predicted mean or None, predicted covariance or None, updated mean)]``
    in the order the tracker added the tracks (confirmed tentative tracks, then with ``m = 1``
    the returns that start and confirm a track at once, which have no prediction).
    """
    x0, P0, hits0 = before
    xp, Pp = predict_tracks(initiator.motion, x0, P0, dt)
    gated = gate_tracks(xp, Pp, Z_unused, initiator.model)
    a = gnn_associate(gnn_gains(gated, initiator.model))
    x, _, detected = gnn_update(gated, a, initiator.model)
    out = [(int(np.flatnonzero(a == k)[0]), xp[k], Pp[k], x[k]) for k in np.flatnonzero(hits0 + detected >= initiator.m)]
    if initiator.m == 1:
        out += [(int(i), None, None, None) for i in np.flatnonzero(a < 0)]
    return out


def tracker_class():
    require_stonesoup()
    from stonesoup.base import Property
    from stonesoup.tracker.base import Tracker
    from stonesoup.types.detection import MissedDetection
    from stonesoup.types.hypothesis import SingleHypothesis, SingleProbabilityHypothesis
    from stonesoup.types.multihypothesis import MultipleHypothesis
    from stonesoup.types.prediction import GaussianStatePrediction
    from stonesoup.types.track import Track
    from stonesoup.types.update import GaussianStateUpdate

    class HypotrackTracker(Tracker):
        """A hypotrack tracker driven by a Stone Soup detector (see :mod:`hypotrack.interop.stonesoup`).

        Iteration follows Stone Soup's trackers: ``iter(tracker)`` creates the detector's iterator
        once (``detector_iter``) and returns the tracker; each ``next`` processes the detector's
        next scan. A loop after some ``next`` calls continues where they stopped, a finished
        tracker stays finished, and :meth:`update_tracker` feeds one scan by hand without
        touching the detector's iterator.

        Scan times (one rule for every algorithm, as Stone Soup's predictor–updater pair with a
        zero time interval): a scan is predicted over the time since the previous scan, or since
        ``initial_states``' timestamp before the first scan (priors without a timestamp, or no
        priors, are taken at the first scan's time). That time may be zero: a scan stamped like
        the previous one, or a first scan at the priors' time, is processed as an additional scan
        with no prediction (``dt = 0``) and each track gets another state with that timestamp,
        as Stone Soup's ``MultiTargetTracker`` appends one state per scan. For the hypothesis
        filters such a scan is a full step of the recursion (births, survival and clutter are per
        scan), as for GNN/JPDA/PDAF (misses count per scan). This is also how several sensors'
        detections at one time are fed: one scan per sensor. A scan earlier than the previous one
        raises ``ValueError``.

        States appended to the tracks: a ``GaussianStateUpdate`` when the object was associated
        with a detection at that scan, its ``hypothesis`` a ``SingleHypothesis`` holding the
        ``Detection`` and the object's ``GaussianStatePrediction`` (``None`` for an object born
        from that detection without a Gaussian prior: M-of-N one-point initiation, HOMHT's seeded
        births); a ``GaussianStatePrediction`` when it was missed. JPDA and PDAF follow Stone
        Soup's JPDA tracker: the hypothesis is a ``MultipleHypothesis`` of
        ``SingleProbabilityHypothesis`` (the missed detection and every gated detection with its
        association probability β), and the state is an update when some detection is more
        probable than the miss. For the hypothesis filters "associated" is the association of the
        maximum-a-posteriori hypothesis.

        A detection's own ``measurement_model`` is honoured (:class:`DetectionFrame`): a
        linear-Gaussian model measuring the same components (any order, any ``noise_covar``) is
        translated into the tracker's frame; a scan whose detections need different noise
        covariances, a non-linear model or another ``ndim_meas`` raise ``ValueError`` naming
        ``measurement_model``.

        ``options`` go to the hypotrack constructor: for ``gnn``/``jpda``/``pdaf`` those of
        :class:`~hypotrack.trackers.SingleHypothesisTracker` plus ``p_gate``, ``new_target_density``
        and ``initiator`` (a dict of :class:`~hypotrack.trackers.MOfNInitiator` options, or absent for
        no initiation); for the hypothesis filters those of the preset (``n_steps``,
        ``max_hypotheses``, ``gate_probability``, ``population``, ``seed``, ...); for ``glmb`` and
        ``glmb_murty`` also ``birth_states``, ``birth_probability`` and ``survival_probability``
        (:func:`~hypotrack.interop.stonesoup._build.glmb_population`).

        Examples
        --------
        Stone Soup's models, two objects known at ``t0`` (Stone Soup's state order ``x, vx, y, vy``)
        and a detector of one scan, a second later, with a detection near each:

        >>> import datetime
        >>> import numpy as np
        >>> from stonesoup.models.measurement.linear import LinearGaussian
        >>> from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
        >>> from stonesoup.types.detection import Detection
        >>> from stonesoup.types.state import GaussianState
        >>> from hypotrack.interop.stonesoup import HypotrackTracker
        >>> t0 = datetime.datetime(2025, 1, 1)
        >>> t1 = t0 + datetime.timedelta(seconds=1)
        >>> transition = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.05), ConstantVelocity(0.05)])
        >>> measurement = LinearGaussian(4, (0, 2), np.eye(2))
        >>> prior = np.diag([4.0, 1.0, 4.0, 1.0])
        >>> priors = [GaussianState([[0.0], [1.0], [0.0], [0.0]], prior, timestamp=t0),
        ...           GaussianState([[20.0], [0.0], [0.0], [1.0]], prior, timestamp=t0)]
        >>> scan = {Detection([[1.2], [0.1]], timestamp=t1, measurement_model=measurement),
        ...         Detection([[19.9], [0.8]], timestamp=t1, measurement_model=measurement)}
        >>> tracker = HypotrackTracker(
        ...     detector=[(t1, scan)], transition_model=transition, measurement_model=measurement,
        ...     algorithm="homht", detection_probability=0.9, clutter_rate=1.0,
        ...     clutter_region=[[-50, 50], [-50, 50]], initial_states=priors, options={"max_hypotheses": 10})
        >>> time, tracks = next(iter(tracker))
        >>> time == t1, len(tracks)
        (True, 2)

        Each track (its id the object's label) is updated with its detection, in Stone Soup's order:

        >>> [(t.id, type(t.state).__name__, np.round(t.state_vector.ravel().astype(float), 2).tolist())
        ...  for t in sorted(tracks, key=lambda t: t.id)]   # doctest: +NORMALIZE_WHITESPACE
        [('0', 'GaussianStateUpdate', [1.17, 1.03, 0.08, 0.02]),
         ('1', 'GaussianStateUpdate', [19.92, -0.02, 0.83, 0.97])]
        """

        transition_model = Property(object, doc="CombinedLinearGaussianTransitionModel of ConstantVelocity.")
        measurement_model = Property(object, doc="LinearGaussian position measurement model (that of detections "
                                                 "without their own; clutter_region is in its measured axes).")
        algorithm: str = Property(doc="A kind of hypotrack.registry (gnn, jpda, pdaf, hfisst, rfisst, homht, "
                                      "homht_kbest, glmb, glmb_murty, ... and any kind registered since).")
        detection_probability: float = Property(doc="P_D of every object, in (0, 1).")
        clutter_rate: float = Property(doc="Expected clutter returns per scan (> 0).")
        clutter_region = Property(object, doc="[[low, high], ...] per measured axis: where clutter falls.")
        detector = Property(object, default=None, doc="Detector yielding (time, set of detections).")
        initial_states = Property(list, default=None,
                                  doc="GaussianStates of the objects known at the start (ids 0, 1, ...), sharing "
                                      "one timestamp (None: the first scan's).")
        options: dict = Property(default=None, doc="Keyword options of the hypotrack tracker.")

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.detector_iter = None
            if self.algorithm not in kinds():
                raise ValueError(f"algorithm must be a registered tracker kind ({', '.join(kinds())}), "
                                 f"got {self.algorithm!r}")
            motion, measurement, self._perm = translate_models(self.transition_model, self.measurement_model)
            check_tracker_inputs(self.algorithm, self.detection_probability, self.clutter_rate, self.initial_states,
                                 motion.ndim)
            self._inverse = np.argsort(self._perm)
            self._frame = DetectionFrame(self.measurement_model, self._perm, measurement.H, measurement.R)
            region = _region(self.clutter_region, measurement.dim)
            priors = list(self.initial_states or [])
            d = motion.ndim
            means = np.array([np.ravel(s.state_vector)[self._perm] for s in priors]).reshape(-1, d)
            covs = np.array([np.asarray(s.covar)[np.ix_(self._perm, self._perm)] for s in priors]).reshape(-1, d, d)
            times = {s.timestamp for s in priors}
            if len(times) > 1:
                raise ValueError(f"initial_states must share one timestamp, got {sorted(map(str, times))}")
            self._time = times.pop() if times else None  # previous scan's time (the priors' before the first)
            self._epoch = self._time
            options = glmb_population(self.algorithm, self.options or {}, self._perm, measurement.H, measurement.R)
            self.tracker = _build(self.algorithm, motion, measurement, self.detection_probability,
                                  self.clutter_rate, region, means, covs, options)
            family = preset(self.algorithm).family
            self._single = family == "single"
            if self._single:  # _step_single reads every scan's whole gating (last_gated), so no scan is cut in blocks
                self.tracker.block_pairs = None
            self._stepper = (self._step_single if family == "single" else
                             self._step_pmbm if family == "poisson_mb" else self._step_filter)
            self._tracks = {}
            self._current = set()
            self._n_scans = 0

        @property
        def tracks(self) -> set:
            """Tracks present at the current scan."""
            return set(self._current)

        @property
        def all_tracks(self) -> set:
            """Every track seen so far (what metric managers want at the end of a run)."""
            return set(self._tracks.values())

        def __iter__(self):
            if self.detector is None:
                raise AttributeError("detector is not set: pass detector=... or call update_tracker(time, detections)")
            if self.detector_iter is None:
                self.detector_iter = iter(self.detector)
            return self

        def __next__(self):
            time, detections = next(self.detector_iter)
            return self.update_tracker(time, detections)

        def update_tracker(self, time: datetime.datetime, detections) -> tuple:
            """Process one scan; returns ``(time, tracks present now)``.

            Raises ``ValueError`` (and leaves the tracker as it was) for a scan earlier than the
            previous one, for a detection whose timestamp is not ``time`` and for detections the
            tracker cannot take (see the class docstring); ``TypeError`` for a ``time`` that is not
            a ``datetime.datetime`` or ``detections`` that are not Stone Soup ``Detection`` objects.
            """
            Z, dets, variant = self._frame.returns(detections, check_scan_time(time))
            previous = self._time
            if previous is not None and time < previous:
                what = "the previous scan's" if self._n_scans else "initial_states'"
                raise ValueError(f"time: scan times must not decrease; scan at {time} is earlier than {what} "
                                 f"time {previous}")
            dt = 0.0 if previous is None else (time - previous).total_seconds()
            R = None if variant is None else self._frame.variants[variant]
            settings = scan_settings(self.tracker, R)
            with _applied(settings):
                ids, means, covs, states = self._stepper(time, Z, dets, dt)
            self._time = time
            self._n_scans += 1
            if self._epoch is None:
                self._epoch = time
            inv = self._inverse
            means, covs = means[:, inv, None], covs[:, inv][:, :, inv]  # back to Stone Soup's state order
            self._current = set()
            for track_id, mean, cov, (kind, hypothesis) in zip(ids.tolist(), means, covs, states):
                track = self._tracks.get(track_id)
                if track is None:
                    track = self._tracks[track_id] = Track(id=str(track_id))
                if kind:
                    track.append(GaussianStateUpdate(mean, cov, hypothesis, timestamp=time))
                else:
                    track.append(GaussianStatePrediction(mean, cov, timestamp=time))
                self._current.add(track)
            return time, self.tracks

        # ------------------------------------------------------------------ outputs
        def _predictions(self, x, P, time):
            """``prediction(j)``: object ``j``'s Stone Soup prediction from hypotrack-order means ``x``
            and covariances ``P``, made on demand (a Stone Soup state costs ~10 µs to construct and
            only the objects associated with a detection need one)."""
            inv = self._inverse
            means, covs = x[:, inv, None], np.asarray(P)[:, inv][:, :, inv]
            return lambda j: GaussianStatePrediction(means[j], covs[j], timestamp=time)

        def _step_single(self, time, Z, dets, dt):
            """GNN/JPDA/PDAF step; per confirmed track ``(is_update, hypothesis)``."""
            tr = self.tracker
            epoch = self._epoch if self._epoch is not None else time
            t = (time - epoch).total_seconds()
            ids_before, time_before = tr.ids, tr.time
            ini = tr.initiator
            ini_before = None if ini is None else (ini.x, ini.P, ini.hits)
            est = tr.step(Z, t)
            gated, assoc = tr.last_gated, tr.last_association
            preds = self._predictions(gated.x, gated.P, time)
            pos = {int(i): j for j, i in enumerate(ids_before.tolist())}
            gnn = tr.association == "gnn"
            if gnn:
                ret = np.full(len(ids_before), -1)
                hit = np.flatnonzero(assoc >= 0)
                ret[assoc[hit]] = hit
                unused = assoc < 0
            else:
                unused = ~gated.valid.any(axis=1)
            new = [k for k, i in enumerate(est.ids.tolist()) if i not in pos]
            births = {}
            if new:
                u_idx = np.flatnonzero(unused)
                dt_f = 0.0 if time_before is None else t - time_before
                found = _initiated(ini, ini_before, Z[u_idx], dt_f)
                if len(found) != len(new) or any(
                        x is not None and not np.array_equal(x, est.x[k]) for k, (*_, x) in zip(new, found)):
                    raise RuntimeError("hypotrack's initiator confirmed tracks the adapter cannot match to returns; "
                                       "please report this (MOfNInitiator.step changed?)")
                for k, (i, xp, Pp, _) in zip(new, found):
                    pred = None if xp is None else self._predictions(xp[None], Pp[None], time)(0)
                    births[k] = (True, SingleHypothesis(pred, dets[u_idx[i]]))
            states = []
            for k, track_id in enumerate(est.ids.tolist()):
                if k in births:
                    states.append(births[k])
                    continue
                j = pos[track_id]
                if gnn:
                    i = ret[j]
                    states.append((True, SingleHypothesis(preds(j), dets[i])) if i >= 0 else (False, None))
                    continue
                beta = assoc[j]
                gated_returns = np.flatnonzero(beta[1:] > 0)
                if gated_returns.size and beta[1:].max() > beta[0]:
                    pred = preds(j)
                    hyps = [SingleProbabilityHypothesis(pred, MissedDetection(timestamp=time), probability=beta[0])]
                    hyps += [SingleProbabilityHypothesis(pred, dets[i], probability=beta[1 + i]) for i in gated_returns]
                    states.append((True, MultipleHypothesis(hyps)))
                else:
                    states.append((False, None))
            return est.ids, est.x, est.P, states

        def _step_filter(self, time, Z, dets, dt):
            """Hypothesis-filter step; per object of the MAP hypothesis ``(is_update, hypothesis)``."""
            f = self.tracker
            store, lists = f.store, f.track_lists
            epoch = self._epoch if self._epoch is not None else time
            best = f.step(Z, (time - epoch).total_seconds()).map_estimate  # a zero interval: no prediction
            # The MAP hypothesis' child: its parent, association event and silent events give each
            # object's return, in the order HypothesisFilter._materialise lists the child's objects.
            h = int(np.argsort(-f.log_weights, kind="stable")[0])
            kept = f.last_kept
            parent = lists[int(kept.parent[h])]
            M, ev = len(parent), kept.events[h]
            dead, unseen = kept.silent_events(h, M)
            ret = np.full(M, -1)
            on = np.flatnonzero((ev >= 0) & (ev < M))
            ret[ev[on]] = on
            alive = np.array([j for j in range(M) if j not in dead], dtype=np.int64)
            born = np.flatnonzero(ev >= M)
            seeded = np.flatnonzero(ev == SEEDED_BIRTH)
            n_alive = len(alive)
            if (n_alive + len(born) + len(seeded) + len(unseen) != len(best.labels)
                    or not np.array_equal(store.labels[parent[alive]], best.labels[:n_alive])):
                raise RuntimeError("the adapter cannot match the MAP hypothesis' objects to its association; "
                                   "please report this (HypothesisFilter._materialise changed?)")
            states = []
            if n_alive:
                x, P = predict_with(f.motion, store.means[parent[alive]], store.covs[parent[alive]], dt)
                preds = self._predictions(x, P, time)
                states += [(True, SingleHypothesis(preds(k), dets[ret[j]])) if ret[j] >= 0 else (False, None)
                           for k, j in enumerate(alive)]
            pop = f.population
            for i in born:
                term = pop.birth_densities[int(ev[i] - M)]
                states.append((True, SingleHypothesis(self._prior(term, time), dets[i])))
            density = getattr(f.weights, "birth_density", None)
            states += [(True, SingleHypothesis(self._prior(density, time), dets[i])) for i in seeded]
            states += [(False, None)] * len(unseen)
            return best.labels, best.means, best.covs, states

        def _step_pmbm(self, time, Z, dets, dt):
            """PMBM step; per Bernoulli of the estimator's global hypothesis ``(is_update, hypothesis)``: the
            return that updated it at this scan with its prediction (none for a track the return started
            from the Poisson part, whose prior is a mixture), or a prediction when it was missed."""
            f = self.tracker
            epoch = self._epoch if self._epoch is not None else time
            f.step(Z, (time - epoch).total_seconds())
            loc = f.estimated_local_hypotheses()
            est = f.estimates()
            ret = f.last_return[loc]
            x, P = (a[loc] for a in f.last_prediction)
            preds = self._predictions(np.nan_to_num(x), np.nan_to_num(P), time)
            states = [(False, None) if j < 0 else
                      (True, SingleHypothesis(None if np.isnan(x[k]).any() else preds(k), dets[j]))
                      for k, j in enumerate(ret.tolist())]
            return est.labels, est.x, est.P, states

        def _prior(self, density, time):
            """A birth density's Gaussian prior as the prediction of the object it gives birth to."""
            if not hasattr(density, "prior"):
                return None
            mean, cov = density.prior()
            return self._predictions(np.asarray(mean, dtype=float)[None], np.asarray(cov, dtype=float)[None], time)(0)

    return HypotrackTracker

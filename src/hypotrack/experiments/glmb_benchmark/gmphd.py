"""Stone Soup's GM-PHD filter on the GLMB benchmark: the peer baseline of :mod:`.glmb_benchmark`.

The Gaussian-mixture PHD filter of Vo & Ma (2006), composed from Stone Soup's documented parts
(Kalman predictor and updater, ``DistanceHypothesiser`` gating on the Mahalanobis distance,
``GaussianMixtureHypothesiser``, ``PHDUpdater``, ``GaussianMixtureReducer``) with the scenario's
models: the same discrete-white-noise CV motion (``Q = σ_v² G Gᵀ``, not Stone Soup's continuous
``ConstantVelocity``), position returns with ``σ_r``, ``p_S``, ``p_D`` and the clutter intensity
``κ = λ / V``; the birth intensity is the Gaussian mixture of the four birth terms, each with
weight ``r_B`` (Vo & Ma 2006 Eq. 31 with the labeled-Bernoulli terms' densities). Two properties
of Stone Soup's ``PHDUpdater`` are kept as they are (they are the peer's): the undetected part of
the birth intensity, ``(1 − p_D) r_B`` per term, is dropped, and a detected birth component is
multiplied by ``p_S`` — compensated by giving the birth components weight ``r_B / p_S``. The mixture is
pruned below ``prune_threshold``, merged within ``merge_threshold`` (squared Mahalanobis) and
capped at ``max_components`` (Vo & Ma 2006 Table II: 1e-5, 4, 100). State extraction: one
estimate per component with weight above ``extraction_threshold`` (0.5; Vo & Ma Table III rounds
the weight instead, which differs only for components above 1.5). Stone Soup is imported only
when the tracker is built, so the engine never depends on it.
"""

from __future__ import annotations

import datetime
from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2

from ..._validation import check_int, check_positive, check_probability

__all__ = ["GMPHDPeer", "make_gmphd"]

_T0 = datetime.datetime(2000, 1, 1)


@dataclass(frozen=True)
class _Estimate:
    means: np.ndarray


@dataclass(frozen=True)
class _Posterior:
    """The two fields :func:`.glmb_benchmark.run_tracker` reads from a posterior."""

    map_estimate: _Estimate
    expected_number: float


def _transition_model(sigma_v: float):
    from stonesoup.base import Property
    from stonesoup.models.base import TimeVariantModel
    from stonesoup.models.transition.linear import LinearGaussianTransitionModel

    class DiscreteWhiteNoiseCV(LinearGaussianTransitionModel, TimeVariantModel):
        """State ``[x, y, vx, vy]``; ``F(dt)``, ``Q(dt) = σ_v² G Gᵀ`` as the benchmark's model
        (identity and zero at ``dt = 0``, so birth components placed at the scan time stay put)."""

        noise_std: float = Property(doc="acceleration noise std (m/s^2)")

        @property
        def ndim_state(self):
            return 4

        def matrix(self, time_interval=datetime.timedelta(0), **kwargs):
            dt = time_interval.total_seconds()
            F = np.eye(4)
            F[0, 2] = F[1, 3] = dt
            return F

        def covar(self, time_interval=datetime.timedelta(0), **kwargs):
            dt = time_interval.total_seconds()
            G = np.vstack([dt**2 / 2 * np.eye(2), dt * np.eye(2)])
            return self.noise_std**2 * G @ G.T

    return DiscreteWhiteNoiseCV(noise_std=sigma_v)


class GMPHDPeer:
    """Stone Soup's GM-PHD filter behind the engine's ``step(Z) -> posterior`` interface
    (``map_estimate.means``: the extracted states; ``expected_number``: the PHD's mass)."""

    def __init__(self, model, options: dict):
        from stonesoup.hypothesiser.distance import DistanceHypothesiser
        from stonesoup.hypothesiser.gaussianmixture import GaussianMixtureHypothesiser
        from stonesoup.measures import Mahalanobis
        from stonesoup.mixturereducer.gaussianmixture import GaussianMixtureReducer
        from stonesoup.models.measurement.linear import LinearGaussian
        from stonesoup.predictor.kalman import KalmanPredictor
        from stonesoup.types.state import TaggedWeightedGaussianState
        from stonesoup.updater.kalman import KalmanUpdater
        from stonesoup.updater.pointprocess import PHDUpdater

        p_gate = check_probability(options.get("gate_probability", 0.9999999), "gate_probability",
                                   low_open=True, high_open=True)
        self.extraction_threshold = check_positive(options.get("extraction_threshold", 0.5), "extraction_threshold")
        sensor = model.sensor
        self._measurement_model = LinearGaussian(ndim_state=4, mapping=(0, 1), noise_covar=sensor.measurement.R)
        predictor = KalmanPredictor(_transition_model(model.motion.sigma_v))
        kalman = KalmanUpdater(self._measurement_model)
        self._updater = PHDUpdater(kalman, clutter_spatial_density=sensor.clutter.intensity, prob_detection=sensor.detection.p_D,
                                   prob_survival=model.p_survive)
        gate = float(np.sqrt(chi2.ppf(p_gate, 2)))
        self._hypothesiser = GaussianMixtureHypothesiser(
            DistanceHypothesiser(predictor, kalman, Mahalanobis(), missed_distance=gate), order_by_detection=True)
        self._reducer = GaussianMixtureReducer(
            prune_threshold=check_positive(options.get("prune_threshold", 1e-5), "prune_threshold"),
            merge_threshold=check_positive(options.get("merge_threshold", 4.0), "merge_threshold"),
            max_number_components=check_int(options.get("max_components", 100), "max_components", minimum=1))
        # Stone Soup's PHDUpdater multiplies a detected birth component by p_S too (the hypothesiser
        # retags it before the update); r_B / p_S makes the detected birth weight the model's r_B
        self._births = [TaggedWeightedGaussianState(m.reshape(-1, 1), model.birth_cov,
                                                    weight=model.r_birth / model.p_survive,
                                                    tag=TaggedWeightedGaussianState.BIRTH)
                        for m in model.birth_means]
        self._components = []
        self._k = 0

    def step(self, Z):
        from stonesoup.types.detection import Detection

        self._k += 1
        now = _T0 + datetime.timedelta(seconds=self._k)
        detections = {Detection(z.reshape(-1, 1), timestamp=now, measurement_model=self._measurement_model)
                      for z in np.asarray(Z, dtype=float).reshape(-1, 2)}
        for b in self._births:
            b.timestamp = now  # the birth intensity is stated at the scan time (Vo & Ma Eq. 31)
        hyps = self._hypothesiser.hypothesise([*self._components, *self._births], detections, now)
        self._components = list(self._reducer.reduce(self._updater.update(hyps).components))
        kept = [c for c in self._components if c.weight > self.extraction_threshold]
        means = np.array([np.asarray(c.state_vector, dtype=float).ravel()[:4] for c in kept]).reshape(-1, 4)
        return _Posterior(_Estimate(means), float(sum(float(c.weight) for c in self._components)))


def make_gmphd(model, options: dict) -> GMPHDPeer:
    """The peer GM-PHD tracker for the benchmark ``model`` (options: ``gate_probability``,
    ``prune_threshold``, ``merge_threshold``, ``max_components``, ``extraction_threshold``)."""
    return GMPHDPeer(model, options)

"""Kalman predict/update and predictive likelihood against Stone Soup on the same numbers."""

import datetime

import numpy as np
import pytest
from scipy.stats import multivariate_normal

stonesoup = pytest.importorskip("stonesoup")

from stonesoup.models.measurement.linear import LinearGaussian  # noqa: E402
from stonesoup.models.transition.linear import (  # noqa: E402
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity as SSConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor  # noqa: E402
from stonesoup.types.detection import Detection  # noqa: E402
from stonesoup.types.hypothesis import SingleHypothesis  # noqa: E402
from stonesoup.types.state import GaussianState as SSGaussianState  # noqa: E402
from stonesoup.updater.kalman import KalmanUpdater  # noqa: E402

from hypotrack import gaussian as g  # noqa: E402
from hypotrack.models import ConstantVelocity  # noqa: E402


def test_kalman_cycle_equals_stonesoup():
    rng = np.random.default_rng(11)
    q, dt = 0.05, 2.0
    R = np.array([[0.8, 0.1], [0.1, 0.5]])
    # Stone Soup orders the state [x, vx, y, vy]; hypotrack [x, y, vx, vy].
    perm = [0, 2, 1, 3]
    ss_trans = CombinedLinearGaussianTransitionModel([SSConstantVelocity(q), SSConstantVelocity(q)])
    ss_meas = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=R)
    predictor, updater = KalmanPredictor(ss_trans), KalmanUpdater(ss_meas, force_symmetric_covariance=True)

    model = ConstantVelocity(q)
    H = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    t0 = datetime.datetime(2026, 1, 1)
    x = rng.normal(size=4)
    A = rng.normal(size=(4, 4))
    P = A @ A.T + np.eye(4)
    ss_state = SSGaussianState(x[perm].reshape(-1, 1), P[np.ix_(perm, perm)], timestamp=t0)
    for k in range(1, 21):
        t = t0 + datetime.timedelta(seconds=dt * k)
        z = rng.normal(size=2) * 3
        ss_pred = predictor.predict(ss_state, timestamp=t)
        ss_mpred = updater.predict_measurement(ss_pred)
        ss_state = updater.update(SingleHypothesis(ss_pred, Detection(z.reshape(-1, 1), timestamp=t, measurement_model=ss_meas)))

        x, P = g.predict_with(model, x, P, dt)
        np.testing.assert_allclose(x[perm], np.ravel(ss_pred.state_vector), rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(P[np.ix_(perm, perm)], ss_pred.covar, rtol=1e-10, atol=1e-10)
        z_pred, S, _ = g.innovation(x, P, H, R)
        np.testing.assert_allclose(z_pred, np.ravel(ss_mpred.state_vector), rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(S, ss_mpred.covar, rtol=1e-10)
        # Density of Stone Soup's predicted measurement (what its PDAHypothesiser evaluates).
        ll_ss = multivariate_normal.logpdf(z, mean=np.ravel(ss_mpred.state_vector), cov=ss_mpred.covar)
        assert g.log_likelihood(z, z_pred, S) == pytest.approx(ll_ss, rel=1e-10)
        x, P = g.update(x, P, z, H, R)
        np.testing.assert_allclose(x[perm], np.ravel(ss_state.state_vector), rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(P[np.ix_(perm, perm)], ss_state.covar, rtol=1e-9, atol=1e-10)

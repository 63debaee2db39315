"""The closely-spaced-target filters on close targets, where association matters: each PDAF
variant against per-update Gaussian-mixture moments (hypotrack.gaussian) or its stated rule in
explicit loops; the scan interval; single-run scans; the state before the first scan."""

import numpy as np
import pytest

from hypotrack import gaussian
from hypotrack.models import OrnsteinUhlenbeck
from hypotrack.scenarios.closely_spaced import simulate_closely_spaced
from hypotrack.trackers.ecmht import ECMHTFilter, GNNFilter, IdealFilter, PDAFilter

MODEL = OrnsteinUhlenbeck(0.01, 0.005)
H = np.eye(1)
N_SENSORS = 4


def close_scans(seed=2, n_runs=3, n_scans=5):
    real = simulate_closely_spaced(MODEL, n_runs=n_runs, n_scans=n_scans, n_sensors=N_SENSORS, R=1.0,
                                   initial_variance=0.0, rng=seed)
    return real.scans + np.array([0.0, 0.8])  # targets 0.8 m apart, noise σ = 1 m: returns interleave


def jumping_scans():
    """Close targets, then at the last scan run 1's returns jump 80 m (≈ 70 σ) away from both tracks
    while run 0's stay near: the association weights must be normalised per run and per sensor."""
    scans = close_scans()
    scans[1, -1] += 80.0
    return scans


def mixture_update(x, P, zs, R):
    """PDA update (P_D = 1, no clutter) as the moments of the mixture of Kalman updates on each return."""
    xa, Pa = np.array([x]), np.array([[P]])
    z_pred, S, _ = gaussian.innovation(xa, Pa, H, np.array([[R]]))
    logw = np.array([gaussian.log_likelihood(np.array([z]), z_pred, S) for z in zs])
    w = np.exp(logw - logw.max())
    w /= w.sum()
    parts = [gaussian.update(xa, Pa, np.array([z]), H, np.array([[R]])) for z in zs]
    means = np.array([m[0] for m, _ in parts])
    mean = w @ means
    return mean, parts[0][1][0, 0] + w @ (means - mean) ** 2


def predicted(f_prev_x, f_prev_P):
    A, Q = MODEL.F(1.0)[0, 0], MODEL.Q(1.0)[0, 0]
    return A * f_prev_x, A * f_prev_P * A + Q


@pytest.mark.parametrize("variant", ["sequential", "equivalent", "parallel"])
def test_pdaf_variants_on_close_targets(variant):
    scans = jumping_scans()
    f = PDAFilter(MODEL, 1.0, N_SENSORS, variant=variant)
    f.step(scans[:, 0])
    spread_seen = 0.0
    for k in range(1, scans.shape[1]):
        x_prev, P_prev = f.x.copy(), f.P.copy()
        f.step(scans[:, k])
        for r in range(scans.shape[0]):
            for j in range(2):
                x, P = predicted(x_prev[r, j], P_prev[r, j])
                Z = scans[r, k]
                if variant == "sequential":  # the single-sensor PDAF, sensor after sensor, variance R
                    for n in range(N_SENSORS):
                        x, P = mixture_update(x, P, Z[n], 1.0)
                elif variant == "equivalent":  # one PDAF on the order-statistic averages, variance R/N
                    x, P = mixture_update(x, P, np.sort(Z, axis=-1).mean(axis=0), 1.0 / N_SENSORS)
                else:  # β per sensor with S = P + R; innovations averaged; the R/N gain
                    nus, spread = [], 0.0
                    for n in range(N_SENSORS):
                        nu = Z[n] - x
                        logw = -0.5 * nu**2 / (P + 1.0)
                        w = np.exp(logw - logw.max())
                        beta = w / w.sum()
                        nus.append(beta @ nu)
                        spread += beta @ nu**2 - nus[-1] ** 2
                    L = P / (P + 1.0 / N_SENSORS)
                    x, P = x + L * np.mean(nus), (1 - L) * P + L**2 * spread / N_SENSORS**2
                    spread_seen = max(spread_seen, spread)
                assert f.x[r, j] == pytest.approx(x, rel=1e-10, abs=1e-10)
                assert f.P[r, j] == pytest.approx(P, rel=1e-10, abs=1e-10)
    if variant == "parallel":
        assert spread_seen > 0.05  # the spread term is exercised


@pytest.mark.parametrize("make", [lambda: IdealFilter(MODEL, 2.5, N_SENSORS, dt=2.5),
                                  lambda: GNNFilter(MODEL, 2.5, N_SENSORS, dt=2.5),
                                  lambda: ECMHTFilter(MODEL, 2.5, N_SENSORS, dt=2.5, rng=0),
                                  lambda: PDAFilter(MODEL, 2.5, N_SENSORS, dt=2.5, variant="equivalent")])
def test_scan_interval_and_noise_set_the_prediction_and_update(make):
    """dt = 2.5 s: P(k|k−1) = e^{−2γΔt} P + σ²/(2γ)(1 − e^{−2γΔt}) (Eqs. 5.8–5.9); R = 2.5 m²: the
    Kalman variance (1 − L) P(k|k−1) with L = P / (P + R/N) (Eqs. 6.4, 6.11)."""
    scans = close_scans()
    f = make()
    assert f.model is MODEL and f.dt == 2.5 and f.R == 2.5
    f.step(scans[:, 0])
    f.step(scans[:, 1])
    a = np.exp(-0.005 * 2.5)
    q = 0.01 / (2 * 0.005) * (1 - np.exp(-2 * 0.005 * 2.5))
    P_pred = a * (2.5 / N_SENSORS) * a + q
    np.testing.assert_allclose(f.P_pred, P_pred, rtol=1e-12)
    first = scans[:, 0] if isinstance(f, IdealFilter) else np.sort(scans[:, 0], axis=-1)  # ideal: labelled
    np.testing.assert_allclose(f.predictions(), a * first.mean(axis=1), rtol=1e-12)
    if not isinstance(f, PDAFilter):  # the PDAF adds the spread of the innovations
        np.testing.assert_allclose(f.P, (1 - P_pred / (P_pred + 2.5 / N_SENSORS)) * P_pred, rtol=1e-12)


def test_single_run_scans_gain_a_run_axis_and_match_the_batch():
    scans = close_scans(n_runs=2)
    one, batch = ECMHTFilter(MODEL, 1.0, N_SENSORS, rng=4), ECMHTFilter(MODEL, 1.0, N_SENSORS, rng=4)
    for k in range(scans.shape[1]):
        est = one.step(scans[0, k])  # (N, 2): one run
        batch.step(scans[:1, k])
        assert est.shape == (1, 2)
        np.testing.assert_array_equal(est, batch.estimates())
    with pytest.raises(ValueError, match=r"^Z has 2 runs, the filter was initialised with 1$"):
        one.step(scans[:, 0])
    with pytest.raises(ValueError, match=r"^Z must have shape \(n_runs, 4, 2\) or \(4, 2\), got \(1, 4, 3\)"):
        one.step(np.zeros((4, 3)))


@pytest.mark.parametrize("cls", [IdealFilter, GNNFilter, PDAFilter])
def test_nothing_to_report_before_the_first_scan(cls):
    f = cls(MODEL, 1.0, N_SENSORS)
    assert f.x is None and f.P is None and f.x_pred is None and f.P_pred is None
    with pytest.raises(RuntimeError, match="^no scan processed yet$"):
        f.estimates()
    with pytest.raises(RuntimeError, match="^no scan processed yet$"):
        f.predictions()
    f.step(close_scans()[:, 0])
    assert np.isnan(f.predictions()).all() and np.isnan(f.P_pred).all()
    np.testing.assert_allclose(f.P, 1.0 / N_SENSORS)


def test_gnn_labels_follow_the_predicted_order():
    """Track 1 starts below track 0 (labelled ideal initialisation is not used by GNN: it sorts),
    then the lower predicted track takes the averaged smaller returns whatever its label."""
    f = GNNFilter(MODEL, 1.0, 2)
    f.step(np.array([[0.0, 1.0], [0.0, 1.0]]))
    np.testing.assert_allclose(f.x, [[0.0, 1.0]])
    f.x = f.x[:, ::-1].copy()  # relabel: track 0 is now the upper one
    f.step(np.array([[0.1, 0.9], [0.1, 0.9]]))
    assert f.x[0, 0] > f.x[0, 1]
    A = np.exp(-0.005)
    P = A * 0.5 * A + MODEL.Q(1.0)[0, 0]
    L = P / (P + 0.5)
    np.testing.assert_allclose(f.x[0], [A + L * (0.9 - A), L * 0.1], rtol=1e-12)


def test_pda_weights_are_normalised_per_run_without_underflow():
    """Run 1's returns lie ~60 σ from its prediction: its weights must not underflow against run 0's."""
    from hypotrack.trackers.ecmht import _pda_update

    x, P = np.array([0.0, 0.0]), np.array([1.0, 1.0])
    Zc = np.array([[0.1, -0.2], [85.0, 86.0]])
    x_new, P_new = _pda_update(x, P, Zc, 1.0)
    for r in range(2):
        want_x, want_P = mixture_update(x[r], P[r], Zc[r], 1.0)
        assert x_new[r] == pytest.approx(want_x, rel=1e-12) and P_new[r] == pytest.approx(want_P, rel=1e-9)


def test_mospa_shapes():
    from hypotrack.trackers.ecmht import mospa_two_targets

    e = np.zeros((3, 5, 2))
    t = np.ones((3, 5, 2))
    np.testing.assert_allclose(mospa_two_targets(e, t), np.ones((3, 5)))
    with pytest.raises(ValueError, match=r"^estimates and truth must have equal shapes \(\.\.\., 2\), got \(3, 2\) and \(4, 2\)"):
        mospa_two_targets(np.zeros((3, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="estimates and truth must have equal shapes"):
        mospa_two_targets(np.zeros((3, 3)), np.zeros((3, 3)))


def test_constructor_messages_name_the_argument():
    with pytest.raises(TypeError, match="^model must be an OrnsteinUhlenbeck, got str$"):
        GNNFilter("ou", 1.0, 3)
    with pytest.raises(ValueError, match=r"^n_sensors must be an integer in \[1, inf\], got 0$"):
        GNNFilter(MODEL, 1.0, 0)
    with pytest.raises(ValueError, match="^dt must be a finite number > 0, got 0.0$"):
        GNNFilter(MODEL, 1.0, 3, dt=0.0)
    with pytest.raises(ValueError, match=r"^rng must be given \(a numpy Generator or an int seed\): the ECMHT draws sensor orders$"):
        ECMHTFilter(MODEL, 1.0, 3)
    f = ECMHTFilter(MODEL, 1.0, 3, rng=0)
    assert f.last_swaps is None

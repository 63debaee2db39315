"""Chi-square gates and the validation matrix."""

import numpy as np
import pytest
from scipy.stats import norm

from hypotrack.association import gate_measurements, gate_threshold, validation_matrix


def test_threshold_closed_forms():
    # 2 degrees of freedom: P(χ²₂ ≤ γ) = 1 − exp(−γ/2)  ⇒  γ = −2 ln(1 − p).
    for p in (0.5, 0.9, 0.99, 0.999):
        assert gate_threshold(p, 2) == pytest.approx(-2 * np.log1p(-p), rel=1e-12)
    # 1 degree of freedom: χ²₁ = N(0,1)², so γ = Φ⁻¹((1 + p)/2)².
    for p in (0.6827, 0.9545, 0.99):
        assert gate_threshold(p, 1) == pytest.approx(norm.ppf((1 + p) / 2) ** 2, rel=1e-10)
    # The textbook table value for P_G = 0.99 in 2-D is 9.21.
    assert round(gate_threshold(0.99, 2), 2) == 9.21
    assert gate_threshold(1.0, 3) == np.inf


def test_gate_probability_monte_carlo():
    # Returns drawn from a track's predictive density fall in its gate with probability P_G.
    rng = np.random.default_rng(5)
    S = np.array([[4.0, 1.2], [1.2, 1.0]])
    z_pred = np.array([[10.0, -3.0]])
    Z = rng.multivariate_normal(z_pred[0], S, size=40_000)
    validation, _ = gate_measurements(Z, z_pred, S[None], 0.9)
    frac = validation.mean()
    sigma = np.sqrt(0.9 * 0.1 / len(Z))
    assert abs(frac - 0.9) < 4 * sigma


def test_gate_measurements_matches_direct_solve():
    rng = np.random.default_rng(6)
    n, m, p = 4, 7, 2
    z_pred = rng.normal(size=(n, p)) * 3
    A = rng.normal(size=(n, p, p))
    S = A @ np.swapaxes(A, 1, 2) + 0.5 * np.eye(p)
    Z = rng.normal(size=(m, p)) * 3
    validation, d2 = gate_measurements(Z, z_pred, S, 0.95)
    direct = np.array(
        [[(Z[i] - z_pred[j]) @ np.linalg.solve(S[j], Z[i] - z_pred[j]) for j in range(n)] for i in range(m)]
    )
    np.testing.assert_allclose(d2, direct, rtol=1e-10)
    np.testing.assert_array_equal(validation, direct <= gate_threshold(0.95, p))


def test_validation_matrix_boundary_and_infinity():
    d2 = np.array([[0.0, 9.0, np.inf], [9.0000001, 3.0, 1.0]])
    np.testing.assert_array_equal(validation_matrix(d2, 9.0), [[True, True, False], [False, True, True]])
    np.testing.assert_array_equal(validation_matrix(d2, np.inf), [[True, True, True], [True, True, True]])


def test_empty_scan_and_no_tracks():
    v, d2 = gate_measurements(np.zeros((0, 2)), np.zeros((3, 2)), np.broadcast_to(np.eye(2), (3, 2, 2)), 0.99)
    assert v.shape == (0, 3) and d2.shape == (0, 3)
    v, d2 = gate_measurements(np.ones((4, 2)), np.zeros((0, 2)), np.zeros((0, 2, 2)), 0.99)
    assert v.shape == (4, 0)
    assert validation_matrix(np.zeros((0, 0)), 1.0).shape == (0, 0)


@pytest.mark.parametrize("p_gate", [0.0, -0.1, 1.5, np.nan])
def test_bad_gate_probability(p_gate):
    with pytest.raises(ValueError, match="p_gate"):
        gate_threshold(p_gate, 2)


def test_bad_arguments():
    with pytest.raises(ValueError, match="dim"):
        gate_threshold(0.9, 0)
    with pytest.raises(ValueError, match="d2"):
        validation_matrix(np.array([[-1.0]]), 1.0)
    with pytest.raises(ValueError, match="d2"):
        validation_matrix(np.array([[np.nan]]), 1.0)
    with pytest.raises(ValueError, match="d2"):
        validation_matrix(np.ones(3), 1.0)
    for bad in (0.0, -2.0, np.nan):
        with pytest.raises(ValueError, match="threshold"):
            validation_matrix(np.ones((2, 2)), bad)
    S = np.eye(2)[None]
    with pytest.raises(ValueError, match="Z"):
        gate_measurements([[np.nan, 0.0]], [[0.0, 0.0]], S, 0.9)
    with pytest.raises(ValueError, match="Z"):
        gate_measurements([[1.0, 2.0, 3.0]], [[0.0, 0.0]], S, 0.9)
    with pytest.raises(ValueError, match="S"):
        gate_measurements([[1.0, 2.0]], [[0.0, 0.0]], -S, 0.9)
    with pytest.raises(ValueError, match="S"):
        gate_measurements([[1.0, 2.0]], [[0.0, 0.0]], np.stack([S[0], S[0]]), 0.9)
    with pytest.raises(ValueError, match="z_pred"):
        gate_measurements([[1.0, 2.0]], [0.0, 0.0], S, 0.9)
    with pytest.raises(ValueError, match="p_gate"):
        gate_measurements([[1.0, 2.0]], [[0.0, 0.0]], S, 0.0)


def test_messages_name_the_offending_argument():
    """Each bad argument is named at the start of the message, with the rule it breaks."""
    S = np.eye(2)[None]
    with pytest.raises(ValueError, match=r"^Z must have shape \(m, 2\), got \(1, 3\)$"):
        gate_measurements([[1.0, 2.0, 3.0]], [[0.0, 0.0]], S, 0.9)
    with pytest.raises(ValueError, match=r"^z_pred must be a 2-D array, got shape \(2,\)$"):
        gate_measurements([[1.0, 2.0]], [0.0, 0.0], S, 0.9)
    with pytest.raises(ValueError, match=r"^d2 must hold squared distances: >= 0 and not NaN$"):
        validation_matrix(np.array([[1.0, np.nan]]), 1.0)
    with pytest.raises(ValueError, match=r"^threshold must be a finite number > 0, got -2\.0$"):
        validation_matrix(np.ones((2, 2)), -2.0)


def test_innovation_covariance_of_another_dimension_is_refused():
    """A 3x3 innovation covariance for 2-D returns is a caller's mistake, caught before any distance."""
    with pytest.raises(ValueError, match=r"^S must be 2x2, got shape \(1, 3, 3\)$"):
        gate_measurements([[1.0, 2.0]], [[0.0, 0.0]], np.eye(3)[None], 0.9)


def test_exact_rational_distances_are_read_as_numbers():
    """d2 given as exact fractions (e.g. from a symbolic check) is compared as real numbers."""
    from fractions import Fraction

    d2 = [[Fraction(1, 2), Fraction(19, 2)], [Fraction(9), Fraction(0)]]
    np.testing.assert_array_equal(validation_matrix(d2, 9.0), [[True, False], [True, True]])


def test_dimension_message_names_dim_and_its_range():
    with pytest.raises(ValueError, match=r"^dim must be an integer in \[1, inf\], got 0$"):
        gate_threshold(0.9, 0)

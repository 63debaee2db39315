"""LinearMeasurement's small parts by hand (residual rows, view points, the log-determinant of a track seen by
no return) and the errors of bad models, each naming the parameter; :func:`as_measurement` takes a model only
when it has the whole surface."""

import numpy as np
import pytest

from hypotrack.models.measurement import ExtendedMeasurement, LinearMeasurement, as_measurement

H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
R = np.diag([0.25, 4.0])


def test_residual_rows_and_view_points_by_hand():
    m = LinearMeasurement(H, R)
    x = np.array([[1.0, 9.0, 2.0, 9.0], [-3.0, 9.0, 5.0, 9.0]])
    np.testing.assert_array_equal(m.residual_rows(np.array([[2.0, 2.5], [0.0, 0.0]]), m.predict(x)),
                                  [[1.0, 0.5], [3.0, -5.0]])
    np.testing.assert_array_equal(m.view_points(x), [[1.0, 2.0], [-3.0, 5.0]])
    given = np.array([[7.0, 7.0], [8.0, 8.0]])
    assert m.view_points(x, given) is given
    assert m.dim == 2 and m.ndim_state == 4


def test_bad_models_name_the_parameter():
    with pytest.raises(ValueError, match="H must be finite"):
        LinearMeasurement([[1.0, np.nan]], [[1.0]])
    with pytest.raises(ValueError, match="H must be a 2-D array"):
        LinearMeasurement(np.ones((1, 2, 2)), [[1.0]])
    with pytest.raises(ValueError, match="R must be 2x2"):
        LinearMeasurement(H, np.eye(3))
    with pytest.raises(ValueError, match="R must be positive definite"):
        LinearMeasurement(H, np.diag([1.0, -1.0]))


class _Only:
    def __init__(self, **attrs):
        self.__dict__.update(attrs)


def test_as_measurement_takes_a_model_only_with_the_whole_surface():
    f = _Only.__init__  # any callable stands for a method here
    # a model: innovation, update and residual
    full = _Only(innovation=f, update=f, residual=f)
    assert as_measurement(full) is full
    # part of the surface and H, R: the H, R are what is used
    for part in ({"residual": f}, {"innovation": f}, {"innovation": f, "update": f}):
        got = as_measurement(_Only(H=H, R=R, **part))
        assert isinstance(got, LinearMeasurement) and np.array_equal(got.H, H) and np.array_equal(got.R, R)
    for attrs in ({"H": H}, {"R": R}, {"residual": f}, {"innovation": f, "update": f}):
        with pytest.raises(TypeError, match="must have H and R, or be a measurement model, got _Only"):
            as_measurement(_Only(**attrs))


class _Lin(ExtendedMeasurement):
    def __init__(self, R):
        self.R = R

    def h(self, means):
        return means @ H.T

    def jacobian(self, means):
        return np.broadcast_to(H, (len(means), 2, 4)).copy()


def test_a_track_seen_by_no_return_keeps_its_log_determinant():
    m = _Lin(R)
    S = np.array([[[4.0, 1.0], [1.0, 2.0]]])
    d2, logdet = m.mahalanobis2(np.zeros((0, 2)), np.zeros((1, 2)), S)
    assert d2.shape == (0, 1)
    assert logdet[0] == pytest.approx(np.log(7.0), rel=1e-14)
    d2, logdet = m.mahalanobis2(np.array([[2.0, 1.0]]), np.zeros((1, 2)), S)
    assert d2[0, 0] == pytest.approx(np.array([2.0, 1.0]) @ np.linalg.solve(S[0], [2.0, 1.0]), rel=1e-13)
    assert logdet[0] == pytest.approx(np.log(7.0), rel=1e-14)

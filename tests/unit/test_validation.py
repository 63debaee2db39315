"""Bad scans and seeds are refused with a message that names the parameter, not NumPy's own."""

import pickle

import numpy as np
import pytest

from hypotrack._validation import check_measurements, check_seed
from hypotrack.hypotheses import hfisst
from hypotrack.models import ConstantVelocity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor


@pytest.mark.parametrize("Z", [["a", "b"], [[1.0, 2.0], [3.0]], [[1.0, "x"]], [["1", "2"]],
                               np.array([["1", "2"]]), "1 2"])
def test_strings_and_ragged_rows_name_the_scan(Z):
    with pytest.raises(TypeError, match="Z must"):
        check_measurements(Z, "Z", 2)


def test_numeric_scans_pass_unchanged():
    Z = [[1.0, 2.0], [3, 4]]
    np.testing.assert_array_equal(check_measurements(Z, "Z", 2), np.array(Z, dtype=float))
    assert check_measurements([], "Z", 2).shape == (0, 2)


@pytest.mark.parametrize("seed, err", [("abc", TypeError), (1.5, TypeError), (-1, ValueError), (True, TypeError)])
def test_bad_seeds_name_the_seed(seed, err):
    with pytest.raises(err, match="seed must"):
        check_seed(seed)


@pytest.mark.parametrize("seed", [None, 0, 7, np.int64(3), [1, 2], np.random.SeedSequence(1),
                                  np.random.default_rng(1), np.random.PCG64(2)])
def test_valid_seeds_pass_unchanged(seed):
    assert check_seed(seed) is seed


def _tracker(**kw):
    region = Box([-50.0, -50.0], [50.0, 50.0])
    sensor = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4), DetectionModel(p_D=0.9, fov=region),
                    PoissonClutter(rate=1.0, region=region))
    return hfisst(ConstantVelocity(q=0.1), sensor, dt=1.0, max_hypotheses=10, **kw)


def test_a_filter_refuses_a_string_seed_and_a_string_scan_without_changing():
    with pytest.raises(TypeError, match="seed must"):
        _tracker(seed="abc")
    t = _tracker(seed=1)
    t.initialise(means=[[0.0, 0.0, 0.0, 0.0]], covs=np.eye(4)[None])
    before = pickle.dumps((t.hypotheses, t.rng.bit_generator.state))
    with pytest.raises(TypeError, match="Z must"):
        t.step([[0.0, "x"]])
    with pytest.raises(TypeError, match="Z must"):
        t.step([[0.0, 1.0], [2.0]])
    assert pickle.dumps((t.hypotheses, t.rng.bit_generator.state)) == before

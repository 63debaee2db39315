"""A birth term's measurement noise is checked once per distinct ``R``
(:func:`~hypotrack.hypotheses.population_lmb._checked_noise`): the array ``check_covariance`` returns, bit for bit,
and the same error for a bad one, every time."""

import numpy as np
import pytest

from hypotrack._validation import check_covariance
from hypotrack.hypotheses import population_lmb
from hypotrack.hypotheses.population_lmb import GaussianBirthTerm, _checked_noise


class _Meas:
    linear = False

    def __init__(self, R):
        self.R = R


def test_the_remembered_noise_is_the_check_bit_for_bit_and_a_copy():
    R = np.array([[1e-3, 2e-9], [2.000000001e-9, 1e-6]])  # asymmetric by rounding: the check symmetrises it
    ref = check_covariance(R, "measurement.R")
    a, b = _checked_noise(R), _checked_noise(R.copy())
    assert a.tobytes() == ref.tobytes() and b.tobytes() == ref.tobytes()
    assert a[0, 1] == 0.5 * (2e-9 + 2.000000001e-9)
    a[0, 0] = 7.0  # a copy each time: changing one leaves the next
    assert _checked_noise(R)[0, 0] == 1e-3


@pytest.mark.parametrize("R, message", [(np.diag([1.0, -1.0]), "positive definite"),
                                        (np.array([[1.0, 0.5], [0.0, 1.0]]), "symmetric"),
                                        (np.diag([1.0, np.nan]), "finite")])
def test_a_bad_noise_raises_each_time_as_the_check_does(R, message):
    for _ in range(2):
        with pytest.raises(ValueError, match=message):
            check_covariance(R, "measurement.R")
        with pytest.raises(ValueError, match=f"measurement.R must .*{message}"):
            _checked_noise(R)
    assert not any(k[2] == np.asarray(R).tobytes() for k in population_lmb._CHECKED_NOISE)


def test_birth_terms_hold_the_checked_noise():
    R = np.diag([1e-3, 1e-6])
    terms = GaussianBirthTerm.many(np.zeros((3, 4)), np.broadcast_to(np.eye(4), (3, 4, 4)).copy(), None, None, 0.99,
                                   _Meas(R))
    assert all(t.R.tobytes() == check_covariance(R, "R").tobytes() for t in terms)
    single = GaussianBirthTerm(np.zeros(4), np.eye(4), None, None, 0.99, _Meas(R))
    assert single.R.tobytes() == R.tobytes()

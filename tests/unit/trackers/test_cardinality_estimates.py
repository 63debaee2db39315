"""The counts-only negative controls and helpers, by hand: the data-free estimate λ_b/p_χ, the per-scan moment
estimate max(0, (r − λ_fa)/p_d) (clipped at zero below λ_fa), the live count Σ (b − χ) as exact integers, and an
empty count sequence solved to empty integer counts."""

import numpy as np
import pytest

from hypotrack.trackers.cardinality import (CountModel, alive_from_counts, constant_count_estimate, exact_count_dp,
                                            per_scan_count_estimate)

MODEL = CountModel(0.5, 0.25, 1.5, 1.0)  # p_d, p_chi, lambda_b, lambda_fa


def test_constant_estimate_is_the_steady_state_population():
    np.testing.assert_array_equal(constant_count_estimate(3, MODEL), [6.0, 6.0, 6.0])  # 1.5 / 0.25
    assert constant_count_estimate(0, MODEL).shape == (0,)
    with pytest.raises(ValueError, match=r"^n_scans must be an integer in \[0, inf\], got -1$"):
        constant_count_estimate(-1, MODEL)


def test_per_scan_estimate_by_hand():
    # (r − 1)/0.5, clipped at 0: r = 0 → −2 → 0; r = 1 → 0; r = 3 → 4; r = 7 → 12
    np.testing.assert_array_equal(per_scan_count_estimate([0, 1, 3, 7], MODEL), [0.0, 0.0, 4.0, 12.0])


def test_alive_counts_are_exact_integers():
    n = alive_from_counts([0.0, 1.0, 1.0, 0.0], [2.0, 1.0, 0.0, 3.0])  # counts held as floats
    assert n.dtype == np.int64
    assert n.tolist() == [2, 2, 1, 4]


def test_no_scans_give_empty_integer_counts():
    sol = exact_count_dp([], MODEL)
    assert sol.J == 0.0
    for name in ("chi", "d", "b", "f", "n"):
        a = getattr(sol, name)
        assert a.shape == (0,) and a.dtype == np.int64, name

"""Property tests: OSPA and GOSPA (α = 2) are metrics bounded as their definitions say."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hypotrack.metrics import gospa, ospa

coords = st.floats(-20, 20, allow_nan=False, allow_infinity=False)
point_sets = st.lists(st.tuples(coords, coords), min_size=0, max_size=4).map(
    lambda pts: np.array(pts, float).reshape(-1, 2)
)
orders = st.sampled_from([1.0, 2.0, 3.5, np.inf])
cutoffs = st.floats(0.1, 30)


@settings(max_examples=200, deadline=None)
@given(point_sets, point_sets, point_sets, cutoffs, orders)
def test_ospa_is_a_bounded_metric(X, Y, Z, c, p):
    d_xy = ospa(X, Y, c, p)
    assert 0 <= d_xy <= c * (1 + 1e-12)
    assert d_xy == ospa(Y, X, c, p) or np.isclose(d_xy, ospa(Y, X, c, p), rtol=1e-12)
    assert ospa(X, X, c, p) == 0.0
    assert d_xy <= ospa(X, Z, c, p) + ospa(Z, Y, c, p) + 1e-9


@settings(max_examples=200, deadline=None)
@given(point_sets, point_sets, point_sets, cutoffs, orders)
def test_gospa_is_a_metric_with_consistent_parts(X, Y, Z, c, p):
    r = gospa(X, Y, c, p)
    assert np.isclose(r.value, gospa(Y, X, c, p).value, rtol=1e-12, atol=1e-12)
    assert gospa(X, X, c, p).value == 0.0
    assert r.value <= gospa(X, Z, c, p).value + gospa(Z, Y, c, p).value + 1e-9
    assert r.n_false == len(X) - len(r.assignment) and r.n_missed == len(Y) - len(r.assignment)
    if np.isfinite(p):
        assert np.isclose(r.localisation + r.missed + r.false, r.value**p, rtol=1e-9)

"""The operator's scorecard on a tiny constructed case, every number by hand.

Three objects A = 1, B = 2, C = 3 on the x axis at 0, 10 and 100 km; five estimates: 10 on A, 20 on B,
30 on C, 40 a duplicate of C, 50 false (far from everything). Returns: A's at 0.05 km (correlates to 10,
owned by A: correct), B's at 1.5 km (nearest estimate 10 at 1.4 km, owned by A: a cross-tag), C's at
(100.35, 0.35) (nearest 40 at 0.07 km, owned by nobody: an orphan), C's at 105 km (no estimate within 2 km:
uncorrelated), and a clutter return (left out).
"""

import numpy as np
import pytest

from hypotrack.metrics import gospa
from hypotrack.metrics_scorecard import (CHI2_95_3D, CROSS_TAG_CAUSES, chi2_share, correlate_returns, cross_tag_causes,
                                         gospa_parts_per_object, id_switches,
                                         label_owners, mahalanobis2, mean_se, per, purity_counts, return_tallies,
                                         ric_error, time_to_orbit, within)

TRUTH = np.array([[0.0, 0, 0], [10.0, 0, 0], [100.0, 0, 0]])
EST_LAB = np.array([10, 20, 30, 40, 50])
EST = np.array([[0.1, 0, 0], [10.2, 0, 0], [100.5, 0, 0], [100.3, 0.4, 0], [500.0, 0, 0]])
RET = np.array([[0.05, 0, 0], [1.5, 0, 0], [100.35, 0.35, 0], [105.0, 0, 0], [300.0, 0, 0]])
ORIGIN = np.array([1, 2, 3, 3, -1])


def test_correlation_and_tallies():
    cor = correlate_returns(RET, EST_LAB, EST, gate_km=2.0)
    assert cor.tolist() == [10, 10, 40, -1, -1]
    # owners: 10 assigned to A three times and to B once; 20 to B twice; 30 to C; 40 never
    owners = label_owners([1, 1, 1, 2, 2, 2, 3], [10, 10, 10, 10, 20, 20, 30])
    assert owners == {10: 1, 20: 2, 30: 3}
    t = return_tallies(ORIGIN, cor, owners)
    assert t == dict(n_returns=4, correct=1, cross_tags=1, orphan=1, uncorrelated=1)
    assert per(t["cross_tags"], t["n_returns"], 1e4) == 2500.0
    assert np.isnan(per(0, 0, 1e4))


def test_owner_ties_and_unassigned():
    # label 60 once each to targets 5 and 4: the smaller id owns it; -1 labels ignored
    assert label_owners([5, 4, 7], [60, 60, -1]) == {60: 4}
    assert label_owners([], []) == {}
    with pytest.raises(ValueError, match="same length"):
        label_owners([1], [1, 2])


def test_purity_by_hand():
    # 10-A, 20-B and one of 30/40 on C are assigned; the other of 30/40 is a duplicate, 50 is false
    assert purity_counts(TRUTH, EST, 20.0) == dict(n_estimates=5, false=1, duplicate=1)
    assert purity_counts(TRUTH, EST[:0], 20.0) == dict(n_estimates=0, false=0, duplicate=0)
    assert purity_counts(TRUTH[:0], EST, 20.0) == dict(n_estimates=5, false=5, duplicate=0)
    assert per(1, 5, 1e3) == 200.0


def test_gospa_per_object_by_hand():
    # localisation 0.1 + 0.2 + 0.5 (C to 30 or to 40: both 0.5 km); two unassigned estimates, c / alpha = 10 each
    g = gospa(EST, TRUTH, c=20.0, p=1.0)
    assert (g.localisation, g.missed, g.false) == pytest.approx((0.8, 0.0, 20.0))
    out = gospa_parts_per_object([g.localisation], [g.missed], [g.false], [3])
    assert out["gospa_per_object_km"] == pytest.approx(20.8 / 3)
    assert out["gospa_false_per_object_km"] == pytest.approx(20.0 / 3)
    assert out["gospa_localisation_per_object_km"] == pytest.approx(0.8 / 3)


def test_ric_by_hand():
    # equatorial prograde: R = x, C = z, I = y
    x = np.array([[7000.0, 0, 0, 0, 7.5, 0], [0, 7000.0, 0, 0, 0, 7.5]])
    est = np.array([[7001.0, 2, -3], [1.0, 7000, 2]])
    # second: R = y, C = r x v = +x, I = C x R = z: error (1, 0, 2) -> (0, 2, 1)
    assert ric_error(x, est) == pytest.approx(np.array([[1.0, 2, -3], [0.0, 2, 1]]))


def test_mahalanobis_and_realism():
    assert mahalanobis2(np.array([[1.0, 2, 0]]), np.diag([1.0, 4, 9])[None]) == pytest.approx([2.0])
    assert CHI2_95_3D == pytest.approx(7.8147, abs=1e-4)
    assert chi2_share([1.0, 7.8, 7.9, 20.0]) == 0.5
    assert np.isnan(chi2_share([]))
    with pytest.raises(ValueError, match="must match"):
        mahalanobis2(np.zeros((2, 3)), np.zeros((2, 2, 2)))


def test_within_and_mean_se():
    assert within([[0.0, 0, 0], [0, 6, 0]], [[3.0, 4, 0], [0, 0, 0]], 5.0).tolist() == [True, False]
    m, se = mean_se([1.0, 2, 3, 4])
    assert (m, se) == pytest.approx((2.5, 1.2909944 / 2))
    assert np.isnan(mean_se([3.0])[1])
    with pytest.raises(ValueError, match="radius_km"):
        within([[0.0, 0, 0]], [[0.0, 0, 0]], 0.0)
    with pytest.raises(ValueError, match="gate_km"):
        correlate_returns(RET, EST_LAB, EST, gate_km=-1.0)


# Four catalogued objects 1-4 over five scans (scan, target, label; -1 none): labels 1 and 2 swap at scan 2,
# object 3 is missed at scan 2 and then held by a newborn label 50, and at scan 4 object 4 is held by label 3.
ASSIGN = np.array([(0, 1, 1), (0, 2, 2), (0, 3, 3), (0, 4, 4),
                   (1, 1, 1), (1, 2, 2), (1, 3, 3), (1, 4, 4),
                   (2, 1, 2), (2, 2, 1), (2, 3, -1), (2, 4, 4),
                   (3, 1, 2), (3, 2, 1), (3, 3, 50), (3, 4, 4),
                   (4, 1, 2), (4, 2, 1), (4, 3, 50), (4, 4, 3)])
# returns (scan, origin, correlated label); origin -1 clutter, label -1 uncorrelated
RETURNS = np.array([(0, 1, 1), (1, 2, 2), (2, 1, 2), (2, 3, 1), (4, 4, 3), (3, 3, 50), (4, 2, 50), (1, -1, 4),
                    (3, 4, -1)])


def test_id_switches_by_hand():
    s, t, lab = ASSIGN.T
    # per object: 1: 1,1,2,2,2 (one switch); 2: 2,2,1,1,1 (one); 3: 3,3,-,50,50 (one: the gap is skipped);
    # 4: 4,4,4,4,3 (one)
    assert id_switches(s, t, lab) == 4
    perm = np.random.default_rng(0).permutation(len(s))  # the order of the rows does not matter
    assert id_switches(s[perm], t[perm], lab[perm]) == 4
    assert id_switches([], [], []) == 0
    with pytest.raises(ValueError, match="same length"):
        id_switches([0], [1, 2], [1])


def test_cross_tag_causes_by_hand():
    s, t, lab = ASSIGN.T
    owners = label_owners(t, lab)
    # label 1: object 1 twice, object 2 three times; label 2 the reverse; label 3: object 3 twice, 4 once
    assert owners == {1: 2, 2: 1, 3: 3, 4: 4, 50: 3}
    rs, ro, rc = RETURNS.T
    # cross-tags: (0,1,1) and (1,2,2) own labels on their own objects; (2,3,1) label 1 is on object 2 then;
    # (4,4,3) label 3 carried onto object 4; (4,2,50) a newborn label owned by object 3
    assert return_tallies(ro, rc, owners) == dict(n_returns=8, correct=2, cross_tags=5, orphan=0, uncorrelated=1)
    causes = cross_tag_causes(rs, ro, rc, owners, s, t, lab, catalogued=[1, 2, 3, 4])
    assert causes == dict(newborn=1, own_label=2, carried_label=1, elsewhere=1)
    assert tuple(causes) == CROSS_TAG_CAUSES
    # label 50 counted as catalogued: then it is on object 3, not on the return's origin 2, at scan 4
    assert cross_tag_causes(rs, ro, rc, owners, s, t, lab, catalogued=[1, 2, 3, 4, 50])["elsewhere"] == 2
    with pytest.raises(ValueError, match="same length"):
        cross_tag_causes([0], [1], [1, 2], owners, s, t, lab, [1])


def test_time_to_orbit_by_hand():
    # Object 7: first detected at 30 s (detections at 50, 30, 40 out of order); its passes end at 20 s
    # (re-acquires, but before the first detection: a catalogued track's, not the detected object's orbit),
    # 100 s (misses) and 700 s (re-acquires) -> 700 - 30 = 670 s. Object 8: first detected at 200 s, passes
    # ending at 900 (ok) and 400 (ok; the earlier one counts) -> 200 s. Object 9: detected, never re-acquired;
    # object 11: a good pass but never detected -> both left out.
    objs, secs = time_to_orbit([7, 7, 8, 7, 9, 8], [50.0, 30.0, 200.0, 40.0, 60.0, 210.0],
                               [7, 7, 7, 8, 8, 9, 11], [20.0, 100.0, 700.0, 900.0, 400.0, 300.0, 50.0],
                               [True, False, True, True, True, False, True])
    assert objs.tolist() == [7, 8]
    assert secs.tolist() == [670.0, 200.0]
    # a pass ending at the detection itself counts (0 s), and nothing detected gives nothing
    assert time_to_orbit([3], [10.0], [3], [10.0], [True])[1].tolist() == [0.0]
    o, s = time_to_orbit([], [], [1], [5.0], [True])
    assert len(o) == 0 and len(s) == 0


def test_time_to_orbit_bad_input():
    with pytest.raises(ValueError, match="det_target and det_time"):
        time_to_orbit([1, 2], [0.0], [], [], [])
    with pytest.raises(ValueError, match="pass_target, pass_end and pass_ok"):
        time_to_orbit([1], [0.0], [1], [5.0, 6.0], [True])
    with pytest.raises(ValueError, match="finite"):
        time_to_orbit([1], [np.nan], [1], [5.0], [True])

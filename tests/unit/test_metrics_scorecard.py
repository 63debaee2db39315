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
from hypotrack.metrics_scorecard import (CHI2_95_3D, CROSS_TAG_CAUSES, catalogue_owners, chi2_share, correlate_returns,
                                         cross_tag_causes,
                                         gospa_parts_per_object, id_switches,
                                         label_owners, mahalanobis2, mean_se, per, purity_counts, return_tallies,
                                         ric_error, ric_frame, time_to_orbit, within)

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


def test_a_swap_kept_for_good_is_correct_by_purity_and_cross_tags_by_the_catalogue():
    """Catalogued objects 7 and 8 swapped at their first return and never swapped back (object 7's returns on entry
    8, object 8's on entry 7), object 9 kept its own, a newborn label 100 carried object 9's last return: purity
    owns 7 by 8 and 8 by 7 (no cross-tag); the catalogue owns each entry by its own object, so the six swapped
    returns are cross-tags, while the newborn label keeps its purity owner (9: correct)."""
    origin = [7, 7, 7, 8, 8, 8, 9, 9]
    label = [8, 8, 8, 7, 7, 7, 9, 100]
    owners = label_owners(origin, label)
    assert owners == {7: 8, 8: 7, 9: 9, 100: 9}
    assert return_tallies(origin, label, owners)["cross_tags"] == 0
    cat = catalogue_owners(owners, [7, 8, 9])
    assert cat == {7: 7, 8: 8, 9: 9, 100: 9}
    assert return_tallies(origin, label, cat) == dict(n_returns=8, correct=2, cross_tags=6, orphan=0, uncorrelated=0)
    assert catalogue_owners(owners, []) == owners
    with pytest.raises(ValueError, match="catalogued"):
        catalogue_owners(owners, [7.5])


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


# --- cases where a near-miss of the definitions gives another number (ids 0, ties at the bounds, one element) ---

def test_correlation_edges_by_hand():
    # a return exactly on the gate (3-4-5 triangle: 5.0 km) is correlated; 5.0 + 1e-9 is not
    assert correlate_returns([[3.0, 4, 0]], [7], [[0.0, 0, 0]], 5.0).tolist() == [7]
    assert correlate_returns([[3.0, 4, 0]], [7], [[0.0, 0, 0]], 5.0 - 1e-9).tolist() == [-1]
    # one return, one estimate, label 0: a real label, returned as is
    assert correlate_returns([[1.0, 0, 0]], [0], [[0.0, 0, 0]], 2.0).tolist() == [0]
    # returns but no estimates: every return uncorrelated; no returns: nothing
    assert correlate_returns(RET, [], np.zeros((0, 3)), 2.0).tolist() == [-1] * 5
    assert correlate_returns(np.zeros((0, 3)), EST_LAB, EST, 2.0).tolist() == []
    # labels beyond 2^53 come back exactly (a float round trip would turn 2^60 + 1 into 2^60)
    big = 2**60 + 1
    assert correlate_returns([[0.0, 0, 0]], [big], [[0.0, 0, 0]], 1.0).tolist() == [big]


def test_owner_of_label_zero_and_object_zero():
    # label 0 held by object 0 once (one row only), label 1 by objects 0 and 2 twice each: the smaller id 0
    assert label_owners([0], [0]) == {0: 0}
    assert label_owners([0, 2, 2, 0], [1, 1, 1, 1]) == {1: 0}
    # object 0's return on label 0 (owned by 0) is correct; object 1's on label 0 a cross-tag; object 1's on
    # label 5 (owned by nobody) an orphan; object 0's uncorrelated; a clutter return (-1) left out
    t = return_tallies([0, 1, 1, 0, -1], [0, 0, 5, -1, 0], {0: 0, 3: 1})
    assert t == dict(n_returns=4, correct=1, cross_tags=1, orphan=1, uncorrelated=1)
    # object 2's return on label 3, owned by object 0: a cross-tag, not an orphan
    assert return_tallies([2], [3], {3: 0}) == dict(n_returns=1, correct=0, cross_tags=1, orphan=0, uncorrelated=0)
    assert return_tallies([], [], {}) == dict(n_returns=0, correct=0, cross_tags=0, orphan=0, uncorrelated=0)
    assert return_tallies([-1, -1], [3, -1], {3: 0}) == dict(n_returns=0, correct=0, cross_tags=0, orphan=0,
                                                             uncorrelated=0)


def test_id_switch_counts_label_zero():
    # object 0 held by labels 0, 0, 1, 0 over scans 0-3: two switches (0 -> 1 -> 0); label 0 is a label
    assert id_switches([0, 1, 2, 3], [0, 0, 0, 0], [0, 0, 1, 0]) == 2
    # the same as float scans and ids of whole value, and as (n, 1) columns
    assert id_switches([0.0, 1.0, 2.0, 3.0], [0.0] * 4, [0.0, 0.0, 1.0, 0.0]) == 2
    assert id_switches(np.array([[0], [1], [2], [3]]), np.zeros((4, 1)), np.array([[0], [0], [1], [0]])) == 2


def test_cross_tag_causes_ids_zero_and_repeats():
    # objects 0 and 1, catalogued labels 0 and 1; label 0 owned by object 1 (held by it at scans 1-3), label 1
    # by object 0; labels 7 and 8 newborn, owned by object 1 and object 0.
    owners = {0: 1, 1: 0, 7: 1, 8: 0}
    assign = np.array([(0, 0, 0), (1, 1, 0), (1, 0, 1), (2, 1, 0), (3, 1, 0)])
    s, t, lab = assign.T
    # returns (scan, origin, label): object 0 on label 0 at scan 0 (assigned to it then: own label);
    # object 0 on label 7 twice (newborn, two cross-tags); object 1 on label 8 (newborn); object 0 on label 5,
    # owned by nobody (an orphan, no cross-tag); object 0 on label 0 at scan 2 (then on object 1: elsewhere)
    rs = [0, 1, 2, 3, 1, 2]
    ro = [0, 0, 0, 1, 0, 0]
    rc = [0, 7, 7, 8, 5, 0]
    causes = cross_tag_causes(rs, ro, rc, owners, s, t, lab, catalogued=[0, 1])
    assert causes == dict(newborn=3, own_label=1, carried_label=0, elsewhere=1)
    assert sum(causes.values()) == return_tallies(ro, rc, owners)["cross_tags"] == 5
    # with label 0 also assigned to object 0 at scan 2, the last return is on its origin's own catalogued
    # label, assigned to it at that scan: a second own_label (elsewhere drops to 0)
    assign2 = np.vstack([assign, [(2, 0, 0)]])
    s2, t2, lab2 = assign2.T
    assert cross_tag_causes(rs, ro, rc, owners, s2, t2, lab2, catalogued=[0, 1]) == dict(
        newborn=3, own_label=2, carried_label=0, elsewhere=0)
    # object 1's return on label 1 (owned by object 0) at scan 1, where label 1 is on object 0: elsewhere; with
    # label 1 on object 1 at scan 1 instead, the right association of object 1's own label: own_label
    assert cross_tag_causes([1], [1], [1], owners, s, t, lab, [0, 1])["elsewhere"] == 1
    assert cross_tag_causes([1], [1], [1], owners, [1], [1], [1], [0, 1])["own_label"] == 1
    # nothing given: nothing counted
    assert cross_tag_causes([], [], [], {}, [], [], [], []) == dict.fromkeys(CROSS_TAG_CAUSES, 0)


def test_fractional_or_missing_ids_are_refused_by_name():
    # 2.5 would be cast to object 2 and NaN to an arbitrary integer: each entry point names the argument
    bad = [1, 2.5]
    cases = [
        ("est_labels", lambda: correlate_returns([[0.0, 0, 0]] * 2, bad, [[0.0, 0, 0]] * 2, 1.0)),
        ("targets", lambda: label_owners(bad, [1, 2])),
        ("labels", lambda: label_owners([1, 2], bad)),
        ("origin", lambda: return_tallies(bad, [1, 2], {})),
        ("correlated", lambda: return_tallies([1, 2], bad, {})),
        ("scans", lambda: id_switches(bad, [1, 2], [1, 2])),
        ("targets", lambda: id_switches([1, 2], bad, [1, 2])),
        ("labels", lambda: id_switches([1, 2], [1, 2], bad)),
        ("scan", lambda: cross_tag_causes(bad, [1, 2], [1, 2], {}, [], [], [], [])),
        ("origin", lambda: cross_tag_causes([1, 2], bad, [1, 2], {}, [], [], [], [])),
        ("correlated", lambda: cross_tag_causes([1, 2], [1, 2], bad, {}, [], [], [], [])),
        ("assign_scans", lambda: cross_tag_causes([], [], [], {}, bad, [1, 2], [1, 2], [])),
        ("assign_targets", lambda: cross_tag_causes([], [], [], {}, [1, 2], bad, [1, 2], [])),
        ("assign_labels", lambda: cross_tag_causes([], [], [], {}, [1, 2], [1, 2], bad, [])),
        ("catalogued", lambda: cross_tag_causes([], [], [], {}, [], [], [], bad)),
        ("det_target", lambda: time_to_orbit(bad, [0.0, 1.0], [], [], [])),
        ("pass_target", lambda: time_to_orbit([], [], bad, [0.0, 1.0], [True, True])),
    ]
    for name, call in cases:
        with pytest.raises(ValueError, match=rf"^{name} must be integer ids, got \[1(\.0)?, 2\.5\]$"):
            call()
    for v in (np.nan, np.inf):
        with pytest.raises(ValueError, match=r"^labels must be integer ids"):
            label_owners([1, 2], [1, v])
    # object columns of ints (a pandas column), beyond 2^53 too, and empty columns of any dtype are ids
    big = 2**60 + 1
    assert label_owners(np.array([3, big], dtype=object), np.array([big, 4], dtype=object)) == {big: 3, 4: big}
    assert label_owners(np.array([], dtype=object), np.array([], dtype=object)) == {}
    assert time_to_orbit(np.array([], dtype=object), [], np.array([], dtype=object), [], [])[0].tolist() == []
    for bad_kind in (["a"], [True], np.array([None], dtype=object)):  # strings, booleans, None are not ids
        with pytest.raises(ValueError, match=r"^labels must be integer ids"):
            label_owners([1], bad_kind)
    # whole-valued floats are ids: the same owners as the integers
    assert label_owners([1.0, 1.0, 2.0], [10.0, 10.0, 20.0]) == {10: 1, 20: 2}
    # unsigned ids and single-precision whole values are ids too
    assert label_owners(np.array([3], np.uint8), np.array([4], np.uint8)) == {4: 3}
    assert label_owners(np.array([3.0], np.float32), np.array([4.0], np.float32)) == {4: 3}


def test_shape_and_length_errors_name_the_arguments():
    with pytest.raises(ValueError, match=r"^est_labels must have one label per estimate \(2\), got 1$"):
        correlate_returns([[0.0, 0, 0]], [1], [[0.0, 0, 0]] * 2, 1.0)
    with pytest.raises(ValueError, match=r"^origin and correlated must have the same length, got 1 and 2$"):
        return_tallies([1], [1, 2], {})
    for name, call in [("returns", lambda: correlate_returns([[np.nan, 0, 0]], [1], [[0.0, 0, 0]], 1.0)),
                       ("est_pos", lambda: correlate_returns([[0.0, 0, 0]], [1], [[np.inf, 0, 0]], 1.0)),
                       ("truth_pos", lambda: purity_counts([[np.nan, 0, 0]], [[0.0, 0, 0]], 1.0)),
                       ("est_pos", lambda: purity_counts([[0.0, 0, 0]], [[np.nan, 0, 0]], 1.0)),
                       ("pred_pos", lambda: within([[np.nan, 0, 0]], [[0.0, 0, 0]])),
                       ("true_pos", lambda: within([[0.0, 0, 0]], [[np.nan, 0, 0]]))]:
        with pytest.raises(ValueError, match=rf"^{name} must be finite positions \(n, 3\)$"):
            call()
    for name, call in [("gate_km", lambda: correlate_returns(RET, EST_LAB, EST, 0.0)),
                       ("cutoff_km", lambda: purity_counts(TRUTH, EST, -1.0)),
                       ("radius_km", lambda: within([[0.0, 0, 0]], [[0.0, 0, 0]], -2.0))]:
        with pytest.raises(ValueError, match=rf"^{name} must be a finite number > 0"):
            call()
    with pytest.raises(ValueError, match=r"^prob must lie in \[0, 1\]"):
        chi2_share([1.0], prob=1.5)
    with pytest.raises(ValueError, match=r"^det_time and pass_end must be finite times \(s\)$"):
        time_to_orbit([1], [0.0], [1], [np.inf], [True])


def test_purity_edges_by_hand():
    # one estimate 5 km from the only truth (3-4-5) with cut-off 5: not within c (strictly closer is
    # assigned), so false; with cut-off 5.0001 it is assigned
    assert purity_counts([[0.0, 0, 0]], [[3.0, 4, 0]], 5.0) == dict(n_estimates=1, false=1, duplicate=0)
    assert purity_counts([[0.0, 0, 0]], [[3.0, 4, 0]], 5.0001) == dict(n_estimates=1, false=0, duplicate=0)
    # two estimates on one truth, the second exactly at c: false, not a duplicate; at 4.9 km a duplicate
    assert purity_counts([[0.0, 0, 0]], [[0.1, 0, 0], [3.0, 4, 0]], 5.0) == dict(n_estimates=2, false=1,
                                                                                duplicate=0)
    assert purity_counts([[0.0, 0, 0]], [[0.1, 0, 0], [4.9, 0, 0]], 5.0) == dict(n_estimates=2, false=0,
                                                                                duplicate=1)
    # two far estimates and one duplicate: false 2, duplicate 1 (the counts are not interchangeable)
    assert purity_counts([[0.0, 0, 0]], [[0.0, 0, 0], [1.0, 0, 0], [50.0, 0, 0], [-50.0, 0, 0]], 5.0) == dict(
        n_estimates=4, false=2, duplicate=1)


def test_ric_frame_with_radial_velocity_and_integer_states():
    # r = (3, 0, 0), v = (4, 5, 0): R = x (r alone, not the first four components), C = r x v = (0, 0, 15) -> z,
    # I = C x R = y; integer states are accepted
    F = ric_frame([[3, 0, 0, 4, 5, 0]])
    assert F[0] == pytest.approx(np.eye(3))
    # full six-component estimates: only the position is compared, error (1, 2, -3) in RIC = (1, 2, -3)
    assert ric_error([[3, 0, 0, 4, 5, 0]], [[4.0, 2, -3, 9, 9, 9]]) == pytest.approx(np.array([[1.0, 2, -3]]))


def test_mahalanobis_symmetric_part_and_empty():
    # P = [[2, 1], [0, 2]] read as its symmetric part S = [[2, .5], [.5, 2]]: det 3.75,
    # S^-1 = [[2, -.5], [-.5, 2]] / 3.75, e = (1, 1): (2 - .5 - .5 + 2) / 3.75 = 0.8
    assert mahalanobis2([[1.0, 1.0]], [[[2.0, 1.0], [0.0, 2.0]]]) == pytest.approx([0.8])
    out = mahalanobis2(np.zeros((0, 3)), np.zeros((0, 3, 3)))
    assert out.shape == (0,)


def test_chi2_share_bound_and_single_values():
    # d2 exactly on the bound counts as inside; one value: share 1 or 0; a scalar is one value
    assert chi2_share([CHI2_95_3D]) == 1.0
    assert chi2_share([CHI2_95_3D + 1e-9]) == 0.0
    assert chi2_share([3.0]) == 1.0
    assert chi2_share(3.0) == 1.0
    # 2-D bound: chi2_2(0.5) = 2 ln 2 = 1.386: one of (1.0, 2.0) inside
    assert chi2_share([1.0, 2.0], prob=0.5, dim=2) == 0.5


def test_within_default_radius_and_offset_positions():
    # the default radius is 5 km: 4.9 km within, 5.1 km not
    assert within([[0.0, 0, 0], [0.0, 0, 0]], [[4.9, 0, 0], [0, 5.1, 0]]).tolist() == [True, False]
    # far from the origin, 1 km apart: within (the difference, not the sum, of the positions)
    assert within([[7000.0, 0, 0]], [[7000.0, 1, 0]], 2.0).tolist() == [True]
    assert within([], [], 5.0).tolist() == []


def test_rates_and_means_by_hand():
    # 3 cross-tags in 4 returns per 10^4: 7500
    assert per(3, 4, 1e4) == 7500.0
    # one value: its mean and no standard error, without a warning; two values 1, 3: s = sqrt(2), s.e. 1
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m, se = mean_se([3.0])
    assert m == 3.0 and np.isnan(se)
    assert mean_se([1.0, 3.0]) == pytest.approx((2.0, 1.0))
    m0, se0 = mean_se([])
    assert np.isnan(m0) and np.isnan(se0)
    assert mean_se([np.nan, 2.0, np.inf, 4.0]) == pytest.approx((3.0, 1.0))


def test_gospa_parts_with_missed_and_no_objects():
    # sums over two scans: localisation 1, missed 4, false 3, over 2 + 3 = 5 objects in view:
    # 0.2, 0.8, 0.6 and 8 / 5 = 1.6 in all; no object in view: every part NaN
    out = gospa_parts_per_object([0.5, 0.5], [4.0, 0.0], [1.0, 2.0], [2, 3])
    assert out == pytest.approx(dict(gospa_localisation_per_object_km=0.2, gospa_missed_per_object_km=0.8,
                                     gospa_false_per_object_km=0.6, gospa_per_object_km=1.6))
    empty = gospa_parts_per_object([0.0], [0.0], [2.0], [0])
    assert set(empty) == {"gospa_localisation_per_object_km", "gospa_missed_per_object_km",
                          "gospa_false_per_object_km", "gospa_per_object_km"}
    assert all(np.isnan(v) for v in empty.values())


def test_time_to_orbit_pass_order_and_shapes():
    # object 4 first detected at 10 s; good passes ending at 400 s then 900 s (in that order): 390 s
    objs, secs = time_to_orbit([4], [10.0], [4, 4], [400.0, 900.0], [True, True])
    assert objs.tolist() == [4] and secs.tolist() == [390.0]
    # the same given as (n, 1) columns and with float ids of whole value
    objs, secs = time_to_orbit(np.array([[4.0]]), np.array([[10.0]]), np.array([[4], [4]]),
                               np.array([[400.0], [900.0]]), np.array([[True], [True]]))
    assert objs.tolist() == [4] and secs.tolist() == [390.0]
    o, _ = time_to_orbit([], [], [], [], [])
    assert o.dtype == np.int64
    # pass_ok as a column too: the first pass (400 s) does not re-acquire, so the 900 s one counts: 890 s
    objs, secs = time_to_orbit([4], [10.0], [4, 4], [400.0, 900.0], np.array([[False], [True]]))
    assert objs.tolist() == [4] and secs.tolist() == [890.0]
    # a missing time (None) is not a time
    with pytest.raises(ValueError, match=r"^det_time and pass_end must be finite times \(s\)$"):
        time_to_orbit([1], [None], [1], [5.0], [True])
    with pytest.raises(ValueError, match=r"^det_time and pass_end must be finite times \(s\)$"):
        time_to_orbit([1], [0.0], [1], [None], [True])

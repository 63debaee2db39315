"""The ssa_breakup custody measures on small tables, every share by hand."""

import warnings

import numpy as np
import pandas as pd

from hypotrack.experiments.ssa_breakup.custody import first_return_own, reacquired_same_label


def test_first_return_own_by_hand():
    # object 1: first return (scan 3) to its own label 1; object 2: first return (scan 2) to label 1, later its
    # own; object 3: only uncorrelated returns (left out); object 4: two returns at scan 5, the first in table
    # order to label 7; object 9 is not catalogued (left out); clutter (origin -1) left out
    r = pd.DataFrame(dict(scan=[3, 4, 2, 4, 1, 5, 5, 0, 0], origin=[1, 2, 2, 3, 3, 4, 4, 9, -1],
                          label=[1, 2, 1, -1, -1, 7, 4, 9, 1]))
    assert first_return_own(r, [1, 2, 3, 4]) == 1 / 3
    assert first_return_own(r, [1]) == 1.0
    assert np.isnan(first_return_own(r, [3]))


def test_reacquired_same_label_by_hand():
    passes = pd.DataFrame(dict(target=[1, 1, 2, 2, 2, 3, 3], pass_no=[0, 1, 0, 1, 2, 0, 1],
                               first_scan=[0, 10, 0, 10, 20, 0, 10], last_scan=[2, 14, 2, 12, 21, 1, 11]))
    rows = [(0, 1, 1), (1, 1, 1), (2, 1, 5),                              # object 1 ends pass 0 on label 5
            (10, 1, 5), (11, 1, 1), (12, 1, 1), (13, 1, -1), (14, 1, 5),  # pass 1: 5 and 1 twice each: 1 (smaller)
            (0, 2, 2), (1, 2, 2), (2, 2, -1),                             # object 2 ends pass 0 on 2 (last assigned)
            (10, 2, 2), (11, 2, 2), (12, 2, 3),                           # pass 1: mostly 2 (kept), ends on 3
            (20, 2, 3), (21, 2, 3),                                       # pass 2: 3 (kept)
            (0, 3, 3), (1, 3, 3), (10, 3, -1), (11, 3, -1)]               # object 3 unassigned in pass 1: left out
    a = pd.DataFrame(rows, columns=["scan", "target", "label"])
    assert reacquired_same_label(a, passes) == 2 / 3
    assert reacquired_same_label(a[a["target"] == 2], passes) == 1.0
    assert np.isnan(reacquired_same_label(a[a["target"] == 3], passes))


def test_label_zero_is_a_label_and_a_catalogue_of_one_id():
    """Object 0 (a valid id) whose first return goes to its own label 0, object 5 first to label 0 (not its own):
    1/2; a single id (a 0-d catalogue) selects that object alone."""
    r = pd.DataFrame(dict(scan=[0, 1, 2], origin=[0, 5, 5], label=[0, 0, 5]))
    assert first_return_own(r, [0, 5]) == 0.5
    assert first_return_own(r, np.int64(0)) == 1.0 and first_return_own(r, 5) == 0.0


def test_first_return_ties_go_to_table_order_in_a_long_table():
    """50 returns of three objects (origin = scan, so every object's returns tie on the scan): each object's first
    return in table order is to its own label, the rest to label 99, so the share is 1. (An unstable sort, such as
    numpy's introsort on a table this long, would pick another of the tied rows.)"""
    scan = np.random.default_rng(0).integers(0, 3, 50)
    first = np.zeros(50, bool)
    first[[np.flatnonzero(scan == k)[0] for k in range(3)]] = True
    r = pd.DataFrame(dict(scan=scan, origin=scan, label=np.where(first, scan, 99)))
    assert first_return_own(r, [0, 1, 2]) == 1.0


def test_reacquisition_label_zero_pass_edges_and_the_most_frequent_label():
    """Object 1 ends pass 0 (scans 0-3) on label 0 and is assigned in pass 1 (scans 10-13) only at its first scan,
    to 0: kept. Object 2 is assigned in pass 0 only at its first scan (label 4) and in pass 1 only at its last scan
    (label 4): kept. Object 3 ends pass 0 on 5; pass 1 holds 3 once and 5 twice: the most frequent, 5 (not the
    smallest): kept. Object 4 ends pass 0 on 0 and holds 2 in pass 1: not kept. 3 of 4."""
    passes = pd.DataFrame(dict(target=[1, 1, 2, 2, 3, 3, 4, 4], pass_no=[0, 1] * 4,
                               first_scan=[0, 10] * 4, last_scan=[3, 13] * 4))
    rows = [(0, 1, 7), (3, 1, 0), (10, 1, 0),
            (0, 2, 4), (13, 2, 4),
            (3, 3, 5), (10, 3, 3), (11, 3, 5), (12, 3, 5),
            (1, 4, 0), (11, 4, 2)]
    a = pd.DataFrame(rows, columns=["scan", "target", "label"])
    assert reacquired_same_label(a, passes) == 0.75
    for t, want in ((1, 1.0), (2, 1.0), (3, 1.0), (4, 0.0)):
        assert reacquired_same_label(a[a["target"] == t], passes) == want, t


def test_nothing_to_share_is_nan_without_a_warning():
    passes = pd.DataFrame(dict(target=[1], pass_no=[0], first_scan=[0], last_scan=[3]))
    a = pd.DataFrame(dict(scan=[0], target=[1], label=[2]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no mean of an empty list
        assert np.isnan(reacquired_same_label(a, passes))
        assert np.isnan(first_return_own(a.assign(origin=1).iloc[:0], [1]))

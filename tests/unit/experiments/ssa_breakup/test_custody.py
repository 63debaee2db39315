"""The ssa_breakup custody measures on small tables, every share by hand."""

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

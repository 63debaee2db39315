"""SGP4 is not asked for instants years from the element sets' epochs."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.scenarios.catalogue.propagation import MAX_EPOCH_SPAN_DAYS, propagate, reference_epoch
from hypotrack.scenarios.catalogue.scenario import simulate_catalogue
from hypotrack.scenarios.catalogue.sensors import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.tle import parse_tle

ISS = """ISS (ZARYA)
1 25544U 98067A   19343.69339541  .00001764  00000-0  38792-4 0  9991
2 25544  51.6439 211.2001 0007417  17.6667  85.6398 15.50103472202482
"""


@pytest.mark.parametrize("start, word", [("2140-12-09", "after"), ("1990-01-01", "before")])
def test_a_start_decades_from_the_epoch_is_refused(start, word):
    cat = parse_tle(ISS)
    with pytest.raises(ValueError, match=rf"propagation time {start}.* days {word} the element epoch 2019-12-09.*"
                                         r"NORAD 25544.*at most 731 days"):
        propagate(cat, np.array([0.0, 60.0]), start)


def test_the_bound_counts_the_times_too():
    cat = parse_tle(ISS)
    start = reference_epoch(cat)
    propagate(cat, np.array([0.0, 86400.0 * (MAX_EPOCH_SPAN_DAYS - 1)]), start)  # inside: runs
    with pytest.raises(ValueError, match="propagation time"):
        propagate(cat, np.array([0.0, 86400.0 * (MAX_EPOCH_SPAN_DAYS + 1)]), start)


def test_the_scenario_refuses_the_same_start():
    with pytest.raises(ValueError, match=r"propagation time 2140-12-09.*NORAD 25544"):
        simulate_catalogue(parse_tle(ISS), [DEFAULT_RADAR], n_scans=2, seed=0, start=pd.Timestamp("2140-12-09"))

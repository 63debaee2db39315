"""The PMBM paper's own filter under GNU Octave, driven by this project's glue (hypotrack.experiments.williams2015
.reference and workflows/scripts/williams2015_reference.m) on exported scans. Runs only where Octave and
checkouts of Agarciafernandez/MTT and the NRL Tracker Component Library are present (the paths of the default
config's williams2015.reference, or HYPOTRACK_MTT_DIR / HYPOTRACK_TCL_DIR)."""

import os

import numpy as np
import pytest
import yaml

from hypotrack.experiments.williams2015.reference import read_estimates, reference_available, run_reference
from hypotrack.experiments.williams2015.run import score_estimates
from hypotrack.experiments.williams2015.scenario import draw_truth, scenario, simulate_scans

CFG = yaml.safe_load(open("workflows/config/default.yaml"))["williams2015"]
MTT = os.environ.get("HYPOTRACK_MTT_DIR", CFG["reference"]["mtt_dir"])
TCL = os.environ.get("HYPOTRACK_TCL_DIR", CFG["reference"]["tcl_dir"])

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not reference_available(MTT, TCL), reason="needs Octave and the reference code")]


def test_reference_follows_objects_on_clean_scans():
    """p_D = 1 and almost no clutter, 7 steps: after its first two scans the reference holds every object
    within a metre or two (GOSPA ≤ 3 m, c = 10; four objects, then three after the mid-point), so states, order [x, vx, y, vy] and units crossed the glue intact;
    and with the returns shifted 100 m the same filter is far off (the check can fail)."""
    m = scenario({**CFG, "n_steps": 7, "p_D": 1.0, "clutter_rate": 1e-6})
    X = draw_truth(m, np.random.default_rng(0))
    scans = simulate_scans(m, X, np.random.default_rng(1))
    shifted = [Z + [100.0, 0.0] for Z in scans]
    est, times = run_reference({0: scans, 1: shifted}, m, "workflows/scripts/williams2015_reference.m", MTT, TCL)
    assert sorted(times.run.unique()) == [0, 1] and (times.cpu_s >= 0).all() and len(times) == 14
    good = score_estimates(read_estimates(est, 0, 7), X, 10.0, 2.0)
    bad = score_estimates(read_estimates(est, 1, 7), X, 10.0, 2.0)
    assert (good.gospa.iloc[2:] <= 3.0).all() and (good.n_est == good.n_true).iloc[2:].all()
    assert (bad.gospa.iloc[2:] >= 9.0).all()
    # the Bernoulli tags link the estimates into one trajectory per object: four labels in all on clean scans
    assert est[est.run == 0].label.nunique() == 4

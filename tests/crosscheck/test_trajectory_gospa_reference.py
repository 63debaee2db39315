"""Trajectory GOSPA against its authors' code (García-Fernández, Rahmathullah & Svensson 2020,
``LPTrajMetric_cluster.m`` of ``Agarciafernandez/MTT``, run under GNU Octave with glpk as its LP solver).

The fixtures (tests/fixtures/trajectory_gospa_reference/: ``cases.json`` inputs, ``reference.csv`` the
reference's outputs; ``generate.py`` remakes them) are seeded random sets of 1–5 trajectories over 4–8
steps with births, deaths, one-step gaps, estimates that swap objects part-way and spurious tracks, at
several c, p and γ, and one case with no estimates. The reference's base distance is the p-norm of the
difference, hypotrack's the Euclidean norm: the cases are 2-D for p = 2 and 1-D for p = 1, where both agree. The reference solves the same LP by clustering the
trajectories and a different solver, so agreement of the value and of each cost is independent evidence.
"""

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hypotrack.metrics_trajectory import trajectory_gospa

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "trajectory_gospa_reference"
CASES = json.loads((FIXTURES / "cases.json").read_text())
REFERENCE = pd.read_csv(FIXTURES / "reference.csv").set_index("case")


def _array(rows, T, d):
    if not rows:
        return np.zeros((0, T, d))
    return np.array([[[np.nan] * d if s is None else s for s in traj] for traj in rows], dtype=float)


@pytest.mark.parametrize("case", CASES, ids=[f"case{c['case']}" for c in CASES])
def test_trajectory_gospa_matches_the_authors_code(case):
    X, Y = _array(case["X"], case["T"], case["d"]), _array(case["Y"], case["T"], case["d"])
    ref = REFERENCE.loc[case["case"]]
    r = trajectory_gospa(X, Y, c=case["c"], p=case["p"], gamma=case["gamma"])
    assert r.value == pytest.approx(ref.value, rel=1e-7, abs=1e-9)
    # the reference's X is the truth: its missed cost is ours (truth unassigned), its false ours
    parts = (r.localisation, r.missed, r.false, r.switches)
    assert parts == pytest.approx((ref.localisation, ref.missed, ref["false"], ref.switches), rel=1e-6, abs=1e-7)


def test_the_fixtures_decide_something():
    """The cases hold switches, missed and false costs, not only localisation."""
    assert (REFERENCE.switches > 0).sum() >= 2
    assert (REFERENCE.missed > 0).sum() >= 4 and (REFERENCE["false"] > 0).sum() >= 4
    assert len(CASES) == len(REFERENCE) >= 10

"""ssa50's claims name the tracker they are about, whichever tracker it is."""

import pandas as pd

from hypotrack.experiments import ssa as st


def _inputs():
    metrics = pd.DataFrame({"scan": [0, 1, 2], "n_catalogue": [2, 3, 3], "expected_number": [2.0, 2.9, 3.0],
                            "map_n_objects": [2, 3, 3], "effective_hypotheses": [1.0, 2.0, 1.0],
                            "ospa_in_view": 0.1, "ospa_catalogue": 0.2})
    cardinality = pd.DataFrame({"scan": [2, 2], "n_objects": [3, 4], "probability": [0.9, 0.1]})
    weights = pd.DataFrame({"scan": [0], "rank": [1], "weight": [1.0]})
    matched = pd.DataFrame({"scan": [1, 2], "role": "estimate", "status": "correct"})
    births = pd.DataFrame({"first_in_view_scan": [1], "tracked_at_end": [True], "delay_scans": [0]})
    return metrics, cardinality, weights, matched, births


def test_every_row_names_its_tracker_once():
    own = st.ssa50_claims(*_inputs(), estimate_scans=[2], n_scans=3, error_bound_probability=0.99,
                          tracker="delta-GLMB (Gibbs)", per_object_death=True)
    items = [c.item for c in st.labelled(own, "delta-GLMB (Gibbs)", "glmb_")]
    assert "delta-GLMB (Gibbs) recognises every birth" in items
    assert not any("R-FISST" in i for i in items)
    assert all(i.startswith("delta-GLMB (Gibbs)") and i.count("delta-GLMB") == 1 for i in items)
    p_end = next(c for c in own if c.key == "PEnd")
    assert "may die at every scan" in p_end.note and "Eq. 30" not in p_end.note
    primary = st.ssa50_claims(*_inputs(), estimate_scans=[2], n_scans=3, error_bound_probability=0.99)
    assert "R-FISST recognises every birth" in [c.item for c in primary]
    assert "Eq. 30 neither penalises" in next(c for c in primary if c.key == "PEnd").note


def test_one_verdict_per_claim_and_glmb_rows_are_extensions():
    """ssa50's single-run rows of a claim that ssa_seeds decides become illustrations with the over-seed
    row's claim id; a tracker 000 never ran (δ-GLMB) gets extensions, never a reproduction of 000."""
    from hypotrack.reporting.ledger import Claim, numeric_claim

    rows = [numeric_claim("ssa50", "expected number of objects at the end", "000 Fig. 11", 50, 50.06, abs_tol=0.1,
                          key="ExpectedEnd"),
            numeric_claim("ssa50", "P(N = 50) at the end", "000 Fig. 11", 1.0, 0.93, abs_tol=0.05, key="PEnd"),
            Claim("ssa50", "no red stars", "000 Figs 8-10", "all correct", "45/45", "ellipse", "reproduced",
                  key="NoRedStars")]
    chain = st.one_verdict(rows, "ssa50", "rfisst_chain", seed_trackers=["rfisst_chain", "rfisst"])
    assert [c.status for c in chain] == ["illustration", "illustration", "reproduced"]
    assert chain[1].claim == st.seed_claim_id("ssa50", "rfisst_chain", "P(N = true number) at the end")
    assert chain[0].note.startswith("one realisation; the verdict is the ssa_seeds row")
    other = st.one_verdict(rows, "ssa50", "rfisst_fixed", seed_trackers=["rfisst_chain"])
    assert [c.status for c in other] == ["reproduced", "not reproduced", "reproduced"]  # not run over seeds
    glmb = st.one_verdict(rows, "ssa50", "glmb", seed_trackers=["rfisst_chain"], extension=True)
    assert {c.status for c in glmb} == {"extension"} and glmb[0].source == "extension (000 Fig. 11's claim)"
    assert glmb[2].note.startswith("this project's filter, which 000 never ran")

"""The ambiguity output policy (:mod:`hypotrack.experiments.ssa_breakup.identities`) on hand-built sequences, and the
scorecard's cross-tags and identity switches of a swap as the MAP and as the policy report it."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.experiments.ssa_breakup.identities import WITHHELD, OutputIdentities, output_identities, relabel
from hypotrack.metrics_scorecard import id_switches, label_owners, return_tallies

B = 1000  # fresh identities count from here in these tests


def test_one_break_per_episode_rearmed_above_p_min_and_only_in_view():
    pol = OutputIdentities(0.8, base=B)
    seq = [  # (labels, p, in_view) -> expected identities
        (([1, 2, 3], [0.99, 0.95, 0.5], [True, True, False]), [1, 2, 3]),   # 3 ambiguous but out of view: kept
        (([1, 2, 3], [0.55, 0.51, 0.5], [True, True, True]), [B, B + 1, B + 2]),  # three break (1, 2, 3 in order)
        (([1, 2, 3], [0.45, 0.6, 0.9], [True, True, True]), [B, B + 1, B + 2]),   # still ambiguous: no re-break
        (([1, 2, 4], [0.85, 0.7, 0.3], [True, True, True]), [B, B + 1, B + 3]),   # 1 re-arms; 4 (newborn) breaks
        (([1, 2, 3], [0.79, 0.79, 0.2], [True, True, True]), [B + 4, B + 1, B + 2]),  # 1 breaks again, 3 re-armed at 0.9
    ]
    for (lab, p, v), want in seq[:4]:
        assert pol.update(lab, p, v).tolist() == want
    lab, p, v = seq[4][0]
    assert pol.update(lab, p, v).tolist() == [B + 4, B + 1, B + 5]
    assert pol.n_breaks == 6 and pol.identity(2) == B + 1 and pol.identity(9) == 9


def test_withhold_mode_untags_the_episode_and_resumes_under_a_fresh_identity():
    pol = OutputIdentities(0.8, base=B, mode="withhold")
    W = WITHHELD
    seq = [
        (([1, 2, 3], [0.99, 0.95, 0.5], [True, True, False]), [1, 2, 3]),    # 3 out of view: no episode
        (([1, 2, 3], [0.55, 0.51, 0.5], [True, True, True]), [W, W, W]),     # three episodes start: withheld
        (([1, 2, 3], [0.45, 0.6, 0.9], [False, True, True]), [W, W, B]),     # 3 resolved: a fresh identity
        (([1, 2, 3], [0.85, 0.7, 0.95], [True, True, True]), [B + 1, W, B]),  # 1 resolved; 2 still withheld
        (([1, 2, 3], [0.9, 0.7, 0.5], [True, False, True]), [B + 1, W, W]),  # 3's second episode
    ]
    for (lab, p, v), want in seq:
        assert pol.update(lab, p, v).tolist() == want
    assert pol.n_breaks == 2 and pol.identity(2) == W and pol.identity(1) == B + 1
    with pytest.raises(ValueError, match=r"mode must be one of \('fresh', 'withhold'\), got 'drop'"):
        OutputIdentities(0.5, mode="drop")


def test_p_min_zero_never_breaks_and_one_breaks_every_uncertain_episode():
    for p_min, want in ((0.0, [5, 6]), (1.0, [B, 6])):
        pol = OutputIdentities(p_min, base=B)
        assert pol.update([5, 6], [0.9999, 1.0], [True, True]).tolist() == want


def test_empty_scan_and_bad_input():
    pol = OutputIdentities(0.5)
    assert pol.update([], [], []).tolist() == []
    with pytest.raises(ValueError, match=r"p_min must be in \[0, 1\], got 1.5"):
        OutputIdentities(1.5)
    with pytest.raises(ValueError, match="p must hold probabilities"):
        pol.update([1], [1.2], [True])
    with pytest.raises(ValueError, match="labels must be distinct"):
        pol.update([1, 1], [0.5, 0.5], [True, True])
    with pytest.raises(ValueError, match="1-D of one length"):
        pol.update([1, 2], [0.5], [True])


def _swap_run():
    """Objects 1, 2 and 3 over 6 scans, one return each per scan, labels = object ids; at scan 2 the MAP swaps
    labels 1 and 2 (p 0.51) and keeps the swap to the end (p 0.6 at scan 3, then 0.95); 3 is never in doubt."""
    scans = np.repeat(np.arange(6), 3)
    target = np.tile([1, 2, 3], 6)
    label = np.where(scans >= 2, np.tile([2, 1, 3], 6), target)
    p = np.select([scans == 2, scans == 3], [0.51, 0.6], 0.95)
    p = np.where(target == 3, 1.0, p)
    marg = pd.DataFrame(dict(scan=scans, label=label, p=p, in_view=True))
    return scans, target, label, marg


def test_a_kept_swap_is_a_cross_tag_in_the_map_and_a_lost_track_in_the_policy():
    scans, target, label, marg = _swap_run()
    # MAP: labels 1 and 2 each held 2 scans by their own object and 4 by the other: owners swap, the first two scans'
    # returns of objects 1 and 2 are cross-tags (4), and each object changes label once (2 switches)
    own = label_owners(target, label)
    assert return_tallies(target, label, own)["cross_tags"] == 4
    assert id_switches(scans, target, label) == 2
    tab = output_identities(marg.iloc[::-1], 0.8, base=B)  # any row order: the policy runs scan by scan
    out = relabel(scans, label, tab)
    assert out.tolist() == np.where(scans >= 2, np.tile([B + 1, B, 3], 6), target).tolist()
    own = label_owners(target, out)
    assert return_tallies(target, out, own)["cross_tags"] == 0
    assert id_switches(scans, target, out) == 2
    assert relabel([0, 3], [-1, 7], tab).tolist() == [-1, 7]  # none stays none; a label the table lacks is kept
    # withheld: the swap's first scan (p 0.51) and the next (0.6) untagged, fresh identities from scan 4 on: no
    # cross-tag, one switch per object (its label before, a fresh one after), 4 returns uncorrelated
    out = relabel(scans, label, output_identities(marg, 0.8, base=B, mode="withhold"))
    swapped = np.tile([B, B + 1, 3], 6)
    assert out.tolist() == np.select([scans < 2, scans < 4], [target, np.where(target == 3, 3, -1)], swapped).tolist()
    own = label_owners(target, out)
    tal = return_tallies(target, out, own)
    assert (tal["cross_tags"], tal["uncorrelated"]) == (0, 4)
    assert id_switches(scans, target, out) == 2


def test_ambiguity_sweep_by_hand():
    from hypotrack.experiments.ssa_breakup.summary import ambiguity_sweep

    cards = pd.DataFrame(dict(scenario="breakup", tracker="gnn", seed=[2, 3], cross_tags_per_1e4=[2.0, 4.0],
                              id_switches_per_1e4=[10.0, 20.0]))
    sweep = pd.DataFrame(dict(scenario="breakup", tracker="homht_kbest_amb", mode="withhold", seed=[2, 3, 2, 3],
                              p_min=[0.8, 0.8, 0.9, 0.9], cross_tags_per_1e4=[1.0, 4.0, 0.0, 2.0],
                              id_switches_per_1e4=[5.0, 30.0, 12.0, 24.0], uncorrelated_per_1e4=[3.0, 5.0, 6.0, 8.0]))
    t = ambiguity_sweep(sweep, cards, "gnn", 0.5).set_index("p_min")
    # p_min 0.8: cross-tag ratios 0.5 and 1.0 -> 0.75 +- 0.25 (not met); switches 0.5 and 1.5 -> 1.0 +- 0.5
    assert t.loc[0.8, ["xtag_ratio", "xtag_ratio_se", "idsw_ratio", "idsw_ratio_se"]].tolist() == pytest.approx(
        [0.75, 0.25, 1.0, 0.5])
    assert not t.loc[0.8, "xtag_meets_goal"] and not t.loc[0.8, "idsw_meets_goal"]
    # p_min 0.9: cross-tags 0 and 0.5 -> 0.25 +- 0.25 (met); switches 1.2 and 1.2 (not met)
    assert t.loc[0.9, ["xtag_ratio", "xtag_ratio_se", "idsw_ratio"]].tolist() == pytest.approx([0.25, 0.25, 1.2])
    assert t.loc[0.9, "xtag_meets_goal"] and not t.loc[0.9, "idsw_meets_goal"]
    assert t.loc[0.9, ["cross_tags_per_1e4", "uncorrelated_per_1e4", "n_seeds"]].tolist() == pytest.approx([1.0, 7.0, 2])
    assert ambiguity_sweep(sweep.iloc[:0], cards).empty


def test_the_output_claim_states_what_it_withheld():
    from hypotrack.experiments.ssa_breakup.summary import breakup_claims, density_table, scorecard_summary

    cards = pd.DataFrame([dict(scenario="breakup", tracker=t, seed=k, cross_tags_per_1e4=1.0, completeness=0.5,
                               duplicate_per_1000=1.0, false_per_1000=1.0, nn_in_gate_share=0.5, reacquisitions=3.0,
                               uncorrelated_per_1e4=u * k)
                          for t, u in (("gnn", 10.0), ("homht_kbest", 20.0), ("homht_kbest_amb", 50.0)) for k in (1, 3)])
    acc, _ = scorecard_summary(cards)
    dens = density_table([dict(scenario="breakup", seed=1, n_pairs=3, nn_median_km=1.0, gate_km=2.0, share_in_gate=0.5,
                               share_in_5_gates=1.0)])
    notes = {c.key: c.note for c in breakup_claims(acc, pd.DataFrame(columns=["scenario", "tracker"]), dens)}
    # means over seeds 1 and 3: 100 against 40
    assert notes["crosstags_breakup_homht_kbest_amb"].endswith(
        "; uncorrelated 100 per 10^4 returns against 40 for the plain output (withheld while ambiguous)")
    assert "uncorrelated" not in notes["crosstags_breakup_homht_kbest"] and "uncorrelated" not in notes["crosstags_breakup_gnn"]


def test_probability_bounds_are_closed_nan_is_refused_and_the_messages_are_exact():
    pol = OutputIdentities(0.5, base=B)
    # p = 0 and p = 1 are probabilities: label 1 at 0 breaks, label 2 at 1 does not
    assert pol.update([1, 2], [0.0, 1.0], [True, True]).tolist() == [B, 2]
    for bad in (np.nan, -0.1, np.inf):
        with pytest.raises(ValueError, match=r"^p must hold probabilities in \[0, 1\]$"):
            pol.update([3], [bad], [True])
    with pytest.raises(ValueError, match="^labels must be distinct within a scan$"):
        pol.update([4, 4], [0.9, 0.9], [True, True])


def test_identities_are_exact_integers():
    """Identities above 2^53 (base 2^60) survive only as int64: a float array would round B + 1 to B."""
    base = 1 << 60
    out = OutputIdentities(0.5, base=base).update([1, 2], [0.1, 0.2], [True, True])
    assert out.dtype == np.int64 and out.tolist() == [base, base + 1]
    marg = pd.DataFrame(dict(scan=[0, 0, 1], label=[1, 2, 1], p=[0.1, 0.2, 0.9], in_view=True))
    t = output_identities(marg, 0.5, base)
    assert t["identity"].dtype == np.int64 and t["identity"].tolist() == [base, base + 1, base]


def test_a_label_never_seen_keeps_its_value_in_either_mode():
    for mode in ("fresh", "withhold"):
        pol = OutputIdentities(0.5, base=B, mode=mode)
        pol.update([1], [0.1], [True])
        assert pol.identity(7) == 7, mode
        assert pol.identity(1) == (B if mode == "fresh" else WITHHELD), mode


def test_relabel_returns_integer_identities_for_labels_read_as_floats():
    """Labels read back as floats (a CSV column with a gap) still come out as int64 identities: (scan 1, label 2)
    moved to B, the rest kept."""
    marg = pd.DataFrame(dict(scan=[0, 1], label=[2, 2], p=[0.9, 0.1], in_view=True))
    out = relabel([0, 1, 1], [2.0, 2.0, -1.0], output_identities(marg, 0.5, B))
    assert out.dtype == np.int64 and out.tolist() == [2, B, -1]

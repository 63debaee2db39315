"""The ssa50 sensitivity grid (hypotrack.experiments.ssa.sensitivity) on fabricated numbers."""

import matplotlib
import numpy as np
import pandas as pd
import pytest
from scipy import stats

from hypotrack.experiments.ssa import sensitivity as sv

matplotlib.use("Agg")


def test_grid_is_the_product_with_lambda_fastest_and_rejects_bad_values():
    g = sv.grid({"clutter_rates": [0.0, 1.0, 2.0], "p_D": [0.95, 0.99]})
    assert g["setting"].tolist() == list(range(6))
    assert g["clutter_rate"].tolist() == [0.0, 1.0, 2.0] * 2 and g["p_D"].tolist() == [0.95] * 3 + [0.99] * 3
    with pytest.raises(ValueError, match="clutter_rates must be >= 0"):
        sv.grid({"clutter_rates": [-1.0], "p_D": [0.9]})
    with pytest.raises(ValueError, match="p_D must lie in"):
        sv.grid({"clutter_rates": [1.0], "p_D": [0.0]})
    with pytest.raises(ValueError, match="repeat"):
        sv.grid({"clutter_rates": [1.0, 1.0], "p_D": [0.9]})


def _runs(values, blind=0.0):
    rows = []
    for setting, (lam, p_d, xs) in enumerate(values):
        for i, x in enumerate(xs):
            for tracker, p in (("chain", x), ("blind", blind)):
                rows.append({"setting": setting, "clutter_rate": lam, "p_D": p_d, "seed_index": i, "tracker": tracker,
                             "n_true_end": 50, "p_n_end": p, "expected_number_end": 45 + 5 * p,
                             "p_more_end": 1 - p if tracker == "chain" else 0.0,
                             "p_less_end": 0.0 if tracker == "chain" else 1 - p})
    return pd.DataFrame(rows, columns=sv.RUN_COLUMNS)


def test_table_applies_the_monte_carlo_rule_per_setting_by_hand():
    good = [0.99, 1.0, 0.98, 1.0, 0.99]  # mean 0.992, sd 0.008367
    bad = [0.6, 0.7, 0.65, 0.62, 0.68]  # mean 0.65: far below 0.95
    t = sv.sensitivity_table(_runs([(0.0, 0.95, good), (1.0, 0.95, bad)]), tracker="chain", tolerance=0.05)
    r0, r1 = t.iloc[0], t.iloc[1]
    se = np.std(good, ddof=1) / np.sqrt(5)
    q = stats.t.ppf(0.5 + 0.9973 / 2, df=4)  # 5.5: the rule's interval at n = 5
    assert (r0["n"], r0["p_n_end_mean"], r0["p_n_end_se"]) == (5, pytest.approx(0.992), pytest.approx(se))
    assert (r0["low"], r0["high"]) == (pytest.approx(0.992 - q * se), pytest.approx(0.992 + q * se))
    # 0.992 ± 5.5 · 0.00374 = [0.971, 1.013] lies inside [0.95, 1.05]
    assert r0["status"] == "reproduced" and r1["status"] == "not reproduced"
    assert r0["expected_number_end_mean"] == pytest.approx(45 + 5 * 0.992)
    assert r0["p_more_end_mean"] == pytest.approx(1 - 0.992)
    # the blind tracker never holds a birth: P(N = 50) = 0, which the same rule rejects
    assert (r0["control_p_n_end_mean"], r0["control_status"]) == (0.0, "not reproduced")
    # two seeds: the interval (q = 235 at one degree of freedom) reaches outside the tolerance
    two = sv.sensitivity_table(_runs([(0.0, 0.95, [0.99, 1.0])]), tracker="chain", tolerance=0.05)
    assert two["status"].iloc[0] == "inconclusive"
    with pytest.raises(ValueError, match="tolerance"):
        sv.sensitivity_table(_runs([(0.0, 0.95, good)]), tracker="chain", tolerance=2.0)


def test_claims_and_macros_name_the_settings_that_reproduce():
    good, bad = [0.99, 1.0, 0.98, 1.0, 0.99], [0.6, 0.7, 0.65, 0.62, 0.68]
    t = sv.sensitivity_table(_runs([(0.0, 0.95, good), (1.0, 0.95, bad)]), tracker="chain", tolerance=0.05)
    (claim,), macros = sv.sensitivity_claims(t, tolerance=0.05, configured=(1.0, 0.95))
    assert claim.status == "extension" and claim.key == "PEndGrid" and claim.evidence == "measurement"
    assert claim.reproduced == "reproduced at 1 of 2 settings: (λ = 0, p_D = 0.95)"
    assert "λ = 1, p_D = 0.95: 0.650 (not reproduced)" in claim.note
    assert "blind tracker (the control) reproduces at 0 settings" in claim.note
    assert macros["NReproduced"] == 1 and macros["NSettings"] == 2 and macros["NSeeds"] == 5
    assert (macros["PEndConfigured"], macros["StatusConfigured"]) == ("0.650", "not reproduced")
    assert (macros["PEndNoClutterMin"], macros["PEndMin"], macros["PEndMax"]) == ("0.992", "0.650", "0.992")
    fig = sv.plot_sensitivity(t, tolerance=0.05)
    ax = fig.axes[0]
    assert ax.get_legend() is not None and ax.get_xlabel().startswith("clutter rate")
    labels = {text.get_text() for text in ax.get_legend().get_texts()}
    assert labels == {"published 1 ± 0.05", "$p_D$ = 0.95", "reproduced", "not reproduced", "inconclusive"}


def test_run_setting_is_deterministic_and_keeps_the_orbits_across_settings():
    from pathlib import Path

    import yaml

    root = Path(__file__).resolve().parents[4]
    config = yaml.safe_load((root / "workflows" / "config" / "default.yaml").read_text())
    config["ssa50"]["max_hypotheses"] = 3
    config["ssa50"]["sensitivity"].update(n_seeds=2, n_scans=8, n_steps=100, clutter_rates=[0.0, 2.0], p_D=[0.9])
    rows, timing = sv.run_setting(config, 1, progress=None)
    again, _ = sv.run_setting(config, 1, progress=None)
    pd.testing.assert_frame_equal(rows, again)
    assert list(rows.columns) == sv.RUN_COLUMNS and len(timing) == 2
    assert rows["tracker"].tolist() == ["rfisst_chain", "blind"] * 2
    assert (rows["clutter_rate"].unique().tolist(), rows["p_D"].unique().tolist()) == ([2.0], [0.9])
    blind = rows[rows["tracker"] == "blind"]
    assert (blind["expected_number_end"] == 45).all()
    # the same realisation at another setting: same truth, different returns (clutter only at lambda = 2)
    a, b = sv._scenario(config, 0.0, 0.9, 1), sv._scenario(config, 2.0, 0.9, 1)
    pd.testing.assert_frame_equal(a.truth, b.truth)
    assert (a.scans["origin"] == -1).sum() == 0 and (b.scans["origin"] == -1).sum() > 0
    with pytest.raises(ValueError, match="setting must lie in"):
        sv.run_setting(config, 2, progress=None)

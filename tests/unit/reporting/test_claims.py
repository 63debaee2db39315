"""The cell formatting of hypotrack.reporting.claims, against hand-written cells."""

import math

from hypotrack.reporting.claims import KEY_PATTERN, format_value, measured_text, monte_carlo_claim


def test_format_value_by_hand():
    assert format_value("0.5 %", 4) == "0.5 %"  # text as is
    assert format_value(None, 4) == "--" and format_value(math.nan, 4) == "--"
    assert format_value(63591, 4) == "63591" and format_value(2.0, 4) == "2"  # integers without a point
    assert format_value(0.0363456, 3) == "0.0363"
    assert format_value(3e-14, 4) == "3e-14"
    assert format_value(1e16, 4) == "1e+16"  # too large to be written as an integer


def test_measured_text_of_a_plain_and_a_monte_carlo_row():
    assert measured_text({"reproduced": "0.85", "n": ""}) == "0.85"
    row = {"reproduced": "0.85", "n": "100", "mean": "0.851", "se": "0.002", "z": "1.50"}
    assert measured_text(row) == "0.851 ± 0.002 (n = 100, z = 1.50)"
    assert measured_text({**row, "z": ""}) == "0.851 ± 0.002 (n = 100)"


def test_key_pattern():
    assert KEY_PATTERN.fullmatch("Mass1Sigma") and KEY_PATTERN.fullmatch("a_1")
    assert not KEY_PATTERN.fullmatch("1a") and not KEY_PATTERN.fullmatch("a-b")


def test_a_passing_check_on_a_calibrated_reading_is_a_calibration_never_a_reproduction():
    import pandas as pd
    from dataclasses import asdict

    from hypotrack.reporting.claims import ledger_problems, monte_carlo_claim, numeric_claim

    # 0.0363 within ±0.0001 of 0.0363: reproduced on a published number, a calibration on a calibrated reading
    assert numeric_claim("e", "i", "s", 0.0363, 0.03634, abs_tol=1e-4).status == "reproduced"
    assert numeric_claim("e", "i", "s", 0.0363, 0.03634, abs_tol=1e-4, evidence="calibration").status == "calibration"
    # a calibrated reading that misses stays a failure
    assert numeric_claim("e", "i", "s", 0.0363, 0.05, abs_tol=1e-4, evidence="calibration").status == "not reproduced"
    # Monte Carlo: mean 0.0364 ± 0.0002 (n = 100) inside 0.0363 ± 10 %
    mc = monte_carlo_claim("e", "i", "s", 0.0363, n=100, mean=0.0364, se=0.0002, rel_tol=0.1, evidence="calibration")
    assert mc.status == "calibration"
    rows = pd.DataFrame([asdict(mc)])
    assert ledger_problems(rows) == []
    # the same row hand-marked "reproduced" is caught, twice: the calibration rule and the recomputed status
    bad = ledger_problems(rows.assign(status="reproduced"))
    assert any("on a calibration" in p for p in bad) and any("Monte Carlo rule gives 'calibration'" in p for p in bad)


def test_the_z_of_seeds_that_agree_to_rounding_is_short():
    """Three chain seeds agreeing to rounding (the E[N] at the end, 50.0717 ± 5e-15 against 50): z ~ 1.4e13 is given
    to three significant digits, a z under 10⁶ to two decimals, a zero s.e. as inf."""
    tight = monte_carlo_claim("e", "i", "s", 50.0, n=3, mean=50.0717, se=5.02e-15, abs_tol=0.1)
    assert tight.z == "1.43e+13"
    assert monte_carlo_claim("e", "i", "s", 50.0, n=3, mean=50.0717, se=0.0123, abs_tol=0.1).z == "5.83"
    assert monte_carlo_claim("e", "i", "s", 50.0, n=3, mean=49.9, se=0.0, abs_tol=0.1).z == "-inf"

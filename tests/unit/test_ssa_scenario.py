"""The tidy-table schema (hypotrack.scenarios.tables) and the SSA scenario generator."""

import numpy as np
import pandas as pd
import pytest

from hypotrack.scenarios import tables

# --- tables ---------------------------------------------------------------------------------


def small_scans():
    # Scan 1 is empty; sensor 1 only reports in scan 2.
    return tables.scans_table(
        scan=[0, 0, 2, 2, 2],
        time=[0.0, 0.0, 120.0, 120.0, 120.0],
        sensor=[0, 0, 0, 0, 1],
        Z=[[1, 2], [3, 4], [5, 6], [7, 8], [9, 10]],
        origin=[3, -1, -1, 3, 0],
    )


def test_scans_table_schema_and_return_numbering():
    df = small_scans()
    assert list(df.columns) == ["scan", "time", "sensor", "return", "z_0", "z_1", "origin"]
    assert df["return"].tolist() == [0, 1, 0, 1, 0]
    assert df["origin"].dtype == np.int64 and df["time"].dtype == float


def test_scans_to_list_keeps_empty_scans_given_times():
    df = small_scans()
    out = tables.scans_to_list(df, times=[0.0, 60.0, 120.0], sensor=0, with_origin=True)
    assert [t for t, _, _ in out] == [0.0, 60.0, 120.0]
    np.testing.assert_array_equal(out[0][1], [[1, 2], [3, 4]])
    assert out[1][1].shape == (0, 2) and out[1][2].shape == (0,)
    np.testing.assert_array_equal(out[2][2], [-1, 3])
    with pytest.raises(ValueError, match="pass sensor="):
        tables.scans_to_list(df)
    with pytest.raises(ValueError, match="pass times="):
        tables.scans_to_list(df, sensor=0)


def test_scans_by_sensor_is_synchronous():
    out = tables.scans_by_sensor(small_scans(), 2, times=[0.0, 60.0, 120.0])
    assert len(out) == 3 and all(len(Zs) == 2 for _, Zs in out)
    assert out[0][1][1].shape == (0, 2)
    np.testing.assert_array_equal(out[2][1][1], [[9, 10]])


def test_tables_round_trip_through_csv(tmp_path):
    truth = tables.truth_table([0, 0, 1], [0.0, 0.0, 60.0], [0, 1, 0], np.arange(12.0).reshape(3, 4) / 7, [True, False, True])
    scans = small_scans()
    for df, validate in ((truth, tables.validate_truth), (scans, tables.validate_scans)):
        path = tmp_path / "t.csv"
        tables.write_table(df, path)
        back = validate(pd.read_csv(path))
        pd.testing.assert_frame_equal(back, df, check_exact=False, rtol=1e-9)
        tables.write_table(back, tmp_path / "u.csv")
        assert path.read_bytes() == (tmp_path / "u.csv").read_bytes()


def test_truth_to_list_and_zero_targets():
    truth = tables.truth_table([0, 0, 2], [0.0, 0.0, 2.0], [5, 1, 5], np.ones((3, 2)), [True, False, False])
    out = tables.truth_to_list(truth, times=[0.0, 1.0, 2.0], in_view_only=True)
    assert out[0][1].tolist() == [5] and out[1][2].shape == (0, 2) and out[2][1].shape == (0,)
    empty = tables.truth_table([], [], [], np.zeros((0, 4)), [])
    assert [len(ids) for _, ids, _ in tables.truth_to_list(empty, times=[0.0, 1.0])] == [0, 0]
    no_returns = tables.scans_table([], [], [], np.zeros((0, 2)), [])
    assert [Z.shape for _, Z in tables.scans_to_list(no_returns, times=[0.0, 1.0])] == [(0, 2), (0, 2)]


@pytest.mark.parametrize(
    "mutate, match",
    [
        (lambda d: d.drop(columns="origin"), "missing columns"),
        (lambda d: d.rename(columns={"z_1": "z_2"}), "numbered 0..n-1"),
        (lambda d: d.assign(origin=-2), "origin"),
        (lambda d: d.assign(z_0=np.nan), "finite"),
        (lambda d: d.assign(scan=0.5), "integers"),
        (lambda d: d.assign(**{"return": 0}), "more than one row"),
    ],
)
def test_validate_scans_rejects_bad_tables(mutate, match):
    with pytest.raises(ValueError, match=match):
        tables.validate_scans(mutate(small_scans()))


def test_validate_truth_rejects_bad_tables():
    truth = tables.truth_table([0], [0.0], [0], [[1.0, 2.0]], [True])
    with pytest.raises(ValueError, match="state_<i>"):
        tables.validate_truth(truth.drop(columns=["state_0", "state_1"]))
    with pytest.raises(ValueError, match="more than one row"):
        tables.validate_truth(pd.concat([truth, truth]))
    with pytest.raises(TypeError, match="DataFrame"):
        tables.validate_truth({"scan": [0]})

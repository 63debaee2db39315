"""The tidy-table schema (hypotrack.scenarios.tables) and the SSA scenario generator."""

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy import stats

from hypotrack.config import ConfigError, validate_config
from hypotrack.models.orbit import EARTH_RADIUS, MU_EARTH, angular_momentum, specific_energy
from hypotrack.scenarios import tables
from hypotrack.scenarios.ssa import (
    SSAParams,
    params_from_config,
    prior_table,
    read_prior,
    scenario_from_config,
    simulate_ssa,
)

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
    truth = tables.truth_table(
        [0, 0, 1], [0.0, 0.0, 60.0], [0, 1, 0], np.arange(12.0).reshape(3, 4) / 7, [True, False, True]
    )
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


# --- SSA scenario -----------------------------------------------------------------------------

CONFIG_DIR = Path(__file__).resolve().parents[3] / "workflows" / "config"


@pytest.fixture(scope="module")
def ssa50():
    return simulate_ssa(SSAParams(), 2026)


@pytest.fixture(scope="module")
def ssa15():
    return simulate_ssa(SSAParams(n_objects=15, n_known=15, start_in_view=True), 15)


def states_at(scenario, k):
    t = scenario.truth
    return t[t["scan"] == k].sort_values("target")[tables.state_columns(4)].to_numpy()


def test_ssa50_population_and_births(ssa50):
    p = ssa50.params
    assert ssa50.truth["target"].nunique() == 50 and len(ssa50.times) == 720
    np.testing.assert_array_equal(ssa50.prior_ids, np.arange(45))
    np.testing.assert_array_equal(ssa50.birth_ids, np.arange(45, 50))
    # Every object passes through the FOV during the run (document 000 Sec. IV-A).
    assert (ssa50.first_in_view_scan >= 0).all()
    # Births are out of view at t = 0 and first enter inside the birth window, spread out.
    first = ssa50.first_in_view_scan[ssa50.birth_ids]
    run_scans = p.n_scans - 1
    assert (first > 0).all()
    assert (first >= math.floor(0.1 * run_scans)).all() and (first <= math.ceil(0.5 * run_scans) + 1).all()
    assert len(set(first.tolist())) == 5


def test_ssa_orbits_within_design_ranges(ssa50, ssa15):
    for sc in (ssa50, ssa15):
        X0 = states_at(sc, 0)
        a = -MU_EARTH / (2 * specific_energy(X0))
        h = angular_momentum(X0)
        e = np.sqrt(1 - h**2 / (MU_EARTH * a))
        assert (h > 0).all()  # prograde
        # Process noise perturbs the drawn elements only at the 1e-6 level in one step.
        assert a.min() > 6778 - 1e-3 and a.max() < 26578 + 1e-3
        assert e.max() <= 0.1 + 1e-6
        perigee = a * (1 - e)
        assert perigee.min() >= EARTH_RADIUS + 200 - 1e-3
        assert (a * (1 + e)).max() <= 30000


def test_ssa15_all_start_in_view(ssa15):
    assert ssa15.truth.query("scan == 0")["in_view"].all()
    assert len(ssa15.birth_ids) == 0 and len(ssa15.prior_ids) == 15


def test_truth_follows_two_body_dynamics_with_process_noise(ssa50):
    m = ssa50.motion
    L = np.linalg.cholesky(m.Q(60.0))
    resid = []
    for k in (0, 100, 500):
        pred = m.propagate(states_at(ssa50, k), 60.0)
        resid.append(np.linalg.solve(L, (states_at(ssa50, k + 1) - pred).T).T)
    w = np.concatenate(resid).ravel()  # whitened: must be N(0, 1)
    assert stats.kstest(w, "norm").pvalue > 1e-3
    assert abs(w.std() - 1) < 0.15


def test_scans_are_consistent_with_truth_and_sensor(ssa50):
    p = ssa50.params
    truth = ssa50.truth.set_index(["scan", "target"])
    det = ssa50.scans[ssa50.scans["origin"] >= 0]
    X = truth.loc[list(zip(det["scan"], det["origin"])), ["state_0", "state_1"]].to_numpy()
    assert truth.loc[list(zip(det["scan"], det["origin"])), "in_view"].all()
    err = (det[["z_0", "z_1"]].to_numpy() - X) / p.sigma
    chi2 = float(np.sum(err**2))
    dof = err.size
    assert stats.chi2(dof).ppf(1e-4) < chi2 < stats.chi2(dof).ppf(1 - 1e-4)
    n_in_view = int(ssa50.truth["in_view"].sum())
    assert abs(len(det) / n_in_view - p.p_D) < 5 * math.sqrt(p.p_D * (1 - p.p_D) / n_in_view)
    clutter = ssa50.scans[ssa50.scans["origin"] == -1]
    assert ssa50.fov.contains(clutter[["z_0", "z_1"]].to_numpy()).all()
    assert abs(len(clutter) / p.n_scans - p.clutter_rate) < 5 * math.sqrt(p.clutter_rate / p.n_scans)
    # Each object yields at most one return per scan.
    assert not det.duplicated(["scan", "origin"]).any()


def test_initial_hypothesis_errors_are_draws_from_P0(ssa50):
    p = ssa50.params
    np.testing.assert_array_equal(
        ssa50.prior_covs, np.broadcast_to(np.diag([1.0, 1.0, 1e-6, 1e-6]), (45, 4, 4))
    )
    err = ssa50.prior_means - states_at(ssa50, 0)[:45]
    chi2 = float(np.sum(err**2 / np.diag(p.P0)))
    assert stats.chi2(180).ppf(1e-4) < chi2 < stats.chi2(180).ppf(1 - 1e-4)


def test_ssa_is_deterministic_and_streams_are_separate(tmp_path):
    small = SSAParams(n_scans=40)
    a, b = simulate_ssa(small, 7), simulate_ssa(small, 7)
    for name in ("truth", "scans"):
        tables.write_table(getattr(a, name), tmp_path / f"a_{name}.csv")
        tables.write_table(getattr(b, name), tmp_path / f"b_{name}.csv")
        assert (tmp_path / f"a_{name}.csv").read_bytes() == (tmp_path / f"b_{name}.csv").read_bytes()
    np.testing.assert_array_equal(a.prior_means, b.prior_means)
    other = simulate_ssa(small, 8)
    assert not np.allclose(states_at(other, 0), states_at(a, 0))
    # A different sensor leaves the truth unchanged (separate random streams).
    noisier = simulate_ssa(SSAParams(n_scans=40, sigma=3.0, p_D=0.5, clutter_rate=4.0), 7)
    pd.testing.assert_frame_equal(noisier.truth, a.truth)


def test_zero_objects_and_empty_scans():
    sc = simulate_ssa(SSAParams(n_objects=0, n_known=0, n_scans=30, clutter_rate=0.5), 3)
    assert sc.truth.empty and sc.prior_means.shape == (0, 4) and sc.first_in_view_scan.shape == (0,)
    scans = sc.scan_list(with_origin=True)
    assert len(scans) == 30 and any(len(Z) == 0 for _, Z, _ in scans)
    assert all((origin == -1).all() for _, _, origin in scans)
    assert [len(ids) for _, ids, _ in sc.truth_list()] == [0] * 30


def test_perfect_sensor_reports_exactly_the_objects_in_view():
    sc = simulate_ssa(SSAParams(n_objects=12, n_known=10, n_scans=50, p_D=1.0, clutter_rate=0.0), 4)
    per_scan = sc.truth.groupby("scan")["in_view"].sum().to_numpy()
    got = np.array([len(Z) for _, Z in sc.scan_list()])
    np.testing.assert_array_equal(got, per_scan)


@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        ({"p_D": 0.0}, ValueError, r"p_D must lie in \(0, 1\]"),
        ({"p_D": 1.5}, ValueError, r"p_D must lie in \(0, 1\]"),
        ({"clutter_rate": -1.0}, ValueError, "clutter_rate"),
        ({"sigma": 0.0}, ValueError, "sigma"),
        ({"q": -1e-10}, ValueError, "q must be"),
        ({"e_max": 1.0}, ValueError, "e_max"),
        ({"a_min": 6500.0}, ValueError, "a_min"),
        ({"a_max": 6000.0, "a_min": 6778.0}, ValueError, "a_max"),
        ({"a_max": 29000.0}, ValueError, "r_max"),
        ({"r_min": 7000.0}, ValueError, "r_min"),
        ({"full_angle_deg": 0.0}, ValueError, "full_angle_deg"),
        ({"n_known": 51}, ValueError, "n_known"),
        ({"n_objects": -1}, ValueError, "n_objects"),
        ({"n_scans": 0}, ValueError, "n_scans"),
        ({"dt": -60.0}, ValueError, "dt"),
        ({"birth_window": (0.6, 0.2)}, ValueError, "birth_window"),
        ({"birth_window": (0.1,)}, ValueError, "birth_window"),
        ({"start_in_view": "yes"}, TypeError, "start_in_view"),
    ],
)
def test_ssa_params_bad_input(kwargs, exc, match):
    with pytest.raises(exc, match=match):
        SSAParams(**kwargs)


def test_simulate_ssa_bad_input():
    with pytest.raises(TypeError, match="params"):
        simulate_ssa({"n_objects": 3}, 1)
    with pytest.raises(ValueError, match="seed"):
        simulate_ssa(SSAParams(n_scans=2), -1)
    # A birth after the period of the longest allowed orbit cannot be a first entry.
    with pytest.raises(ValueError, match="birth"):
        simulate_ssa(SSAParams(a_max=8000.0, n_scans=720, birth_window=(0.9, 1.0)), 1)


def load_config(*names):
    config = {}
    for name in names:
        with open(CONFIG_DIR / name) as fh:
            for k, v in (yaml.safe_load(fh) or {}).items():
                config[k] = config.get(k, {}) | v if isinstance(v, dict) else v
    return validate_config(config, CONFIG_DIR / "schema")


def test_config_sections_build_the_paper_cases():
    config = load_config("default.yaml")
    assert params_from_config(config["ssa"], "ssa50") == SSAParams()
    p15 = params_from_config(config["ssa"], "ssa15")
    assert (p15.n_objects, p15.n_known, p15.start_in_view) == (15, 15, True)
    quick = load_config("default.yaml", "quick.yaml")
    assert params_from_config(quick["ssa"], "ssa50").n_scans < 720
    with pytest.raises(ValueError, match="unknown SSA case"):
        params_from_config(config["ssa"], "ssa7")


def test_config_schema_rejects_bad_values():
    for field, value in (("p_D", 0.0), ("clutter_rate", -1.0), ("n_scans", 0), ("bogus", 1)):
        config = load_config("default.yaml")
        config["ssa"][field] = value
        with pytest.raises(ConfigError, match="ssa"):
            validate_config(config, CONFIG_DIR / "schema")


def test_scenario_from_config_and_prior_table_round_trip(tmp_path):
    config = load_config("default.yaml", "quick.yaml")
    sc = scenario_from_config(config, "ssa50")
    again = scenario_from_config(config, "ssa50")
    pd.testing.assert_frame_equal(sc.scans, again.scans)
    tables.write_table(prior_table(sc), tmp_path / "prior.csv")
    ids, means, covs = read_prior(pd.read_csv(tmp_path / "prior.csv"))
    np.testing.assert_array_equal(ids, sc.prior_ids)
    np.testing.assert_allclose(means, sc.prior_means, rtol=1e-9)
    np.testing.assert_allclose(covs, sc.prior_covs, rtol=1e-9)


def test_birth_model_over_the_fov(ssa50):
    m = ssa50.birth_model(alpha=1e-3, beta=1e-4, n_birth_regions=10)
    assert len(m.birth_regions) == 10
    d = m.birth_density(0)
    x = d.sample(200, np.random.default_rng(0))
    assert ssa50.fov.contains(x[:, :2]).all()
    speed_ratio = np.hypot(x[:, 2], x[:, 3]) / np.sqrt(MU_EARTH / np.hypot(x[:, 0], x[:, 1]))
    assert 0.7 < speed_ratio.mean() < 1.3


def test_plot_scenario_marks_every_birth(ssa50):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hypotrack.experiments.ssa.scenario_figures import plot_scenario

    small = simulate_ssa(SSAParams(n_scans=60), 9)
    fig = plot_scenario(small.truth, small.scans, small.fov, small.prior_ids)
    ax = fig.axes[1]
    stars = [ln for ln in ax.get_lines() if ln.get_marker() == "*"]
    assert len(stars) == 5
    plt.close(fig)

"""Timing at scale (hypotrack.experiments.ssa_catalogue.scale): a run's figures are consistent with its CPU
seconds and counts, an isolated run reports its own peak memory, and the summary's medians, spreads and
log-log slopes are those of the runs (a synthetic cost N^0.8 gives slope 0.8); plus lazy GNN/JPDA on the
catalogue's own scans: the eager posterior (gating in view) to rounding."""

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.ssa_catalogue.lazy_sht import lazy_sht_timing
from hypotrack.experiments.ssa_catalogue.scale import measure_run, run_isolated, scale_runs, scale_summary


@pytest.fixture(scope="module")
def cfg():
    with open("workflows/config/default.yaml") as fh:
        c = yaml.safe_load(fh)["ssa_catalogue"]
    c["scale"] = dict(sizes=[60], n_scans=4, runs=1, trackers=["gnn"], factored={"fast_path": True}, chunk=25)
    return c


def test_a_run_reports_consistent_figures(cfg):
    r = measure_run(cfg, "gnn", 1500, 3)
    assert r["n_scans"] == 3 and r["n_objects"] == 1500 and r["cpu_s"] > 0 and r["in_view_per_scan"] > 5
    np.testing.assert_allclose(r["cpu_s_per_scan"] * 3, r["cpu_s"])
    np.testing.assert_allclose(r["us_per_object"], 1e6 * r["cpu_s"] / (1500 * 3))
    np.testing.assert_allclose(r["us_per_object_in_view"] * r["in_view_per_scan"] * 3, 1e6 * r["cpu_s"])
    np.testing.assert_allclose(r["us_per_return"] * r["returns_per_scan"] * 3, 1e6 * r["cpu_s"])
    np.testing.assert_allclose(r["real_time_factor"], 30.0 / r["cpu_s"])  # 3 scans of 10 s simulated
    assert r["peak_rss_mb"] > 50  # numpy, pandas and the scenario are resident
    # the dearest of the three timed scans over their median
    assert r["slowest_scan_ratio"] >= 1.0


def test_warm_scans_are_stepped_untimed_and_a_bad_value_is_refused(cfg):
    """``warm_scans = 2``: scans 0 and 1 untimed, so two of the four scans are timed; the real-time
    factor counts the timed scans' simulated seconds only."""
    c = dict(cfg, scale=dict(cfg["scale"], warm_scans=2))
    r = measure_run(c, "gnn", 1500, 3)
    assert r["n_scans"] == 2
    np.testing.assert_allclose(r["real_time_factor"], 20.0 / r["cpu_s"])
    for bad in (0, 4):
        with pytest.raises(ValueError, match=rf"^scale\.warm_scans must lie in \[1, n_scans = 4\), got {bad}$"):
            measure_run(dict(cfg, scale=dict(cfg["scale"], warm_scans=bad)), "gnn", 60, 3)


def test_isolated_runs_are_deterministic_but_for_the_clock(cfg):
    a, b = run_isolated(cfg, "gnn", 60, 3), run_isolated(cfg, "gnn", 60, 3)
    for k in ("n_scans", "in_view_per_scan", "returns_per_scan"):
        assert a[k] == b[k]
    assert a["peak_rss_mb"] > 50
    assert a["blas_threads"] == b["blas_threads"] == "1"  # the child's BLAS on one thread (scale.ONE_THREAD)


def test_an_in_process_run_reports_the_blas_threads_it_had(cfg, monkeypatch):
    monkeypatch.delenv("OPENBLAS_NUM_THREADS", raising=False)
    assert measure_run(cfg, "gnn", 60, 3)["blas_threads"] == "default"
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "2")
    assert measure_run(cfg, "gnn", 60, 3)["blas_threads"] == "2"


def test_summary_medians_spreads_and_slopes():
    rows = []
    for n in (1000, 10000, 100000):
        for run, f in enumerate((0.9, 1.0, 1.3)):
            cpu = 1e-3 * n**0.8 * f
            rows.append(dict(tracker="a", n_objects=n, n_scans=10, in_view_per_scan=n / 100, returns_per_scan=n / 110,
                             cpu_s_per_scan=cpu, us_per_object_in_view=1e6 * cpu / (n / 100),
                             us_per_object=1e6 * cpu / n, us_per_return=1e6 * cpu / (n / 110),
                             real_time_factor=10 / cpu, peak_rss_mb=100 + run, load_before=1.0, load_after=3.0,
                             run=run))
    t = scale_summary(pd.DataFrame(rows))
    assert len(t) == 3 and (t["runs"] == 3).all()
    np.testing.assert_allclose(t["cpu_s_per_scan_median"], 1e-3 * np.array([1e3, 1e4, 1e5]) ** 0.8)
    np.testing.assert_allclose(t["cpu_s_per_scan_max"] / t["cpu_s_per_scan_min"], 1.3 / 0.9)
    np.testing.assert_allclose(t["slope_cpu_vs_n"], 0.8)
    assert (t["peak_rss_mb_median"] == 101).all() and (t["load_mean"] == 2.0).all()


def test_lazy_gnn_jpda_on_the_catalogue_scans_hold_the_eager_posterior(cfg):
    c = dict(cfg, n_scans=40)
    df = lazy_sht_timing(c, 300, 2, n_scans=40).set_index(["tracker", "mode"])
    for name in ("gnn", "jpda"):
        lazy = df.loc[(name, "lazy")]
        assert lazy["same_in_view"] and lazy["max_in_view_diff"] <= 1e-10
        assert lazy["max_x_diff"] <= 1e-10 and lazy["max_P_diff"] <= 1e-10
        # out-of-view tracks were really deferred: far fewer predicted per scan than held
        assert lazy["predicted_per_scan"] < 0.2 * df.loc[(name, "eager_in_view")]["predicted_per_scan"]


def test_a_run_over_the_time_limit_is_stopped_and_its_tracker_skipped_at_that_n_and_above(cfg):
    """``timeout_s`` far below a process's start-up: the first run of each tracker at the smallest size times
    out, every later run of it (larger N, later repetitions) is skipped; the summary counts them and gives NaN
    figures; a bad limit is refused by name."""
    c = dict(cfg, scale=dict(cfg["scale"], sizes=[60, 100], runs=2, trackers=["gnn", "glmb"], timeout_s=0.01))
    runs = scale_runs(c, 3, log=lambda s: None)
    assert list(zip(runs["tracker"], runs["n_objects"], runs["run"], runs["status"])) == [
        ("gnn", 60, 0, "timed_out"), ("glmb", 60, 0, "timed_out"), ("gnn", 100, 0, "skipped"),
        ("glmb", 100, 0, "skipped"), ("gnn", 60, 1, "skipped"), ("glmb", 60, 1, "skipped"),
        ("gnn", 100, 1, "skipped"), ("glmb", 100, 1, "skipped")]
    t = scale_summary(runs).set_index(["tracker", "n_objects"])
    assert t.loc[("gnn", 60), ["runs", "runs_timed_out", "runs_skipped"]].tolist() == [0, 1, 1]
    assert t.loc[("gnn", 100), ["runs", "runs_timed_out", "runs_skipped"]].tolist() == [0, 0, 2]
    assert np.isnan(t.loc[("glmb", 60), "real_time_factor_median"]) and np.isnan(t.loc[("glmb", 60), "slope_cpu_vs_n"])
    assert np.isfinite(t.loc[("glmb", 60), "load_mean"]) and np.isnan(t.loc[("glmb", 100), "load_mean"])
    with pytest.raises(ValueError, match=r"^scale\.timeout_s must be > 0"):
        scale_runs(dict(c, scale=dict(c["scale"], timeout_s=0)), 3)


def test_a_summary_with_some_runs_stopped_takes_the_finished_ones():
    rows = [dict(tracker="a", n_objects=n, run=k, status="done", n_scans=10, in_view_per_scan=n / 100,
                 returns_per_scan=n / 110, cpu_s_per_scan=1e-4 * n * f, us_per_object_in_view=1.0,
                 us_per_object=1.0, us_per_return=1.0, real_time_factor=10 / (1e-4 * n * f), peak_rss_mb=100.0,
                 load_before=1.0, load_after=3.0) for n in (1000, 10000) for k, f in enumerate((1.0, 2.0))]
    rows.append(dict(tracker="a", n_objects=100000, run=0, status="timed_out", load_before=5.0, load_after=7.0))
    rows.append(dict(tracker="a", n_objects=100000, run=1, status="skipped"))
    t = scale_summary(pd.DataFrame(rows)).set_index("n_objects")
    np.testing.assert_allclose(t.loc[1000, "cpu_s_per_scan_median"], 0.15)  # median of 0.1 and 0.2
    np.testing.assert_allclose(t["slope_cpu_vs_n"], 1.0)  # over the two sizes that finished
    assert t.loc[100000, "runs"] == 0 and t.loc[100000, "load_mean"] == 6.0


def test_a_steady_state_start_keeps_the_priors_at_the_epoch_and_shifts_the_scans(cfg):
    """``start_after_s``: the population simulated from that many seconds after the epoch (its first scan is the
    epoch-started run's scan 2 at 20 s, same SGP4 instant), the priors the same states at the epoch (same seeded
    errors), so a tracker predicts each object over the whole gap; a negative value is refused."""
    from hypotrack.experiments.ssa_catalogue.run import initial_tracks
    from hypotrack.experiments.ssa_catalogue.scale import clone_scenario

    _, unk0, sc0, seed0 = clone_scenario(cfg, 60, 3, n_scans=4, chunk=25)
    _, unk1, sc1, seed1 = clone_scenario(cfg, 60, 3, n_scans=4, chunk=25, start_after_s=20.0)
    assert seed0 == seed1 and np.array_equal(unk0, unk1)
    np.testing.assert_allclose(sc1.states(np.array([0.0]))[0], sc0.states(np.array([20.0]))[0], rtol=0, atol=1e-6)
    m0, P0, l0 = initial_tracks(sc0, unk0, cfg, seed0)
    m1, P1, l1 = initial_tracks(sc1, unk1, cfg, seed1, at=-20.0)
    np.testing.assert_array_equal(l0, l1)
    np.testing.assert_array_equal(P0, P1)
    np.testing.assert_allclose(m1, m0, rtol=0, atol=1e-6)
    assert not np.allclose(sc1.states(np.array([0.0]))[0], sc0.states(np.array([0.0]))[0], atol=1.0)  # 20 s apart
    r = measure_run(dict(cfg, scale=dict(cfg["scale"], start_after_s=600.0)), "gnn", 60, 3)
    assert r["start_after_s"] == 600.0 and r["n_scans"] == 3
    with pytest.raises(ValueError, match=r"^scale\.start_after_s must be >= 0 .*got -1\.0$"):
        measure_run(dict(cfg, scale=dict(cfg["scale"], start_after_s=-1.0)), "gnn", 60, 3)


def test_a_failed_run_is_recorded_with_its_reason_and_its_tracker_skipped_at_that_n_and_above(cfg, monkeypatch):
    """A run whose process fails (here glmb at N = 100: a stand-in for an out-of-memory kill) is a ``failed`` row with
    the reason, later runs of that tracker at N = 100 and above are skipped, the other tracker runs on; the summary
    counts the failure and the scale record's cell says so."""
    import hypotrack.experiments.ssa_catalogue.scale as scale
    from hypotrack.experiments.ssa_catalogue.scale_record import scale_record_markdown

    def fake(cfg, tracker, n, seed, timeout=None):
        if tracker == "glmb" and n >= 100:
            raise scale.ScaleRunFailed(f"scale run {tracker} at N = {n} failed: killed by signal 9", "killed by signal 9")
        return dict(tracker=tracker, n_objects=n, n_scans=2, in_view_per_scan=1.0, returns_per_scan=1.0, cpu_s=0.2,
                    cpu_s_per_scan=0.1 * n / 60, us_per_object_in_view=1.0, us_per_object=1.0, us_per_return=1.0,
                    real_time_factor=100.0, peak_rss_mb=100.0, wall_s=1.0, load_before=1.0, load_after=1.0,
                    blas_threads="1")

    monkeypatch.setattr(scale, "run_isolated", fake)
    c = dict(cfg, scale=dict(cfg["scale"], sizes=[60, 100, 1000], runs=2, trackers=["gnn", "glmb"]))
    runs = scale_runs(c, 3, log=lambda s: None)
    got = {(t, n, r): s for t, n, r, s in zip(runs["tracker"], runs["n_objects"], runs["run"], runs["status"])}
    assert got[("glmb", 100, 0)] == "failed" and got[("glmb", 60, 0)] == got[("glmb", 60, 1)] == "done"
    assert got[("glmb", 1000, 0)] == got[("glmb", 100, 1)] == got[("glmb", 1000, 1)] == "skipped"
    assert all(got[("gnn", n, r)] == "done" for n in (60, 100, 1000) for r in (0, 1))
    assert runs.loc[runs["status"] == "failed", "error"].tolist() == ["killed by signal 9"]
    t = scale_summary(runs).set_index(["tracker", "n_objects"])
    assert t.loc[("glmb", 100), ["runs", "runs_failed", "runs_skipped"]].tolist() == [0, 1, 1]
    assert t.loc[("glmb", 1000), ["runs", "runs_failed", "runs_skipped"]].tolist() == [0, 0, 2]
    md = scale_record_markdown(scale_summary(runs))
    assert "not run (stopped at a smaller N)" in md  # glmb at the largest N: skipped after its failure at 100
    assert "recorded as failed" in md

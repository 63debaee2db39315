"""The SSA tracking driver (hypotrack.experiments.ssa) on tiny SSA scenarios.

Oracles: the scenario's own truth (a near-perfect sensor must give the catalogue's size and
measurement-level errors), exhaustive H-FISST (R-FISST must find the same posterior), and
hand-built estimate tables whose verdicts are known by construction.
"""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments import ssa as st
from hypotrack.reporting.ledger import STATUSES
from hypotrack.scenarios.ssa import SSAParams, prior_table, simulate_ssa
from hypotrack.scenarios.tables import state_columns, write_table

ROOT = Path(__file__).resolve().parents[4]
SIGMA = 1.0  # km, the scenarios' measurement noise


def _scenario(**kw):
    params = SSAParams(n_objects=5, n_known=4, **kw)
    sim = simulate_ssa(params, 3)
    return sim, st.scenario_from_tables(params, sim.truth, sim.scans, prior_table(sim))


def _run(scenario, kind, seed=1, **settings):
    tracker = st.make_tracker(scenario, st.TrackerSettings(kind=kind, max_hypotheses=10, n_birth_regions=2,
                                                           **settings), st.tracker_seed(seed, "test", kind))
    snapshots = st.snapshot_scans(len(scenario.times), [0.1, 0.5, 1.0])
    return st.run_tracker(tracker, scenario, snapshots=snapshots, progress=None)


@pytest.fixture(scope="module")
def perfect():
    """Near-perfect sensor: p_D = 0.999, no clutter; one birth enters mid-run. No deaths (β = 0):
    with p_D → 1 a death would explain a missed detection at the FOV edge better than a miss."""
    sim, scenario = _scenario(n_scans=30, p_D=0.999, clutter_rate=0.0)
    run = _run(scenario, "rfisst", beta=0.0)
    metrics, matched = st.evaluate_map(run.map_estimates, scenario)
    return scenario, run, metrics, matched


@pytest.fixture(scope="module")
def cluttered():
    """p_D = 0.95, two clutter returns per scan, births and deaths; R-FISST and exhaustive
    H-FISST with the same gate."""
    _, scenario = _scenario(n_scans=25, p_D=0.95, clutter_rate=2.0)
    opts = dict(gate_probability=1 - 1e-9, beta=1e-4)
    return scenario, {kind: _run(scenario, kind, **opts) for kind in ("hfisst", "rfisst")}, opts


# --- scenario from the saved tables -----------------------------------------------------------


def test_scenario_from_tables_rebuilds_the_simulated_scenario():
    sim, scenario = _scenario(n_scans=30, p_D=0.999, clutter_rate=0.0)
    np.testing.assert_array_equal(scenario.first_in_view_scan, sim.first_in_view_scan)
    np.testing.assert_array_equal(scenario.birth_ids, sim.birth_ids)
    np.testing.assert_allclose(scenario.prior_means, sim.prior_means, rtol=0, atol=0)
    assert scenario.motion == sim.motion
    assert scenario.sensor.detection == sim.sensor.detection and scenario.sensor.clutter == sim.sensor.clutter
    np.testing.assert_array_equal(scenario.sensor.measurement.R, sim.sensor.measurement.R)
    assert scenario.birth_ids.tolist() == [4] and 0 < scenario.first_in_view_scan[4] < 30
    with pytest.raises(ValueError, match="n_scans"):
        st.scenario_from_tables(SSAParams(n_objects=5, n_known=4, n_scans=31), sim.truth, sim.scans,
                                prior_table(sim))
    with pytest.raises(ValueError, match="objects"):
        st.scenario_from_tables(SSAParams(n_objects=6, n_known=4, n_scans=30), sim.truth, sim.scans,
                                prior_table(sim))


def test_catalogue_holds_the_known_objects_and_each_birth_from_its_first_view():
    _, scenario = _scenario(n_scans=30, p_D=0.999, clutter_rate=0.0)
    cat = st.catalogue_mask(scenario)
    f = scenario.first_in_view_scan[4]
    assert cat[:, :4].all()
    assert not cat[:f, 4].any() and cat[f:, 4].all()


# --- near-perfect sensor: the truth is the oracle ---------------------------------------------


def test_perfect_sensor_expected_number_is_the_catalogue_size(perfect):
    scenario, run, metrics, _ = perfect
    f = scenario.first_in_view_scan[4]
    e = run.summary["expected_number"].to_numpy()
    n_true = metrics["n_catalogue"].to_numpy()
    # A lone first return of a newborn is as well explained by clutter (α = 1e-3): the birth is
    # accepted at its second detection, so the entry scan and the next are excused.
    settled = np.ones(len(e), dtype=bool)
    settled[f:f + 2] = False
    np.testing.assert_allclose(e[settled], n_true[settled], rtol=0, atol=0.01)
    assert n_true[0] == 4 and n_true[-1] == 5
    assert run.summary["map_n_objects"].iloc[-1] == 5


def test_perfect_sensor_errors_are_at_the_measurement_noise_level(perfect):
    _, _, metrics, matched = perfect
    # Every estimate of an object in view is within its error bound and no object is lost.
    est = matched[matched["role"] == "estimate"]
    assert (est["status"] == "correct").all()
    assert metrics["n_missed"].sum() <= 1  # at most the birth's entry scan
    # OSPA (p = 2) is the RMS position error: below σ√2 (a single measurement's error) once
    # the filter has averaged several returns, and not implausibly small.
    in_view_ospa = metrics["ospa_in_view"].dropna()
    assert 0.2 * SIGMA < in_view_ospa.mean() < np.sqrt(2) * SIGMA
    # Consistency: the squared Mahalanobis error of a 2-D position is chi-square(2), mean 2.
    d2 = est.loc[est["in_view"], "d2"]
    assert len(d2) > 60
    assert 0.8 < d2.mean() < 3.2


def test_no_objects_at_all_is_a_normal_case():
    """An empty sky with clutter: no initial object, no birth; the filter must stay near 0 objects."""
    params = SSAParams(n_objects=0, n_known=0, n_scans=12, clutter_rate=1.0)
    sim = simulate_ssa(params, 2)
    scenario = st.scenario_from_tables(params, sim.truth, sim.scans, prior_table(sim))
    run = _run(scenario, "rfisst")
    assert run.summary["expected_number"].max() < 0.05  # a lone clutter return is not a birth
    metrics, matched = st.evaluate_map(run.map_estimates, scenario)
    assert run.summary["map_n_objects"].max() == 0 and len(run.map_estimates) == 0
    # Nothing in view on either side: in-view OSPA undefined, catalogue OSPA of two empty sets 0.
    assert (metrics["n_catalogue"] == 0).all() and metrics["ospa_in_view"].isna().all()
    assert (metrics["ospa_catalogue"] == 0).all() and len(matched) == 0


# --- R-FISST against exhaustive H-FISST -------------------------------------------------------


def test_rfisst_finds_the_exhaustive_hfisst_posterior(cluttered):
    scenario, runs, _ = cluttered
    h, r = runs["hfisst"], runs["rfisst"]
    np.testing.assert_allclose(r.summary["expected_number"], h.summary["expected_number"], rtol=0, atol=1e-6)
    agreement = st.map_agreement(h.map_estimates, r.map_estimates, scenario.prior_ids)
    assert agreement["agree"].all()
    ch = h.cardinality.set_index(["scan", "n_objects"])["probability"]
    cr = r.cardinality.set_index(["scan", "n_objects"])["probability"]
    both = pd.concat([ch, cr], axis=1).fillna(0.0).to_numpy()
    np.testing.assert_allclose(both[:, 0], both[:, 1], rtol=0, atol=1e-6)
    # The scenario is not trivial: births, clutter and more than one hypothesis with weight.
    assert h.summary["effective_hypotheses"].max() > 1.05
    assert h.summary["expected_number"].iloc[-1] == pytest.approx(5.0, abs=0.05)


def test_same_seed_gives_byte_identical_tables(cluttered, tmp_path):
    scenario, runs, opts = cluttered
    again = _run(scenario, "rfisst", **opts)
    for name in st.TrackingRun.TABLES:
        a, b = tmp_path / f"a_{name}.csv", tmp_path / f"b_{name}.csv"
        write_table(getattr(runs["rfisst"], name), a)
        write_table(getattr(again, name), b)
        assert a.read_bytes() == b.read_bytes(), name


# --- evaluation and agreement on hand-built tables --------------------------------------------


def _estimates_at(scenario, k, ids, labels=None, shift=None, var=0.25):
    X = scenario.truth[scenario.truth["scan"] == k].set_index("target").loc[ids, state_columns(4)].to_numpy()
    if shift is not None:
        X = X + shift
    df = pd.DataFrame(X, columns=state_columns(4))
    df.insert(0, "label", np.asarray(ids if labels is None else labels, dtype=np.int64))
    df.insert(0, "scan", k)
    return df.assign(cov_0_0=var, cov_0_1=0.0, cov_1_1=var)


def test_evaluate_map_gives_the_papers_verdicts(perfect):
    scenario = perfect[0]
    f = int(scenario.first_in_view_scan[4])
    K = len(scenario.times)
    rows = [_estimates_at(scenario, k, [0, 1, 2, 3]) for k in range(K)]
    exact = pd.concat(rows, ignore_index=True)
    metrics, matched = st.evaluate_map(exact, scenario)
    assert metrics.loc[: f - 1, "ospa_catalogue"].max() == 0.0
    assert (metrics.loc[f:, "n_missed"] == 1).all()  # the birth, not in these estimates
    assert (matched.loc[matched["role"] == "estimate", "status"] == "correct").all()

    shift = np.zeros((4, 4))
    shift[0, 0] = 50.0  # object 0 estimated 50 km off (100 standard deviations)
    shifted = _estimates_at(scenario, 0, [0, 1, 2, 3], shift=shift)
    swapped = _estimates_at(scenario, 1, [0, 1, 2, 3], labels=[0, 2, 1, 3])
    born = _estimates_at(scenario, f, [0, 1, 2, 3, 4], labels=[0, 1, 2, 3, 99])
    early = _estimates_at(scenario, f - 1, [0, 1, 2, 3, 4], labels=[0, 1, 2, 3, 99])
    table = pd.concat([shifted, swapped, born, early], ignore_index=True)
    _, m = st.evaluate_map(table, scenario)
    est = m[m["role"] == "estimate"].set_index(["scan", "id"])
    assert est.loc[(0, 0), "status"] == "incorrect" and est.loc[(0, 1), "status"] == "correct"
    assert est.loc[(1, 1), "status"] == "incorrect" and est.loc[(1, 2), "status"] == "incorrect"
    assert est.loc[(f, 99), "status"] == "correct" and est.loc[(f, 99), "truth_id"] == 4
    assert est.loc[(f - 1, 99), "status"] == "false"  # the birth is not yet catalogued
    truth = m[m["role"] == "truth"].set_index(["scan", "id"])
    assert truth.loc[(0, 0), "status"] == "missed" and truth.loc[(f - 1, 4), "status"] == "unseen"


def test_map_agreement_separates_rounding_from_a_different_hypothesis(cluttered):
    scenario, runs, _ = cluttered
    a = runs["hfisst"].map_estimates
    b = a.copy()
    born = ~b["label"].isin(scenario.prior_ids)
    b.loc[born, "label"] += 1000  # newborn labels are bookkeeping: paired by position
    b["state_0"] += 5e-6  # half the last digit of a 10-digit CSV position: rounding, not a difference
    k = int(b["scan"].iloc[len(b) // 2])
    first = b.index[b["scan"] == k][0]
    b.loc[first, "state_1"] += 0.01  # ten metres: a different association somewhere
    ag = st.map_agreement(a, b, scenario.prior_ids).set_index("scan")
    assert not ag.loc[k, "agree"] and ag.loc[k, "same_objects"]
    assert ag.drop(index=k)["agree"].all()
    dropped = st.map_agreement(a, b.drop(index=first), scenario.prior_ids).set_index("scan")
    assert not dropped.loc[k, "same_objects"] and not dropped.loc[k, "agree"]


def test_snapshot_scans_follow_the_fraction_of_the_run():
    np.testing.assert_array_equal(st.snapshot_scans(720, [0.0, 0.1, 0.5, 0.75, 1.0]), [1, 72, 360, 539, 719])
    np.testing.assert_array_equal(st.snapshot_scans(1, [0.0, 1.0]), [0])
    with pytest.raises(ValueError, match="fractions"):
        st.snapshot_scans(10, [1.2])


# --- configuration ----------------------------------------------------------------------------


def test_tracker_settings_from_the_shipped_config():
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    r = st.TrackerSettings.from_config(config["ssa50"], "rfisst")
    assert (r.kind, r.max_hypotheses, r.gate_probability, r.population) == ("rfisst", 100, None, True)
    assert (r.alpha, r.beta, r.n_birth_regions, r.label) == (1e-3, 1e-4, 10, "R-FISST + completion")
    chain = st.TrackerSettings.from_config(config["ssa50"], "rfisst_chain")
    assert (chain.completion_rounds, chain.label) == (0, "R-FISST, paper chain")
    assert config["ssa50"]["primary"] == "rfisst_chain"
    for section in ("ssa50", "ssa15"):
        settings = {n: st.TrackerSettings.from_config(config[section], n) for n in config[section]["trackers"]}
        assert st.completion_pair(settings) == ("rfisst_chain", "rfisst")
    h = st.TrackerSettings.from_config(config["ssa15"], "homht")
    assert (h.kind, h.population, h.gate_probability) == ("homht", False, config["ssa15"]["gate_probability"])
    f = st.TrackerSettings.from_config(config["ssa15"], "rfisst_fixed")
    assert (f.kind, f.population, f.label) == ("rfisst", False, "R-FISST + completion, fixed number")
    for pair in config["ssa15"]["comparisons"]:
        assert set(pair) <= set(config["ssa15"]["trackers"])
    with pytest.raises(ValueError, match="unknown tracker"):
        st.TrackerSettings.from_config(config["ssa15"], "gnn")
    hb = st.TrackerSettings(kind="homht", population=True)  # HOMHT with R-FISST's births and deaths (Eq. 30)
    assert hb.population and hb.label.endswith("with births and deaths")
    with pytest.raises(ValueError, match="kind"):
        st.TrackerSettings(kind="jpda")
    with pytest.raises(ValueError, match="gate_probability"):
        st.TrackerSettings(gate_probability=1.0)
    with pytest.raises(ValueError, match="max_hypotheses"):
        st.TrackerSettings(max_hypotheses=0)
    with pytest.raises(ValueError, match="completion_rounds"):
        st.TrackerSettings(completion_rounds=-1)


def test_completion_rounds_reach_the_generator_and_the_comparison_tables(perfect):
    """The named setting builds the paper's chain (0 rounds) or chain + completion, and the
    completion tables and claims report hand-computable numbers."""
    scenario = perfect[0]
    for rounds in (0, 2):
        tracker = st.make_tracker(scenario, st.TrackerSettings(completion_rounds=rounds, n_birth_regions=2), 1)
        assert tracker.generator.completion_rounds == rounds
    settings = {"chain": st.TrackerSettings(completion_rounds=0), "comp": st.TrackerSettings(completion_rounds=2),
                "homht": st.TrackerSettings(kind="homht", population=False)}
    assert st.completion_pair(settings) == ("chain", "comp")
    assert st.completion_pair({"comp": settings["comp"], "homht": settings["homht"]}) is None
    summary = lambda ch: pd.DataFrame({"scan": [0, 1, 2, 3], "n_children": ch, "effective_hypotheses": 1.0,
                                       "expected_number": [3.0, 3.0, 3.5, 4.0]})
    agree = lambda flags: pd.DataFrame({"agree": flags})
    table = st.completion_table({"chain": summary([0, 2, 4, 9]), "comp": summary([0, 6, 6, 9]),
                                 "homht": summary([0, 1, 1, 1])}, settings,
                                {"chain": agree([True, False, True, True]), "comp": agree([True] * 4)},
                                reference="homht")
    t = table.set_index("tracker")
    assert t.loc["chain", "children_per_scan_mean"] == 5.0 and t.loc["comp", "children_total"] == 21
    assert (t.loc["chain", "map_agreement"], t.loc["comp", "map_agreement"]) == (0.75, 1.0)
    assert np.isnan(t.loc["homht", "map_agreement"]) and t.loc["homht", "reference"] == ""
    timing = st.completion_timing({n: pd.DataFrame({"scan": [0, 1, 2], "seconds": [0.0, 1.0, 3.0],
                                                    "cpu_seconds": [0.0, 1.0, 1.0 + (n == "comp")]})
                                   for n in settings}, settings)
    claims, macros, timing_claims, timing_macros = st.completion_claims("ssa15", table, timing, ("chain", "comp"),
                                                                        reference_label="HOMHT")
    assert (macros["CompletionChildrenChain"], macros["CompletionChildrenCompletion"]) == (5.0, 7.0)
    assert macros["CompletionChildrenRatio"] == pytest.approx(1.4)
    assert (macros["CompletionAgreementChain"], macros["CompletionAgreement"]) == ("75.0", "100.0")
    assert timing_macros["CompletionCpuRatio"] == pytest.approx(1.5)
    assert {c.status for c in claims + timing_claims} == {"extension"}
    assert {c.evidence for c in claims + timing_claims} == {"measurement"}


# --- claims and figures -----------------------------------------------------------------------


def test_claims_and_figures_from_the_runs(perfect, cluttered, tmp_path):
    scenario, run, metrics, matched = perfect
    K = len(scenario.times)
    merged = run.summary.merge(metrics, on="scan")
    births = st.birth_recognition(matched, scenario)
    assert births["tracked_at_end"].all() and (births["delay_scans"] <= 2).all()
    snaps = st.snapshot_scans(K, [0.1, 0.5, 1.0])
    claims = st.ssa50_claims(merged, run.cardinality, run.weights, matched, births, estimate_scans=snaps,
                             n_scans=K, error_bound_probability=0.9999)
    by_item = {c.item: c for c in claims}
    assert all(c.status in STATUSES for c in claims)
    assert by_item["expected number of objects at the end"].status == "reproduced"
    assert by_item["R-FISST recognises every birth"].status == "reproduced"

    c_scen, runs, _ = cluttered
    ev = {k: st.evaluate_map(r.map_estimates, c_scen) for k, r in runs.items()}
    c_metrics = pd.concat([runs[k].summary.merge(ev[k][0], on="scan").assign(tracker=k) for k in runs])
    c_matched = pd.concat([ev[k][1].assign(tracker=k) for k in runs])
    agreements = {("rfisst", "hfisst"): st.map_agreement(runs["rfisst"].map_estimates,
                                                         runs["hfisst"].map_estimates, c_scen.prior_ids)}
    labels = {"rfisst": "R-FISST", "hfisst": "H-FISST"}
    c_claims = st.ssa15_claims(c_metrics, agreements, c_matched, estimate_scans=snaps,
                               n_scans=len(c_scen.times), error_bound_probability=0.9999, labels=labels)
    assert c_claims[0].status == "reproduced"  # same MAP hypothesis at every scan
    assert c_claims[1].status == "reproduced"  # hence never a worse OSPA

    figures = {
        "weights": st.plot_weight_snapshots(run.weights, K, title="weights"),
        "estimates": st.plot_estimate_snapshots(matched[matched["scan"].isin(snaps)], scenario.fov, K,
                                                title="estimates"),
        "expected": st.plot_expected_number(merged, run.cardinality, title="expected number"),
        "ospa": st.plot_ospa(merged, st.OSPASettings(), title="ospa", labels={"": "R-FISST"}),
        "comparison": st.plot_comparison(agreements, c_metrics, st.OSPASettings(), labels=labels,
                                         title="comparison"),
    }
    for name, fig in figures.items():
        for ax in fig.axes:
            if ax.get_visible():
                assert ax.get_title(), name
                assert ax.get_ylabel() or ax.get_shared_y_axes().get_siblings(ax) != [ax], name
        assert fig.texts or fig._suptitle is not None, name
        st.save_figure(fig, tmp_path / f"{name}.pdf", tmp_path / f"{name}.png", dpi=40)
        assert (tmp_path / f"{name}.pdf").stat().st_size > 5_000, name

"""SSA verdicts over chain seeds (hypotrack.experiments.ssa_seeds.chains): the report's realisation kept to the
last bit, a new MCMC stream per chain seed, and chain-seed ledger rows judged jointly with the scenario-seed rows."""

import copy
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.experiments.ssa import scenario_from_files
from hypotrack.experiments.ssa_seeds import chains as ch
from hypotrack.experiments.ssa_seeds import claims as sc
from hypotrack.experiments.ssa_seeds import run as ss
from hypotrack.experiments.ssa_seeds.figures import CHAIN_COLOR, SEED_COLOR, plot_distributions
from hypotrack.reporting.claim_verdicts import claim_verdicts, evidence_table, load_claims_file
from hypotrack.reporting.findings import chain_spread_macros
from hypotrack.reporting.ledger_io import read_claims, write_claims
from hypotrack.scenarios.ssa import prior_table, scenario_from_config
from hypotrack.scenarios.tables import write_table

ROOT = Path(__file__).resolve().parents[4]


def _config(n_scans=5):
    config = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    config["ssa"]["n_scans"] = n_scans  # the report's realisation, shortened
    config["ssa_seeds"].update(n_seeds=3, n_scans=4, n_steps=200, n_chain_seeds={"ssa50": 2})
    for case in ("ssa50", "ssa15"):
        config[case]["max_hypotheses"] = 3
    return config


def _saved_tables(config, case, tmp_path):
    """What rule ssa_scenario writes and rule ssa50_run reads back."""
    drawn = scenario_from_config(config, case)
    paths = [tmp_path / f"{case}_{t}.csv" for t in ("truth", "scans", "prior")]
    for table, path in zip((drawn.truth, drawn.scans, prior_table(drawn)), paths):
        write_table(table, path)
    return scenario_from_files(config, case, *paths)


def _same_scenario(a, b):
    pd.testing.assert_frame_equal(a.truth, b.truth, check_exact=True)
    pd.testing.assert_frame_equal(a.scans, b.scans, check_exact=True)
    for name in ("prior_ids", "prior_means", "prior_covs", "birth_ids", "first_in_view_scan", "times"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_the_chain_scenario_is_the_reports_realisation_to_the_last_bit(tmp_path):
    config = _config()
    report = _saved_tables(config, "ssa50", tmp_path)
    _same_scenario(ch.chain_scenario(config, "ssa50"), report)
    # the saved tables' 10 significant digits are what the report's runs see, not the drawn floats
    drawn = scenario_from_config(config, "ssa50")
    assert not drawn.scans[["z_0", "z_1"]].equals(report.scans[["z_0", "z_1"]])
    # ssa_seeds.n_scans shortens the scenario-seed realisations, never the report's
    other = copy.deepcopy(config)
    other["ssa_seeds"]["n_scans"] = 3
    _same_scenario(ch.chain_scenario(other, "ssa50"), report)
    # a scenario-seed realisation is another sky (seed 0 is not the report's)
    assert len(ss.seed_scenario(config, "ssa50", 0).times) == 4 and len(report.times) == 5
    with pytest.raises(ValueError, match="case must be one of"):
        ch.chain_scenario(config, "ssa20")


def test_chain_seeds_run_on_the_reports_scenario_each_with_its_own_stream(tmp_path, monkeypatch):
    config = _config()
    report = _saved_tables(config, "ssa50", tmp_path)
    seen = []
    make = ss.make_tracker

    def spy(scenario, settings, rng):
        seen.append((scenario, settings.label, rng.bit_generator.state["state"]["state"]))
        return make(scenario, settings, rng)

    monkeypatch.setattr(ss, "make_tracker", spy)
    rows0, timing0 = ch.run_chain_seed(config, "ssa50", 0, progress=None)
    rows1, _ = ch.run_chain_seed(config, "ssa50", 1, progress=None, scenario=report)
    scen_rows, _ = ss.run_seed(config, 0, progress=None)
    assert len(seen) == 2 + 2 + 2 + 5  # ssa50: rfisst_chain, rfisst per chain seed; the scenario seed: both cases
    for scenario, _, _ in seen[:4]:
        _same_scenario(scenario, report)
    # every tracker's stream is the documented key's; chain seeds 0 and 1 and the scenario seed all differ
    expect = {(j, t): np.random.default_rng(experiment_seeds(config["seed"], f"ssa_seeds/ssa50/chain/{j}/{t}", 1)[0])
              .bit_generator.state["state"]["state"] for j in (0, 1) for t in ("rfisst_chain", "rfisst")}
    assert [s[2] for s in seen[:4]] == [expect[(0, "rfisst_chain")], expect[(0, "rfisst")],
                                        expect[(1, "rfisst_chain")], expect[(1, "rfisst")]]
    assert len({s[2] for s in seen}) == len(seen)
    assert ch.chain_stream("ssa50", 3, "rfisst") == "ssa_seeds/ssa50/chain/3/rfisst"
    # rows: the R-FISST trackers and the blind control; the blind tracker uses no stream, so the same realisation
    # gives it the same row on every chain seed
    assert list(rows0.columns) == ch.CHAIN_COLUMNS and list(rows0["tracker"]) == ["rfisst_chain", "rfisst", "blind"]
    assert list(timing0["tracker"]) == ["rfisst_chain", "rfisst"] and (rows1["chain_index"] == 1).all()
    blind = [r[r["tracker"] == "blind"].drop(columns="chain_index").reset_index(drop=True) for r in (rows0, rows1)]
    pd.testing.assert_frame_equal(*blind)
    # the report's realisation has its own number of objects in the catalogue; determinism per chain seed
    assert (rows0["n_scans"] == 5).all() and (scen_rows["n_scans"] == 4).all()
    monkeypatch.setattr(ss, "make_tracker", make)
    again, _ = ch.run_chain_seed(config, "ssa50", 0, progress=None)
    pd.testing.assert_frame_equal(rows0, again)


def test_chain_cases_read_the_config_and_refuse_unknown_cases():
    config = _config()
    assert ch.chain_cases(config) == {"ssa50": 2}
    config["ssa_seeds"]["n_chain_seeds"] = {"ssa50": 0, "ssa15": 4}
    assert ch.chain_cases(config) == {"ssa15": 4}
    config["ssa_seeds"]["trackers"] = {"ssa50": ["rfisst"]}
    with pytest.raises(ValueError, match="ssa_seeds.n_chain_seeds names cases not in ssa_seeds.trackers"):
        ch.chain_cases(config)
    config["ssa_seeds"]["n_chain_seeds"] = {"ssa50": -1}
    with pytest.raises(ValueError, match="ssa_seeds.n_chain_seeds.ssa50"):
        ch.chain_cases(config)
    del config["ssa_seeds"]["n_chain_seeds"]
    assert ch.chain_cases(config) == {}


# ------------------------------------------------------------------ ledger rows and the joint verdict


def _table(p_end, index="seed_index", blind_p=0.0, births_missed=0):
    """Hand-made ssa50 rows of the paper chain (rfisst_chain) and the blind control, one per seed."""
    rows = []
    for i, p in enumerate(p_end):
        base = {"case": "ssa50", index: i, "n_scans": 720, "n_catalogue_end": 50, "births": 5,
                "birth_latency_mean": 1.0, "birth_latency_max": 2.0, "reference": "", "map_agreement": np.nan,
                "births_reference": "", "map_agreement_births": np.nan, "ospa_in_view_mean": 1.0,
                "ospa_catalogue_mean": 2.0}
        rows.append({**base, "tracker": "rfisst_chain", "label": "R-FISST, paper chain", "p_n_end": p,
                     "expected_number_end": 50.0, "expected_number_error": 0.0,
                     "births_tracked_end": 5 - (i < births_missed), "children_per_scan_mean": 9.0})
        rows.append({**base, "tracker": "blind", "label": "blind tracker", "p_n_end": blind_p,
                     "expected_number_end": 45.0, "expected_number_error": -5.0, "births_tracked_end": 0,
                     "reference": "rfisst_chain", "children_per_scan_mean": 0.0})
    return pd.DataFrame(rows)


TEN = [0.99, 1.0, 0.98, 1.0, 0.99, 1.0, 0.98, 1.0, 0.99, 1.0]  # mean 0.993, se 0.0026: reproduced (z = -2.69)


def test_chain_seed_rows_mirror_the_scenario_seed_rows():
    seeds = {c.key: c for c in sc.ssa_seeds_claims(_table(TEN))}
    chains = {c.key: c for c in sc.chain_seed_claims(_table([0.5, 0.52, 0.48], index="chain_index"))}
    assert sorted(chains) == sorted(k + sc.CHAIN_SUFFIX for k in seeds)
    for key, row in seeds.items():
        c = chains[key + sc.CHAIN_SUFFIX]
        # the same claim (its chain-seed half: one verdict per claim id in the ledger), published value and
        # tolerance; its own numbers
        assert (c.claim, c.published, c.tolerance, c.source) == (row.claim + " (over chain seeds)", row.published,
                                                                 row.tolerance, row.source)
        assert c.item.endswith("(over chain seeds)") and c.claim
    p = chains["ssa50_rfisst_chain_PEndChains"]
    assert (p.status, p.n, float(p.mean)) == ("not reproduced", "3", pytest.approx(0.5))
    assert p.note.startswith("over 3 chain seeds of the report's realisation; min 0.48, median 0.5, max 0.52")
    assert p.control.startswith("blind tracker") and "mean 0 over 3 chain seeds (not reproduced) -> fails" in p.control
    assert chains["ssa50_rfisst_chain_BirthsChains"].reproduced == "15 of 15 births over 3 chain seeds"
    one = {c.key: c for c in sc.chain_seed_claims(_table([1.0], index="chain_index"))}["ssa50_rfisst_chain_PEndChains"]
    assert one.status == "inconclusive" and "1 chain seed(s): too few" in one.note
    # the scenario-seed rows keep their words
    assert seeds["ssa50_rfisst_chain_PEnd"].note.startswith("over 10 scenario seeds;")
    assert seeds["ssa50_rfisst_chain_Births"].reproduced == "50 of 50 births over 10 seeds"


def _claims_file_verdicts(tmp_path, chain_p, spec=None, chain_births_missed=0):
    rows = sc.ssa_seeds_claims(_table(TEN)) + sc.chain_seed_claims(
        _table(chain_p, index="chain_index", births_missed=chain_births_missed))
    write_claims(rows, tmp_path / "claims.csv")
    ledger = read_claims([tmp_path / "claims.csv"])
    spec = spec or load_claims_file()
    return claim_verdicts(ledger, spec).set_index("id")["verdict"], evidence_table(ledger, spec)


def test_a_claim_reproduced_over_scenario_seeds_but_not_over_chain_seeds_is_not_reproduced(tmp_path):
    verdicts, ev = _claims_file_verdicts(tmp_path, [0.5, 0.52, 0.48])
    assert verdicts["000.fig11.p_end"] == "not reproduced"
    rows = ev[ev["claim"] == "000.fig11.p_end"].set_index("row")
    # the scenario-seed row itself reproduces; judged jointly with its chain-seed row it does not
    assert rows.loc["ssa_seeds/ssa50_rfisst_chain_PEnd", ["ledger_status", "status"]].tolist() == [
        "reproduced", "not reproduced"]
    # E[N] sits at 50 on every chain seed: that claim reproduces over both sources of randomness
    assert verdicts["000.fig11.expected_end"] == "reproduced"
    # without the joint entries the same rows only contradict each other
    loose = load_claims_file()
    loose = {**loose, "claims": [{**c, "evidence": [{k: v for k, v in e.items() if k != "joint"} if isinstance(e, dict)
                                                    else e for e in c["evidence"]]} for c in loose["claims"]]}
    verdicts, _ = _claims_file_verdicts(tmp_path, [0.5, 0.52, 0.48], spec=loose)
    assert verdicts["000.fig11.p_end"] == "contested"


def test_an_undecided_chain_seed_row_leaves_the_claim_undecided_and_both_positive_reproduce(tmp_path):
    # three chain seeds near 1: the interval is too wide to decide (inconclusive), so the claim is not reproduced
    verdicts, _ = _claims_file_verdicts(tmp_path, [0.99, 1.0, 0.98])
    assert verdicts["000.fig11.p_end"] == "inconclusive"
    verdicts, _ = _claims_file_verdicts(tmp_path, TEN)
    assert verdicts["000.fig11.p_end"] == "reproduced"
    # a birth missed on one chain seed: "every birth" is not reproduced, though every scenario seed tracked all
    verdicts, _ = _claims_file_verdicts(tmp_path, TEN, chain_births_missed=1)
    assert verdicts["000.sec4a.births"] == "not reproduced"


# ------------------------------------------------------------------ figure and findings macros


def test_the_figure_draws_each_chain_seed_row_under_its_scenario_seed_row():
    per_chain = _table([0.5, 0.52, 0.48], index="chain_index")
    fig = plot_distributions(_table(TEN), title="SSA verdicts over seeds", per_chain=per_chain)
    ax = fig.axes[list(ss.METRICS).index("p_n_end")]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["ssa50: R-FISST, paper chain",
                                                            "ssa50: R-FISST, paper chain, chain seeds"]
    dots = {line.get_color(): line for line in ax.lines if line.get_marker() == "o"}
    assert sorted(dots) == sorted([SEED_COLOR, CHAIN_COLOR])
    assert sorted(dots[CHAIN_COLOR].get_xdata()) == [0.48, 0.5, 0.52] and min(dots[CHAIN_COLOR].get_ydata()) > 0.5
    assert sorted(dots[SEED_COLOR].get_xdata()) == sorted(TEN) and max(dots[SEED_COLOR].get_ydata()) < 0.5
    assert "3 chain seeds" in fig._suptitle.get_text()


def test_chain_spread_macros_are_the_min_and_max_over_chain_seeds():
    per_chain = pd.concat([_table([0.5, 0.52, 0.48], index="chain_index"),
                           _table([0.91, 0.934, 0.87], index="chain_index").replace({"rfisst_chain": "rfisst"})])
    values = chain_spread_macros(per_chain[per_chain["tracker"] != "blind"])
    assert values == {"htFindingsChainSeedsN": "3", "htFindingsChainSeedsChainPEndMin": "0.48",
                      "htFindingsChainSeedsChainPEndMax": "0.52", "htFindingsChainSeedsCompletionPEndMin": "0.87",
                      "htFindingsChainSeedsCompletionPEndMax": "0.93"}
    with pytest.raises(ValueError, match="no rows for case 'ssa15'"):
        chain_spread_macros(per_chain, case="ssa15")

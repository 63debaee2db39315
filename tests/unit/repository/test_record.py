"""The committed record of the default run (paper/record/) is written only by its explicit step."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import yaml

from hypotrack.reporting import readme as readme_mod
from hypotrack.reporting.record import FILES, RECORD, config_differences, default_config, full_config, update_record

ROOT = Path(__file__).resolve().parents[3]


def _fake_run(tmp_path: Path, config: dict) -> Path:
    """A finished run's paper/ folder: the committed record's tables and the given config."""
    paper = tmp_path / "results" / "paper"
    paper.mkdir(parents=True)
    for name in ("ledger.csv", "ledger_timing.csv", "pipeline_timing.csv"):
        shutil.copyfile(RECORD / name, paper / name)
    (paper / "run_config.json").write_text(json.dumps(config))
    return tmp_path / "results"


def _quick_config() -> dict:
    default = yaml.safe_load((ROOT / "workflows/config/default.yaml").read_text())
    quick = yaml.safe_load((ROOT / "workflows/config/quick.yaml").read_text())
    for key, value in quick.items():  # Snakemake merges a --configfile over the default, section by section
        default[key] = {**default[key], **value} if isinstance(value, dict) and isinstance(default.get(key), dict) else value
    return default


def test_the_record_refuses_a_quick_run_and_names_what_differs(tmp_path):
    results = _fake_run(tmp_path, _quick_config())
    readme = tmp_path / "README.md"
    shutil.copyfile(ROOT / "README.md", readme)
    with pytest.raises(ValueError, match=r"not workflows/config/default.yaml \(differs at belief_space\.eq43\.n_offsets, .*cardinality\.n_runs"):
        update_record(results, record=tmp_path / "record", readme=readme)
    assert not (tmp_path / "record").exists()
    assert readme.read_text() == (ROOT / "README.md").read_text()


def test_the_record_takes_a_default_run_wherever_it_wrote(tmp_path):
    config = {**default_config(), "results": "/scratch/elsewhere"}
    results = _fake_run(tmp_path, config)
    readme = tmp_path / "README.md"
    readme.write_text((ROOT / "README.md").read_text().replace("claims of the five documents: **", "claims of the five documents: **1"))
    written = update_record(results, record=tmp_path / "record", readme=readme)
    assert sorted(p.name for p in written) == sorted([*FILES, "README.md"])
    for name in ("ledger.csv", "ledger_timing.csv", "pipeline_timing.csv"):
        assert (tmp_path / "record" / name).read_bytes() == (RECORD / name).read_bytes()
    # the README is regenerated from the new record: equal to the committed README's generated text
    assert readme_mod.check_readme(readme, tmp_path / "record" / "ledger.csv") is None


def test_an_unfinished_run_is_not_recorded(tmp_path):
    (tmp_path / "results" / "paper").mkdir(parents=True)
    with pytest.raises(FileNotFoundError, match="ledger.csv"):
        update_record(tmp_path / "results", record=tmp_path / "record", readme=tmp_path / "README.md")


def test_config_differences_are_dotted_keys():
    assert config_differences({"a": {"b": 1, "c": 2}, "d": 3}, {"a": {"b": 1, "c": 5}, "d": 3, "e": 1}) == ["a.c", "e"]
    assert config_differences({"a": {"b": [1, 2]}}, {"a": {"b": [1, 2]}}) == []


def test_the_record_holds_a_default_run():
    """The committed record's run_config.json is the default config (when a record with it is committed)."""
    path = RECORD / "run_config.json"
    if not path.exists():
        pytest.skip("record made before run_config.json was written")
    from hypotrack.reporting.record import comparable

    assert config_differences(comparable(json.loads(path.read_text())), comparable(default_config())) == []


def test_the_catalogue_record_joins_a_full_run_and_refuses_another(tmp_path):
    """paper/record/ssa_catalogue_full.csv: accuracy and timing joined per (tracker, N), written only
    from a run of full.yaml's ssa_catalogue section (a default-config run is refused, naming the sizes)
    by the experiment's own step; the README's catalogue block is rendered beside it
    (ssa_catalogue_full.md) and the README rewritten from it (slope by hand:
    log(70.9/6.6) / log(10855/300) = 0.66)."""
    from hypotrack.experiments.ssa_catalogue.record import update_catalogue_record

    full = full_config()
    src = tmp_path / "results" / "ssa_catalogue"
    src.mkdir(parents=True)
    (src / "summary.csv").write_text("tracker,n_objects,n_scans,mean_in_view,gospa_km,born,unknown_in_view\n"
                                     "glmb,300,60,2.0,1.5,1,1\nglmb,10855,60,105.7,52.0,34,39\n")
    (src / "summary_timing.csv").write_text(
        "tracker,n_objects,cpu_s_per_scan,cpu_ms_per_object_in_view,peak_bytes,mean_in_view\n"
        "glmb,10855,0.0709,0.67,40031470,105.7\nglmb,300,0.0066,3.3,1283569,2.0\n")
    from hypotrack.experiments.ssa_catalogue.run import evaluated_on

    # what the table job writes: the seed the runs used (the section's evaluated one) and the section
    seed = evaluated_on(full["ssa_catalogue"], full["seed"])[0]
    (src / "run_config.json").write_text(json.dumps({"seed": seed, "ssa_catalogue": full["ssa_catalogue"]}))
    record = tmp_path / "record"
    readme = tmp_path / "README.md"
    readme.write_text("x\n<!-- catalogue:begin -->\nold\n<!-- catalogue:end -->\n<!-- ledger:begin (generated by "
                      "`python -m hypotrack.reporting.record`; do not edit) -->\n<!-- ledger:end -->\n")
    written = update_catalogue_record(tmp_path / "results", record=record, readme=readme)
    assert sorted(p.name for p in written) == ["README.md", "ssa_catalogue_full.csv", "ssa_catalogue_full.md",
                                               "ssa_catalogue_full_config.json"]
    rows = (record / "ssa_catalogue_full.csv").read_text().splitlines()
    assert rows[0] == ("tracker,n_objects,n_scans,mean_in_view,gospa_km,born,unknown_in_view,cpu_s_per_scan,"
                       "cpu_ms_per_object_in_view,peak_bytes")
    assert rows[1:] == ["glmb,300,60,2,1.5,1,1,0.0066,3.3,1283569",
                        "glmb,10855,60,105.7,52,34,39,0.0709,0.67,40031470"]
    row = "| δ-GLMB (Gibbs), factored | 70.9 | 0.67 | 0.66 | 40 | 52 | 34 of 39 |"
    assert row in (record / "ssa_catalogue_full.md").read_text()
    text = readme.read_text()
    assert row in text and "old" not in text
    assert 10855 in full["ssa_catalogue"]["sizes"]  # the full run tracks the whole catalogue
    default = default_config()
    (src / "run_config.json").write_text(json.dumps({"seed": default["seed"], "ssa_catalogue": default["ssa_catalogue"]}))
    with pytest.raises(ValueError, match=r"ssa_catalogue\.sizes"):
        update_catalogue_record(tmp_path / "results", record=record, readme=readme)


def test_the_committed_catalogue_block_is_rendered_from_the_committed_table(tmp_path):
    """paper/record/ssa_catalogue_full.md (what the README quotes) is the rendering of the committed
    ssa_catalogue_full.csv by the current code; after a change to the rendering, re-render it with
    ``python -m hypotrack.experiments.ssa_catalogue.record --render``."""
    from hypotrack.experiments.ssa_catalogue.record import BLOCK, SCALE, TABLE, render_record

    if not (RECORD / TABLE).exists():
        pytest.skip("no whole-catalogue record committed yet")
    for name in (TABLE, SCALE):  # the block renders the timing-at-scale table too when it is committed
        if (RECORD / name).exists():
            shutil.copyfile(RECORD / name, tmp_path / name)
    assert render_record(tmp_path).read_text() == (RECORD / BLOCK).read_text()

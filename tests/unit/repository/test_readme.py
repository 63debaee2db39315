"""The README's library example runs and prints what it says (so the README stays true)."""

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parents[3] / "README.md"


def test_readme_example_runs_and_tracks_both_targets():
    code = re.search(r"```python\n(.*?)```", README.read_text(), re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {})
    lines = out.getvalue().splitlines()
    assert lines[0] == "63591"
    assert lines[1].startswith("2.0 ")  # expected number of objects after five scans
    nums = [float(x) for x in re.findall(r"-?\d+\.\d", " ".join(lines[1:])[4:])]
    # two tracks near the truths (-15, 0) and (15, 0) after five scans, within a few sigma of R = I
    assert abs(nums[0] + 15) < 3 and abs(nums[2] - 15) < 3
    assert lines[-1] == "[1 2]"  # estimates() keeps the labels given to initialise


def test_readme_quick_start_matches_ci():
    text = README.read_text()
    ci = (README.parent / ".ci" / "run").read_text()
    test_cmd = re.findall(r"```bash\n(python -m pip install -r envs/requirements-test.txt[^\n]*)\n```", text)
    assert len(test_cmd) == 1 and test_cmd[0] in ci
    assert "python -m pip install -r envs/requirements.txt -e . && snakemake -c2\n" in text


LEDGER = README.parent / "paper" / "record" / "ledger.csv"


def _ledger(tmp_path):
    tmp_path.mkdir(parents=True, exist_ok=True)
    """A small ledger of the real kinds, keyed as the claims file names them: a Monte Carlo row, a
    deterministic row, a qualitative row (each with a control that fails)."""
    from hypotrack.reporting.ledger import Claim, monte_carlo_claim, numeric_claim, write_claims
    from hypotrack.reporting.verdict import with_control

    rows = [with_control(monte_carlo_claim("closely_spaced", "MHT MOSPA", "003 Table 6.1", 0.1376, n=2000,
                                           mean=0.1385, se=0.0002, rel_tol=0.1, key="MospaMht",
                                           note="the OU set-up is reconstructed"), "random hypothesis", "0.2", False),
            with_control(numeric_claim("theory", "A(10, 5)", "000 Eq. 4", 63591, 63591, abs_tol=0,
                                       evidence="brute force", key="count_example"), "no false alarms", "30240", False),
            with_control(Claim("sht", "coalescence", "004", "qualitative", "holds", "--", "qualitative", "",
                               "measurement", key="coalescence"), "GNN", "no lag", False)]
    path = tmp_path / "ledger.csv"
    write_claims(rows, path)
    return path


def test_readme_ledger_block_matches_the_committed_ledger():
    from hypotrack.reporting.readme import check_readme

    assert check_readme(README, LEDGER) is None  # regenerate: python -m hypotrack.reporting.readme <ledger> README.md


def test_readme_block_is_generated_and_an_edited_ledger_value_fails(tmp_path):
    from hypotrack.reporting.readme import check_readme, main, readme_block

    ledger, readme = _ledger(tmp_path), tmp_path / "README.md"
    readme.write_text(README.read_text())
    assert main([str(ledger), str(readme)]) == 0
    assert check_readme(readme, ledger) is None and main(["--check", str(ledger), str(readme)]) == 0
    text = readme.read_text()
    # counted per claim: 0.1385 +/- 3.004 * 0.0002 lies inside 0.1376 +/- 10 %: the Monte Carlo row reproduces
    assert "3 claims of the five documents: **2 reproduced**, **0 reproduced in part**, **0 contested**, " \
           "**1 qualitative**, **0 not reproduced**" in text
    assert "**38 not run**" in text  # the claims file's other claims have no row in this ledger
    assert "| 003 | MOSPA of the MHT 0.1376 | Table 6.1 | **reproduced** |" in text  # one verdict per claim
    # the statuses that occur, none with a zero count
    assert "3 ledger rows: 2 reproduced, 1 qualitative. " in text and "paper/record/ledger.csv" in text
    # the full ledger is linked, not copied: no row-level table in the README
    assert "| experiment | item |" not in text and "hypotrack_report.pdf" in text
    # one value changed in the ledger (not in the README) -> the Monte Carlo verdict and the block change
    ledger.write_text(ledger.read_text().replace(",0.1385,", ",0.2,"))
    msg = check_readme(readme, ledger)
    assert msg is not None and "not reproduced" in msg and main(["--check", str(ledger), str(readme)]) == 1
    # a hand edit of the README block fails the same way
    ledger.write_text(ledger.read_text().replace(",0.2,", ",0.1385,"))
    assert check_readme(readme, ledger) is None
    readme.write_text(text.replace("**2 reproduced**", "**3 reproduced**"))
    assert check_readme(readme, ledger) is not None
    assert readme_block(None).startswith("No ledger is recorded yet")
    # timing rows beside the ledger (ledger_timing.csv) are counted as extensions
    from hypotrack.reporting.ledger import Claim, write_claims

    write_claims([Claim("perf_sht", "GNN speed-up", "extension", ">= 30x", "62x to 76x", "--", "extension", "",
                        "measurement")], ledger.with_name("ledger_timing.csv"))
    assert check_readme(readme, ledger) is not None
    assert main([str(ledger), str(readme)]) == 0 and "and 1 timing row " in readme.read_text()
    assert "4 ledger rows in all" in readme.read_text()


def _benchmark(root, rule, name, wall, cpu, rss, mtime):
    path = root / "benchmarks" / rule / f"{name}.tsv"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("s\th:m:s\tmax_rss\tmax_vms\tmax_uss\tmax_pss\tio_in\tio_out\tmean_load\tcpu_time\n"
                    f"{wall}\t0:00:00\t{rss}\t0\t0\t0\t0\t0\t0\t{cpu}\n")
    import os

    os.utime(path, (mtime, mtime))


def test_pipeline_time_record_counts_only_this_run_and_feeds_the_readme(tmp_path):
    import pandas as pd

    from hypotrack.reporting.pipeline_time import WHOLE_RUN, write_run_record
    from hypotrack.reporting.readme import check_readme, main

    # two shards of one rule and one job of another in this run; one older job from an earlier run
    _benchmark(tmp_path, "ssa50_run", "rfisst", 600.0, 590.5, 300.0, 2000)
    _benchmark(tmp_path, "sht_shard", "0", 30.0, 20.0, 100.0, 2000)
    _benchmark(tmp_path, "sht_shard", "1", 40.0, 25.0, 120.0, 2000)
    _benchmark(tmp_path, "theory_claims", "job", 5.0, 4.0, 50.0, 500)
    path = write_run_record(tmp_path, started=1000, finished=1000 + 1500, cores=2)
    record = pd.read_csv(path)
    assert list(record["rule"]) == [WHOLE_RUN, "ssa50_run", "sht_shard"]  # sorted by CPU, old job left out
    whole = record.iloc[0]
    assert (whole["jobs"], whole["wall_s"], whole["cpu_s"], whole["max_rss_mib"], whole["cores"]) == (3, 1500, 635.5, 300, 2)
    assert tuple(record.iloc[2][["jobs", "wall_s", "cpu_s", "max_rss_mib"]]) == (2, 70.0, 45.0, 120.0)
    assert write_run_record(tmp_path, started=3000, finished=3100, cores=2) is None  # nothing ran: kept
    # a run resumed after an interruption: the two invocations' elapsed times, not the pause between
    resumed = pd.read_csv(write_run_record(tmp_path, started=1000, finished=9000, cores=2, elapsed_s=1500))
    assert resumed.equals(record)
    # a run through an executor (cluster profile) has no number of cores
    from hypotrack.reporting.pipeline_time import runtime_sentence

    cluster = pd.read_csv(write_run_record(tmp_path, started=1000, finished=1600, cores=None))
    assert pd.isna(cluster.loc[0, "cores"]) and runtime_sentence(cluster).startswith(
        "10 minutes measured through an executor (a cluster) (11 CPU-minutes over 3 jobs")
    write_run_record(tmp_path, started=1000, finished=2500, cores=2)
    # the README's run-time span is generated from the record beside the ledger
    ledger = _ledger(tmp_path / "paper")
    readme = tmp_path / "README.md"
    readme.write_text(README.read_text())
    assert main([str(ledger), str(readme)]) == 0
    assert ("25 minutes measured on 2 cores (11 CPU-minutes over 3 jobs; largest, in CPU-minutes: ssa50_run 10, "
            "sht_shard 1)") in readme.read_text()
    record.loc[0, "wall_s"] = 3000
    record.to_csv(path, index=False)
    assert "50 minutes" in check_readme(readme, ledger)


def test_readme_states_the_detection_probability_ranges_the_code_enforces():
    """The README said p_D lies in (0, 1] while the hypothesis filters refuse 1."""
    import numpy as np
    import pytest

    from hypotrack.hypotheses import hfisst
    from hypotrack.models import ConstantVelocity
    from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
    from hypotrack.trackers import ScanModel, SingleHypothesisTracker

    text = " ".join(README.read_text().split())
    assert "lies in (0, 1) for the hypothesis filters" in text and "(0, 1] for GNN, JPDA and PDAF" in text
    region = Box([-10.0, -10.0], [10.0, 10.0])
    sensor = Sensor(LinearPositionSensor(np.eye(2), ndim_state=4), DetectionModel(p_D=1.0, fov=region),
                    PoissonClutter(rate=1.0, region=region))
    with pytest.raises(ValueError, match=r"p_D must lie in \(0, 1\)"):
        hfisst(ConstantVelocity(q=0.1), sensor)
    H = np.hstack([np.eye(2), np.zeros((2, 2))])
    for association in ("gnn", "jpda", "pdaf"):
        SingleHypothesisTracker(ConstantVelocity(0.1), ScanModel(H, np.eye(2), 1.0, 0.99, 1e-3), association=association)


def test_results_readme_lists_every_folder_the_rules_write_and_names_real_modules():
    """results/README.md named a module that does not exist and omitted three result folders."""
    import importlib

    root = README.parent
    text = (root / "results" / "README.md").read_text()
    rules = "\n".join(p.read_text() for p in [root / "Snakefile", *sorted((root / "workflows" / "rules").glob("*.smk"))])
    folders = set(re.findall(r"\{RESULTS\}/([A-Za-z0-9_]+)(?=[/\"])", rules))
    assert {"ssa", "paper", "logs", "benchmarks", "glmb_benchmark", "samplers", "ssa_catalogue"} <= folders
    listed = set(re.findall(r"^\| `([A-Za-z0-9_]+)/` \|", text, re.M))
    assert folders <= listed, f"results/README.md does not list {sorted(folders - listed)}"
    modules = set(re.findall(r"`(?:python -m )?(hypotrack(?:\.[A-Za-z_][A-Za-z0-9_]*)+)", text))
    assert modules
    for name in sorted(modules):
        importlib.import_module(name)


def test_readme_report_command_takes_the_runs_config():
    """Without the run's --configfile the report mixed two configs (46 missing-metadata warnings)."""
    text = README.read_text()
    commands = re.findall(r"^snakemake --report [^\n]*", text, re.M)
    assert commands and all("--configfile" in c for c in commands)
    assert "they must match" in " ".join(text.split())


def test_a_record_assembled_from_several_invocations_states_cpu_time_and_no_wall_clock(tmp_path):
    import pandas as pd

    from hypotrack.reporting.pipeline_time import WHOLE_RUN, assembled_run_record, runtime_sentence

    # jobs of one config written by two invocations (mtimes 500 and 2000): every job counts
    _benchmark(tmp_path, "ssa50_run", "rfisst", 600.0, 590.5, 300.0, 500)
    _benchmark(tmp_path, "sht_shard", "0", 30.0, 20.0, 100.0, 2000)
    _benchmark(tmp_path, "theory_claims", "job", 5.0, 4.0, 50.0, 2000)
    record = pd.read_csv(assembled_run_record(tmp_path, cores=2))
    whole = record.iloc[0]
    assert whole["rule"] == WHOLE_RUN and whole["jobs"] == 3 and whole["cpu_s"] == 614.5 and pd.isna(whole["wall_s"])
    # 614.5 CPU-s = 10.2 CPU-minutes: on 2 cores at least 5 minutes
    assert runtime_sentence(record) == ("not measured as one run (10 CPU-minutes over 3 jobs; largest, in CPU-minutes: "
                                        "ssa50_run 10, sht_shard 0, theory_claims 0; at least 5 minutes on 2 cores)")

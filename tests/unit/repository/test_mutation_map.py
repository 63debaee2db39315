"""The mutation runner's module -> tests map is derived from the test layout (tests/unit mirrors
src/hypotrack) and still finds every test file the hand-kept map listed."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def _runner():
    spec = importlib.util.spec_from_file_location("run_mutation", ROOT / "workflows" / "mutation" / "run_mutation.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


RUNNER = _runner()

# The map as kept by hand before it was derived (its files at their mirrored paths).
HAND_KEPT = {
    "gaussian": ["tests/unit/test_gaussian.py", "tests/unit/test_bad_input_catalogue.py"],
    "metrics": ["tests/unit/test_metrics.py", "tests/property/test_metrics_properties.py",
                "tests/unit/test_bad_input_catalogue.py"],
    "hypotheses": ["tests/unit/hypotheses/test_filter.py", "tests/unit/hypotheses/test_weights.py",
                   "tests/unit/hypotheses/test_filter_exact.py", "tests/unit/hypotheses/test_parts.py",
                   "tests/unit/hypotheses/test_glmb.py", "tests/unit/hypotheses/test_glmb_exact.py",
                   "tests/crosscheck/test_equivalence_glmb.py",
                   "tests/unit/hypotheses/test_problems.py", "tests/unit/hypotheses/test_population_events.py",
                   "tests/unit/test_protocol_transactional.py",
                   "tests/property/test_pretrim_exact.py", "tests/property/test_hypotheses_properties.py",
                   "tests/unit/test_bad_input_catalogue.py"],
    "association": ["tests/unit/association/test_assignment.py", "tests/unit/association/test_clustering.py",
                    "tests/unit/association/test_counting.py", "tests/unit/association/test_enumeration.py",
                    "tests/unit/association/test_gating.py", "tests/unit/association/test_marginals.py",
                    "tests/unit/association/test_mcmc.py", "tests/property/test_association_assignment_properties.py",
                    "tests/property/test_association_clustering_properties.py",
                    "tests/property/test_association_enumeration_properties.py",
                    "tests/crosscheck/test_cardinality_assignment.py", "tests/unit/test_bad_input_catalogue.py"],
    "trackers": ["tests/unit/trackers/test_gnn.py", "tests/unit/trackers/test_jpda.py",
                 "tests/unit/trackers/test_initiation.py", "tests/unit/trackers/test_ecmht.py",
                 "tests/unit/trackers/test_ecmht_mospa.py", "tests/unit/trackers/test_cardinality.py",
                 "tests/unit/trackers/test_cardinality_oracles.py", "tests/unit/trackers/test_tracker_values.py",
                 "tests/unit/trackers/test_jpda_values.py", "tests/unit/trackers/test_ecmht_values.py",
                 "tests/unit/trackers/test_gnn_values.py", "tests/unit/test_protocol_transactional.py",
                 "tests/crosscheck/test_stonesoup_sht.py", "tests/unit/test_bad_input_catalogue.py"],
    # single modules added to the map since: their mirrored unit tests
    "models.measurement": ["tests/unit/models/test_measurement.py"],
    "models.plausibility": ["tests/unit/models/test_plausibility.py"],
    "scenarios.catalogue.radar_model": ["tests/unit/scenarios/catalogue/test_radar_model.py"],
    "scenarios.catalogue.admissible": ["tests/unit/scenarios/catalogue/test_admissible.py"],
    "scenarios.catalogue.snr": ["tests/unit/scenarios/catalogue/test_snr.py"],
    "trackers.deferred": ["tests/unit/trackers/test_deferred.py"],
    "metrics_scorecard": ["tests/unit/test_metrics_scorecard.py"],
    "metrics_trajectory": ["tests/unit/test_metrics_trajectory.py"],
    "scenarios.catalogue.sbm": ["tests/unit/scenarios/catalogue/test_sbm.py",
                                "tests/unit/scenarios/catalogue/test_breakup.py"],
    "experiments.ssa_breakup.identities": ["tests/unit/experiments/ssa_breakup/test_identities.py"],
    "experiments.ssa_breakup.custody": ["tests/unit/experiments/ssa_breakup/test_custody.py"],
    "experiments.ssa_breakup.summary": ["tests/unit/experiments/ssa_breakup/test_summary.py",
                                        "tests/unit/experiments/ssa_breakup/test_identities.py"],
    "experiments.ssa_breakup.tuning": ["tests/unit/experiments/ssa_breakup/test_tuning.py"],
    "experiments.ssa_breakup.scorecard": ["tests/unit/experiments/ssa_breakup/test_scorecard.py"],
    "scenarios.catalogue.fov_edge": ["tests/unit/scenarios/catalogue/test_fov_edge.py"],
}


def test_the_same_modules_are_mutated():
    assert set(RUNNER.MODULES) == set(HAND_KEPT)


@pytest.mark.parametrize("module", sorted(HAND_KEPT))
def test_the_derived_map_finds_unit_tests_for_every_core_module(module):
    sources, tests = RUNNER.MODULES[module]
    derived = [t for s in sources for t in RUNNER.unit_tests(s)]
    assert derived and all(t.startswith("tests/unit/") for t in derived)
    assert set(HAND_KEPT[module]) <= set(tests)  # nothing the hand-kept map ran is lost
    assert all((ROOT / t).is_file() for t in tests)
    assert len(tests) == len(set(tests))
    # the scratch project imports test modules by file name (pytest's default import mode)
    assert len({Path(t).name for t in tests}) == len(tests)


def test_extras_are_only_tests_outside_the_mirror():
    """Crosscheck, property and package-wide tests are listed by hand, and the unit tests of another module that
    exercise this one (the breakup scenario's tests draw from the breakup model); a module's own mirrored unit test
    never is."""
    for module, extras in RUNNER.EXTRA_TESTS.items():
        for t in extras:
            assert (ROOT / t).is_file(), t
            assert t not in [u for s in RUNNER.SOURCES[module] for u in RUNNER.unit_tests(s)], t


def test_each_file_is_mutated_in_one_module_only():
    """A folder module leaves out the files a single module names (each mutant is counted in one row)."""
    owner = {}
    for module, (files, _) in RUNNER.MODULES.items():
        for f in files:
            assert f not in owner, (f, owner.get(f), module)
            owner[f] = module
    assert owner["src/hypotrack/trackers/deferred.py"] == "trackers.deferred"
    assert owner["src/hypotrack/trackers/gnn.py"] == "trackers"
    assert all((ROOT / f).is_file() for f in owner)


def test_the_derivation_rule(tmp_path):
    for rel in ["tests/unit/test_metrics.py", "tests/unit/test_metrics_extra.py", "tests/unit/test_logspace.py",
                "tests/unit/test_gaussian.py", "tests/unit/a/test_b.py", "tests/unit/a/test_b_values.py",
                "tests/unit/a/test_bc.py", "tests/unit/a/test_c.py", "tests/unit/a/d/test_e.py",
                "tests/unit/a/helper.py", "tests/unit/x/test_b.py"]:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).touch()
    rule = RUNNER.unit_tests
    assert rule("src/hypotrack/metrics.py", tmp_path) == ["tests/unit/test_metrics.py",
                                                          "tests/unit/test_metrics_extra.py"]
    assert rule("src/hypotrack/_logspace.py", tmp_path) == ["tests/unit/test_logspace.py"]
    assert rule("src/hypotrack/a/b.py", tmp_path) == ["tests/unit/a/test_b.py", "tests/unit/a/test_b_values.py",
                                                      "tests/unit/a/test_bc.py"]
    assert rule("src/hypotrack/a/*", tmp_path) == ["tests/unit/a/d/test_e.py", "tests/unit/a/test_b.py",
                                                   "tests/unit/a/test_b_values.py", "tests/unit/a/test_bc.py",
                                                   "tests/unit/a/test_c.py"]
    assert rule("src/hypotrack/none.py", tmp_path) == []


def test_the_scratch_project_collects_its_tests(tmp_path):
    """The module's tests, copied with the shared scene builders, import in the scratch project."""
    n = RUNNER.prepare_files("hypotheses", ["src/hypotrack/hypotheses/presets.py"], tmp_path)
    assert n == len(RUNNER.MODULES["hypotheses"][1])
    assert (tmp_path / "tests" / "scenes.py").is_file()
    out = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", *RUNNER.MODULES["hypotheses"][1]],
                         cwd=tmp_path, capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": str(tmp_path / "src")})
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert " error" not in out.stdout


def test_test_data_folders_exist_and_reach_the_scratch_project(tmp_path):
    """A module's tests that read repository folders (the tuning tests read workflows/config) get them copied into
    the scratch project and named in its ``also_copy`` (mutmut copies them into mutants/, where the tests run)."""
    import tomllib

    for module, folders in RUNNER.TEST_DATA.items():
        assert module in RUNNER.SOURCES and all((ROOT / d).is_dir() for d in folders), module
    module = "experiments.ssa_breakup.tuning"
    RUNNER.prepare_files(module, RUNNER.MODULES[module][0], tmp_path)
    cfg = tomllib.loads((tmp_path / "pyproject.toml").read_text())["tool"]["mutmut"]
    assert cfg["also_copy"] == ["workflows/config"] and (tmp_path / "workflows" / "config" / "default.yaml").is_file()
    other = tmp_path / "other"
    RUNNER.prepare_files("experiments.ssa_breakup.custody", RUNNER.MODULES["experiments.ssa_breakup.custody"][0], other)
    assert "also_copy" not in tomllib.loads((other / "pyproject.toml").read_text())["tool"]["mutmut"]

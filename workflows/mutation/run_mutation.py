"""Mutation testing of hypotrack with mutmut 3, one module at a time (a standing quality measure,
not a pipeline rule and not part of CI).

For each module it builds a scratch project under ``results/quality/mutmut/<module>/`` holding
the package source and only the test files that exercise the module, and runs
``mutmut run --max-children <n>`` there (mutmut 3 maps every mutated function to the tests that
execute it, so each mutant runs only those). It then reads mutmut's per-file ``.meta`` results
and writes ``paper/record/mutation.csv``::

    module, mutants, killed, survived, no_tests, timeout, not_run, equivalent, killed_pct_non_equivalent,
    seconds, scope (the files mutated)

``not_run`` counts mutants an interrupted run did not reach (left out of the score).
``equivalent`` counts the surviving mutants listed, each with a one-line reason, in
``workflows/mutation/equivalent.yaml`` (mutants that change no observable behaviour); the score
is ``(killed + timeout) / (mutants − equivalent − not_run)`` (a mutant that makes the tests hang
is detected), so a survivor and a mutant no selected test reaches ("no tests") count against it. The surviving, non-equivalent mutants are
listed in ``paper/record/mutation_survivors.csv`` (``mutmut show <name>`` in the scratch
directory prints the diff).

Usage (from the repository root; about 10 min for ``gaussian`` on one shared core, far longer for
the engine modules)::

    python workflows/mutation/run_mutation.py gaussian metrics hypotheses association trackers
    python workflows/mutation/run_mutation.py models.measurement trackers.deferred   # single modules
    python workflows/mutation/run_mutation.py --report-only   # re-read the last runs' results
    python workflows/mutation/run_mutation.py trackers --resume   # after adding tests: rerun the rest
    python workflows/mutation/run_mutation.py hypotheses --mutants 'hypotrack.hypotheses.gibbs*'
        # only these mutants (names or globs): a long module a few files at a time

``--resume`` keeps the module's scratch directory, copies the current source and tests into it
and reruns only the mutants not yet detected (survivors, "no tests", not run, and every mutant
of a function whose source changed). A detected mutant stays detected when tests are only
added, so its verdict is kept from the earlier run (mutmut itself clears all verdicts when the
list of test files changes; they are restored for functions whose source hash is unchanged).
``--mutants`` limits a run or a resume to the named mutants (the first such run prepares the
scratch project over the module's whole scope and leaves the other mutants "not run"); the
row's ``scope`` then names the files whose mutants all ran and, after ``| not run:``, the others.

Modules already in ``mutation.csv`` and not named on the command line keep their rows.
"""

from __future__ import annotations

import argparse
import csv
import fnmatch
import json
import os
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "paper" / "record"  # the committed record; scratch copies stay under results/quality/
WORK = ROOT / "results" / "quality" / "mutmut"
EQUIVALENT = Path(__file__).with_name("equivalent.yaml")

# The modules mutated (a subpackage as ``<folder>/*``) and the tests each runs. The unit tests are
# found from the layout, tests/unit mirroring src/hypotrack (unit_tests); only the crosscheck,
# property and package-wide tests that also guard a module are listed by hand.
SOURCES = {
    "gaussian": ["src/hypotrack/gaussian.py"],
    "metrics": ["src/hypotrack/metrics.py"],
    "hypotheses": ["src/hypotrack/hypotheses/*"],
    "association": ["src/hypotrack/association/*"],
    "trackers": ["src/hypotrack/trackers/*"],
    # Single modules, keyed by their dotted path under hypotrack (the prefix of their mutants' names);
    # a folder module above leaves out the files one of these claims.
    "models.measurement": ["src/hypotrack/models/measurement.py"],
    "models.plausibility": ["src/hypotrack/models/plausibility.py"],
    "scenarios.catalogue.radar_model": ["src/hypotrack/scenarios/catalogue/radar_model.py"],
    "scenarios.catalogue.admissible": ["src/hypotrack/scenarios/catalogue/admissible.py"],
    "scenarios.catalogue.snr": ["src/hypotrack/scenarios/catalogue/snr.py"],
    "trackers.deferred": ["src/hypotrack/trackers/deferred.py"],
    "metrics_scorecard": ["src/hypotrack/metrics_scorecard.py"],
    "metrics_trajectory": ["src/hypotrack/metrics_trajectory.py"],
    "scenarios.catalogue.sbm": ["src/hypotrack/scenarios/catalogue/sbm.py"],
    "experiments.ssa_breakup.identities": ["src/hypotrack/experiments/ssa_breakup/identities.py"],
    "experiments.ssa_breakup.custody": ["src/hypotrack/experiments/ssa_breakup/custody.py"],
    "experiments.ssa_breakup.summary": ["src/hypotrack/experiments/ssa_breakup/summary.py"],
    "experiments.ssa_breakup.tuning": ["src/hypotrack/experiments/ssa_breakup/tuning.py"],
    "experiments.ssa_breakup.scorecard": ["src/hypotrack/experiments/ssa_breakup/scorecard.py"],
    "scenarios.catalogue.fov_edge": ["src/hypotrack/scenarios/catalogue/fov_edge.py"],
}
CATALOGUE = "tests/unit/test_bad_input_catalogue.py"  # bad input at every public entry point
STEPS = "tests/unit/test_protocol_transactional.py"  # every tracker's step is all-or-nothing
EXTRA_TESTS = {
    "gaussian": [CATALOGUE],
    "metrics": ["tests/property/test_metrics_properties.py", CATALOGUE],
    "hypotheses": ["tests/crosscheck/test_equivalence_glmb.py", "tests/property/test_pretrim_exact.py",
                   "tests/property/test_hypotheses_properties.py", STEPS, CATALOGUE],
    "association": ["tests/property/test_association_assignment_properties.py",
                    "tests/property/test_association_clustering_properties.py",
                    "tests/property/test_association_enumeration_properties.py",
                    "tests/crosscheck/test_cardinality_assignment.py", "tests/crosscheck/test_equivalence_glmb_gibbs.py",
                    CATALOGUE],
    "trackers": ["tests/crosscheck/test_stonesoup_sht.py", STEPS, CATALOGUE],
    "scenarios.catalogue.sbm": ["tests/unit/scenarios/catalogue/test_breakup.py"],
    # the ambiguity output's sweep table and withheld note, checked by hand beside the policy
    "experiments.ssa_breakup.summary": ["tests/unit/experiments/ssa_breakup/test_identities.py"],
}
# Imported by the tests (``from scenes import ...``, the array form of the quiet step; the scratch pyproject puts
# tests/ on the path).
TEST_HELPERS = ["tests/scenes.py", "tests/sleeping_arrays.py"]
# Repository folders a module's tests read (copied into the scratch project and, as mutmut's ``also_copy``, into
# its mutants/ copy, where the tests run).
TEST_DATA = {"experiments.ssa_breakup.tuning": ["workflows/config"],
             "scenarios.catalogue.fov_edge": ["workflows/config"]}  # its filter test reads the breakup config


def unit_tests(source: str, root: Path = ROOT) -> list:
    """The unit tests of a source file or subpackage, from the mirrored layout: the tests of
    ``src/hypotrack/a/b.py`` are ``tests/unit/a/test_b*.py`` (a leading underscore of the module
    dropped), those of a subpackage ``src/hypotrack/a/*`` every ``test_*.py`` under ``tests/unit/a/``."""
    rel = Path(source).relative_to("src/hypotrack")
    folder = root / "tests" / "unit" / rel.parent
    found = folder.rglob("test_*.py") if rel.name == "*" else folder.glob(f"test_{rel.stem.lstrip('_')}*.py")
    return sorted(p.relative_to(root).as_posix() for p in found)


def module_tests(module: str, root: Path = ROOT) -> list:
    """The test files run against ``module``'s mutants: its unit tests, then its listed extras."""
    derived = [t for source in SOURCES[module] for t in unit_tests(source, root)]
    return list(dict.fromkeys(derived + EXTRA_TESTS.get(module, [])))


def mutated_files(module: str, root: Path = ROOT) -> list:
    """The files mutated for ``module``: its sources, a folder ``a/*`` as the files under it less those
    another module names itself (each mutant counted in one row only)."""
    claimed = {s for m, sources in SOURCES.items() if m != module for s in sources if not s.endswith("/*")}
    out = []
    for source in SOURCES[module]:
        if source.endswith("/*"):
            found = sorted(p.relative_to(root).as_posix() for p in (root / source[:-2]).rglob("*.py"))
            out += [f for f in found if f not in claimed]
        else:
            out.append(source)
    return out


MODULES = {module: (mutated_files(module), module_tests(module)) for module in SOURCES}

# mutmut 3 exit codes (mutmut.stats.status_by_exit_code)
# (-11: the tests crashed with SIGSEGV, e.g. a mutant indexing out of bounds in compiled code: detected;
# -9: SIGKILL, mutmut's hard stop one CPU second after the SIGXCPU of its time limit: a timeout)
KILLED, SURVIVED, NO_TESTS = {1, 3, -11}, {0}, {5, 33}
TIMEOUT = {36, 24, -24, 152, 255, -9}
FIELDS = ["module", "mutants", "killed", "survived", "no_tests", "timeout", "not_run", "equivalent",
          "killed_pct_non_equivalent", "seconds", "scope"]


def _toml_list(values) -> str:
    return "[" + ", ".join(json.dumps(v) for v in values) + "]"


def prepare(module: str, only=None) -> Path:
    """Scratch project: the package source, the module's tests and a pyproject for mutmut."""
    work = WORK / module
    if work.exists():
        shutil.rmtree(work)
    prepare_files(module, only or MODULES[module][0], work)
    return work


def prepare_files(module: str, only, work: Path) -> int:
    """Copy the source and the module's tests into ``work`` and write its pyproject; the number of test files."""
    tests = MODULES[module][1]
    shutil.copytree(ROOT / "src", work / "src", ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    for t in [*tests, *TEST_HELPERS]:
        (work / t).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / t, work / t)
    for d in TEST_DATA.get(module, []):
        shutil.copytree(ROOT / d, work / d, dirs_exist_ok=True)
    base = tomllib.loads((ROOT / "pyproject.toml").read_text()).get("tool", {}).get("mutmut", {})
    lines = ["[tool.pytest.ini_options]", 'addopts = "-p no:cacheprovider"', 'pythonpath = ["tests"]', "",
             "[tool.mutmut]"]
    opts = {**base, "source_paths": ["src/hypotrack"], "only_mutate": only,
            "pytest_add_cli_args_test_selection": tests}
    if module in TEST_DATA:
        opts["also_copy"] = TEST_DATA[module]
    for k, v in opts.items():
        lines.append(f"{k} = {_toml_list(v) if isinstance(v, list) else json.dumps(v)}")
    (work / "pyproject.toml").write_text("\n".join(lines) + "\n")
    return len(tests)


def _mutmut(work: Path, max_children: int, names=(), mode: str = "w") -> None:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}  # import the mutated copy only
    env.setdefault("NUMBA_CACHE_DIR", str(work / ".numba_cache"))
    with open(work / "mutmut.log", mode) as log:
        proc = subprocess.run([sys.executable, "-m", "mutmut", "run", "--max-children", str(max_children), *names],
                              cwd=work, env=env, stdout=log, stderr=subprocess.STDOUT)
    if proc.returncode != 0:
        raise SystemExit(f"[mutation] {work.name}: mutmut exited {proc.returncode}; see {work / 'mutmut.log'}")


def run(module: str, max_children: int, only=None) -> float:
    work = prepare(module, only)
    t0 = time.perf_counter()
    _mutmut(work, max_children)
    return time.perf_counter() - t0


def _metas(work: Path) -> dict:
    """Per mutated file: (module prefix of its mutant names, mutmut's meta data)."""
    out = {}
    for meta in (work / "mutants").rglob("*.py.meta"):
        rel = meta.relative_to(work / "mutants" / "src").with_suffix("").with_suffix("")
        out[meta] = (".".join(rel.parts) + ".", json.loads(meta.read_text()))
    return out


def _function(prefix: str, key: str) -> str:
    return re.sub(r"__mutmut_\d+$", "", key[len(prefix):])


def _named(keys, names) -> list:
    """The mutant names among ``keys`` that match one of ``names`` (exact or glob); all without names."""
    return [k for k in keys if not names or any(k == n or fnmatch.fnmatchcase(k, n) for n in names)]


def resume(module: str, max_children: int, only=None, names=None) -> float:
    """Rerun the mutants an earlier run of ``module`` did not detect, with the current tests
    (only those matching ``names`` if given; without an earlier run, run just those)."""
    work = WORK / module
    if not (work / "mutants").exists():
        if not names:
            raise SystemExit(f"[mutation] {module}: nothing to resume under {work}; run it first")
        prepare(module, only)
        t0 = time.perf_counter()
        _mutmut(work, max_children, names)
        return time.perf_counter() - t0
    old = _metas(work)
    detected = KILLED | TIMEOUT
    pending = _named([k for _, data in old.values() for k, c in data["exit_code_by_key"].items()
                      if c not in detected], names)
    kept = {prefix + fn: h for prefix, data in old.values() for fn, h in data["hash_by_function_name"].items()}
    old_codes = {k: c for _, data in old.values() for k, c in data["exit_code_by_key"].items()}
    only = only or _scope(module)
    # Refresh the scratch project in place (mutmut regenerates the mutants of changed files).
    shutil.rmtree(work / "src")
    staged = prepare_files(module, only, work)
    t0 = time.perf_counter()
    if pending:
        _mutmut(work, max_children, pending)
    # Restore the detected verdicts of unchanged functions that mutmut cleared.
    for meta, (prefix, data) in _metas(work).items():
        codes, hashes = data["exit_code_by_key"], data["hash_by_function_name"]
        changed = False
        for k, c in codes.items():
            fn = _function(prefix, k)
            if c is None and old_codes.get(k) in detected and kept.get(prefix + fn) == hashes.get(fn):
                codes[k] = old_codes[k]
                changed = True
        if changed:
            meta.write_text(json.dumps(data, indent=4))
    rest = _named([k for _, data in _metas(work).values() for k, c in data["exit_code_by_key"].items() if c is None],
                  names)
    if rest:
        _mutmut(work, max_children, rest, mode="a")
    print(f"[mutation] {module}: resumed ({len(pending)} undetected, {len(rest)} new or changed; tests {staged})",
          flush=True)
    return time.perf_counter() - t0


def _scope(module: str) -> list:
    """The files mutated in the module's last run (from its scratch pyproject)."""
    cfg = WORK / module / "pyproject.toml"
    if not cfg.exists():
        return MODULES[module][0]
    return tomllib.loads(cfg.read_text())["tool"]["mutmut"]["only_mutate"]


def scope_text(module: str) -> str:
    """The row's scope: the mutated files whose mutants were all run, then those left (partly)
    unrun with their count, so that a partial run says what it covers."""
    done, left = [], []
    for meta, (_, data) in sorted(_metas(WORK / module).items()):
        codes = data["exit_code_by_key"]
        n = sum(c is None for c in codes.values())
        path = str(meta.relative_to(WORK / module / "mutants").with_suffix(""))
        if codes:
            (left.append(f"{path} ({n} of {len(codes)})") if n else done.append(path))
    if not left:
        return " ".join(_scope(module))
    return " ".join(done) + " | not run: " + " ".join(left)


def _equivalent() -> dict:
    data = yaml.safe_load(EQUIVALENT.read_text()) if EQUIVALENT.exists() else None
    return {k: str(v) for k, v in (data or {}).items()}


def summarise(module: str, seconds: float, equivalent: dict):
    """One CSV row and the surviving non-equivalent mutants of a finished run."""
    codes = {}
    for meta in (WORK / module / "mutants").rglob("*.meta"):
        codes.update(json.loads(meta.read_text())["exit_code_by_key"])
    if not codes:
        raise SystemExit(f"[mutation] {module}: no mutmut results under {WORK / module}")
    survivors, row = [], dict.fromkeys(FIELDS[1:-3], 0)
    for name, code in sorted(codes.items()):
        row["mutants"] += 1
        if code is None:  # an interrupted run: not tested yet, left out of the score
            row["not_run"] += 1
            continue
        if code in KILLED:
            row["killed"] += 1
            continue
        if name in equivalent:
            row["equivalent"] += 1
            continue
        if code in TIMEOUT:
            row["timeout"] += 1
            continue
        kind = "no_tests" if code in NO_TESTS else "survived"
        row[kind] += 1
        survivors.append({"module": module, "mutant": name, "status": kind,
                          "function": re.sub(r"__mutmut_\d+$", "", name)})
    denom = row["mutants"] - row["equivalent"] - row["not_run"]
    detected = row["killed"] + row["timeout"]  # a mutant that hangs the tests is caught too
    row["killed_pct_non_equivalent"] = round(100.0 * detected / denom, 1) if denom else 100.0
    return {"module": module, **row, "seconds": round(seconds)}, survivors


def _read(path: Path) -> list:
    if not path.exists():
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _write(path: Path, rows: list, fields: list) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("modules", nargs="*", help=f"modules to mutate, of {', '.join(MODULES)} (default: all)")
    ap.add_argument("--max-children", type=int, default=1, help="parallel mutant runs (default 1)")
    ap.add_argument("--report-only", action="store_true", help="re-read finished runs, run nothing")
    ap.add_argument("--resume", action="store_true",
                    help="keep the scratch results and rerun only the mutants not yet detected (after adding tests)")
    ap.add_argument("--only", nargs="+", metavar="GLOB",
                    help="mutate only these files of one module (a partial run; its row says so)")
    ap.add_argument("--mutants", nargs="+", metavar="NAME",
                    help="limit one module's run to these mutants (mutmut names or globs such as "
                         "'hypotrack.hypotheses.gibbs*'): a fresh scratch project runs just them, an existing "
                         "one reruns those of them not yet detected (as --resume)")
    args = ap.parse_args(argv)
    modules = args.modules or list(MODULES)
    unknown = sorted(set(modules) - set(MODULES))
    if unknown:
        ap.error(f"unknown module(s) {unknown}; choose from {list(MODULES)}")
    if args.only and len(modules) != 1:
        ap.error("--only needs exactly one module")
    if args.mutants and len(modules) != 1:
        ap.error("--mutants needs exactly one module")
    OUT.mkdir(parents=True, exist_ok=True)
    table, surv_path = OUT / "mutation.csv", OUT / "mutation_survivors.csv"
    rows = {r["module"]: r for r in _read(table)}
    equivalent = _equivalent()
    for module in modules:
        if args.report_only:
            seconds = float(rows.get(module, {}).get("seconds") or 0.0)
        elif args.resume or args.mutants:
            print(f"[mutation] {module}: resuming over {', '.join(args.only or _scope(module))}"
                  + (f" ({len(args.mutants)} mutant names or globs)" if args.mutants else ""), flush=True)
            # A resume adds to the time already spent on the same scratch copy; a fresh one starts at 0.
            fresh = not (WORK / module / "mutants").exists()
            before = 0.0 if fresh else float(rows.get(module, {}).get("seconds") or 0.0)
            seconds = before + resume(module, args.max_children, args.only, args.mutants)
        else:
            print(f"[mutation] {module}: mutmut run over {', '.join(args.only or MODULES[module][0])}", flush=True)
            seconds = run(module, args.max_children, args.only)
        rows[module], surv = summarise(module, seconds, equivalent)
        rows[module]["scope"] = scope_text(module)
        r = rows[module]
        print(f"[mutation] {module}: {r['mutants']} mutants, {r['killed']} killed, {r['equivalent']} equivalent, "
              f"{r['killed_pct_non_equivalent']} % of the non-equivalent killed ({r['seconds']} s)", flush=True)
        # Re-read the tables just before writing: another module's run may have finished meanwhile.
        current = {r["module"]: r for r in _read(table)} | {module: rows[module]}
        kept = [s for s in _read(surv_path) if s["module"] != module]
        _write(table, [current[m] for m in MODULES if m in current], FIELDS)
        _write(surv_path, kept + surv, ["module", "mutant", "status", "function"])


if __name__ == "__main__":
    main()

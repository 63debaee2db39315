"""The Snakemake pipeline, end to end on the quick config (workflow-marked, part of the default suite).

Every run happens in a temporary copy of the workflow source (Snakefile, workflows/, theory/,
paper/) with an absolute temporary results folder, so Snakemake's .snakemake/ metadata, locks and
any stray output stay out of the checkout. (``--directory`` would not do: the rules name inputs
such as ``theory/<name>.py`` and ``paper/ms.tex`` relative to the working directory.)

1. a local run of every rule with the README's command (``snakemake -c2 --configfile=...quick.yaml``,
   results in the default ``results/``) in a temporary git clone of the checkout: afterwards
   ``git status --porcelain`` is empty (no run changes a tracked file); then ``--summary``: every
   declared output exists;
2. ``--report``: every PNG the run wrote is in the report with a caption;
3. a second run from scratch through snakemake-executor-plugin-cluster-generic
   (workflows/profiles/cluster-local: each cluster job a separate process in its own scratch copy of the
   source, sharing only the results folder; ``HYPOTRACK_GROUP_JOBS=experiment`` makes each experiment's
   connected jobs one cluster job, which saves a Snakemake start-up per rule): it completes, and every table except timing tables
   has the same SHA-256 as in the local run (claims tables and the ledger without their
   measurement rows: run times).
"""

import hashlib
import json
import os
import re
import shutil
import subprocess
import time
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
SOURCES = ("Snakefile", "workflows", "theory", "paper")
QUICK = "workflows/config/quick.yaml"
pytestmark = pytest.mark.workflow

SNAKEMAKE = shutil.which("snakemake")
needs_snakemake = pytest.mark.skipif(SNAKEMAKE is None, reason="snakemake not installed")


TIMING_COLUMN = re.compile(r"(^|_)(seconds|per_second|ms|speedup)(_|$)")


def _is_timing_table(path: Path) -> bool:
    """Timing tables are named so (project convention); a table with a timing column counts as one too.

    Measured run times are not reproducible, so neither table is compared between runs.
    """
    header = path.read_text().split("\n", 1)[0].split(",")
    return "timing" in path.name or any(TIMING_COLUMN.search(c) for c in header)


def _deterministic_bytes(path: Path) -> bytes:
    """The table, without the ledger rows that report a measurement (a timing) when it holds claims."""
    import pandas as pd

    if "evidence" not in path.read_text().split("\n", 1)[0].split(","):
        return path.read_bytes()
    claims = pd.read_csv(path, dtype=str, keep_default_na=False)
    return claims[claims["evidence"] != "measurement"].to_csv(index=False).encode()


def copy_workflow(dest: Path) -> Path:
    generated = shutil.ignore_patterns(".snakemake", "__pycache__", "generated", "*.pdf", "*.aux", "*.log",
                                       "*.fls", "*.fdb_latexmk", "*.out", "*.bbl", "*.blg")
    dest.mkdir(parents=True)
    for name in SOURCES:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, dest / name, ignore=generated)
        else:
            shutil.copy2(src, dest / name)
    return dest


def clone_checkout(dest: Path) -> Path:
    """A git repository holding the checkout's files as they are now (committed or not, ignored ones left out)."""
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                            capture_output=True, text=True, check=True).stdout.split("\0")
    dest.mkdir(parents=True)
    for name in filter(None, listed):
        src = ROOT / name
        if src.is_file():
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)
    git = ["git", "-c", "user.name=test", "-c", "user.email=test@example.org"]
    for cmd in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "checkout"]):
        subprocess.run(git + cmd, cwd=dest, check=True, capture_output=True)
    return dest


def git_status(workdir: Path) -> str:
    return subprocess.run(["git", "status", "--porcelain"], cwd=workdir, capture_output=True, text=True,
                          check=True).stdout


def snakemake(workdir, *args, timeout=1800, env_extra=None):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT / "src"), os.environ.get("PYTHONPATH")])),
           **(env_extra or {})}
    return subprocess.run([SNAKEMAKE, *args], cwd=workdir, capture_output=True, text=True, timeout=timeout, env=env)


def _tail(res, n=4000):
    return (res.stdout + res.stderr)[-n:]


def _experiments():
    return sorted(p.stem for p in (ROOT / "workflows" / "rules").glob("*.smk"))


def _checkout_state():
    """What a test could leave behind in the checkout: Snakemake's folder, results/, paper/generated/."""
    found = {}
    for rel in (".snakemake", "results", "paper/generated"):
        path = ROOT / rel
        found[rel] = sorted(str(p.relative_to(ROOT)) for p in path.rglob("*")) if path.exists() else None
    return found


def _table_hashes(results: Path) -> dict:
    return {
        str(p.relative_to(results)): hashlib.sha256(_deterministic_bytes(p)).hexdigest()
        for p in sorted(results.rglob("*.csv"))
        if not _is_timing_table(p)
    }


@pytest.fixture(scope="module")
def quick_runs(tmp_path_factory):
    """The quick config run twice (local, then cluster-generic), the report, the summary, timings."""
    if SNAKEMAKE is None:
        pytest.skip("snakemake not installed")
    before = _checkout_state()
    tmp = tmp_path_factory.mktemp("pipeline")
    workdir = clone_checkout(tmp / "checkout")
    local_args = [f"--configfile={QUICK}"]  # the README's quick run, writing to the default results/
    out = {"workdir": workdir, "local": workdir / "results", "cluster": tmp / "results_cluster",
           "local_args": local_args}
    config = ["--configfile", QUICK, "--config"]

    start = time.perf_counter()
    out["local_run"] = snakemake(workdir, "-c2", *local_args)
    out["local_seconds"] = time.perf_counter() - start
    out["git_status"] = git_status(workdir)
    if out["local_run"].returncode == 0:
        out["summary"] = snakemake(workdir, "--summary", *local_args)
        out["report_path"] = tmp / "report.html"
        out["report"] = snakemake(workdir, "--report", str(out["report_path"]), *local_args)

    cluster_workdir = copy_workflow(tmp / "workflow_cluster")
    out["cluster_logs"] = cluster_workdir / ".snakemake" / "cluster-logs"
    out["cluster_run"] = None
    if out["local_run"].returncode == 0:  # else the local run's failure is the news; save the time
        start = time.perf_counter()
        out["cluster_run"] = snakemake(cluster_workdir, "--profile", "workflows/profiles/cluster-local", *config,
                                       f"results={out['cluster']}", env_extra={"HYPOTRACK_GROUP_JOBS": "experiment"})
        out["cluster_seconds"] = time.perf_counter() - start
        print(f"\nquick pipeline: local {out['local_seconds']:.0f} s, cluster-generic {out['cluster_seconds']:.0f} s")
    yield out
    assert _checkout_state() == before, "a pipeline test left files in the checkout"


@needs_snakemake
def test_quick_pipeline_writes_every_declared_output(quick_runs):
    run = quick_runs["local_run"]
    assert run.returncode == 0, _tail(run)
    summary = quick_runs["summary"]
    assert summary.returncode == 0, _tail(summary)
    rows = [line.split("\t") for line in summary.stdout.splitlines() if line.startswith("results/")]
    assert len(rows) > 50
    missing = [r[0] for r in rows if not (quick_runs["workdir"] / r[0]).exists() or "missing" in r]
    assert not missing, f"declared outputs not written: {missing}"
    rules_with_outputs = {r[2] for r in rows}
    dry = snakemake(quick_runs["workdir"], "-n", "--forceall", "--quiet", "rules", *quick_runs["local_args"])
    job_rules = set(_job_counts(dry.stdout)) - {"total"}
    # Every rule that declares outputs ran and wrote them (target-only rules such as `all` have none).
    assert job_rules - rules_with_outputs <= set(_experiments()) | {"all"}, job_rules - rules_with_outputs
    # Every job wrote a benchmark, and the run's time record (the README's run time) counts them all.
    import pandas as pd

    record = pd.read_csv(quick_runs["local"] / "paper" / "pipeline_timing.csv")
    whole = record.iloc[0]
    assert whole["rule"] == "(whole run)" and whole["cores"] == 2
    counts = _job_counts(dry.stdout)
    jobs_with_outputs = sum(n for r, n in counts.items() if r not in set(_experiments()) | {"all", "total"})
    assert whole["jobs"] == record["jobs"].iloc[1:].sum() == jobs_with_outputs
    assert 0 < whole["wall_s"] <= quick_runs["local_seconds"] and whole["cpu_s"] > 0


def _job_counts(stdout):
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+)\s+(\d+)$", stdout, re.M)} | {"total": 0}


@needs_snakemake
def test_every_experiment_rule_is_defined_and_complete(quick_runs):
    """One rule per workflows/rules/<experiment>.smk, and after the quick run none has work left."""
    assert quick_runs["local_run"].returncode == 0, _tail(quick_runs["local_run"])
    config = quick_runs["local_args"]
    listed = snakemake(quick_runs["workdir"], "--list-rules", *config)
    assert listed.returncode == 0, _tail(listed)
    missing = [e for e in _experiments() if e not in listed.stdout.split()]
    assert not missing, f"experiment rules missing from the workflow: {missing}"  # no skip
    dry = snakemake(quick_runs["workdir"], *_experiments(), "-n", "--quiet", "rules", *config)
    assert dry.returncode == 0, _tail(dry)
    pending = {r for r, n in _job_counts(dry.stdout).items() if n} - set(_experiments())
    assert not pending, f"rules with work left after the run: {pending}"


@needs_snakemake
def test_report_captions_every_figure(quick_runs):
    assert quick_runs["local_run"].returncode == 0, _tail(quick_runs["local_run"])
    assert quick_runs["report"].returncode == 0, _tail(quick_runs["report"])
    report_log = quick_runs["report"].stdout + quick_runs["report"].stderr
    assert "(ERROR/" not in report_log, "a caption is not valid reStructuredText: " + _tail(quick_runs["report"])
    html = quick_runs["report_path"].read_text()
    results = json.loads(re.search(r"var results = (\{.*?\});\n", html, re.S).group(1))
    pngs = sorted(str(p.relative_to(quick_runs["workdir"])) for p in quick_runs["local"].rglob("*.png"))
    assert pngs
    uncaptioned = [p for p in pngs if not re.sub(r"<[^>]+>|\s", "", results.get(p, {}).get("caption", ""))]
    assert not uncaptioned, f"figures missing from the report or without a caption: {uncaptioned}"
    ledger = [entry for entry in results.values() if entry["name"] == "ledger.html"]
    assert len(ledger) == 1 and ledger[0]["caption"] and ledger[0]["mime_type"] == "text/html"


@needs_snakemake
def test_the_readme_quick_run_changes_no_tracked_file(quick_runs):
    """The README's smaller run (quick config, default results/) leaves ``git status`` clean, so the
    README test still passes after it (the README quotes the committed record, not results/)."""
    assert quick_runs["local_run"].returncode == 0, _tail(quick_runs["local_run"])
    assert (quick_runs["local"] / "paper" / "ledger.csv").exists()
    assert quick_runs["git_status"] == "", f"the quick run changed tracked files:\n{quick_runs['git_status']}"
    from hypotrack.reporting.readme import check_readme

    workdir = quick_runs["workdir"]
    assert check_readme(workdir / "README.md", workdir / "paper" / "record" / "ledger.csv") is None


@needs_snakemake
def test_cluster_run_reproduces_every_table(quick_runs):
    assert quick_runs["local_run"].returncode == 0, _tail(quick_runs["local_run"])
    run = quick_runs["cluster_run"]
    logs = quick_runs["cluster_logs"]
    failed = [p for p in sorted(logs.glob("*.log")) if "Error" in p.read_text()] if logs.exists() else []
    assert run.returncode == 0, _tail(run) + "".join(f"\n--- {p.name}\n{p.read_text()[-2000:]}" for p in failed)
    local, cluster = _table_hashes(quick_runs["local"]), _table_hashes(quick_runs["cluster"])
    assert local.keys() == cluster.keys()
    differ = sorted(k for k in local if local[k] != cluster[k])
    assert not differ, f"tables differ between two runs of the same config (name timing tables *timing*): {differ}"


def _merged(base, over):
    return {k: _merged(base[k], over[k]) if isinstance(base.get(k), dict) and isinstance(over.get(k), dict)
            else over.get(k, base.get(k)) for k in base.keys() | over.keys()}


@needs_snakemake
def test_shard_counts_are_config_values(tmp_path):
    """Every Monte Carlo shard rule runs as many jobs as a config value of its experiment says.

    The value is ``n_shards`` (or, for one shard per seed, ``n_seeds``) of the experiment's section or of
    the sub-section the rule is named after; raising every such value by one adds one job to each rule.
    """
    workdir = copy_workflow(tmp_path / "workflow")
    quick = yaml.safe_load((workdir / QUICK).read_text())
    effective = _merged(yaml.safe_load((workdir / "workflows/config/default.yaml").read_text()), quick)

    def shard_jobs(*extra):
        dry = snakemake(workdir, "-n", "--forceall", "--quiet", "rules", "--configfile", QUICK, *extra,
                        "--config", f"results={tmp_path / 'results'}")
        assert dry.returncode == 0, _tail(dry)
        return {m.group(1): int(m.group(2)) for m in re.finditer(r"^(\w+_shard)\s+(\d+)$", dry.stdout, re.M)}

    jobs = shard_jobs()
    assert jobs, "no sharded Monte Carlo rule found"
    bumped = {}
    for rule, count in jobs.items():
        if rule == "ssa_seeds_chain_shard":  # one job per chain seed of each case: ssa_seeds.n_chain_seeds.<case>
            per_case = effective["ssa_seeds"]["n_chain_seeds"]
            assert sum(per_case.values()) == count
            bumped.setdefault("ssa_seeds", {})["n_chain_seeds"] = {c: n + (i == 0) for i, (c, n) in enumerate(per_case.items())}
            continue
        experiment = next((e for e in sorted(effective, key=len, reverse=True) if rule.startswith(e + "_")), None)
        assert experiment is not None, f"{rule}: no config section names its experiment"
        path, section = [experiment], effective[experiment]
        part = rule[len(experiment) + 1:-len("_shard")]  # e.g. sht_sweep_shard -> the `sweep` sub-section
        if isinstance(section.get(part), dict):
            path, section = [experiment, part], section[part]
        key = next((k for k in ("n_shards", "n_seeds") if section.get(k) == count), None)
        assert key is not None, f"{rule}: {count} jobs, but no n_shards/n_seeds of {'.'.join(path)} says so"
        node = bumped
        for name in path:
            node = node.setdefault(name, {})
        node[key] = count + 1
        if key == "n_shards" and section.get("n_runs", count + 1) < count + 1:
            node["n_runs"] = count + 1  # the config refuses more shards than runs
    more = tmp_path / "more_shards.yaml"
    more.write_text(yaml.safe_dump(_merged(quick, bumped)))
    assert shard_jobs(str(more)) == {rule: n + 1 for rule, n in jobs.items()}


@needs_snakemake
def test_bad_config_value_stops_with_field_named(tmp_path):
    workdir = copy_workflow(tmp_path / "workflow")
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"seed": -1}))
    res = snakemake(workdir, "-n", "--configfile", str(bad))
    assert res.returncode != 0
    assert "seed" in res.stdout + res.stderr

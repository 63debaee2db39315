"""The Snakemake pipeline: dry run lists every experiment; a bad config value stops it with the field named."""

import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.workflow

SNAKEMAKE = shutil.which("snakemake")
needs_snakemake = pytest.mark.skipif(SNAKEMAKE is None, reason="snakemake not installed")


def _snakemake(*args, cwd=ROOT):
    return subprocess.run([SNAKEMAKE, *args], cwd=cwd, capture_output=True, text=True, timeout=600)


def _experiments():
    return sorted(p.stem for p in (ROOT / "workflows" / "rules").glob("*.smk"))


@needs_snakemake
def test_dry_run_lists_every_experiment_rule():
    res = _snakemake("-n", "--forceall", "--quiet", "rules")
    assert res.returncode == 0, res.stderr
    for experiment in _experiments():
        assert experiment in res.stdout, f"rule {experiment} missing from the default dry run"


@needs_snakemake
def test_bad_config_value_stops_with_field_named(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump({"seed": -1}))
    res = _snakemake("-n", "--configfile", str(bad))
    assert res.returncode != 0
    assert "seed" in res.stdout + res.stderr


@needs_snakemake
def test_quick_ssa_rule_writes_figure(tmp_path):
    if "ssa" not in _experiments():
        pytest.skip("ssa rule not present")
    out = tmp_path / "results"
    # Targets go first: --configfile and --config take several values and would swallow them.
    res = _snakemake(
        "ssa", "-c2", "--nolock", "--configfile", "workflows/config/quick.yaml", "--config", f"results={out}",
    )
    assert res.returncode == 0, res.stderr[-3000:]
    for ext in ("pdf", "png"):
        fig = out / "ssa" / f"ssa50_scenario.{ext}"
        assert fig.exists() and fig.stat().st_size > 10_000

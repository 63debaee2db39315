"""The committed record of the default run: the only step that writes it.

A pipeline run writes its outputs under ``results/`` (git-ignored) whatever its config, so no run
changes a tracked file. The README's generated results and run time quote a *record* instead:
``paper/record/`` holds the ledger (``ledger.csv``), its timing rows (``ledger_timing.csv``) and the
run-time table (``pipeline_timing.csv``) of one run of the default configuration, plus the
configuration it ran with (``run_config.json``). After such a run::

    python -m hypotrack.reporting.record            # results/ -> paper/record/, then README.md

copies those files and regenerates the README's blocks (:mod:`hypotrack.reporting.readme`). It
refuses a run whose configuration differs from ``workflows/config/default.yaml`` (apart from where
the results were written): a quick or reseeded run is not the record. The mutation-testing record
(``mutation.csv``, ``mutation_survivors.csv``) sits beside it and is written only by
``workflows/mutation/run_mutation.py``.

The catalogue-scale run (``ssa_catalogue`` under ``workflows/config/full.yaml``: every object of the
catalogue, longer than the default budget) is recorded the same way by its experiment's own command,
which uses this module's config checks (:func:`comparable`, :func:`config_differences`, :func:`full_config`)::

    python -m hypotrack.experiments.ssa_catalogue.record results-full   # -> paper/record/ssa_catalogue_full.*
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

import yaml

from ..config import validate_config
from .readme import generated_readme

ROOT = Path(__file__).resolve().parents[3]
RECORD = ROOT / "paper" / "record"
FILES = ("ledger.csv", "ledger_timing.csv", "pipeline_timing.csv", "run_config.json")
IGNORED_KEYS = ("results",)  # where a run writes is not part of what it computes


def default_config(workflow_dir=ROOT / "workflows") -> dict:
    """``default.yaml`` as the pipeline sees it: validated, schema defaults filled."""
    config = yaml.safe_load((Path(workflow_dir) / "config" / "default.yaml").read_text())
    return validate_config(config, Path(workflow_dir) / "config" / "schema")


def comparable(config: dict) -> dict:
    """The config without the keys that do not change results, through JSON (tuples become lists)."""
    return json.loads(json.dumps({k: v for k, v in config.items() if k not in IGNORED_KEYS}, sort_keys=True))


def config_differences(run: dict, default: dict, prefix: str = "") -> list[str]:
    """The dotted keys at which two configs differ (sorted)."""
    out = []
    for key in sorted(set(run) | set(default)):
        a, b, name = run.get(key), default.get(key), f"{prefix}{key}"
        if isinstance(a, dict) and isinstance(b, dict):
            out += config_differences(a, b, name + ".")
        elif a != b:
            out.append(name)
    return out


def overlaid_config(names, workflow_dir=ROOT / "workflows") -> dict:
    """The config files ``names`` of ``workflows/config`` overlaid in order (dictionaries merged key by key, as
    Snakemake merges several ``--configfile``s), validated."""
    def merge(a, b):
        out = dict(a)
        for k, v in b.items():
            out[k] = merge(a[k], v) if isinstance(v, dict) and isinstance(a.get(k), dict) else v
        return out

    cfg = Path(workflow_dir) / "config"
    config = {}
    for name in names:
        config = merge(config, yaml.safe_load((cfg / name).read_text()))
    return validate_config(config, cfg / "schema")


def full_config(workflow_dir=ROOT / "workflows") -> dict:
    """``default.yaml`` overlaid with ``full.yaml`` (:func:`overlaid_config`)."""
    return overlaid_config(("default.yaml", "full.yaml"), workflow_dir)


def update_record(results="results", record=RECORD, readme=ROOT / "README.md", workflow_dir=ROOT / "workflows",
                  force: bool = False) -> list[Path]:
    """Copy a default run's ledger and timings from ``results/paper/`` to ``record``; regenerate the README.

    Raises
    ------
    FileNotFoundError
        when the run did not write one of :data:`FILES` (it has not finished).
    ValueError
        when the run's config is not the default one (names the differing keys); ``force`` records it anyway.
    """
    source = Path(results) / "paper"
    missing = [f for f in FILES if not (source / f).exists()]
    if missing:
        raise FileNotFoundError(f"results {source} lacks {', '.join(missing)}: run the pipeline to its end first")
    run = comparable(json.loads((source / "run_config.json").read_text()))
    differ = config_differences(run, comparable(default_config(workflow_dir)))
    if differ and not force:
        raise ValueError("the run's config is not workflows/config/default.yaml (differs at "
                         + ", ".join(differ[:8]) + (" ..." if len(differ) > 8 else "") + "); the record is the default run")
    Path(record).mkdir(parents=True, exist_ok=True)
    written = []
    for name in FILES:
        shutil.copyfile(source / name, Path(record) / name)
        written.append(Path(record) / name)
    return [*written, rewrite_readme(readme, record)]


def rewrite_readme(readme, record=RECORD) -> Path:
    """``readme`` with its generated blocks rewritten from the record folder ``record``."""
    readme = Path(readme)
    readme.write_text(generated_readme(readme.read_text(), Path(record) / "ledger.csv"))
    return readme


def run_step(step) -> int:
    """A recording ``step`` (a callable returning the paths it wrote) run as a command's body: prints
    what it wrote and returns 0, or prints why it refused (a run unfinished or of another config) and returns 1."""
    try:
        written = step()
    except (FileNotFoundError, ValueError) as exc:
        print(f"record: {exc}", file=sys.stderr)
        return 1
    print("record: wrote " + ", ".join(str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p) for p in written))
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hypotrack.reporting.record", description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="?", default="results", help="the run's results folder (default: results)")
    parser.add_argument("--force", action="store_true", help="record a run of another config (not the default)")
    args = parser.parse_args(argv)
    return run_step(lambda: update_record(args.results, force=args.force))


if __name__ == "__main__":
    raise SystemExit(main())

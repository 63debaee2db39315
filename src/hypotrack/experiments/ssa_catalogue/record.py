"""The committed whole-catalogue record: the only step that writes it.

The catalogue-scale run (``ssa_catalogue`` under ``workflows/config/full.yaml``: every object of the
catalogue, longer than the default budget) writes under its results folder like any run; after it::

    python -m hypotrack.experiments.ssa_catalogue.record results-full   # -> paper/record/ssa_catalogue_full.*

joins its accuracy and timing tables (one row per tracker and population size) into
``ssa_catalogue_full.csv``, copies the configuration it ran with (``ssa_catalogue_full_config.json``),
renders the README's whole-catalogue block into ``ssa_catalogue_full.md`` (:func:`.summary.full_record_markdown`)
and regenerates the README (:func:`hypotrack.reporting.record.rewrite_readme`, which reads that block
as text: reporting never imports an experiment). It refuses a run whose ``ssa_catalogue`` section or
seed is not the full configuration's (``--force`` records it anyway). ``--render`` only re-renders the
block from the committed CSV (after a change to the rendering) and regenerates the README.

The timing at scale (:mod:`.scale`: the catalogue cloned to 10⁵ and 10⁶ objects) is recorded beside it,
``ssa_catalogue_scale.csv`` (the summary: medians and spreads) and ``ssa_catalogue_scale_runs.csv`` (every run),
whenever the results hold the scale harness's tables (``scale_summary_timing.csv``, ``scale_runs_timing.csv``);
``--scale`` records those alone (the scale rule runs without the accuracy runs)::

    python -m hypotrack.experiments.ssa_catalogue.record results-full --scale

refusing tables whose sizes, trackers, runs or timed scans are not ``full.yaml``'s ``ssa_catalogue.scale``
(:func:`.scale_record.scale_config_differences`; ``--force`` records them anyway). The README's block is the
whole-catalogue table followed by the scale table (:func:`.scale_record.scale_record_markdown`) when both
are committed, either alone otherwise.
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

import pandas as pd

from ...reporting.readme import CATALOGUE_RECORD
from ...reporting.record import RECORD, ROOT, comparable, config_differences, full_config, rewrite_readme, run_step
from .run import evaluated_on
from .scale_record import scale_config_differences, scale_record_markdown
from .summary import full_record_markdown

__all__ = ["TABLE", "CONFIG", "BLOCK", "SCALE", "SCALE_RUNS", "render_record", "update_catalogue_record",
           "update_scale_record"]

TABLE = "ssa_catalogue_full.csv"
CONFIG = "ssa_catalogue_full_config.json"
BLOCK = CATALOGUE_RECORD  # ssa_catalogue_full.md, read by the README's generation
SCALE = "ssa_catalogue_scale.csv"
SCALE_RUNS = "ssa_catalogue_scale_runs.csv"
SCALE_SOURCES = {"scale_summary_timing.csv": SCALE, "scale_runs_timing.csv": SCALE_RUNS}


def render_record(record=RECORD) -> Path:
    """``record/ssa_catalogue_full.md``: the README's whole-catalogue block rendered from the
    committed ``record/ssa_catalogue_full.csv``, followed by the scale table of ``record/ssa_catalogue_scale.csv``
    when it is committed (either alone when the other is not)."""
    record = Path(record)
    parts = [render(pd.read_csv(record / name)) for name, render in
             ((TABLE, full_record_markdown), (SCALE, scale_record_markdown)) if (record / name).exists()]
    if not parts:
        raise FileNotFoundError(f"{record} holds neither {TABLE} nor {SCALE}: nothing to render")
    path = record / BLOCK
    path.write_text("\n\n".join(parts) + "\n")
    return path


def copy_scale_tables(source, record, force: bool = False, workflow_dir=ROOT / "workflows") -> list[Path]:
    """The scale harness's two tables in ``source`` copied into ``record`` (:data:`SCALE`, :data:`SCALE_RUNS`);
    ``ValueError`` when the summary is not a run of ``full.yaml``'s ``ssa_catalogue.scale`` (``force``: copy
    anyway), ``FileNotFoundError`` when either table is missing."""
    source, record = Path(source), Path(record)
    missing = [f for f in SCALE_SOURCES if not (source / f).exists()]
    if missing:
        raise FileNotFoundError(f"results {source} lacks {', '.join(missing)}: run the ssa_catalogue_scale rule first")
    summary = pd.read_csv(source / "scale_summary_timing.csv")
    differ = scale_config_differences(summary, full_config(workflow_dir)["ssa_catalogue"]["scale"])
    if differ and not force:
        raise ValueError("the scale tables are not a run of workflows/config/full.yaml's ssa_catalogue.scale ("
                         + "; ".join(differ) + ")")
    record.mkdir(parents=True, exist_ok=True)
    for src, dst in SCALE_SOURCES.items():
        shutil.copyfile(source / src, record / dst)
    return [record / dst for dst in SCALE_SOURCES.values()]


def update_scale_record(results, record=RECORD, readme=ROOT / "README.md", workflow_dir=ROOT / "workflows",
                        force: bool = False) -> list[Path]:
    """``record/ssa_catalogue_scale*.csv`` from a full-configuration scale run (:func:`copy_scale_tables`),
    the README block re-rendered (:func:`render_record`), the README's generated blocks rewritten."""
    copied = copy_scale_tables(Path(results) / "ssa_catalogue", record, force, workflow_dir)
    return copied + [render_record(record), rewrite_readme(readme, record)]


def update_catalogue_record(results, record=RECORD, readme=ROOT / "README.md", workflow_dir=ROOT / "workflows",
                            force: bool = False) -> list[Path]:
    """``record/ssa_catalogue_full.csv``: the accuracy (``summary.csv``) and timing
    (``summary_timing.csv``) tables of a full-configuration ``ssa_catalogue`` run joined on
    (tracker, N); the configuration it ran with; the README block rendered from them
    (:func:`render_record`); the README's generated blocks rewritten.

    Raises ``FileNotFoundError`` when the run has not written them, ``ValueError`` when its
    ``ssa_catalogue`` section or seed differ from the full configuration's (``force``: record anyway).
    """
    source = Path(results) / "ssa_catalogue"
    need = ("summary.csv", "summary_timing.csv", "run_config.json")
    missing = [f for f in need if not (source / f).exists()]
    if missing:
        raise FileNotFoundError(f"results {source} lacks {', '.join(missing)}: run the ssa_catalogue rules first")
    run = comparable(json.loads((source / "run_config.json").read_text()))
    full = full_config(workflow_dir)
    want = comparable({"seed": evaluated_on(full["ssa_catalogue"], full["seed"])[0], "ssa_catalogue": full["ssa_catalogue"]})
    differ = config_differences(run, want)
    if differ and not force:
        raise ValueError("the run's ssa_catalogue config is not workflows/config/full.yaml's (differs at "
                         + ", ".join(differ) + "); the catalogue record is the full run")
    acc = pd.read_csv(source / "summary.csv")
    tim = pd.read_csv(source / "summary_timing.csv")
    table = acc.merge(tim.drop(columns=[c for c in ("mean_in_view",) if c in tim]), on=["tracker", "n_objects"])
    Path(record).mkdir(parents=True, exist_ok=True)
    table.to_csv(Path(record) / TABLE, index=False, float_format="%.6g")
    shutil.copyfile(source / "run_config.json", Path(record) / CONFIG)
    scale = (copy_scale_tables(source, record, force, workflow_dir)
             if all((source / f).exists() for f in SCALE_SOURCES) else [])
    block = render_record(record)
    return [Path(record) / TABLE, Path(record) / CONFIG, *scale, block, rewrite_readme(readme, record)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hypotrack.experiments.ssa_catalogue.record",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="?", help="the full run's results folder (e.g. results-full)")
    parser.add_argument("--force", action="store_true", help="record a run of another config (not full.yaml's)")
    parser.add_argument("--render", action="store_true",
                        help="only re-render ssa_catalogue_full.md from the committed CSV and regenerate the README")
    parser.add_argument("--scale", action="store_true",
                        help="record only the timing-at-scale tables of the results (the scale rule's)")
    args = parser.parse_args(argv)
    if args.render == (args.results is not None):
        parser.error("give the results folder, or --render alone")
    if args.render:
        if args.scale:
            parser.error("--scale records a results folder; --render takes none")
        return run_step(lambda: [render_record(), rewrite_readme(ROOT / "README.md")])
    if args.scale:
        return run_step(lambda: update_scale_record(args.results, force=args.force))
    return run_step(lambda: update_catalogue_record(args.results, force=args.force))


if __name__ == "__main__":
    raise SystemExit(main())

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
from .summary import full_record_markdown

__all__ = ["TABLE", "CONFIG", "BLOCK", "render_record", "update_catalogue_record"]

TABLE = "ssa_catalogue_full.csv"
CONFIG = "ssa_catalogue_full_config.json"
BLOCK = CATALOGUE_RECORD  # ssa_catalogue_full.md, read by the README's generation


def render_record(record=RECORD) -> Path:
    """``record/ssa_catalogue_full.md``: the README's whole-catalogue block rendered from the
    committed ``record/ssa_catalogue_full.csv``."""
    path = Path(record) / BLOCK
    path.write_text(full_record_markdown(pd.read_csv(Path(record) / TABLE)) + "\n")
    return path


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
                         + ", ".join(differ[:8]) + "); the catalogue record is the full run")
    acc = pd.read_csv(source / "summary.csv")
    tim = pd.read_csv(source / "summary_timing.csv")
    table = acc.merge(tim.drop(columns=[c for c in ("mean_in_view",) if c in tim]), on=["tracker", "n_objects"])
    Path(record).mkdir(parents=True, exist_ok=True)
    table.to_csv(Path(record) / TABLE, index=False, float_format="%.6g")
    shutil.copyfile(source / "run_config.json", Path(record) / CONFIG)
    block = render_record(record)
    return [Path(record) / TABLE, Path(record) / CONFIG, block, rewrite_readme(readme, record)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hypotrack.experiments.ssa_catalogue.record",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("results", nargs="?", help="the full run's results folder (e.g. results-full)")
    parser.add_argument("--force", action="store_true", help="record a run of another config (not full.yaml's)")
    parser.add_argument("--render", action="store_true",
                        help="only re-render ssa_catalogue_full.md from the committed CSV and regenerate the README")
    args = parser.parse_args(argv)
    if args.render == (args.results is not None):
        parser.error("give the results folder, or --render alone")
    if args.render:
        return run_step(lambda: [render_record(), rewrite_readme(ROOT / "README.md")])
    return run_step(lambda: update_catalogue_record(args.results, force=args.force))


if __name__ == "__main__":
    raise SystemExit(main())

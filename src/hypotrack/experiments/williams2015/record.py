"""Make the committed record of the reference PMBM filter's run (needs GNU Octave and the reference code).

    python -m hypotrack.experiments.williams2015.record MTT_DIR TCL_DIR [N_RUNS]

runs :func:`.reference.run_reference` on runs ``0 .. N_RUNS − 1`` (default: the default config's
``reference.n_runs``) of the default config's scenario and seed, and writes the estimates, the CPU times
and the scenario signature to ``paper/record/williams2015_reference{.csv,_timing.csv,_config.json}``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import yaml

from ...scenarios.tables import write_table
from .reference import run_reference, scenario_signature
from .run import scans_of_run, truth_for

__all__ = ["write_record"]

DRIVER = Path("workflows/scripts/williams2015_reference.m")


def write_record(cfg, seed: int, mtt_dir, tcl_dir, n_runs: int, out_csv) -> None:
    """Run the reference on runs ``0 .. n_runs − 1`` and write the record beside ``out_csv``."""
    model, truth = truth_for(cfg, seed)
    scans = {r: scans_of_run(model, truth, seed, r) for r in range(n_runs)}
    est, times = run_reference(scans, model, DRIVER, mtt_dir, tcl_dir)
    out = Path(out_csv)
    write_table(est, out)
    write_table(times, out.with_name(out.stem + "_timing.csv"))
    out.with_name(out.stem + "_config.json").write_text(json.dumps(scenario_signature(cfg, seed), indent=1) + "\n")


def main(argv=None) -> None:
    args = sys.argv[1:] if argv is None else argv
    if len(args) not in (2, 3):
        raise SystemExit(__doc__)
    config = yaml.safe_load(Path("workflows/config/default.yaml").read_text())
    cfg = config["williams2015"]
    n_runs = int(args[2]) if len(args) == 3 else int(cfg["reference"]["n_runs"])
    write_record(cfg, int(config["seed"]), args[0], args[1], n_runs, cfg["reference"]["record"])


if __name__ == "__main__":
    main()
